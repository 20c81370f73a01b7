/* renderer.c: scene upload, program cache, forward passes, readback. */
#include "passes/renderer.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "gl/gl_program.h"
#include "passes/taa_math.h"
#include "scene/mip.h"

/* >>resources
 * What the forward pass reads and writes (STYLE.md: each pass declares its resources up front). */
typedef struct pass_resource {
    const char *name, *desc;
    GLenum format;
    bool output, optional;
} pass_resource;

/* Each ring's forward passes write these, at the ring's resolution. */
static const pass_resource k_forward_resources[] = {
    {"color", "linear premultiplied radiance, A = opacity", GL_RGBA16F, true, false},
    {"coverage", "opacity contributed by alpha-mapped surfaces", GL_R16F, true, false},
    {"depth", "depth buffer", GL_DEPTH_COMPONENT24, true, false},
    {"motion", "world position last frame - now, of swaying fragments (plan.velocity)", GL_RGBA16F, true, true},
};
enum { RES_COLOR, RES_COVERAGE, RES_DEPTH, RES_MOTION, RES_COUNT };

/* The composite reads every ring's color and coverage and writes these at display resolution. */
static const pass_resource k_composite_resources[] = {
    {"color", "display colour, rings upsampled and blended", GL_RGBA16F, true, false},
    {"coverage", "display coverage", GL_R16F, true, false},
    {"debug", "ring.id (ring + blend weight) and eccentricity (degrees)", GL_RG32F, true, true},
};
enum { OUT_COLOR, OUT_COVERAGE, OUT_DEBUG, OUT_COUNT };

/* >>types */
typedef struct gpu_program {
    GLuint id;
    GLint u_view_proj, u_has_base_tex, u_base_color, u_alpha_cutoff, u_double_sided, u_mip_bias, u_mip_scale, u_eye,
        u_light_dir, u_light_color, u_ambient, u_hash_scale, u_hash_kind, u_hash_aniso, u_fade_n, u_frame, u_time,
        u_prev_time, u_draw_order, u_list_capacity, u_hash_instance, u_hash_primitive;
} gpu_program;

typedef struct composite_program {
    GLuint id;
    GLint u_display_px, u_focal_px, u_gaze_px, u_ring_outer, u_ring_band, u_ring_rect, u_ring_block, u_array_px;
} composite_program;

typedef struct taa_program {
    GLuint id;
    GLint u_layer, u_size, u_prev_size, u_array_px, u_inv_view_proj, u_prev_view_proj, u_history_valid, u_blend,
        u_gamma, u_sparse, u_rect, u_prev_rect, u_block, u_ring_prev_rect, u_ring_block, u_cull_gaze_px,
        u_cull_display_px, u_cull_focal_px, u_ring_hole_deg;
} taa_program;

typedef struct gpu_prim {
    GLuint vao, vbo[4], ibo;
    GLsizei index_count;
    uint32_t first_triangle; /* triangles of the asset's earlier primitives (u_hash_primitive) */
} gpu_prim;

typedef struct gpu_asset {
    gpu_prim *prims;
    GLuint *textures;       /* per image */
    GLuint *castano;        /* per material: coverage-preserving chain of its image at its cutoff, or 0 */
    float *fade_n;          /* per material: hashed fade-in length in mip levels, 0 = no fade */
    GLuint *samplers;       /* per material */
    GLuint instance_vbo;    /* mat4 per instance of this asset, in instance_ids order */
    GLuint sway_vbo;        /* plan.sway: (offset, height), (frequency, phase, 0, 0) per instance */
    int *instance_ids;      /* scene instance index of each slot */
    unsigned char *visible; /* per slot: may be visible in the ring being drawn (frustum culling) */
    float *cull_pad;        /* plan.sway, per slot: how far (asset units) sway may leave the box */
    int instance_count;
    int slot_base;          /* instances of the earlier assets: slot k is the scene's slot_base + k */
} gpu_asset;

/* Ring targets: colour and coverage are texture arrays with one layer per ring, each layer the
 * size of the display (the innermost ring may need all of it); a ring renders into the
 * footprint's (width x height) corner of its layer. Rings draw one after another, so they share
 * one depth buffer. */
typedef struct ring_targets {
    GLuint fbo[MAX_FOV_RINGS];
    GLuint color, coverage, depth;
    GLuint motion; /* plan.velocity: one display-sized 2D target shared by the rings, as depth is */
    /* A2C modes: every ring draws into one shared multisampled target (display-sized), then
     * resolves its footprint corner into its layer. */
    GLuint msaa_fbo, msaa_color, msaa_coverage, msaa_depth, msaa_motion;
} ring_targets;

#define RENDERER_MAX_STAGES (2 * MAX_FOV_RINGS + PLAN_MAX_PASSES + 1)

/* One blended instance to draw, farthest first. */
typedef struct sort_item {
    float dist2;
    int asset, slot;
} sort_item;

struct renderer {
    const scene *sc;
    plan pl;
    gpu_asset *assets;
    sort_item *blend_order;                /* scratch for the BLEND sort: one per instance */
    gpu_program programs[PLAN_MAX_PASSES]; /* one per plan pass, same index */
    composite_program comp;
    composite_program comp_tile;           /* plan.composite_tiles: the rectangles of one ring */
    GLuint tile_vao, tile_vbo;             /* the composite's rectangles, rebuilt every frame */
    fov_tile *tiles;                       /* scratch: fov_tile_max rectangles */
    float *tile_verts;                     /* scratch: 6 vertices (x, y, ring) per rectangle */
    int tile_max;
    ring_targets rt;
    GLuint out_fbo, out_tex[OUT_COUNT];    /* display targets of the composite */
    GLuint empty_vao;                      /* TAA's full-screen triangle needs a bound VAO */
    GLuint ring_sampler;                   /* bilinear, clamp to edge */
    int width, height;
    bool timers;
    int stage_count;                       /* timed stages: passes (rings off) or rings + composite */
    char stage_names[RENDERER_MAX_STAGES][48];
    GLuint time_queries[RENDERER_MAX_STAGES];
    double stage_wall_ms[RENDERER_MAX_STAGES];
    /* Pipeline statistics queries of each stage (GL_ARB_pipeline_statistics_query), one per
     * k_stat_targets entry; 0 when the extension is missing or timers are off. */
    GLuint stat_queries[RENDERER_MAX_STAGES][3];
    bool stat_queries_on;
    bool stats_pending;
    /* >>taa state: resolved rings ping-pong between two pairs of arrays (no read/write of one
     * texture in a pass); the previous frame's unjittered ring matrices and footprints. */
    taa_program taa;
    GLuint taa_color[2], taa_coverage[2], taa_fbo[2][MAX_FOV_RINGS];
    GLuint taa_sampler;
    int parity;                             /* the pair this frame writes */
    int out_parity;                         /* the pair the last frame wrote */
    bool have_prev;
    int prev_index;
    float prev_time;                        /* the previous frame's time (per-object motion) */
    mat4 prev_vp[MAX_FOV_RINGS];
    fov_ring_rect prev_rect[MAX_FOV_RINGS];
    float prev_gaze_px[2], prev_focal_px;   /* plan.ring_cull: where the previous frame's holes were */
    float prev_hole_deg[MAX_FOV_RINGS];     /* fov_ring_hole_deg of the rings that culled, else 0 */
    mat4 draw_vp;                           /* the view-projection the ring being drawn uses */
    bool pass_sync;
    long long shaded_pixels;               /* ring target pixels drawn by the last frame */
    int ring_instances[MAX_FOV_RINGS];     /* instances each ring drew in the last frame */
    float *read_buf, *read_row;            /* renderer_read's scratch, made on first use */
    /* >>lists: the exact reference's list pass (plan.reference_lists; abuffer.h) */
    GLuint list_head;                      /* R32UI, display-sized: each pixel's first node */
    GLuint list_nodes, list_nodes_tex;     /* the node store and its RGBA32UI buffer texture */
    GLuint list_counter;                   /* shader storage: nodes asked for (atomicAdd) */
    uint64_t list_capacity;                /* nodes the store holds */
    uint32_t list_draw_order;              /* instances drawn so far in this pass (draw_order.glsl) */
    int list_phase;                        /* the list pass draws MASK (0), then BLEND (1) materials */
    uint64_t list_initial;                 /* renderer_desc.list_nodes, or 4 per pixel */
    GLuint list_prog;                      /* the resolve (plan.list_resolve) */
    GLint list_u_capacity;
    GLuint list_fbo, list_color, list_coverage; /* its output: RGBA32F, RG32F (coverage, flag) */
    uint32_t *list_head_buf;               /* renderer_read_lists' scratch */
    void *list_node_buf;
    uint64_t list_node_buf_cap;
};

/* >>programs */
/* Builds the program of a plan pass (its shaders and sorted defines). */
static fs_status build_pass_program(const plan_pass *ps, GLuint *id)
{
    const char *defs[PLAN_MAX_DEFINES];
    for (int i = 0; i < ps->define_count; i++)
        defs[i] = ps->defines[i];
    gpu_program_handle h = {0};
    fs_status st = gl_program_build(&(gl_program_desc){.vs = ps->vs, .fs = ps->fs, .defines = defs,
                                                       .define_count = ps->define_count, .label = ps->name},
                                    &h);
    *id = h.id;
    return st;
}

