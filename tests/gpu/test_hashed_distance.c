/* Hashed coverage at distance (issue 16 part 4): hashed alpha testing keeps the reference's coverage
 * at 4, 16, 64 and 256 m and at widths 1280 -> 80 px.
 *
 * Scenes: a "wall" of randomly turned instances of a Quaternius MegaKit plant (../shared/assets, CC0)
 * at distance D, spread over 0.9 D x 0.44 D of the view and +-10 % in depth, seen by a 90-degree
 * camera; 3, 12, 100 and 1500 instances at 4, 16, 64 and 256 m (the far walls overlap, as a far
 * forest does). Two plants with different atlases: Plant_1_Big (Leaves.png, cutoff 0.2) and
 * Bush_Common (Leaves_TwistedTree_C.png, cutoff 0.2). Distances at 320x180; widths 1280, 640, 320,
 * 160, 80 (16:9) at 64 m. Rings off, TAA off, one frame.
 *
 * Measured: coverage ratio = mean coverage of the mode / mean coverage of the exact reference
 * with ONE sub-sample per pixel. That reference is the exact expectation of stochastic alpha
 * testing at the same pixel centres and the same mip level as the render, so the ratio measures
 * the alpha test alone. With S x S sub-samples the reference samples log2 S mip levels finer, and
 * once a pixel is wider than a leaf card's part of the atlas the render's coarser mip averages in
 * neighbouring atlas texels: stochastic alpha testing then shows the same gap as hashed (0.88-0.96
 * of an S = 4 reference for Plant_1_Big at 16-256 m, 1.05 for Bush_Common), which is the texture
 * filter's, not the alpha test's (docs/hashed-alpha.md, "Coverage at distance").
 *
 * Asserted: hashed within 10 % (the bound) everywhere and, since this reference leaves only
 * the alpha test to differ, within 5 % where the reference covers at least 500 pixels (below that
 * one binary sample per pixel is itself noisier than that). 32-36 s on 2 cores with llvmpipe. Before the per-layer hash keys (one threshold shared by every layer
 * in a noise cell) Bush_Common kept 0.92 at 64 m and 0.84 at 256 m, Plant_1_Big 0.92 at 256 m:
 * the test failed. Stochastic is measured alongside and reported. */
#include <unistd.h>

#include "gpu_util.h"
#include "reference/reference.h"
#include "scene/scene.h"

typedef struct plant {
    const char *name; /* MegaKit asset, relative to shared/assets/quaternius_megakit_set_a */
} plant;

static const plant plants[] = {{"Plant_1_Big"}, {"Bush_Common"}};
static const float distances[] = {4, 16, 64, 256};
static const int counts[] = {3, 12, 100, 1500};
static const int widths[] = {1280, 640, 320, 160, 80};
enum { WIDTH_SWEEP_DISTANCE = 2 }; /* 64 m */

static int failures_10, failures_5;

/* Writes the wall scene of `p` at distance index d and loads it. */
static bool load_wall(const plant *p, int d, scene *sc)
{
    char path[1200], asset[2048], cwd[1024];
    snprintf(path, sizeof path, "%s/hashed_distance_%s_%g.json", test_out_dir(), p->name, distances[d]);
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
    float D = distances[d];
    fprintf(f,
            "{\"display\": {\"width\": 320, \"height\": 180, \"hfov\": 90},\n"
            " \"assets\": [{\"name\": \"p\", \"gltf\": \"%s/%s.gltf\"}],\n"
            " \"instances\": [{\"asset\": \"p\", \"scatter\": {\"count\": %d, \"seed\": 1, \"random_yaw\": true,\n"
            "   \"min\": [%g, %g, %g], \"max\": [%g, %g, %g]}}],\n"
            " \"camera\": [{\"time\": 0, \"position\": [0, 1.5, 0], \"target\": [0, 1.5, %g]}]}\n",
            asset, p->name, counts[d], -0.45 * D, 1.5 - 0.22 * D, -1.1 * D, 0.45 * D, 1.5 + 0.22 * D, -0.9 * D, -D);
    fclose(f);
    return scene_load_file(path, sc) == FS_OK;
}

