/* test_scene.c: scene loading (JSON, built-ins, glTF-as-scene), validation, bounds
 * (src/scene/scene.c, src/scene/scene_json.c). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "scene/scene.h"
#include "test.h"

#define FERN_GLTF "assets/quaternius_megakit_set_a/Fern_1.gltf"

/* Writes `text` to <test_out_dir>/<name>; returns the path (static buffer, rotating). */
static const char *write_scene(const char *name, const char *text)
{
    static char buf[4][1200];
    static int k;
    k = (k + 1) & 3;
    snprintf(buf[k], sizeof buf[k], "%s/%s", test_out_dir(), name);
    FILE *f = fopen(buf[k], "wb");
    if (!f) {
        fprintf(stderr, "cannot write %s\n", buf[k]);
        return buf[k];
    }
    fputs(text, f);
    fclose(f);
    return buf[k];
}

static bool scene_is_zeroed(const scene *sc)
{
    static const scene zero;
    return memcmp(sc, &zero, sizeof zero) == 0;
}

static long scene_triangles(const scene *sc)
{
    long n = 0;
    for (int i = 0; i < sc->instance_count; i++) {
        const asset *a = &sc->assets[sc->instances[i].asset];
        for (int p = 0; p < a->prim_count; p++)
            n += a->prims[p].index_count / 3;
    }
    return n;
}

static int mask_materials(const scene *sc)
{
    int n = 0;
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++)
            n += sc->assets[a].materials[m].alpha_kind == ALPHA_KIND_MASK;
    return n;
}

/* Projects world point p with the camera at time t; true when it lands inside the view. */
static bool camera_sees(const scene *sc, float t, vec3 p, float *ndc_x, float *ndc_y)
{
    camera_state cs = camera_path_eval(&sc->camera, t);
    float hfov = cs.hfov_deg > 0 ? cs.hfov_deg : sc->display.hfov_deg;
    mat4 view = m4_look_at(cs.position, cs.target, v3(0, 1, 0));
    mat4 proj = m4_perspective_hfov(hfov * (float)(FS_PI / 180.0),
                                    (float)sc->display.width / (float)sc->display.height, 0.05f, 1000.0f);
    mat4 vp = m4_mul(proj, view);
    const float *m = vp.m;
    float x = m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12];
    float y = m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13];
    float w = m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15];
    if (!(w > 0))
        return false;
    *ndc_x = x / w;
    *ndc_y = y / w;
    return fabsf(*ndc_x) <= 1 && fabsf(*ndc_y) <= 1;
}

/* >>defaults and building blocks */

TEST(defaults)
{
    scene sc;
    memset(&sc, 0x5a, sizeof sc);
    scene_init_defaults(&sc);
    CHECK(sc.display.width == 1280 && sc.display.height == 720);
    CHECK_NEAR(sc.display.hfov_deg, 90, 0);
    CHECK_NEAR(v3_len(sc.light.direction), 1, 1e-6);
    CHECK(sc.light.direction.y < 0);
    CHECK_NEAR(sc.light.direction.x / sc.light.direction.y, 0.4, 1e-5);
    CHECK_NEAR(sc.light.color.y, 0.97, 1e-6);
    CHECK_NEAR(sc.light.ambient.z, 0.32, 1e-6);
    CHECK_NEAR(sc.light.sky.x, 0.45, 1e-6);
    CHECK(sc.alpha_mode == ALPHA_MODE_DEFAULT);
    CHECK(sc.camera.count == 1);
    CHECK_NEAR(sc.camera.keys[0].position.y, 1.6, 1e-6);
    CHECK_NEAR(sc.camera.keys[0].position.z, 5, 1e-6);
    CHECK_NEAR(sc.camera.keys[0].target.y, 1, 1e-6);
    CHECK(sc.asset_count == 0 && sc.assets == NULL && sc.instance_count == 0 && sc.instances == NULL);
    scene_free(&sc);
    CHECK(scene_is_zeroed(&sc));
    scene_free(&sc); /* no-op on a zeroed scene */
    scene_free(NULL);
}

/* One prim, one material: a unit quad in the XY plane, x, y in [0, 1]. */
static void make_quad_asset(asset *a)
{
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "quad");
    a->prim_count = 1;
    a->prims = calloc(1, sizeof(prim));
    a->material_count = 1;
    a->materials = calloc(1, sizeof(material));
    a->materials[0] = (material){.name = "m", .base_color = {1, 1, 1, 1}, .base_color_image = -1, .alpha_cutoff = 0.5f};
    prim *p = &a->prims[0];
    p->vertex_count = 4;
    p->index_count = 6;
    p->positions = calloc(12, sizeof(float));
    p->normals = calloc(12, sizeof(float));
    p->uvs = calloc(8, sizeof(float));
    p->colors = calloc(16, sizeof(float));
    p->indices = calloc(6, sizeof(uint32_t));
    const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    memcpy(p->positions, pos, sizeof pos);
    memcpy(p->indices, idx, sizeof idx);
    for (int i = 0; i < 4; i++) {
        p->normals[3 * i + 2] = 1;
        for (int c = 0; c < 4; c++)
            p->colors[4 * i + c] = 1;
    }
    asset_compute_bounds(a);
}