static fs_status program_create(const plan_pass *ps, gpu_program *out)
{
    fs_status st = build_pass_program(ps, &out->id);
    if (st != FS_OK)
        return st;
    GLuint p = out->id;
    out->u_view_proj = glGetUniformLocation(p, "u_view_proj");
    out->u_has_base_tex = glGetUniformLocation(p, "u_has_base_tex");
    out->u_base_color = glGetUniformLocation(p, "u_base_color");
    out->u_alpha_cutoff = glGetUniformLocation(p, "u_alpha_cutoff");
    out->u_double_sided = glGetUniformLocation(p, "u_double_sided");
    out->u_mip_bias = glGetUniformLocation(p, "u_mip_bias");
    out->u_mip_scale = glGetUniformLocation(p, "u_mip_scale");
    out->u_eye = glGetUniformLocation(p, "u_eye");
    out->u_light_dir = glGetUniformLocation(p, "u_light_dir");
    out->u_light_color = glGetUniformLocation(p, "u_light_color");
    out->u_ambient = glGetUniformLocation(p, "u_ambient");
    out->u_hash_scale = glGetUniformLocation(p, "u_hash_scale");
    out->u_hash_kind = glGetUniformLocation(p, "u_hash_kind");
    out->u_hash_aniso = glGetUniformLocation(p, "u_hash_aniso");
    out->u_fade_n = glGetUniformLocation(p, "u_fade_n");
    out->u_frame = glGetUniformLocation(p, "u_frame");
    out->u_time = glGetUniformLocation(p, "u_time");
    out->u_prev_time = glGetUniformLocation(p, "u_prev_time");
    out->u_draw_order = glGetUniformLocation(p, "u_draw_order");
    out->u_list_capacity = glGetUniformLocation(p, "u_list_capacity");
    out->u_hash_instance = glGetUniformLocation(p, "u_hash_instance");
    out->u_hash_primitive = glGetUniformLocation(p, "u_hash_primitive");
    return FS_OK;
}

static fs_status taa_create(const plan_pass *ps, taa_program *out)
{
    fs_status st = build_pass_program(ps, &out->id);
    if (st != FS_OK)
        return st;
    GLuint h = out->id;
    out->u_layer = glGetUniformLocation(h, "u_layer");
    out->u_size = glGetUniformLocation(h, "u_size");
    out->u_prev_size = glGetUniformLocation(h, "u_prev_size");
    out->u_array_px = glGetUniformLocation(h, "u_array_px");
    out->u_inv_view_proj = glGetUniformLocation(h, "u_inv_view_proj");
    out->u_prev_view_proj = glGetUniformLocation(h, "u_prev_view_proj");
    out->u_history_valid = glGetUniformLocation(h, "u_history_valid");
    out->u_blend = glGetUniformLocation(h, "u_blend");
    out->u_gamma = glGetUniformLocation(h, "u_gamma");
    out->u_sparse = glGetUniformLocation(h, "u_sparse");
    out->u_rect = glGetUniformLocation(h, "u_rect");
    out->u_prev_rect = glGetUniformLocation(h, "u_prev_rect");
    out->u_ring_prev_rect = glGetUniformLocation(h, "u_ring_prev_rect");
    out->u_ring_block = glGetUniformLocation(h, "u_ring_block");
    out->u_block = glGetUniformLocation(h, "u_block");
    out->u_cull_gaze_px = glGetUniformLocation(h, "u_cull_gaze_px");
    out->u_cull_display_px = glGetUniformLocation(h, "u_cull_display_px");
    out->u_cull_focal_px = glGetUniformLocation(h, "u_cull_focal_px");
    out->u_ring_hole_deg = glGetUniformLocation(h, "u_ring_hole_deg");
    return FS_OK;
}

static fs_status composite_create(const plan_pass *ps, composite_program *out)
{
    fs_status st = build_pass_program(ps, &out->id);
    if (st != FS_OK)
        return st;
    GLuint h = out->id;
    out->u_display_px = glGetUniformLocation(h, "u_display_px");
    out->u_focal_px = glGetUniformLocation(h, "u_focal_px");
    out->u_gaze_px = glGetUniformLocation(h, "u_gaze_px");
    out->u_ring_outer = glGetUniformLocation(h, "u_ring_outer");
    out->u_ring_band = glGetUniformLocation(h, "u_ring_band");
    out->u_ring_rect = glGetUniformLocation(h, "u_ring_rect");
    out->u_ring_block = glGetUniformLocation(h, "u_ring_block");
    out->u_array_px = glGetUniformLocation(h, "u_array_px");
    return FS_OK;
}

/* >>upload */
/* Textures are stored as RGBA16 UNORM, linear premultiplied. 16-bit unorm holds every 8-bit
 * value k/255 exactly (k/255 = 257k/65535), so a level-0 alpha equal to a material's cutoff
 * compares exactly as glTF says (alpha >= cutoff); RGBA16F would round 51/255 below a 0.2 cutoff.
 * It also keeps 1/65535 precision for dark premultiplied colour in the averaged mips. */
static GLuint upload_chain(const image_rgba8 *img, float cutoff, bool castano, fs_status *st)
{
    mip_chain mc;
    *st = castano ? mip_chain_build_castano(img, cutoff, &mc) : mip_chain_build(img, &mc);
    if (*st != FS_OK)
        return 0;
    size_t n0 = (size_t)mc.width[0] * (size_t)mc.height[0] * 4;
    uint16_t *buf = malloc(sizeof(uint16_t) * n0);
    if (!buf) {
        mip_chain_free(&mc);
        *st = FS_ERR_NOMEM;
        return 0;
    }
    GLuint t;
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, mc.level_count, GL_RGBA16, mc.width[0], mc.height[0]);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    for (int l = 0; l < mc.level_count; l++) {
        size_t n = (size_t)mc.width[l] * (size_t)mc.height[l] * 4;
        for (size_t i = 0; i < n; i++) {
            float v = mc.rgba[l][i];
            v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* also maps NaN to 0 */
            buf[i] = (uint16_t)lrintf(v * 65535.0f);
        }
        glTextureSubImage2D(t, l, 0, 0, mc.width[l], mc.height[l], GL_RGBA, GL_UNSIGNED_SHORT, buf);
    }
    free(buf);
    mip_chain_free(&mc);
    return t;
}

static GLuint make_sampler(const material *m)
{
    static const GLenum wraps[] = {[TEX_WRAP_REPEAT] = GL_REPEAT, [TEX_WRAP_CLAMP] = GL_CLAMP_TO_EDGE,
                                   [TEX_WRAP_MIRROR] = GL_MIRRORED_REPEAT};
    GLuint s;
    glCreateSamplers(1, &s);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_S, (GLint)wraps[m->wrap_s]);
    glSamplerParameteri(s, GL_TEXTURE_WRAP_T, (GLint)wraps[m->wrap_t]);
    glSamplerParameteri(s, GL_TEXTURE_MAG_FILTER, m->mag_filter == TEX_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR);
    glSamplerParameteri(s, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    return s;
}

/* Per-instance sway attributes (binding 5): (offset.xyz, height) at ATTR_SWAY, (frequency, phase)
 * at ATTR_SWAY_WAVE, 8 floats per instance. */
enum { SWAY_FLOATS = 8 };

static void upload_prim(const prim *p, gpu_prim *g, GLuint instance_vbo, GLuint sway_vbo)
{
    glCreateVertexArrays(1, &g->vao);
    glCreateBuffers(4, g->vbo);
    glCreateBuffers(1, &g->ibo);
    const float *data[4] = {p->positions, p->normals, p->uvs, p->colors};
    const int comps[4] = {3, 3, 2, 4};
    const GLuint locs[4] = {ATTR_POSITION, ATTR_NORMAL, ATTR_UV, ATTR_COLOR};
    for (int i = 0; i < 4; i++) {
        glNamedBufferStorage(g->vbo[i], (GLsizeiptr)(sizeof(float) * (size_t)comps[i] * p->vertex_count), data[i], 0);
        glVertexArrayVertexBuffer(g->vao, (GLuint)i, g->vbo[i], 0, (GLsizei)(sizeof(float) * (size_t)comps[i]));
        glVertexArrayAttribFormat(g->vao, locs[i], comps[i], GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribBinding(g->vao, locs[i], (GLuint)i);
        glEnableVertexArrayAttrib(g->vao, locs[i]);
    }
    glVertexArrayVertexBuffer(g->vao, 4, instance_vbo, 0, sizeof(mat4));
    glVertexArrayBindingDivisor(g->vao, 4, 1);
    for (GLuint c = 0; c < 4; c++) {
        glVertexArrayAttribFormat(g->vao, ATTR_INSTANCE + c, 4, GL_FLOAT, GL_FALSE, c * 4 * sizeof(float));
        glVertexArrayAttribBinding(g->vao, ATTR_INSTANCE + c, 4);
        glEnableVertexArrayAttrib(g->vao, ATTR_INSTANCE + c);
    }
    if (sway_vbo) {
        glVertexArrayVertexBuffer(g->vao, 5, sway_vbo, 0, SWAY_FLOATS * sizeof(float));
        glVertexArrayBindingDivisor(g->vao, 5, 1);
        glVertexArrayAttribFormat(g->vao, ATTR_SWAY, 4, GL_FLOAT, GL_FALSE, 0);
        glVertexArrayAttribFormat(g->vao, ATTR_SWAY_WAVE, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float));
        glVertexArrayAttribBinding(g->vao, ATTR_SWAY, 5);
        glVertexArrayAttribBinding(g->vao, ATTR_SWAY_WAVE, 5);
        glEnableVertexArrayAttrib(g->vao, ATTR_SWAY);
        glEnableVertexArrayAttrib(g->vao, ATTR_SWAY_WAVE);
    }
    glNamedBufferStorage(g->ibo, (GLsizeiptr)(sizeof(uint32_t) * p->index_count), p->indices, 0);
    glVertexArrayElementBuffer(g->vao, g->ibo);
    g->index_count = (GLsizei)p->index_count;
}

/* Fade-in length of the hashed noise for one material (seed 000 §5.5.1, docs/hashed-alpha.md):
 * fade_n mip levels (default 6), but never later than the level where the traditional test's
 * coverage of this texture at this cutoff has drifted by a quarter — a thin wire erodes by mip 3,
 * and noise that arrives at mip 6 would leave it invisible in between. No texture: no mip levels
 * to fade over, so no fade (the noise is the only way to show a constant partial alpha). */