static double mode_coverage(const scene *sc, alpha_mode mode, int w, int h)
{
    exr_image img;
    if (gpu_render(sc, mode, w, h, 0.0f, &img) != FS_OK)
        return NAN;
    double c = plane_mean(&img, "coverage");
    exr_image_free(&img);
    return c;
}

static double reference_coverage(const scene *sc, int w, int h, int ss)
{
    fs_status st;
    reference *rf = reference_create(sc, &(reference_desc){.width = w, .height = h, .supersample = ss, .samples = 4}, &st);
    if (!rf)
        return NAN;
    frame_record fr = frame_record_at(sc, 0, 0.0f, -1.0f, w, h);
    exr_image img;
    reference_info info;
    st = reference_frame(rf, &fr, &img, &info);
    reference_destroy(rf);
    if (st != FS_OK)
        return NAN;
    double c = plane_mean(&img, "coverage");
    exr_image_free(&img);
    return c;
}

/* One case: prints the ratios, asserts hashed's. */
static void check_case(const plant *p, const scene *sc, const char *what, int w, int h)
{
    double ref = reference_coverage(sc, w, h, 1);
    double hashed = mode_coverage(sc, ALPHA_MODE_HASHED, w, h) / ref;
    double stochastic = mode_coverage(sc, ALPHA_MODE_STOCHASTIC, w, h) / ref;
    /* 5 % only where the reference covers >= 500 pixels: the hashed image is one binary sample
     * per pixel, and below that its own noise reaches a few per cent (stochastic too: 1.07 at
     * 80x45, where the plants cover ~45 pixels). */
    double covered = ref * w * h;
    bool ok10 = fabs(hashed - 1.0) <= 0.10, ok5 = covered < 500.0 || fabs(hashed - 1.0) <= 0.05;
    fprintf(stderr, "  %-12s %-16s %4dx%-3d reference coverage %.4f (%6.0f px): hashed %.3f, stochastic %.3f%s\n",
            p->name, what, w, h, ref, covered, hashed, stochastic,
            !ok10 ? "  (outside 10 %)" : !ok5 ? "  (outside 5 %)" : "");
    CHECK(ref > 0.0005); /* the plants are in view: > 25 covered pixels at 320x180 */
    failures_10 += !ok10;
    failures_5 += !ok5;
    CHECK(ok10);
    CHECK(ok5);
}

TEST(hashed_keeps_the_references_coverage_from_4_to_256_m)
{
    for (size_t i = 0; i < sizeof plants / sizeof plants[0]; i++)
        for (int d = 0; d < 4; d++) {
            scene sc;
            CHECK(load_wall(&plants[i], d, &sc));
            char what[32];
            snprintf(what, sizeof what, "%g m", distances[d]);
            check_case(&plants[i], &sc, what, 320, 180);
            scene_free(&sc);
        }
}

TEST(hashed_keeps_the_references_coverage_from_1280_to_80_px)
{
    for (size_t i = 0; i < sizeof plants / sizeof plants[0]; i++) {
        scene sc;
        CHECK(load_wall(&plants[i], WIDTH_SWEEP_DISTANCE, &sc));
        for (size_t k = 0; k < sizeof widths / sizeof widths[0]; k++) {
            char what[32];
            snprintf(what, sizeof what, "%g m, %d px", distances[WIDTH_SWEEP_DISTANCE], widths[k]);
            check_case(&plants[i], &sc, what, widths[k], widths[k] * 9 / 16);
        }
        scene_free(&sc);
    }
}

int main(void)
{
    gpu_begin();
    RUN(hashed_keeps_the_references_coverage_from_4_to_256_m);
    RUN(hashed_keeps_the_references_coverage_from_1280_to_80_px);
    fprintf(stderr, "cases outside 10 %%: %d, outside 5 %%: %d\n", failures_10, failures_5);
    gl_device_destroy();
    return test_summary();
}