TEST(add_bounds_fit_validate)
{
    scene sc;
    scene_init_defaults(&sc);
    snprintf(sc.path, sizeof sc.path, "hand-made");
    asset a;
    make_quad_asset(&a);
    CHECK(scene_add_asset(&sc, &a) == 0);
    CHECK(a.prims == NULL); /* moved into the scene */
    for (int i = 0; i < 100; i++) /* crosses the array's growth steps */
        CHECK(scene_add_instance(&sc, 0, m4_translate(v3((float)i, 0, 0))));
    CHECK(scene_add_instance(&sc, 0, m4_mul(m4_translate(v3(0, 0, -7)), m4_scale(v3(2, 3, 1)))));
    CHECK(sc.instance_count == 101);
    CHECK_NEAR(sc.instances[57].transform.m[12], 57, 0);
    vec3 lo, hi;
    scene_bounds(&sc, &lo, &hi);
    CHECK_NEAR(lo.x, 0, 1e-6);
    CHECK_NEAR(hi.x, 100, 1e-6);
    CHECK_NEAR(lo.y, 0, 1e-6);
    CHECK_NEAR(hi.y, 3, 1e-6);
    CHECK_NEAR(lo.z, -7, 1e-6);
    CHECK_NEAR(hi.z, 0, 1e-6);
    CHECK(scene_validate(&sc) == FS_OK);

    scene_fit_camera(&sc);
    CHECK(sc.camera.count == 1 && sc.duration == 0);
    float x, y;
    CHECK(camera_sees(&sc, 0, v3_scale(v3_add(lo, hi), 0.5f), &x, &y));
    for (int k = 0; k < 8; k++) /* the whole box fits, with the margin */
        CHECK(camera_sees(&sc, 0, v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), &x, &y));
    CHECK(sc.camera.keys[0].position.z > hi.z);             /* from the front */
    CHECK(sc.camera.keys[0].position.y > sc.camera.keys[0].target.y); /* slightly above */

    log_set_quiet_errors(true);
    sc.instances[3].asset = 1;
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.instances[3].asset = 0;
    sc.instances[5].transform.m[13] = NAN;
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.instances[5].transform.m[13] = 0;
    sc.assets[0].prims[0].positions[4] = INFINITY;
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.assets[0].prims[0].positions[4] = 0;
    sc.assets[0].prims[0].material = 1;
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.assets[0].prims[0].material = 0;
    sc.assets[0].materials[0].base_color_image = 0; /* the asset has no images */
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.assets[0].materials[0].base_color_image = -1;
    sc.assets[0].prims[0].index_count = 5;
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    sc.assets[0].prims[0].index_count = 6;
    log_set_quiet_errors(false);
    CHECK(scene_validate(&sc) == FS_OK);
    scene_free(&sc);
    CHECK(scene_is_zeroed(&sc));
}

/* >>built-in scenes */

TEST(builtins_load_and_validate)
{
    const char *list = scene_builtin_list();
    const char *names[] = {"forest", "fence", "tree", "grass"};
    for (int i = 0; i < 4; i++) {
        CHECK(strstr(list, names[i]) != NULL);
        scene sc;
        fs_status s = scene_load_builtin(names[i], &sc);
        CHECK(s == FS_OK);
        if (s != FS_OK)
            continue;
        char want[64];
        snprintf(want, sizeof want, "builtin:%s", names[i]);
        CHECK(strcmp(sc.path, want) == 0);
        CHECK(scene_validate(&sc) == FS_OK);
        CHECK(sc.asset_count >= 1 && sc.instance_count >= 1);
        CHECK(mask_materials(&sc) >= 1);
        CHECK(sc.camera.count >= 2);
        CHECK(sc.duration >= 3 && sc.duration <= 8);
        CHECK_NEAR(sc.duration, sc.camera.keys[sc.camera.count - 1].time, 0);
        long tris = scene_triangles(&sc);
        CHECK(tris > 100 && tris < 150000);
        /* The camera sees the scene's centre at the start and the end of the path. */
        vec3 lo, hi;
        float x, y;
        scene_bounds(&sc, &lo, &hi);
        CHECK(hi.x > lo.x && hi.y > lo.y);
        for (int a = 0; a < sc.asset_count; a++)
            for (int m = 0; m < sc.assets[a].material_count; m++)
                CHECK(sc.assets[a].materials[m].alpha_mode == ALPHA_MODE_DEFAULT);
        if (strcmp(names[i], "grass") != 0) /* the grass camera looks across, not at the centre */
            CHECK(camera_sees(&sc, 0, v3_scale(v3_add(lo, hi), 0.5f), &x, &y) ||
                  camera_sees(&sc, sc.duration, v3_scale(v3_add(lo, hi), 0.5f), &x, &y));
        scene_free(&sc);
    }
}