static fs_status material_fade(const plan *pl, const material *m, const asset *as, float *out)
{
    alpha_mode mode = plan_material_mode(pl, m);
    *out = 0.0f;
    if (m->alpha_kind != ALPHA_KIND_MASK || m->base_color_image < 0 || pl->alpha.no_fade ||
        (mode != ALPHA_MODE_HASHED && mode != ALPHA_MODE_HASHED_A2C))
        return FS_OK;
    mip_chain mc;
    fs_status st = mip_chain_build(&as->images[m->base_color_image], &mc);
    if (st != FS_OK)
        return st;
    int drift = mip_coverage_drift_level(&mc, m->alpha_cutoff, 0.25);
    mip_chain_free(&mc);
    *out = fmaxf(1.0f, fminf(pl->alpha.fade_n, (float)drift));
    log_info("ALPHA: [%s] material \"%s\": hashed noise fades in over %.1f mip levels", as->name, m->name, *out);
    return FS_OK;
}

static fs_status upload_scene(renderer *r)
{
    const scene *sc = r->sc;
    r->assets = calloc((size_t)sc->asset_count + 1, sizeof *r->assets);
    r->blend_order = calloc((size_t)sc->instance_count + 1, sizeof *r->blend_order);
    if (!r->assets || !r->blend_order)
        return FS_ERR_NOMEM;
    for (int a = 0, slots = 0; a < sc->asset_count; a++) {
        const asset *as = &sc->assets[a];
        gpu_asset *ga = &r->assets[a];
        for (int i = 0; i < sc->instance_count; i++)
            ga->instance_count += sc->instances[i].asset == a;
        ga->slot_base = slots;
        slots += ga->instance_count;
        if (ga->instance_count == 0)
            continue; /* nothing places it: nothing to upload */
        ga->instance_ids = malloc(sizeof(int) * (size_t)ga->instance_count);
        ga->visible = malloc((size_t)ga->instance_count);
        mat4 *mats = malloc(sizeof(mat4) * (size_t)ga->instance_count);
        ga->prims = calloc((size_t)as->prim_count + 1, sizeof *ga->prims);
        ga->textures = calloc((size_t)as->image_count + 1, sizeof(GLuint));
        ga->samplers = calloc((size_t)as->material_count + 1, sizeof(GLuint));
        ga->castano = calloc((size_t)as->material_count + 1, sizeof(GLuint));
        ga->fade_n = calloc((size_t)as->material_count + 1, sizeof(float));
        if (!ga->instance_ids || !ga->visible || !mats || !ga->prims || !ga->textures || !ga->samplers ||
            !ga->castano || !ga->fade_n) {
            free(mats);
            return FS_ERR_NOMEM;
        }
        for (int i = 0, k = 0; i < sc->instance_count; i++)
            if (sc->instances[i].asset == a) {
                ga->instance_ids[k] = i;
                mats[k++] = sc->instances[i].transform;
            }
        glCreateBuffers(1, &ga->instance_vbo);
        glNamedBufferStorage(ga->instance_vbo, (GLsizeiptr)(sizeof(mat4) * (size_t)ga->instance_count), mats, 0);
        free(mats);
        if (r->pl.sway) {
            float *sw = malloc(sizeof(float) * SWAY_FLOATS * (size_t)ga->instance_count);
            if (!sw)
                return FS_ERR_NOMEM;
            ga->cull_pad = calloc((size_t)ga->instance_count, sizeof(float));
            if (!ga->cull_pad) {
                free(sw);
                return FS_ERR_NOMEM;
            }
            for (int k = 0; k < ga->instance_count; k++) {
                const instance *in = &sc->instances[ga->instance_ids[k]];
                const instance_sway *w = &in->sway;
                /* Sway moves a vertex up to |offset| (world) from the box: in asset units, that
                 * divided by the transform's smallest axis scale. */
                const float *m = in->transform.m;
                float smin = fminf(v3_len(v3(m[0], m[1], m[2])),
                                   fminf(v3_len(v3(m[4], m[5], m[6])), v3_len(v3(m[8], m[9], m[10]))));
                ga->cull_pad[k] = instance_sways(in) ? v3_len(w->offset) / fmaxf(smin, 1e-20f) : 0.0f;
                const float v[SWAY_FLOATS] = {w->offset.x, w->offset.y, w->offset.z, w->height, w->frequency, w->phase, 0, 0};
                memcpy(sw + SWAY_FLOATS * k, v, sizeof v);
            }
            glCreateBuffers(1, &ga->sway_vbo);
            glNamedBufferStorage(ga->sway_vbo, (GLsizeiptr)(sizeof(float) * SWAY_FLOATS * (size_t)ga->instance_count),
                                 sw, 0);
            free(sw);
        }
        for (int i = 0; i < as->image_count; i++) {
            fs_status st;
            ga->textures[i] = upload_chain(&as->images[i], 0.0f, false, &st);
            if (st != FS_OK)
                return st;
        }
        for (int m = 0; m < as->material_count; m++) {
            const material *mt = &as->materials[m];
            ga->samplers[m] = make_sampler(mt);
            /* Castano: the traditional test on a chain whose alpha is rescaled per level so each
             * level keeps level 0's coverage at this material's cutoff (seed 001). */
            fs_status fst = material_fade(&r->pl, mt, as, &ga->fade_n[m]);
            if (fst != FS_OK)
                return fst;
            if (mt->alpha_kind == ALPHA_KIND_MASK && mt->base_color_image >= 0 &&
                plan_material_mode(&r->pl, mt) == ALPHA_MODE_CASTANO) {
                fs_status st;
                ga->castano[m] = upload_chain(&as->images[mt->base_color_image], mt->alpha_cutoff, true, &st);
                if (st != FS_OK)
                    return st;
            }
        }
        for (int p = 0; p < as->prim_count; p++) {
            upload_prim(&as->prims[p], &ga->prims[p], ga->instance_vbo, ga->sway_vbo);
            if (p > 0)
                ga->prims[p].first_triangle = ga->prims[p - 1].first_triangle + as->prims[p - 1].index_count / 3u;
        }
    }
    return FS_OK;
}

/* >>targets */
static fs_status check_fbo(GLuint fbo, const char *what, int w, int h)
{
    GLenum s = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    if (s != GL_FRAMEBUFFER_COMPLETE) {
        log_error("GL: %s targets %dx%d incomplete (0x%x)", what, w, h, s);
        return FS_ERR_GL;
    }
    return FS_OK;
}

