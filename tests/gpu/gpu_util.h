/* gpu_util.h: shared helpers of the GPU tests (header only): one GL context per test binary,
 * render a scene at a time into an exr_image, simple image statistics. */
#ifndef FOVSIM_GPU_UTIL_H
#define FOVSIM_GPU_UTIL_H

#include <stdio.h>
#include <unistd.h>

#include "gl/gl_device.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "frame/frame.h"
#include "scene/scene.h"
#include "test.h"

static inline void gpu_begin(void)
{
    if (gl_device_create(&(gl_device_desc){.gpu_index = -1}) != FS_OK) {
        fprintf(stderr, "no OpenGL 4.5 context: GPU tests need Mesa's EGL (libegl-mesa0, libgl1-mesa-dri)\n");
        exit(1);
    }
    fprintf(stderr, "renderer: %s\n", gl_device_renderer());
}

/* Foveated rendering options of gpu_render_fov. */
typedef struct gpu_fov {
    const fov_layout *layout; /* NULL = off */
    float gaze[2];            /* normalised, origin top-left */
    bool overlay, debug_channels;
    bool per_pixel;           /* the composite searches every pixel's ring (no tiles) */
    alpha_params alpha;       /* zero = defaults */
    int frame;                /* frame index (stochastic thresholds change with it) */
    ring_lod_spec ring_lod;   /* zero = off */
} gpu_fov;

/* A ring layout from its text form for a w x h display of 90 degrees; exits on a bad spec. */
static inline fov_layout gpu_layout(const char *spec, int w, int h)
{
    fov_layout l;
    char err[256];
    display_desc d = {w, h, 90.0f, 0.0f, 0.0f};
    if (fov_layout_parse(spec, &d, &l, err, sizeof err) != FS_OK) {
        fprintf(stderr, "bad layout %s: %s\n", spec, err);
        exit(1);
    }
    return l;
}

/* Renders `sc` at time t into *img (R, G, B, A, coverage [, ring.id, eccentricity]) at w x h. */
static inline fs_status gpu_render_fov(const scene *sc, alpha_mode mode, int w, int h, float t, const gpu_fov *fv,
                                       exr_image *img)
{
    plan pl;
    plan_options po = {.alpha_mode = mode, .width = w, .height = h, .frames = 1};
    if (fv) {
        if (fv->layout)
            po.layout = *fv->layout;
        po.overlay = fv->overlay;
        po.debug_channels = fv->debug_channels;
        po.composite_per_pixel = fv->per_pixel;
        po.alpha = fv->alpha;
        po.ring_lod = fv->ring_lod;
    }
    fs_status st = plan_build(sc, &po, &pl);
    if (st != FS_OK)
        return st;
    renderer *r = renderer_create(&(renderer_desc){.scene = sc, .plan = &pl}, &st);
    if (!r)
        return st;
    frame_record fr = frame_record_at(sc, fv ? fv->frame : 0, t, -1.0f, w, h);
    display_desc dd = frame_display(&fr, w, h); /* the scene display's principal point */
    frame_record_set_gaze(&fr, &pl.layout, &dd, fv ? fv->gaze[0] : 0.5f, fv ? fv->gaze[1] : 0.5f);
    st = renderer_draw(r, &fr);
    if (st == FS_OK)
        st = renderer_read(r, img);
    renderer_destroy(r);
    return st;
}

/* Full resolution, gaze at the centre. */
static inline fs_status gpu_render(const scene *sc, alpha_mode mode, int w, int h, float t, exr_image *img)
{
    return gpu_render_fov(sc, mode, w, h, t, NULL, img);
}

/* A one-quad asset: corners `pos` (4 x xyz, counter-clockwise seen from +Z), `uv` (4 x uv),
 * normals +Z, white vertex colours, one material `m`, and `img` (moved in: the asset owns its
 * pixels) when m.base_color_image is 0. */
static inline asset quad_asset(const char *name, const float pos[12], const float uv[8], material m, image_rgba8 *img)
{
    asset a = {0};
    snprintf(a.name, sizeof a.name, "%s", name);
    a.prim_count = a.material_count = 1;
    a.prims = calloc(1, sizeof(prim));
    a.materials = calloc(1, sizeof(material));
    a.materials[0] = m;
    if (img) {
        a.image_count = 1;
        a.images = calloc(1, sizeof(image_rgba8));
        a.images[0] = *img;
        memset(img, 0, sizeof *img);
    }
    prim *p = &a.prims[0];
    static const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    p->vertex_count = 4;
    p->index_count = 6;
    p->positions = malloc(12 * sizeof(float));
    p->uvs = malloc(8 * sizeof(float));
    p->indices = malloc(sizeof idx);
    p->normals = calloc(12, sizeof(float));
    p->colors = malloc(16 * sizeof(float));
    memcpy(p->positions, pos, 12 * sizeof(float));
    memcpy(p->uvs, uv, 8 * sizeof(float));
    memcpy(p->indices, idx, sizeof idx);
    for (int i = 0; i < 4; i++)
        p->normals[3 * i + 2] = 1.0f;
    for (int i = 0; i < 16; i++)
        p->colors[i] = 1.0f;
    asset_compute_bounds(&a);
    return a;
}

/* A wall of `count` MegaKit plants (../shared's quaternius_megakit_set_a/<plant>.gltf, scatter seed
 * `seed`) D metres ahead, 0.9-1.1 D deep and as wide and high as a 90 degree view sees there, with
 * a still camera, 320 x 180: written to the test output directory as <tag>.json and loaded. */
static inline bool gpu_load_plant_wall(const char *tag, const char *plant, int count, int seed, float D, scene *sc)
{
    char path[1200], asset[2048], cwd[1024];
    snprintf(path, sizeof path, "%s/%s.json", test_out_dir(), tag);
    /* absolute: the scene file lives in the test output directory */
    const char *dir = test_shared_path("assets/quaternius_megakit_set_a");
    if (dir[0] == '/')
        snprintf(asset, sizeof asset, "%s", dir);
    else if (getcwd(cwd, sizeof cwd))
        snprintf(asset, sizeof asset, "%s/%s", cwd, dir);
    else
        return false;
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    fprintf(f,
            "{\"display\": {\"width\": 320, \"height\": 180, \"hfov\": 90},\n"
            " \"assets\": [{\"name\": \"p\", \"gltf\": \"%s/%s.gltf\"}],\n"
            " \"instances\": [{\"asset\": \"p\", \"scatter\": {\"count\": %d, \"seed\": %d, \"random_yaw\": true,\n"
            "   \"min\": [%g, %g, %g], \"max\": [%g, %g, %g]}}],\n"
            " \"camera\": [{\"time\": 0, \"position\": [0, 1.5, 0], \"target\": [0, 1.5, %g]}]}\n",
            asset, plant, count, seed, -0.45 * D, 1.5 - 0.22 * D, -1.1 * D, 0.45 * D, 1.5 + 0.22 * D, -0.9 * D, -D);
    fclose(f);
    return scene_load_file(path, sc) == FS_OK;
}

static inline double plane_mean(const exr_image *img, const char *ch)
{
    const float *p = exr_image_channel(img, ch);
    if (!p)
        return NAN;
    double s = 0;
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++)
        s += p[i];
    return s / (double)n;
}

static inline bool all_finite(const exr_image *img)
{
    size_t n = (size_t)img->width * (size_t)img->height;
    for (int c = 0; c < img->channel_count; c++)
        for (size_t i = 0; i < n; i++)
            if (!isfinite(img->planes[c][i]))
                return false;
    return true;
}

#endif