TEST(builtin_forest_dollies_backwards)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    CHECK(sc.instance_count >= 12 + 2);
    CHECK(sc.camera.count >= 3 && sc.camera.count <= 5);
    float prev = -INFINITY;
    for (int k = 0; k <= 400; k++) {
        camera_state cs = camera_path_eval(&sc.camera, sc.duration * (float)k / 400.0f);
        CHECK(cs.position.z >= prev); /* moving away along +Z */
        CHECK(cs.target.z < cs.position.z - 5); /* while looking back at the trees */
        prev = cs.position.z;
    }
    CHECK(camera_path_eval(&sc.camera, sc.duration).position.z - camera_path_eval(&sc.camera, 0).position.z > 5);
    scene_free(&sc);
}

TEST(builtin_fence_recedes_from_the_fence)
{
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    vec3 lo, hi;
    scene_bounds(&sc, &lo, &hi);
    CHECK(hi.x - lo.x >= 50); /* a wide panel */
    camera_state a = camera_path_eval(&sc.camera, 0), b = camera_path_eval(&sc.camera, sc.duration);
    CHECK(a.position.z > 1 && a.position.z < 2.5f);
    CHECK(b.position.z > 30 && b.position.z < 50);
    CHECK_NEAR(a.target.x, 0.5f * (lo.x + hi.x), 1e-3);
    float x, y;
    CHECK(camera_sees(&sc, sc.duration, v3(lo.x + 0.2f * (hi.x - lo.x), 1, 0), &x, &y)); /* still wide far away */
    scene_free(&sc);
}

TEST(unknown_builtin)
{
    scene sc;
    log_set_quiet_errors(true);
    CHECK(scene_load_builtin("jungle", &sc) == FS_ERR_SCENE);
    CHECK(scene_is_zeroed(&sc));
    CHECK(scene_load_builtin("../../etc/passwd", &sc) == FS_ERR_SCENE);
    CHECK(scene_load_builtin("", &sc) == FS_ERR_SCENE);
    log_set_quiet_errors(false);
}

/* >>JSON scene files */

/* The path of `target` relative to directory `dir`: up to the root, then down ("../../a/b"). */
static void relative_path(const char *dir, const char *target, char *out, size_t n)
{
    char d[PATH_MAX], t[PATH_MAX];
    if (!realpath(dir, d) || !realpath(target, t)) {
        snprintf(out, n, "%s", target);
        return;
    }
    out[0] = '\0';
    for (const char *c = d; *c; c++)
        if (*c == '/' && c[1])
            strncat(out, "../", n - strlen(out) - 1);
    strncat(out, t + 1, n - strlen(out) - 1);
}