static fs_status create_targets(renderer *r)
{
    static const GLenum bufs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    int n = r->pl.layout.count;
    ring_targets *t = &r->rt;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t->color);
    glTextureStorage3D(t->color, 1, k_forward_resources[RES_COLOR].format, r->width, r->height, n);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t->coverage);
    glTextureStorage3D(t->coverage, 1, k_forward_resources[RES_COVERAGE].format, r->width, r->height, n);
    glCreateTextures(GL_TEXTURE_2D, 1, &t->depth);
    glTextureStorage2D(t->depth, 1, k_forward_resources[RES_DEPTH].format, r->width, r->height);
    int outputs = r->pl.velocity ? 3 : 2;
    if (r->pl.velocity) {
        glCreateTextures(GL_TEXTURE_2D, 1, &t->motion);
        glTextureStorage2D(t->motion, 1, k_forward_resources[RES_MOTION].format, r->width, r->height);
    }
    for (int i = 0; i < n; i++) {
        glCreateFramebuffers(1, &t->fbo[i]);
        glNamedFramebufferTextureLayer(t->fbo[i], GL_COLOR_ATTACHMENT0, t->color, 0, i);
        glNamedFramebufferTextureLayer(t->fbo[i], GL_COLOR_ATTACHMENT1, t->coverage, 0, i);
        glNamedFramebufferTexture(t->fbo[i], GL_DEPTH_ATTACHMENT, t->depth, 0);
        if (r->pl.velocity)
            glNamedFramebufferTexture(t->fbo[i], GL_COLOR_ATTACHMENT2, t->motion, 0);
        glNamedFramebufferDrawBuffers(t->fbo[i], outputs, bufs);
        fs_status st = check_fbo(t->fbo[i], "ring", r->width, r->height);
        if (st != FS_OK)
            return st;
    }
    if (r->pl.msaa) {
        glCreateFramebuffers(1, &t->msaa_fbo);
        GLuint *ms[RES_COUNT] = {&t->msaa_color, &t->msaa_coverage, &t->msaa_depth, &t->msaa_motion};
        static const GLenum att[RES_COUNT] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_DEPTH_ATTACHMENT,
                                              GL_COLOR_ATTACHMENT2};
        for (int k = 0; k < (r->pl.velocity ? RES_COUNT : RES_MOTION); k++) {
            glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, ms[k]);
            glTextureStorage2DMultisample(*ms[k], MSAA_SAMPLES, k_forward_resources[k].format, r->width, r->height,
                                          GL_TRUE);
            glNamedFramebufferTexture(t->msaa_fbo, att[k], *ms[k], 0);
        }
        glNamedFramebufferDrawBuffers(t->msaa_fbo, outputs, bufs);
        fs_status st = check_fbo(t->msaa_fbo, "MSAA ring", r->width, r->height);
        if (st != FS_OK)
            return st;
    }
    if (r->pl.taa) {
        static const GLenum two[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        for (int k = 0; k < 2; k++) {
            glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &r->taa_color[k]);
            glTextureStorage3D(r->taa_color[k], 1, GL_RGBA16F, r->width, r->height, n);
            glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &r->taa_coverage[k]);
            glTextureStorage3D(r->taa_coverage[k], 1, GL_R16F, r->width, r->height, n);
            for (int i = 0; i < n; i++) {
                glCreateFramebuffers(1, &r->taa_fbo[k][i]);
                glNamedFramebufferTextureLayer(r->taa_fbo[k][i], GL_COLOR_ATTACHMENT0, r->taa_color[k], 0, i);
                glNamedFramebufferTextureLayer(r->taa_fbo[k][i], GL_COLOR_ATTACHMENT1, r->taa_coverage[k], 0, i);
                glNamedFramebufferDrawBuffers(r->taa_fbo[k][i], 2, two);
                fs_status st = check_fbo(r->taa_fbo[k][i], "TAA history", r->width, r->height);
                if (st != FS_OK)
                    return st;
            }
        }
        glCreateVertexArrays(1, &r->empty_vao);
        glCreateSamplers(1, &r->taa_sampler);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(r->taa_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    if (plan_find(&r->pl, PLAN_PASS_FORWARD_LIST, ALPHA_MODE_DEFAULT)) {
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_head);
        glTextureStorage2D(r->list_head, 1, GL_R32UI, r->width, r->height);
        /* An integer texture with (the default) linear filtering is incomplete: reads return 0. */
        glTextureParameteri(r->list_head, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(r->list_head, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_color);
        glTextureStorage2D(r->list_color, 1, GL_RGBA32F, r->width, r->height);
        glCreateTextures(GL_TEXTURE_2D, 1, &r->list_coverage);
        glTextureStorage2D(r->list_coverage, 1, GL_RG32F, r->width, r->height);
        glCreateFramebuffers(1, &r->list_fbo);
        glNamedFramebufferTexture(r->list_fbo, GL_COLOR_ATTACHMENT0, r->list_color, 0);
        glNamedFramebufferTexture(r->list_fbo, GL_COLOR_ATTACHMENT1, r->list_coverage, 0);
        glNamedFramebufferDrawBuffers(r->list_fbo, 2, bufs);
        fs_status cst = check_fbo(r->list_fbo, "list resolve", r->width, r->height);
        if (cst != FS_OK)
            return cst;
        if (!r->empty_vao)
            glCreateVertexArrays(1, &r->empty_vao);
        glCreateBuffers(1, &r->list_counter);
        glNamedBufferStorage(r->list_counter, sizeof(GLuint), NULL, GL_DYNAMIC_STORAGE_BIT);
        if (renderer_reserve_list_nodes(r, r->list_initial) != FS_OK) {
            log_error("GL: no room for %llu fragment-list nodes (%.0f MB)", (unsigned long long)r->list_initial,
                      (double)(r->list_initial * sizeof(abuffer_node)) / 1048576.0);
            return FS_ERR_NOMEM;
        }
    }
    if (!r->pl.composite)
        return FS_OK;
    int outs = r->pl.debug_channels ? OUT_COUNT : OUT_DEBUG; /* the debug target only when asked */
    glCreateFramebuffers(1, &r->out_fbo);
    for (int k = 0; k < outs; k++) {
        glCreateTextures(GL_TEXTURE_2D, 1, &r->out_tex[k]);
        glTextureStorage2D(r->out_tex[k], 1, k_composite_resources[k].format, r->width, r->height);
        glNamedFramebufferTexture(r->out_fbo, bufs[k], r->out_tex[k], 0);
    }
    glNamedFramebufferDrawBuffers(r->out_fbo, outs, bufs);
    /* The composite's rectangles: at most one per tile, 6 vertices of (x, y, ring) each. */
    display_desc dd = {r->width, r->height, r->pl.hfov_deg};
    r->tile_max = fov_tile_max(&dd);
    r->tiles = malloc(sizeof *r->tiles * (size_t)r->tile_max);
    r->tile_verts = malloc(sizeof(float) * 18 * (size_t)r->tile_max);
    if (!r->tiles || !r->tile_verts)
        return FS_ERR_NOMEM;
    glCreateBuffers(1, &r->tile_vbo);
    glNamedBufferStorage(r->tile_vbo, (GLsizeiptr)(sizeof(float) * 18 * (size_t)r->tile_max), NULL,
                         GL_DYNAMIC_STORAGE_BIT);
    glCreateVertexArrays(1, &r->tile_vao);
    glVertexArrayVertexBuffer(r->tile_vao, 0, r->tile_vbo, 0, 3 * sizeof(float));
    glVertexArrayAttribFormat(r->tile_vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(r->tile_vao, 0, 0);
    glEnableVertexArrayAttrib(r->tile_vao, 0);
    glCreateSamplers(1, &r->ring_sampler);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(r->ring_sampler, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return check_fbo(r->out_fbo, "composite", r->width, r->height);
}

/* >>lifetime */
static void name_stages(renderer *r)
{
    r->stage_count = 0;
    if (!r->pl.composite) {
        for (int i = 0; i < r->pl.pass_count; i++)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "%s", r->pl.passes[i].name);
        if (r->pl.list_resolve)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "list resolve");
        if (r->pl.taa)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "taa resolve");
        return;
    }
    for (int i = 0; i < r->pl.layout.count; i++) {
        snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "ring %d (1/%d, all passes)", i,
                 1 << r->pl.layout.rings[i].scale_log2);
        if (r->pl.taa)
            snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "ring %d taa resolve", i);
    }
    snprintf(r->stage_names[r->stage_count++], sizeof r->stage_names[0], "composite");
}

renderer *renderer_create(const renderer_desc *desc, fs_status *status)
{
    FS_ASSERT(desc && desc->scene && desc->plan && gl_device_is_valid());
    renderer *r = calloc(1, sizeof *r);
    if (!r) {
        *status = FS_ERR_NOMEM;
        return NULL;
    }
    r->sc = desc->scene;
    r->pl = *desc->plan;
    r->width = r->pl.width;
    r->height = r->pl.height;
    r->timers = desc->timers;
    r->list_initial = desc->list_nodes ? desc->list_nodes : 4 * (uint64_t)r->width * (uint64_t)r->height;
    name_stages(r);
    fs_status st = FS_OK;
    for (int i = 0; i < r->pl.pass_count && st == FS_OK; i++)
        st = program_create(&r->pl.passes[i], &r->programs[i]);
    if (st == FS_OK && r->pl.composite)
        st = composite_create(&r->pl.composite_pass, &r->comp);
    if (st == FS_OK && r->pl.composite_tiles)
        st = composite_create(&r->pl.composite_tile_pass, &r->comp_tile);
    if (st == FS_OK && r->pl.taa)
        st = taa_create(&r->pl.taa_pass, &r->taa);
    if (st == FS_OK && r->pl.list_resolve) {
        st = build_pass_program(&r->pl.list_resolve_pass, &r->list_prog);
        r->list_u_capacity = glGetUniformLocation(r->list_prog, "u_capacity");
    }
    if (st == FS_OK)
        st = upload_scene(r);
    if (st == FS_OK)
        st = create_targets(r);
    if (st == FS_OK && r->timers) {
        glGenQueries(r->stage_count, r->time_queries);
        r->stat_queries_on = gl_device_has_pipeline_stats();
        if (r->stat_queries_on)
            glGenQueries(r->stage_count * 3, &r->stat_queries[0][0]);
    }
    if (st != FS_OK) {
        renderer_destroy(r);
        *status = st;
        return NULL;
    }
    *status = FS_OK;
    return r;
}

void renderer_destroy(renderer *r)
{
    if (!r)
        return;
    if (r->assets) {
        for (int a = 0; a < r->sc->asset_count; a++) {
            gpu_asset *ga = &r->assets[a];
            const asset *as = &r->sc->assets[a];
            if (ga->prims)
                for (int p = 0; p < as->prim_count; p++) {
                    glDeleteVertexArrays(1, &ga->prims[p].vao);
                    glDeleteBuffers(4, ga->prims[p].vbo);
                    glDeleteBuffers(1, &ga->prims[p].ibo);
                }
            if (ga->textures)
                glDeleteTextures(as->image_count, ga->textures);
            if (ga->samplers)
                glDeleteSamplers(as->material_count, ga->samplers);
            if (ga->castano)
                glDeleteTextures(as->material_count, ga->castano);
            free(ga->fade_n);
            glDeleteBuffers(1, &ga->instance_vbo);
            glDeleteBuffers(1, &ga->sway_vbo);
            free(ga->prims);
            free(ga->textures);
            free(ga->samplers);
            free(ga->castano);
            free(ga->instance_ids);
            free(ga->visible);
            free(ga->cull_pad);
        }
        free(r->assets);
    }
    free(r->blend_order);
    for (int i = 0; i < r->pl.pass_count; i++)
        glDeleteProgram(r->programs[i].id);
    glDeleteProgram(r->comp.id);
    glDeleteProgram(r->comp_tile.id);
    glDeleteVertexArrays(1, &r->tile_vao);
    glDeleteBuffers(1, &r->tile_vbo);
    free(r->tiles);
    free(r->tile_verts);
    free(r->read_buf);
    free(r->read_row);
    glDeleteTextures(1, &r->list_head);
    glDeleteTextures(1, &r->list_color);
    glDeleteTextures(1, &r->list_coverage);
    glDeleteFramebuffers(1, &r->list_fbo);
    glDeleteProgram(r->list_prog);
    glDeleteTextures(1, &r->list_nodes_tex);
    glDeleteBuffers(1, &r->list_nodes);
    glDeleteBuffers(1, &r->list_counter);
    free(r->list_head_buf);
    free(r->list_node_buf);
    glDeleteFramebuffers(MAX_FOV_RINGS, r->rt.fbo);
    glDeleteTextures(1, &r->rt.color);
    glDeleteTextures(1, &r->rt.coverage);
    glDeleteTextures(1, &r->rt.depth);
    glDeleteTextures(1, &r->rt.motion);
    glDeleteTextures(1, &r->rt.msaa_motion);
    glDeleteFramebuffers(1, &r->rt.msaa_fbo);
    glDeleteTextures(1, &r->rt.msaa_color);
    glDeleteTextures(1, &r->rt.msaa_coverage);
    glDeleteTextures(1, &r->rt.msaa_depth);
    glDeleteProgram(r->taa.id);
    glDeleteSamplers(1, &r->taa_sampler);
    for (int k = 0; k < 2; k++) {
        glDeleteFramebuffers(MAX_FOV_RINGS, r->taa_fbo[k]);
        glDeleteTextures(1, &r->taa_color[k]);
        glDeleteTextures(1, &r->taa_coverage[k]);
    }
    glDeleteFramebuffers(1, &r->out_fbo);
    glDeleteTextures(OUT_COUNT, r->out_tex);
    glDeleteVertexArrays(1, &r->empty_vao);
    glDeleteSamplers(1, &r->ring_sampler);
    if (r->timers) {
        glDeleteQueries(r->stage_count, r->time_queries);
        if (r->stat_queries_on)
            glDeleteQueries(r->stage_count * 3, &r->stat_queries[0][0]);
    }
    free(r);
}