TEST(json_scene_with_generator_and_gltf)
{
    char rel[PATH_MAX], abs_fern[PATH_MAX];
    relative_path(test_out_dir(), test_shared_path(FERN_GLTF), rel, sizeof rel);
    CHECK(rel[0] != '/');
    CHECK(realpath(test_shared_path(FERN_GLTF), abs_fern) != NULL);
    char text[3 * PATH_MAX];
    snprintf(text, sizeof text,
             "{\n"
             "  \"display\": {\"width\": 640, \"height\": 480, \"hfov\": 70},\n"
             "  \"alpha_mode\": \"stochastic\",\n"
             "  \"light\": {\"direction\": [0, -2, 0], \"color\": [2, 2, 2], \"ambient\": [0.1, 0.1, 0.1], \"sky\": [0, 0, 0]},\n"
             "  \"assets\": [\n"
             "    {\"name\": \"tree\", \"generator\": \"tree\", \"params\": {\"seed\": 3, \"height\": 5, \"card_count\": 20, \"texture_size\": 64}},\n"
             "    {\"name\": \"fern_abs\", \"gltf\": \"%s\"},\n"
             "    {\"gltf\": \"%s\", \"comment\": \"named Fern_1 by default\"}\n"
             "  ],\n"
             "  \"instances\": [\n"
             "    {\"asset\": \"tree\", \"translation\": [1, 2, 3], \"rotation_deg\": [0, 90, 0], \"scale\": 2},\n"
             "    {\"asset\": \"fern_abs\", \"scale\": [1, 2, 3]},\n"
             "    {\"asset\": \"Fern_1\", \"rotation_deg\": [90, 0, 0]}\n"
             "  ],\n"
             "  \"camera\": [\n"
             "    {\"time\": 0, \"position\": [0, 1.6, 8], \"target\": [0, 1, 0], \"hfov\": 60},\n"
             "    {\"time\": 1.5, \"position\": [0, 1.6, 9], \"target\": [0, 1, 0]},\n"
             "    {\"time\": 2.5, \"position\": [5, 1.6, 9], \"target\": [5, 1, 0], \"cut\": true}\n"
             "  ],\n"
             "  \"materials\": {\"Leaves\": {\"alpha_mode\": \"hashed\", \"alpha_cutoff\": 0.3, \"alpha_lod_max\": 4.5}},\n"
             "  \"gaze\": {\"latency\": 50, \"rate\": 120, \"loss\": \"centre\", \"comment\": \"a headset\"}\n"
             "}\n",
             abs_fern, rel);
    const char *path = write_scene("good.json", text);
    scene sc;
    fs_status s = scene_load_file(path, &sc);
    CHECK(s == FS_OK);
    if (s != FS_OK)
        return;
    CHECK(scene_validate(&sc) == FS_OK);
    /* the eye tracker: given keys marked, the others not (the CLI's or 0) */
    CHECK(sc.tracker.latency_set && sc.tracker.desc.latency_ms == 50.0f && sc.tracker.rate_set &&
          sc.tracker.desc.rate_hz == 120.0f && sc.tracker.loss_set && sc.tracker.desc.loss == GAZE_LOSS_CENTRE);
    CHECK(!sc.tracker.noise_set && !sc.tracker.seed_set && sc.tracker.desc.noise_deg == 0.0f);
    CHECK(strcmp(sc.path, path) == 0);
    CHECK(sc.display.width == 640 && sc.display.height == 480);
    CHECK_NEAR(sc.display.hfov_deg, 70, 1e-6);
    CHECK(sc.alpha_mode == ALPHA_MODE_STOCHASTIC);
    CHECK_NEAR(sc.light.direction.y, -1, 1e-6);
    CHECK_NEAR(sc.light.color.x, 2, 1e-6);
    CHECK(sc.asset_count == 3 && sc.instance_count == 3);
    CHECK(sc.assets[0].source == ASSET_SOURCE_GENERATOR);
    CHECK(sc.assets[1].source == ASSET_SOURCE_GLTF && sc.assets[2].source == ASSET_SOURCE_GLTF);

    /* Transform: T * Ry(90) * S(2): asset-space +X lands at (1, 2, 3) + 2 * (0, 0, -1). */
    vec3 p = m4_point(sc.instances[0].transform, v3(1, 0, 0));
    CHECK_NEAR(p.x, 1, 1e-5);
    CHECK_NEAR(p.y, 2, 1e-5);
    CHECK_NEAR(p.z, 1, 1e-5);
    p = m4_point(sc.instances[1].transform, v3(1, 1, 1));
    CHECK_NEAR(p.x, 1, 1e-6);
    CHECK_NEAR(p.y, 2, 1e-6);
    CHECK_NEAR(p.z, 3, 1e-6);
    p = m4_point(sc.instances[2].transform, v3(0, 1, 0)); /* Rx(90): +Y -> +Z */
    CHECK_NEAR(p.z, 1, 1e-6);
    CHECK_NEAR(p.y, 0, 1e-6);

    /* Override applied to every material named "Leaves", in both glTF assets, nowhere else. */
    int leaves = 0;
    for (int a = 0; a < sc.asset_count; a++)
        for (int m = 0; m < sc.assets[a].material_count; m++) {
            const material *mat = &sc.assets[a].materials[m];
            if (strcmp(mat->name, "Leaves") == 0) {
                leaves++;
                CHECK(mat->alpha_mode == ALPHA_MODE_HASHED);
                CHECK_NEAR(mat->alpha_cutoff, 0.3, 1e-6);
                CHECK(mat->has_alpha_lod_max && mat->alpha_lod_max == 4.5f);
            } else {
                CHECK(mat->alpha_mode == ALPHA_MODE_DEFAULT);
                CHECK(!mat->has_alpha_lod_max);
            }
        }
    CHECK(leaves == 2);

    /* Camera: times, hfov filled from the display where a key has none, the cut. */
    CHECK(sc.camera.count == 3);
    CHECK_NEAR(sc.duration, 2.5, 1e-6);
    CHECK_NEAR(sc.camera.keys[0].hfov_deg, 60, 1e-6);
    CHECK_NEAR(sc.camera.keys[1].hfov_deg, 70, 1e-6);
    CHECK(sc.camera.keys[2].cut && !sc.camera.keys[1].cut);
    CHECK(camera_path_cut_between(&sc.camera, 2.0f, 2.5f));
    scene_free(&sc);
    CHECK(scene_is_zeroed(&sc));
}

TEST(camera_defaults_to_fit_and_single_key)
{
    const char *path = write_scene("nocam.json",
                                   "{\"assets\": [{\"generator\": \"fern\"}],"
                                   " \"instances\": [{\"asset\": \"fern\", \"translation\": [10, 0, -20]}]}");
    scene sc;
    CHECK(scene_load_file(path, &sc) == FS_OK);
    CHECK(sc.camera.count == 1 && sc.duration == 0);
    vec3 lo, hi;
    float x, y;
    scene_bounds(&sc, &lo, &hi);
    CHECK(camera_sees(&sc, 0, v3_scale(v3_add(lo, hi), 0.5f), &x, &y));
    CHECK_NEAR(x, 0, 1e-3);
    scene_free(&sc);

    path = write_scene("onekey.json",
                       "{\"assets\": [{\"generator\": \"fern\"}], \"instances\": [{\"asset\": \"fern\"}],"
                       " \"camera\": [{\"position\": [0, 1, 3], \"target\": [0, 0.5, 0]}]}");
    CHECK(scene_load_file(path, &sc) == FS_OK);
    CHECK(sc.camera.count == 1 && sc.camera.keys[0].time == 0 && sc.camera.keys[0].hfov_deg == 0);
    scene_free(&sc);
}

static const char *scatter_doc(int seed)
{
    static char text[1024];
    snprintf(text, sizeof text,
             "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"texture_size\": 16}}],"
             " \"instances\": [{\"asset\": \"f\", \"rotation_deg\": [0, 0, 0], \"scale\": 1,"
             "   \"scatter\": {\"count\": 200, \"seed\": %d, \"min\": [-10, 0, -30], \"max\": [10, 2, -5],"
             "                 \"scale\": [0.8, 1.2], \"random_yaw\": true}},"
             "  {\"asset\": \"f\", \"scatter\": {\"count\": 5, \"min\": [1, 1, 1], \"max\": [1, 1, 1]}}]}",
             seed);
    return text;
}

TEST(scatter_is_deterministic_and_inside_the_box)
{
    scene a, b, c;
    CHECK(scene_load_file(write_scene("scatter7a.json", scatter_doc(7)), &a) == FS_OK);
    CHECK(scene_load_file(write_scene("scatter7b.json", scatter_doc(7)), &b) == FS_OK);
    CHECK(scene_load_file(write_scene("scatter8.json", scatter_doc(8)), &c) == FS_OK);
    CHECK(a.instance_count == 205 && b.instance_count == 205 && c.instance_count == 205);
    if (a.instance_count != 205 || b.instance_count != 205 || c.instance_count != 205)
        return;
    CHECK(memcmp(a.instances, b.instances, sizeof(instance) * 205) == 0);
    int differ = 0;
    float min_y = INFINITY, max_y = -INFINITY, min_x = INFINITY, max_x = -INFINITY;
    for (int i = 0; i < 200; i++) {
        const float *m = a.instances[i].transform.m;
        CHECK(m[12] >= -10 && m[12] <= 10);
        CHECK(m[13] >= 0 && m[13] <= 2);
        CHECK(m[14] >= -30 && m[14] <= -5);
        min_x = fminf(min_x, m[12]);
        max_x = fmaxf(max_x, m[12]);
        min_y = fminf(min_y, m[13]);
        max_y = fmaxf(max_y, m[13]);
        float s = v3_len(v3(m[0], m[1], m[2])); /* uniform scale, yaw only: column length = scale */
        CHECK(s >= 0.8f - 1e-5f && s <= 1.2f + 1e-5f);
        CHECK_NEAR(m[5], s, 1e-5);
        CHECK_NEAR(m[1], 0, 1e-6);
        differ += c.instances[i].transform.m[12] != m[12];
    }
    CHECK(max_x - min_x > 15); /* spread over the box, not bunched */
    CHECK(max_y - min_y > 1.5f);
    CHECK(differ > 190); /* another seed, other positions */
    for (int i = 200; i < 205; i++) { /* a degenerate box is a point */
        CHECK(a.instances[i].transform.m[12] == 1 && a.instances[i].transform.m[13] == 1);
        CHECK(a.instances[i].transform.m[0] == 1); /* no yaw, scale 1 */
    }
    scene_free(&a);
    scene_free(&b);
    scene_free(&c);
}