/* >>draw */
/* History is valid when there was a previous frame, it was the frame just before, and no camera
 * cut lies between (frame_record.cut). */
static bool taa_history_valid(const renderer *r, const frame_record *fr)
{
    return r->have_prev && !fr->cut && fr->index == r->prev_index + 1;
}

static void set_frame_uniforms(const renderer *r, const gpu_program *pg, const frame_record *fr, int ring)
{
    const light_desc *L = &r->sc->light;
    (void)fr;
    glProgramUniformMatrix4fv(pg->id, pg->u_view_proj, 1, GL_FALSE, r->draw_vp.m);
    glProgramUniform3f(pg->id, pg->u_eye, fr->camera.position.x, fr->camera.position.y, fr->camera.position.z);
    glProgramUniform3f(pg->id, pg->u_light_dir, L->direction.x, L->direction.y, L->direction.z);
    glProgramUniform3f(pg->id, pg->u_light_color, L->color.x, L->color.y, L->color.z);
    glProgramUniform3f(pg->id, pg->u_ambient, L->ambient.x, L->ambient.y, L->ambient.z);
    glProgramUniform1f(pg->id, pg->u_mip_bias, r->pl.layout.rings[ring].mip_bias);
    glProgramUniform1f(pg->id, pg->u_mip_scale, exp2f(r->pl.layout.rings[ring].mip_bias));
    const alpha_params *ap = &r->pl.alpha;
    glProgramUniform1f(pg->id, pg->u_hash_scale, ap->hash_scale);
    glProgramUniform1i(pg->id, pg->u_hash_kind, ap->hash_kind);
    glProgramUniform1i(pg->id, pg->u_hash_aniso, ap->anisotropic);
    glProgramUniform1ui(pg->id, pg->u_frame, (GLuint)fr->index);
    if (r->pl.sway) {
        glProgramUniform1f(pg->id, pg->u_time, fr->time);
        /* Motion relative to the frame the history holds; none without history. */
        glProgramUniform1f(pg->id, pg->u_prev_time, taa_history_valid(r, fr) ? r->prev_time : fr->time);
    }
}

static void set_material(const gpu_program *pg, const gpu_asset *ga, const asset *as, int mi)
{
    const material *m = &as->materials[mi];
    bool tex = m->base_color_image >= 0;
    glProgramUniform1i(pg->id, pg->u_has_base_tex, tex);
    glProgramUniform4fv(pg->id, pg->u_base_color, 1, m->base_color);
    glProgramUniform1f(pg->id, pg->u_alpha_cutoff, m->alpha_cutoff);
    glProgramUniform1i(pg->id, pg->u_double_sided, m->double_sided);
    glProgramUniform1f(pg->id, pg->u_fade_n, ga->fade_n[mi]);
    GLuint t = !tex ? 0 : ga->castano[mi] ? ga->castano[mi] : ga->textures[m->base_color_image];
    glBindTextureUnit(TEX_UNIT_BASE_COLOR, t);
    glBindSampler(TEX_UNIT_BASE_COLOR, ga->samplers[mi]);
    if (m->double_sided)
        glDisable(GL_CULL_FACE);
    else
        glEnable(GL_CULL_FACE);
}

/* Which pass draws a primitive of material m. */
static bool prim_in_pass(const renderer *r, const material *m, const plan_pass *ps)
{
    switch (ps->kind) {
    case PLAN_PASS_FORWARD_OPAQUE: return m->alpha_kind == ALPHA_KIND_OPAQUE;
    case PLAN_PASS_FORWARD_MASK: return m->alpha_kind == ALPHA_KIND_MASK && plan_material_mode(&r->pl, m) == ps->mode;
    case PLAN_PASS_FORWARD_BLEND: return m->alpha_kind == ALPHA_KIND_BLEND;
    /* MASK first, then BLEND: equal depths then order as the stochastic passes' depth test would. */
    case PLAN_PASS_FORWARD_SOLID: return m->alpha_kind == ALPHA_KIND_MASK;
    case PLAN_PASS_FORWARD_LIST: return m->alpha_kind == (r->list_phase == 0 ? ALPHA_KIND_MASK : ALPHA_KIND_BLEND);
    }
    return false;
}

/* Draws the primitives of asset `a` that belong to pass `ps`, for `count` instances starting at
 * instance slot `first`. */
static void draw_asset(renderer *r, const gpu_program *pg, const plan_pass *ps, int a, int first, int count)
{
    const gpu_asset *ga = &r->assets[a];
    const asset *as = &r->sc->assets[a];
    for (int p = 0; p < as->prim_count; p++) {
        const material *m = &as->materials[as->prims[p].material];
        if (!prim_in_pass(r, m, ps))
            continue;
        set_material(pg, ga, as, as->prims[p].material);
        if (pg->u_draw_order >= 0) { /* each draw's instances take the next orders (draw_order.glsl) */
            glProgramUniform1ui(pg->id, pg->u_draw_order, r->list_draw_order);
            r->list_draw_order += (uint32_t)count;
        }
        if (pg->u_hash_instance >= 0) { /* the hashed modes' layer keys (draw_order.glsl) */
            glProgramUniform1ui(pg->id, pg->u_hash_instance, (GLuint)(ga->slot_base + first));
            glProgramUniform1ui(pg->id, pg->u_hash_primitive, ga->prims[p].first_triangle);
        }
        glBindVertexArray(ga->prims[p].vao);
        glDrawElementsInstancedBaseInstance(GL_TRIANGLES, ga->prims[p].index_count, GL_UNSIGNED_INT, NULL, count,
                                            (GLuint)first);
    }
}

/* Marks which instances ring `ring` draws: those that may be visible through its frustum (its
 * footprint's cropped projection: inner rings see a narrow cone and skip most instances' vertex
 * work), less, with plan.ring_cull, those whose whole image lies in the ring's hole (the region the
 * finer ring shows alone, fov_ring_cull_deg: it keeps a margin for the filters). Returns how many
 * instances it draws. TAA treats history from the hole as invalid (taa.frag, TAA_RING_CULL). */
static int cull_instances(renderer *r, const frame_record *fr, int ring)
{
    display_desc dd = {r->width, r->height, fr->hfov_deg};
    float hole = r->pl.ring_cull ? fov_ring_cull_deg(&dd, &r->pl.layout, ring) : 0.0f;
    int drawn = 0;
    for (int a = 0; a < r->sc->asset_count; a++) {
        gpu_asset *ga = &r->assets[a];
        const asset *as = &r->sc->assets[a];
        for (int k = 0; k < ga->instance_count; k++) {
            const mat4 *model = &r->sc->instances[ga->instance_ids[k]].transform;
            float d = ga->cull_pad ? ga->cull_pad[k] : 0.0f; /* a swaying instance's box grows */
            vec3 lo = v3_sub(as->bounds_min, v3(d, d, d)), hi = v3_add(as->bounds_max, v3(d, d, d));
            bool vis = !m4_box_outside_clip(m4_mul(fr->ring_view_proj[ring], *model), lo, hi);
            float rect[4];
            if (vis && hole > 0.0f &&
                m4_box_screen_rect(m4_mul(fr->view_proj, *model), lo, hi, (float)r->width, (float)r->height, rect))
                vis = !fov_rect_within_deg(&dd, fr->gaze_px[0], fr->gaze_px[1], rect, hole);
            ga->visible[k] = vis;
            drawn += vis;
        }
    }
    return drawn;
}

/* Every asset, instanced, in runs of consecutive visible instance slots. */
static void draw_instanced(renderer *r, const gpu_program *pg, const plan_pass *ps)
{
    for (int a = 0; a < r->sc->asset_count; a++) {
        const gpu_asset *ga = &r->assets[a];
        for (int k = 0; k < ga->instance_count;) {
            if (!ga->visible[k]) {
                k++;
                continue;
            }
            int first = k;
            while (k < ga->instance_count && ga->visible[k])
                k++;
            draw_asset(r, pg, ps, a, first, k - first);
        }
    }
}

static int cmp_far_first(const void *a, const void *b)
{
    float da = ((const sort_item *)a)->dist2, db = ((const sort_item *)b)->dist2;
    return (da < db) - (da > db);
}

/* BLEND: every instance separately, farthest first (sorted per instance by its bounds centre). */
static void draw_blend_sorted(renderer *r, const gpu_program *pg, const plan_pass *ps, const frame_record *fr)
{
    sort_item *items = r->blend_order;
    int n = 0;
    for (int a = 0; a < r->sc->asset_count; a++) {
        const asset *as = &r->sc->assets[a];
        bool has_blend = false;
        for (int p = 0; p < as->prim_count; p++)
            has_blend |= prim_in_pass(r, &as->materials[as->prims[p].material], ps);
        if (!has_blend)
            continue;
        vec3 c = v3_scale(v3_add(as->bounds_min, as->bounds_max), 0.5f);
        for (int s = 0; s < r->assets[a].instance_count; s++) {
            if (!r->assets[a].visible[s])
                continue;
            vec3 w = m4_point(r->sc->instances[r->assets[a].instance_ids[s]].transform, c);
            vec3 d = v3_sub(w, fr->camera.position);
            items[n++] = (sort_item){v3_dot(d, d), a, s};
        }
    }
    qsort(items, (size_t)n, sizeof *items, cmp_far_first);
    for (int i = 0; i < n; i++)
        draw_asset(r, pg, ps, items[i].asset, items[i].slot, 1);
}

/* What each stage counts (GL_ARB_pipeline_statistics_query), in renderer_stats order. Primitives:
 * GL_PRIMITIVES_SUBMITTED_ARB, what the draw calls send, rather than GL_CLIPPING_INPUT_PRIMITIVES_ARB:
 * it is fixed by the draw calls alone (index counts x instances the CPU culling lets through), so
 * any GPU reports the same number, while what reaches the clipper is implementation-defined. */