/* A minimal valid document is A "," I; each bad case breaks one thing. */
#define A "\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"texture_size\": 16}}]"
#define I "\"instances\": [{\"asset\": \"f\"}]"
#define CAM2 "{\"time\": 0, \"position\": [0,1,5], \"target\": [0,0,0]}, {\"time\": 1, \"position\": [0,1,6], \"target\": [0,0,0]}"

static const struct bad_case {
    const char *what, *text;
    fs_status want;
} k_cases[] = {
    {"control: the base document is valid", "{" A "," I "}", FS_OK},
    {"unknown top-level key", "{" A "," I ", \"foo\": 1}", FS_ERR_SCENE},
    {"unknown instance key", "{" A ", \"instances\": [{\"asset\": \"f\", \"rotate\": [0,0,0]}]}", FS_ERR_SCENE},
    {"unknown asset key", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"seed\": 2}]," I "}", FS_ERR_SCENE},
    {"scale is a string", "{" A ", \"instances\": [{\"asset\": \"f\", \"scale\": \"big\"}]}", FS_ERR_SCENE},
    {"scale has 2 numbers", "{" A ", \"instances\": [{\"asset\": \"f\", \"scale\": [1, 2]}]}", FS_ERR_SCENE},
    {"scale 0", "{" A ", \"instances\": [{\"asset\": \"f\", \"scale\": 0}]}", FS_ERR_SCENE},
    {"NaN (not JSON)", "{" A ", \"instances\": [{\"asset\": \"f\", \"scale\": NaN}]}", FS_ERR_SCENE},
    {"1e999 overflows to inf", "{" A ", \"instances\": [{\"asset\": \"f\", \"translation\": [0, 1e999, 0]}]}", FS_ERR_SCENE},
    {"1e39 overflows a float", "{" A ", \"instances\": [{\"asset\": \"f\", \"translation\": [0, 1e39, 0]}]}", FS_ERR_SCENE},
    {"negative generator size", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"size\": -2}}]," I "}", FS_ERR_SCENE},
    {"unknown generator param", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"leaf_count\": 2}}]," I "}", FS_ERR_SCENE},
    {"texture size not a power of two", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"texture_size\": 100}}]," I "}", FS_ERR_SCENE},
    {"fractional count", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"params\": {\"frond_count\": 2.5}}]," I "}", FS_ERR_SCENE},
    {"unknown generator", "{\"assets\": [{\"name\": \"f\", \"generator\": \"oak\"}]," I "}", FS_ERR_SCENE},
    {"generator and gltf", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\", \"gltf\": \"x.gltf\"}]," I "}", FS_ERR_SCENE},
    {"asset with neither", "{\"assets\": [{\"name\": \"f\"}]," I "}", FS_ERR_SCENE},
    {"duplicate asset names", "{\"assets\": [{\"name\": \"f\", \"generator\": \"fern\"}, {\"name\": \"f\", \"generator\": \"tree\"}]," I "}", FS_ERR_SCENE},
    {"bad scene alpha mode", "{" A "," I ", \"alpha_mode\": \"fuzzy\"}", FS_ERR_SCENE},
    {"alpha mode \"default\" is not a mode", "{" A "," I ", \"alpha_mode\": \"default\"}", FS_ERR_SCENE},
    {"unknown asset name", "{" A ", \"instances\": [{\"asset\": \"tre\"}]}", FS_ERR_SCENE},
    {"instance without asset", "{" A ", \"instances\": [{\"translation\": [0,0,0]}]}", FS_ERR_SCENE},
    {"translation with scatter", "{" A ", \"instances\": [{\"asset\": \"f\", \"translation\": [0,0,0], \"scatter\": {\"count\": 2, \"min\": [0,0,0], \"max\": [1,0,1]}}]}", FS_ERR_SCENE},
    {"scatter min > max", "{" A ", \"instances\": [{\"asset\": \"f\", \"scatter\": {\"count\": 2, \"min\": [0,0,0], \"max\": [-1,0,1]}}]}", FS_ERR_SCENE},
    {"scatter count 0", "{" A ", \"instances\": [{\"asset\": \"f\", \"scatter\": {\"count\": 0, \"min\": [0,0,0], \"max\": [1,0,1]}}]}", FS_ERR_SCENE},
    {"empty assets", "{\"assets\": []," I "}", FS_ERR_SCENE},
    {"missing assets", "{" I "}", FS_ERR_SCENE},
    {"empty instances", "{" A ", \"instances\": []}", FS_ERR_SCENE},
    {"missing instances", "{" A "}", FS_ERR_SCENE},
    {"non-increasing camera times", "{" A "," I ", \"camera\": [{\"time\": 0, \"position\": [0,1,5], \"target\": [0,0,0]},"
     " {\"time\": 2, \"position\": [0,1,6], \"target\": [0,0,0]}, {\"time\": 1.5, \"position\": [0,1,7], \"target\": [0,0,0]}]}", FS_ERR_SCENE},
    {"camera key without time", "{" A "," I ", \"camera\": [" CAM2 ", {\"position\": [0,1,7], \"target\": [0,0,0]}]}", FS_ERR_SCENE},
    {"camera target == position", "{" A "," I ", \"camera\": [{\"position\": [0,1,5], \"target\": [0,1,5]}]}", FS_ERR_SCENE},
    {"camera hfov 180", "{" A "," I ", \"camera\": [{\"position\": [0,1,5], \"target\": [0,0,0], \"hfov\": 180}]}", FS_ERR_SCENE},
    {"cut on the first key", "{" A "," I ", \"camera\": [{\"position\": [0,1,5], \"target\": [0,0,0], \"cut\": true}]}", FS_ERR_SCENE},
    {"empty camera", "{" A "," I ", \"camera\": []}", FS_ERR_SCENE},
    {"camera is an object", "{" A "," I ", \"camera\": {\"position\": [0,1,5], \"target\": [0,0,0]}}", FS_ERR_SCENE},
    {"JSON syntax error (trailing comma)", "{" A "," I ",}", FS_ERR_SCENE},
    {"JSON syntax error (garbage after)", "{" A "," I "} x", FS_ERR_SCENE},
    {"empty file", "", FS_ERR_SCENE},
    {"top level is an array", "[1, 2]", FS_ERR_SCENE},
    {"duplicate key", "{" A "," I "," I "}", FS_ERR_SCENE},
    {"material override matching nothing", "{" A "," I ", \"materials\": {\"bark\": {\"alpha_mode\": \"hashed\"}}}", FS_ERR_SCENE},
    {"material override cutoff 1.5", "{" A "," I ", \"materials\": {\"fronds\": {\"alpha_cutoff\": 1.5}}}", FS_ERR_SCENE},
    {"material override alpha_lod_max 16.5", "{" A "," I ", \"materials\": {\"fronds\": {\"alpha_lod_max\": 16.5}}}", FS_ERR_SCENE},
    {"material override alpha_lod_max -1", "{" A "," I ", \"materials\": {\"fronds\": {\"alpha_lod_max\": -1}}}", FS_ERR_SCENE},
    {"material override bad key", "{" A "," I ", \"materials\": {\"fronds\": {\"cutoff\": 0.5}}}", FS_ERR_SCENE},
    {"display width 0", "{" A "," I ", \"display\": {\"width\": 0}}", FS_ERR_SCENE},
    {"display width too large", "{" A "," I ", \"display\": {\"width\": 100000}}", FS_ERR_SCENE},
    {"display height negative", "{" A "," I ", \"display\": {\"height\": -720}}", FS_ERR_SCENE},
    {"display hfov 180", "{" A "," I ", \"display\": {\"hfov\": 180}}", FS_ERR_SCENE},
    {"light direction zero", "{" A "," I ", \"light\": {\"direction\": [0,0,0]}}", FS_ERR_SCENE},
    {"light colour negative", "{" A "," I ", \"light\": {\"color\": [1,-1,1]}}", FS_ERR_SCENE},
    {"glTF file missing", "{\"assets\": [{\"name\": \"f\", \"gltf\": \"no_such_file.gltf\"}]," I "}", FS_ERR_IO},
    {"gaze tracker unknown key", "{" A "," I ", \"gaze\": {\"lag\": 20}}", FS_ERR_SCENE},
    {"gaze tracker negative latency", "{" A "," I ", \"gaze\": {\"latency\": -5}}", FS_ERR_SCENE},
    {"gaze tracker unknown loss", "{" A "," I ", \"gaze\": {\"loss\": \"blink\"}}", FS_ERR_SCENE},
    {"gaze tracker fractional seed", "{" A "," I ", \"gaze\": {\"seed\": 1.5}}", FS_ERR_SCENE},
    {"gaze tracker not an object", "{" A "," I ", \"gaze\": 20}", FS_ERR_SCENE},
    {"params on a glTF asset", "{\"assets\": [{\"name\": \"f\", \"gltf\": \"x.gltf\", \"params\": {}}]," I "}", FS_ERR_SCENE},
};

TEST(bad_scene_files)
{
    log_set_quiet_errors(true);
    int n = (int)(sizeof k_cases / sizeof k_cases[0]);
    CHECK(n >= 21);
    for (int i = 0; i < n; i++) {
        char name[64];
        snprintf(name, sizeof name, "bad_%02d.json", i);
        scene sc;
        memset(&sc, 0x33, sizeof sc); /* the loader must not rely on a zeroed output */
        fs_status s = scene_load_file(write_scene(name, k_cases[i].text), &sc);
        if (s != k_cases[i].want)
            fprintf(stderr, "  case %d (%s): got %s, want %s\n", i, k_cases[i].what, fs_status_text(s),
                    fs_status_text(k_cases[i].want));
        CHECK(s == k_cases[i].want);
        if (s != FS_OK)
            CHECK(scene_is_zeroed(&sc));
        scene_free(&sc);
    }
    scene sc;
    char missing[1200];
    snprintf(missing, sizeof missing, "%s/no_such_scene.json", test_out_dir());
    CHECK(scene_load_file(missing, &sc) == FS_ERR_IO);
    CHECK(scene_is_zeroed(&sc));
    CHECK(scene_load_file(test_out_dir(), &sc) == FS_ERR_IO); /* a directory */
    CHECK(scene_load_file("no_such_dir/plant.glb", &sc) == FS_ERR_IO);
    CHECK(scene_is_zeroed(&sc));
    log_set_quiet_errors(false);
}