static const GLenum k_stat_targets[3] = {GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_PRIMITIVES_SUBMITTED_ARB,
                                         GL_FRAGMENT_SHADER_INVOCATIONS_ARB};

/* Timed stage boundaries: GL timer and pipeline statistics queries (when timers are on; one query
 * per target may be active at a time, and stages never nest), wall clock with glFinish when
 * pass_sync is on. */
static void stage_begin(renderer *r, int k)
{
    if (r->timers)
        glBeginQuery(GL_TIME_ELAPSED, r->time_queries[k]);
    if (r->stat_queries_on)
        for (int q = 0; q < 3; q++)
            glBeginQuery(k_stat_targets[q], r->stat_queries[k][q]);
}

static void stage_end(renderer *r, int k, double *t_prev)
{
    if (r->timers)
        glEndQuery(GL_TIME_ELAPSED);
    if (r->stat_queries_on)
        for (int q = 0; q < 3; q++)
            glEndQuery(k_stat_targets[q]);
    r->stage_wall_ms[k] = -1.0;
    if (r->pass_sync) {
        glFinish();
        double t = time_now();
        r->stage_wall_ms[k] = (t - *t_prev) * 1e3;
        *t_prev = t;
    }
}

/* Once per frame, where the plan has TAA_COARSE_HISTORY and history is valid: every ring's
 * previous footprint, so that a pixel a saccade moved out of its own ring's footprint can take the
 * innermost coarser ring's history. */
static void taa_set_prev_footprints(renderer *r, const frame_record *fr)
{
    float rects[MAX_FOV_RINGS][4], blocks[MAX_FOV_RINGS];
    for (int k = 0; k < fr->ring_count; k++) {
        const fov_ring_rect *q = &r->prev_rect[k];
        rects[k][0] = (float)q->x0;
        rects[k][1] = (float)q->y0;
        rects[k][2] = (float)q->x1;
        rects[k][3] = (float)q->y1;
        blocks[k] = (float)q->block;
    }
    glProgramUniform4fv(r->taa.id, r->taa.u_ring_prev_rect, fr->ring_count, &rects[0][0]);
    glProgramUniform1fv(r->taa.id, r->taa.u_ring_block, fr->ring_count, blocks);
}

/* TAA of one ring: current (jittered) ring + last frame's resolved ring -> this frame's resolved
 * ring, in the `parity` pair of arrays. */
static void taa_resolve_ring(renderer *r, const frame_record *fr, int ring)
{
    const taa_program *p = &r->taa;
    const fov_ring_rect *rr = &fr->ring_rect[ring];
    bool valid = taa_history_valid(r, fr);
    mat4 inv;
    m4_invert(fr->ring_view_proj[ring], &inv);
    const fov_ring_rect *pr = valid ? &r->prev_rect[ring] : rr;
    glBindFramebuffer(GL_FRAMEBUFFER, r->taa_fbo[r->parity][ring]);
    glViewport(0, 0, rr->width, rr->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(p->id);
    glProgramUniform1i(p->id, p->u_layer, ring);
    glProgramUniform2f(p->id, p->u_size, (float)rr->width, (float)rr->height);
    glProgramUniform2f(p->id, p->u_prev_size, (float)pr->width, (float)pr->height);
    glProgramUniform2f(p->id, p->u_array_px, (float)r->width, (float)r->height);
    glProgramUniformMatrix4fv(p->id, p->u_inv_view_proj, 1, GL_FALSE, inv.m);
    glProgramUniformMatrix4fv(p->id, p->u_prev_view_proj, 1, GL_FALSE,
                              (valid ? r->prev_vp[ring] : fr->ring_view_proj[ring]).m);
    glProgramUniform1i(p->id, p->u_history_valid, valid);
    glProgramUniform1f(p->id, p->u_blend, r->pl.taa_controls.blend);
    glProgramUniform1f(p->id, p->u_gamma, r->pl.taa_controls.gamma);
    glProgramUniform1f(p->id, p->u_sparse, fmaxf(r->pl.taa_controls.sparse, 0.0f));
    glProgramUniform4f(p->id, p->u_rect, (float)rr->x0, (float)rr->y0, (float)rr->x1, (float)rr->y1);
    glProgramUniform4f(p->id, p->u_prev_rect, (float)pr->x0, (float)pr->y0, (float)pr->x1, (float)pr->y1);
    glProgramUniform1f(p->id, p->u_block, (float)rr->block);
    if (r->pl.ring_cull) {
        glProgramUniform2f(p->id, p->u_cull_gaze_px, r->prev_gaze_px[0], r->prev_gaze_px[1]);
        glProgramUniform2f(p->id, p->u_cull_display_px, (float)r->width, (float)r->height);
        glProgramUniform1f(p->id, p->u_cull_focal_px, r->prev_focal_px);
        glProgramUniform1fv(p->id, p->u_ring_hole_deg, fr->ring_count, r->prev_hole_deg);
    }
    glBindTextureUnit(0, r->rt.color);
    glBindTextureUnit(1, r->rt.coverage);
    glBindTextureUnit(2, r->rt.depth);
    if (r->pl.velocity)
        glBindTextureUnit(5, r->rt.motion);
    glBindTextureUnit(3, r->taa_color[1 - r->parity]);
    glBindTextureUnit(4, r->taa_coverage[1 - r->parity]);
    glBindSampler(3, r->taa_sampler); /* bilinear: the 5-tap Catmull-Rom history fetch */
    glBindSampler(4, r->taa_sampler);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindSampler(3, 0);
    glBindSampler(4, 0);
    glEnable(GL_DEPTH_TEST);
}

/* The exact reference's list pass: empty lists, then every MASK and then every BLEND fragment in
 * front of the opaque depth appended (early depth test, no depth or colour writes). */
static void draw_lists(renderer *r, const gpu_program *pg, const plan_pass *ps)
{
    const GLuint end = ABUFFER_END, zero = 0;
    glClearTexImage(r->list_head, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &end);
    glClearNamedBufferData(r->list_counter, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glBindImageTexture(ABUFFER_IMAGE_HEAD, r->list_head, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(ABUFFER_IMAGE_NODES, r->list_nodes_tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32UI);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ABUFFER_COUNTER_BINDING, r->list_counter);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(pg->id, pg->u_list_capacity, (GLuint)r->list_capacity);
    glDepthMask(GL_FALSE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    r->list_draw_order = 0;
    for (r->list_phase = 0; r->list_phase < 2; r->list_phase++)
        draw_instanced(r, pg, ps);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
}

/* The exact reference's lists sorted and composited over the opaque pass (list_resolve.frag). */
static void list_resolve(renderer *r)
{
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(r->list_prog, r->list_u_capacity, (GLuint)r->list_capacity);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ABUFFER_COUNTER_BINDING, r->list_counter);
    glBindFramebuffer(GL_FRAMEBUFFER, r->list_fbo);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glUseProgram(r->list_prog);
    /* No sampler objects (the forward passes leave a material's on unit 0): texelFetch only, and
     * an integer texture under a linear-filtering sampler is incomplete. */
    for (GLuint u = 0; u < 4; u++)
        glBindSampler(u, 0);
    glBindTextureUnit(0, r->list_head);
    glBindTextureUnit(1, r->list_nodes_tex);
    glBindTextureUnit(2, r->rt.color);
    glBindTextureUnit(3, r->rt.coverage);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glEnable(GL_DEPTH_TEST);
}

/* The forward passes of one ring into its target. `stage` >= 0: time each pass as a stage from
 * there (rings off); < 0: the caller times the ring as a whole. */
static void draw_ring(renderer *r, const frame_record *fr, int ring, int stage, double *t_prev)
{
    const light_desc *L = &r->sc->light;
    GLuint fbo = r->pl.msaa ? r->rt.msaa_fbo : r->rt.fbo[ring];
    const fov_ring_rect *rr = &fr->ring_rect[ring];
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, rr->width, rr->height);
    glScissor(0, 0, rr->width, rr->height);
    glEnable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    const float sky[4] = {L->sky.x, L->sky.y, L->sky.z, 0.0f}; /* A = 0: no geometry */
    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, sky);
    glClearNamedFramebufferfv(fbo, GL_COLOR, 1, zero);
    if (r->pl.velocity)
        glClearNamedFramebufferfv(fbo, GL_COLOR, 2, zero);
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glFrontFace(GL_CCW);
    glCullFace(GL_BACK);
    r->ring_instances[ring] = cull_instances(r, fr, ring);
    r->draw_vp = fr->ring_view_proj[ring];
    if (r->pl.taa) {
        /* Sub-pixel jitter (Halton 2,3), in this ring's own pixels: an NDC offset of 2 j / size. */
        float j[2];
        taa_jitter((uint32_t)fr->index, r->pl.taa_controls.jitter_length, j);
        mat4 t = m4_translate(v3(2.0f * j[0] / (float)rr->width, 2.0f * j[1] / (float)rr->height, 0.0f));
        r->draw_vp = m4_mul(t, fr->ring_view_proj[ring]);
    }
    for (int i = 0; i < r->pl.pass_count; i++) {
        const plan_pass *ps = &r->pl.passes[i];
        const gpu_program *pg = &r->programs[i];
        if (stage >= 0)
            stage_begin(r, stage + i);
        glUseProgram(pg->id);
        set_frame_uniforms(r, pg, fr, ring);
        r->list_draw_order = 0;
        if (ps->kind == PLAN_PASS_FORWARD_BLEND) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_ONE, GL_ONE_MINUS_SRC_ALPHA); /* premultiplied "over" */
            glDepthMask(GL_FALSE);
            /* Blended surfaces are see-through: the motion stays that of what lies behind. */
            if (r->pl.velocity)
                glColorMaski(2, GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
            draw_blend_sorted(r, pg, ps, fr);
            if (r->pl.velocity)
                glColorMaski(2, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
            glDepthMask(GL_TRUE);
            glDisable(GL_BLEND);
        } else if (ps->kind == PLAN_PASS_FORWARD_MASK && ps->mode == ALPHA_MODE_A2C) {
            glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
            glEnable(GL_SAMPLE_ALPHA_TO_ONE);
            draw_instanced(r, pg, ps);
            glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
            glDisable(GL_SAMPLE_ALPHA_TO_ONE);
        } else if (ps->kind == PLAN_PASS_FORWARD_SOLID) {
            /* Pushed back, so that the list pass (GL_LESS) still stores these fragments and any
             * coplanar with them, in draw order: they order among themselves in the resolve. */
            glEnable(GL_POLYGON_OFFSET_FILL);
            glPolygonOffset(1.0f, 2.0f);
            glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
            draw_instanced(r, pg, ps);
            glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
            glDisable(GL_POLYGON_OFFSET_FILL);
        } else if (ps->kind == PLAN_PASS_FORWARD_LIST) {
            draw_lists(r, pg, ps);
        } else {
            draw_instanced(r, pg, ps);
        }
        if (stage >= 0)
            stage_end(r, stage + i, t_prev);
    }
    glDisable(GL_SCISSOR_TEST);
    if (r->pl.msaa) {
        /* Resolve the footprint corner, colour, coverage (and motion) separately, into this ring's
         * layer. Motion resolves to the mean of the samples' motions. */
        static const GLenum att[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
        int outputs = r->pl.velocity ? 3 : 2;
        for (int k = 0; k < outputs; k++) {
            glNamedFramebufferReadBuffer(r->rt.msaa_fbo, att[k]);
            glNamedFramebufferDrawBuffer(r->rt.fbo[ring], att[k]);
            glBlitNamedFramebuffer(r->rt.msaa_fbo, r->rt.fbo[ring], 0, 0, rr->width, rr->height, 0, 0, rr->width,
                                   rr->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        }
        glNamedFramebufferDrawBuffers(r->rt.fbo[ring], outputs, att);
        if (r->pl.taa) /* TAA reprojects through this ring's depth */
            glBlitNamedFramebuffer(r->rt.msaa_fbo, r->rt.fbo[ring], 0, 0, rr->width, rr->height, 0, 0, rr->width,
                                   rr->height, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    }
}

/* The composite's uniforms, the same in both of its programs. */
static void composite_uniforms(const renderer *r, const composite_program *c, const frame_record *fr)
{
    const fov_layout *l = &r->pl.layout;
    display_desc d = {r->width, r->height, fr->hfov_deg};
    float outer[MAX_FOV_RINGS], band[MAX_FOV_RINGS], rect[4 * MAX_FOV_RINGS], block[MAX_FOV_RINGS];
    for (int i = 0; i < l->count; i++) {
        float prev = i > 0 ? l->rings[i - 1].outer_deg : 0.0f;
        outer[i] = isinf(l->rings[i].outer_deg) ? 1e9f : l->rings[i].outer_deg;
        band[i] = isinf(l->rings[i].outer_deg) ? 0.0f : fminf(l->blend_deg, 0.5f * (l->rings[i].outer_deg - prev));
        const fov_ring_rect *rr = &fr->ring_rect[i];
        rect[4 * i] = (float)rr->x0;
        rect[4 * i + 1] = (float)rr->y0;
        rect[4 * i + 2] = (float)rr->x1;
        rect[4 * i + 3] = (float)rr->y1;
        block[i] = (float)rr->block;
    }
    glProgramUniform2f(c->id, c->u_display_px, (float)r->width, (float)r->height);
    glProgramUniform2f(c->id, c->u_array_px, (float)r->width, (float)r->height);
    glProgramUniform1f(c->id, c->u_focal_px, fov_focal_px(&d));
    glProgramUniform2f(c->id, c->u_gaze_px, fr->gaze_px[0], fr->gaze_px[1]);
    glProgramUniform1fv(c->id, c->u_ring_outer, l->count, outer);
    glProgramUniform1fv(c->id, c->u_ring_band, l->count, band);
    glProgramUniform4fv(c->id, c->u_ring_rect, l->count, rect);
    glProgramUniform1fv(c->id, c->u_ring_block, l->count, block);
}

/* The display as rectangles (fov_composite_tiles), those of one ring first: writes their vertices
 * into the tile buffer and returns how many of the rectangles are of one ring (*total: all). */
static int composite_rectangles(renderer *r, const frame_record *fr, int *total)
{
    display_desc d = {r->width, r->height, fr->hfov_deg};
    int n = 0;
    if (r->pl.composite_tiles)
        n = fov_composite_tiles(&d, &r->pl.layout, fr->gaze_px[0], fr->gaze_px[1], r->tiles, r->tile_max);
    else /* one rectangle: the display, searched per pixel */
        r->tiles[n++] = (fov_tile){0, 0, r->width, r->height, -1};
    int pure = 0;
    for (int i = 0; i < n; i++)
        pure += r->tiles[i].ring >= 0;
    for (int i = 0, a = 0, b = pure; i < n; i++) {
        const fov_tile *t = &r->tiles[i];
        float x0 = (float)t->x0, y0 = (float)t->y0, x1 = (float)t->x1, y1 = (float)t->y1, k = (float)t->ring;
        const float v[18] = {x0, y0, k, x1, y0, k, x1, y1, k, x0, y0, k, x1, y1, k, x0, y1, k};
        memcpy(r->tile_verts + 18 * (size_t)(t->ring >= 0 ? a++ : b++), v, sizeof v);
    }
    *total = n;
    return pure;
}

static void draw_composite(renderer *r, const frame_record *fr)
{
    int n, pure = composite_rectangles(r, fr, &n);
    glNamedBufferSubData(r->tile_vbo, 0, (GLsizeiptr)(sizeof(float) * 18 * (size_t)n), r->tile_verts);
    /* With TAA the composite reads the resolved rings this frame wrote. */
    glBindTextureUnit(0, r->pl.taa ? r->taa_color[r->parity] : r->rt.color);
    glBindTextureUnit(1, r->pl.taa ? r->taa_coverage[r->parity] : r->rt.coverage);
    glBindSampler(0, r->ring_sampler);
    glBindSampler(1, r->ring_sampler);
    glBindFramebuffer(GL_FRAMEBUFFER, r->out_fbo);
    glViewport(0, 0, r->width, r->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(r->tile_vao);
    if (pure > 0) {
        composite_uniforms(r, &r->comp_tile, fr);
        glUseProgram(r->comp_tile.id);
        glDrawArrays(GL_TRIANGLES, 0, 6 * pure);
    }
    if (n > pure) {
        composite_uniforms(r, &r->comp, fr);
        glUseProgram(r->comp.id);
        glDrawArrays(GL_TRIANGLES, 6 * pure, 6 * (n - pure));
    }
    glBindSampler(0, 0);
    glBindSampler(1, 0);
}

fs_status renderer_draw(renderer *r, const frame_record *fr)
{
    FS_ASSERT(fr->ring_count == r->pl.layout.count);
    if (r->pass_sync)
        glFinish();
    double t_prev = time_now();
    r->shaded_pixels = 0;
    if (!r->pl.composite) {
        draw_ring(r, fr, 0, 0, &t_prev);
        if (r->pl.list_resolve) {
            stage_begin(r, r->pl.pass_count);
            list_resolve(r);
            stage_end(r, r->pl.pass_count, &t_prev);
        }
        if (r->pl.taa) {
            int k = r->pl.pass_count + r->pl.list_resolve;
            stage_begin(r, k);
            taa_resolve_ring(r, fr, 0);
            stage_end(r, k, &t_prev);
        }
        r->shaded_pixels = (long long)fr->ring_rect[0].width * fr->ring_rect[0].height;
    } else {
        /* Stages: each ring's passes, then its TAA resolve (when on), then the composite. */
        if (r->pl.taa_coarse_history && taa_history_valid(r, fr))
            taa_set_prev_footprints(r, fr);
        int k = 0;
        for (int i = 0; i < r->pl.layout.count; i++) {
            stage_begin(r, k);
            draw_ring(r, fr, i, -1, &t_prev);
            stage_end(r, k++, &t_prev);
            if (r->pl.taa) {
                stage_begin(r, k);
                taa_resolve_ring(r, fr, i);
                stage_end(r, k++, &t_prev);
            }
            r->shaded_pixels += (long long)fr->ring_rect[i].width * fr->ring_rect[i].height;
        }
        stage_begin(r, k);
        draw_composite(r, fr);
        stage_end(r, k, &t_prev);
    }
    if (r->pl.taa) {
        for (int i = 0; i < fr->ring_count; i++) {
            r->prev_vp[i] = fr->ring_view_proj[i];
            r->prev_rect[i] = fr->ring_rect[i];
        }
        r->prev_index = fr->index;
        r->prev_time = fr->time;
        display_desc dd = {r->width, r->height, fr->hfov_deg};
        r->prev_gaze_px[0] = fr->gaze_px[0];
        r->prev_gaze_px[1] = fr->gaze_px[1];
        r->prev_focal_px = fov_focal_px(&dd);
        for (int i = 0; i < fr->ring_count; i++)
            r->prev_hole_deg[i] = r->pl.ring_cull && fov_ring_cull_deg(&dd, &r->pl.layout, i) > 0.0f
                                      ? fov_ring_hole_deg(&r->pl.layout, i)
                                      : 0.0f;
        r->have_prev = true;
        r->out_parity = r->parity; /* what renderer_read and the next frame's history use */
        r->parity = 1 - r->parity;
    }
    r->stats_pending = r->timers;
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return FS_OK;
}

void renderer_set_pass_sync(renderer *r, bool on)
{
    r->pass_sync = on;
}

void renderer_finish(renderer *r)
{
    (void)r;
    glFinish();
}

renderer_stats renderer_last_stats(renderer *r)
{
    renderer_stats s = {0};
    s.pass_count = r->stage_count;
    s.shaded_pixels = r->shaded_pixels;
    s.ring_count = r->pl.layout.count;
    memcpy(s.ring_instances, r->ring_instances, sizeof s.ring_instances);
    bool counts = r->stats_pending && r->stat_queries_on;
    s.vs_invocations = s.primitives = s.fragments = counts ? 0 : -1;
    for (int i = 0; i < r->stage_count; i++) {
        snprintf(s.pass_names[i], sizeof s.pass_names[i], "%s", r->stage_names[i]);
        s.pass_ms[i] = -1.0;
        s.pass_wall_ms[i] = r->stage_wall_ms[i];
        if (r->stats_pending) {
            GLuint64 ns = 0;
            glGetQueryObjectui64v(r->time_queries[i], GL_QUERY_RESULT, &ns);
            s.pass_ms[i] = (double)ns * 1e-6;
        }
        long long *dst[3] = {&s.pass_vs_invocations[i], &s.pass_primitives[i], &s.pass_fs_invocations[i]};
        long long *sum[3] = {&s.vs_invocations, &s.primitives, &s.fragments};
        for (int q = 0; q < 3; q++) {
            *dst[q] = -1;
            if (counts) {
                GLuint64 v = 0;
                glGetQueryObjectui64v(r->stat_queries[i][q], GL_QUERY_RESULT, &v);
                *dst[q] = (long long)v;
                *sum[q] += (long long)v;
            }
        }
    }
    return s;
}

/* >>readback */
/* Reverses the row order of p (h rows of w * comps 4-byte values) through `row` (one row). */
static void flip_rows(void *p, void *row, int w, int h, int comps)
{
    size_t n = (size_t)w * (size_t)comps * 4;
    for (int y = 0; y < h / 2; y++) {
        char *a = (char *)p + (size_t)y * n, *b = (char *)p + (size_t)(h - 1 - y) * n;
        memcpy(row, a, n);
        memcpy(a, b, n);
        memcpy(b, row, n);
    }
}

/* Reads `color` (RGBA) and `coverage` (its first channel) at level 0, layer 0, into *img as R, G, B,
 * A and coverage, then any of the debug channels and the list resolve's flags the plan writes. */
static fs_status read_images(renderer *r, exr_image *img, GLuint color, GLuint coverage, bool extras)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    /* The interleaved read-back lives as long as the renderer: nothing in the frame loop is
     * allocated per frame but the image handed to the caller (docs/benchmarks.md, "Allocator"). */
    if (!r->read_buf) {
        r->read_buf = malloc(sizeof(float) * 4 * n);
        r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width);
        if (!r->read_buf || !r->read_row)
            return FS_ERR_NOMEM;
    }
    float *rgba = r->read_buf;
    if (!exr_image_init(img, r->width, r->height))
        return FS_ERR_NOMEM;
    static const char *const names[] = {"R", "G", "B", "A", "coverage", "ring.id", "eccentricity"};
    int channels = extras && r->pl.debug_channels ? 7 : 5;
    float *planes[7], *flags = NULL;
    for (int c = 0; c < channels; c++)
        if (!(planes[c] = exr_image_add_channel(img, names[c]))) {
            exr_image_free(img);
            return FS_ERR_NOMEM;
        }
    if (extras && r->pl.list_resolve && !(flags = exr_image_add_channel(img, RENDERER_LIST_FLAG_CHANNEL))) {
        exr_image_free(img);
        return FS_ERR_NOMEM;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureSubImage(color, 0, 0, 0, 0, r->width, r->height, 1, GL_RGBA, GL_FLOAT,
                         (GLsizei)(sizeof(float) * 4 * n), rgba);
    glGetTextureSubImage(coverage, 0, 0, 0, 0, r->width, r->height, 1, GL_RED, GL_FLOAT,
                         (GLsizei)(sizeof(float) * n), planes[4]);
    flip_rows(rgba, r->read_row, r->width, r->height, 4); /* GL rows are bottom first, EXR top first */
    flip_rows(planes[4], r->read_row, r->width, r->height, 1);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 4; c++)
            planes[c][i] = rgba[4 * i + (size_t)c];
    if (channels == 7) {
        glGetTextureImage(r->out_tex[OUT_DEBUG], 0, GL_RG, GL_FLOAT, (GLsizei)(sizeof(float) * 2 * n), rgba);
        flip_rows(rgba, r->read_row, r->width, r->height, 2);
        for (size_t i = 0; i < n; i++) {
            planes[5][i] = rgba[2 * i];
            planes[6][i] = rgba[2 * i + 1];
        }
    }
    if (flags) {
        glGetTextureImage(coverage, 0, GL_GREEN, GL_FLOAT, (GLsizei)(sizeof(float) * n), flags);
        flip_rows(flags, r->read_row, r->width, r->height, 1);
    }
    return FS_OK;
}

fs_status renderer_read(renderer *r, exr_image *img)
{
    /* Composite: the display targets; rings off: layer 0 of the ring arrays (display-sized); the
     * exact reference: its resolve. */
    GLuint color = r->pl.composite      ? r->out_tex[OUT_COLOR]
                   : r->pl.list_resolve ? r->list_color
                   : r->pl.taa          ? r->taa_color[r->out_parity]
                                        : r->rt.color;
    GLuint coverage = r->pl.composite      ? r->out_tex[OUT_COVERAGE]
                      : r->pl.list_resolve ? r->list_coverage
                      : r->pl.taa          ? r->taa_coverage[r->out_parity]
                                           : r->rt.coverage;
    return read_images(r, img, color, coverage, true);
}

fs_status renderer_read_opaque(renderer *r, exr_image *img)
{
    FS_ASSERT(r->pl.list_resolve);
    return read_images(r, img, r->rt.color, r->rt.coverage, false);
}

fs_status renderer_read_depth(renderer *r, float *depth)
{
    FS_ASSERT(!r->pl.composite && !r->pl.msaa);
    size_t n = (size_t)r->width * (size_t)r->height;
    if (!r->read_row && !(r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width)))
        return FS_ERR_NOMEM;
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(r->rt.depth, 0, GL_DEPTH_COMPONENT, GL_FLOAT, (GLsizei)(sizeof(float) * n), depth);
    flip_rows(depth, r->read_row, r->width, r->height, 1);
    return FS_OK;
}

void renderer_set_mip_bias(renderer *r, int ring, float bias)
{
    FS_ASSERT(ring >= 0 && ring < r->pl.layout.count);
    r->pl.layout.rings[ring].mip_bias = bias;
}

/* >>lists */
uint64_t renderer_list_nodes_max(void)
{
    GLint64 texels = 0;
    glGetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &texels);
    uint64_t n = (uint64_t)(texels > 0 ? texels : 0) / ABUFFER_NODE_TEXELS;
    return n < ABUFFER_END ? n : ABUFFER_END; /* indices must stay below the end marker */
}