/* >>glTF as a scene */

TEST(gltf_as_scene)
{
    scene sc;
    const char *path = test_shared_path(FERN_GLTF);
    fs_status s = scene_load_file(path, &sc);
    CHECK(s == FS_OK);
    if (s != FS_OK)
        return;
    CHECK(scene_validate(&sc) == FS_OK);
    CHECK(strcmp(sc.path, path) == 0);
    CHECK(sc.asset_count == 1 && sc.instance_count == 1);
    CHECK(memcmp(&sc.instances[0].transform, &(mat4){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}},
                 sizeof(mat4)) == 0);
    CHECK(sc.camera.count == 1 && sc.duration == 0);
    CHECK(mask_materials(&sc) >= 1);
    CHECK(sc.display.width == 1280 && sc.display.height == 720);
    vec3 lo, hi;
    float x, y;
    scene_bounds(&sc, &lo, &hi);
    vec3 centre = v3_scale(v3_add(lo, hi), 0.5f);
    CHECK(camera_sees(&sc, 0, centre, &x, &y));
    for (int k = 0; k < 8; k++)
        CHECK(camera_sees(&sc, 0, v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z), &x, &y));
    /* Filling the view, not a speck: the bounding sphere spans a good part of the height. */
    float radius = 0.5f * v3_len(v3_sub(hi, lo));
    float dist = v3_len(v3_sub(sc.camera.keys[0].position, centre));
    CHECK(dist < 4 * radius && dist > radius);
    scene_free(&sc);

    /* A .glb too (case-insensitive extension check is not needed for this one). */
    s = scene_load_file(test_shared_path("assets/polyhaven_fern_02_glb/fern_02.glb"), &sc);
    CHECK(s == FS_OK);
    if (s == FS_OK) {
        CHECK(sc.asset_count == 1 && scene_validate(&sc) == FS_OK);
        scene_bounds(&sc, &lo, &hi);
        CHECK(camera_sees(&sc, 0, v3_scale(v3_add(lo, hi), 0.5f), &x, &y));
    }
    scene_free(&sc);
}

TEST(validate_catches_corrupted_index)
{
    scene sc;
    fs_status s = scene_load_file(test_shared_path(FERN_GLTF), &sc);
    CHECK(s == FS_OK);
    if (s != FS_OK)
        return;
    prim *p = &sc.assets[0].prims[0];
    CHECK(p->index_count >= 3);
    uint32_t keep = p->indices[p->index_count - 1];
    p->indices[p->index_count - 1] = p->vertex_count + 9000;
    log_set_quiet_errors(true);
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    p->indices[p->index_count - 1] = p->vertex_count; /* off by one */
    CHECK(scene_validate(&sc) == FS_ERR_SCENE);
    log_set_quiet_errors(false);
    p->indices[p->index_count - 1] = keep;
    CHECK(scene_validate(&sc) == FS_OK);
    scene_free(&sc);
}

int main(void)
{
    RUN(defaults);
    RUN(add_bounds_fit_validate);
    RUN(builtins_load_and_validate);
    RUN(builtin_forest_dollies_backwards);
    RUN(builtin_fence_recedes_from_the_fence);
    RUN(unknown_builtin);
    RUN(json_scene_with_generator_and_gltf);
    RUN(camera_defaults_to_fit_and_single_key);
    RUN(scatter_is_deterministic_and_inside_the_box);
    RUN(bad_scene_files);
    RUN(gltf_as_scene);
    RUN(validate_catches_corrupted_index);
    return test_summary();
}