fs_status renderer_reserve_list_nodes(renderer *r, uint64_t nodes)
{
    FS_ASSERT(r->list_head);
    uint64_t max = renderer_list_nodes_max();
    nodes = nodes < max ? nodes : max;
    if (nodes <= r->list_capacity)
        return FS_OK;
    while (glGetError() != GL_NO_ERROR) {
    }
    /* The new store first: when the GL has no room for it, the old one stays. */
    GLuint buf, tex;
    glCreateBuffers(1, &buf);
    glNamedBufferStorage(buf, (GLsizeiptr)(nodes * sizeof(abuffer_node)), NULL, 0);
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &tex);
    glTextureBuffer(tex, GL_RGBA32UI, buf);
    if (glGetError() != GL_NO_ERROR) {
        glDeleteTextures(1, &tex);
        glDeleteBuffers(1, &buf);
        return FS_ERR_NOMEM;
    }
    glDeleteTextures(1, &r->list_nodes_tex);
    glDeleteBuffers(1, &r->list_nodes);
    r->list_nodes = buf;
    r->list_nodes_tex = tex;
    r->list_capacity = nodes;
    free(r->list_node_buf); /* the read-back scratch follows the store's size on next use */
    r->list_node_buf = NULL;
    r->list_node_buf_cap = 0;
    return FS_OK;
}

fs_status renderer_read_lists(renderer *r, abuffer_lists *out, bool with_nodes)
{
    FS_ASSERT(r->list_head);
    size_t npix = (size_t)r->width * (size_t)r->height;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint count = 0;
    glGetNamedBufferSubData(r->list_counter, 0, sizeof count, &count);
    uint64_t stored = count < r->list_capacity ? count : r->list_capacity;
    *out = (abuffer_lists){r->width, r->height, NULL, NULL, count, r->list_capacity};
    if (!with_nodes)
        return FS_OK;
    if (!r->list_head_buf && !(r->list_head_buf = malloc(sizeof(uint32_t) * npix)))
        return FS_ERR_NOMEM;
    if (!r->read_row && !(r->read_row = malloc(sizeof(float) * 4 * (size_t)r->width)))
        return FS_ERR_NOMEM;
    if (stored > r->list_node_buf_cap) {
        free(r->list_node_buf);
        r->list_node_buf_cap = 0;
        if (!(r->list_node_buf = malloc((size_t)stored * sizeof(abuffer_node))))
            return FS_ERR_NOMEM;
        r->list_node_buf_cap = stored;
    }
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTextureImage(r->list_head, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, (GLsizei)(sizeof(uint32_t) * npix),
                      r->list_head_buf);
    flip_rows(r->list_head_buf, r->read_row, r->width, r->height, 1); /* rows top first, as the images */
    if (stored > 0)
        glGetNamedBufferSubData(r->list_nodes, 0, (GLsizeiptr)(stored * sizeof(abuffer_node)), r->list_node_buf);
    *out = (abuffer_lists){r->width, r->height, r->list_head_buf, r->list_node_buf, count, r->list_capacity};
    return FS_OK;
}

/* >>present: what the viewer blits (the colour renderer_read reads) */
unsigned renderer_output_framebuffer(const renderer *r)
{
    return r->pl.composite ? r->out_fbo : r->pl.taa ? r->taa_fbo[r->out_parity][0] : r->rt.fbo[0];
}
