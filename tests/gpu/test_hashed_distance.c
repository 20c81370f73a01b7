/* Hashed coverage at distance (docs/hashed-alpha.md "Coverage at distance"): hashed alpha testing keeps the reference's coverage
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
 * one binary sample per pixel is itself noisier than that). Before the per-layer hash keys (one
 * threshold shared by every layer in a noise cell) Bush_Common kept 0.92 at 64 m and 0.84 at
 * 256 m, Plant_1_Big 0.92 at 256 m: the test failed. Stochastic is measured alongside and reported.
 *
 * Also: a grass tuft 1.41 pixels wide at 64 and 128 m (see the test). The whole
 * file takes ~42 s on 2 cores with llvmpipe (the tufts ~17 of them). */
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

/* The wall scene of `p` at distance index d. */
static bool load_wall(const plant *p, int d, scene *sc)
{
    char tag[200];
    snprintf(tag, sizeof tag, "hashed_distance_%s_%g", p->name, distances[d]);
    return gpu_load_plant_wall(tag, p->name, counts[d], 1, distances[d], sc);
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

/* >>tiny */

/* docs/hashed-alpha.md "Assets a pixel or two wide": an asset 1-2 pixels wide lies within a pixel or so of its object origin, where
 * Listing 1's two cells floor(2^lo obj) and floor(2^hi obj) are the same cell. Hashed with one
 * function they gave equal values, and Eq. 1's CDF then let too many fragments of alpha < 0.5 pass.
 * Each level now hashes its own lattice (docs/hashed-alpha.md, "Assets a pixel or two wide").
 *
 * Scene: a generated grass tuft (extent 1, 6 cards, 128^2 texture, alpha_cutoff 0.69, like the
 * issue's held-out grass) sqrt(2) pixels wide at D = 64 and 128 m (320x180, 90-degree view: a pixel
 * is D / 160 m, so the scale is sqrt(2) D / 160), 3000 instances at random in a wall like the
 * plants' above (another layout at each distance). A few cards per tuft, so that the layers of a
 * pixel do not saturate it and hide a bias. sqrt(2) px puts log2(pixScale) half-way between two
 * levels (0.5 +- 0.14 over the wall's +-10 % depth), where Eq. 1 reshapes the most, and makes the
 * coarse cells 1 object unit wide and the fine ones 0.5: the tuft (|x|, |z| < 0.5, 0 <= y < 0.65)
 * lies almost wholly in cells that the two levels share. Each tuft is turned about its x axis so
 * that the plane of its opaque ground quad passes through the camera: the quad is edge-on and
 * covers nothing (measured: with blades 1 mm tall the reference covers 0 pixels), so the blades
 * are all that is measured. Against the S = 1 reference, as above; within 10 % asserted. Before the
 * level keys: hashed 1.158 and 1.16 of the reference (the test failed); stochastic ~1.00. */
static const float tiny_distances[] = {64, 128};
enum { TINY_COUNT = 3000 };

static bool load_tiny(int d, scene *sc)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/hashed_distance_tuft_%g.json", test_out_dir(), tiny_distances[d]);
    FILE *f = fopen(path, "w");
    if (!f)
        return false;
    float D = tiny_distances[d];
    double scale = sqrt(2.0) * D / 160.0;
    fprintf(f,
            "{\"display\": {\"width\": 320, \"height\": 180, \"hfov\": 90},\n"
            " \"assets\": [{\"name\": \"tuft\", \"generator\": \"grass\", \"params\": {\"extent\": 1, \"card_count\": 6,"
            " \"alpha_cutoff\": 0.69}}],\n"
            " \"camera\": [{\"time\": 0, \"position\": [0, 1.5, 0], \"target\": [0, 1.5, %g]}],\n"
            " \"instances\": [\n",
            -D);
    uint64_t s = 0x2545f4914f6cdd1dull + (uint64_t)d; /* another layout at each distance */
    for (int i = 0; i < TINY_COUNT; i++) {
        double u[3];
        for (int k = 0; k < 3; k++) {
            s = s * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(s >> 11) * (1.0 / 9007199254740992.0);
        }
        double x = (u[0] - 0.5) * 0.9 * D, y = (u[1] - 0.5) * 0.44 * D, z = -(0.9 + 0.2 * u[2]) * D;
        /* Rx(a) turns the tuft's up axis to (0, cos a, sin a), perpendicular to (x, y, z) when
         * tan a = -y / z: the ground quad's plane then contains the camera. */
        double a = atan2(-y, z) * 180.0 / 3.14159265358979;
        if (a > 90)
            a -= 180;
        else if (a < -90)
            a += 180;
        fprintf(f,
                "  {\"asset\": \"tuft\", \"translation\": [%.4f, %.4f, %.4f], \"rotation_deg\": [%.5f, 0, 0], "
                "\"scale\": %.5f}%s\n",
                x, 1.5 + y, z, a, scale, i + 1 < TINY_COUNT ? "," : "");
    }
    fprintf(f, " ]}\n");
    fclose(f);
    return scene_load_file(path, sc) == FS_OK;
}

TEST(hashed_keeps_the_references_coverage_of_a_1_to_2_px_asset)
{
    for (int d = 0; d < 2; d++) {
        scene sc;
        CHECK(load_tiny(d, &sc));
        double ref = reference_coverage(&sc, 320, 180, 1);
        double hashed = mode_coverage(&sc, ALPHA_MODE_HASHED, 320, 180) / ref;
        double stochastic = mode_coverage(&sc, ALPHA_MODE_STOCHASTIC, 320, 180) / ref;
        double traditional = mode_coverage(&sc, ALPHA_MODE_TRADITIONAL, 320, 180) / ref;
        double covered = ref * 320 * 180;
        fprintf(stderr, "  grass tuft 1.41 px wide at %g m, %d instances: reference coverage %.4f (%.0f px): hashed %.3f, "
                        "stochastic %.3f, traditional %.3f\n",
                tiny_distances[d], TINY_COUNT, ref, covered, hashed, stochastic, traditional);
        CHECK(covered > 1000.0); /* binomial noise of one sample per pixel: ~3 % */
        CHECK(fabs(hashed - 1.0) <= 0.10);
        scene_free(&sc);
    }
}

int main(void)
{
    gpu_begin();
    RUN(hashed_keeps_the_references_coverage_from_4_to_256_m);
    RUN(hashed_keeps_the_references_coverage_from_1280_to_80_px);
    RUN(hashed_keeps_the_references_coverage_of_a_1_to_2_px_asset);
    fprintf(stderr, "cases outside 10 %%: %d, outside 5 %%: %d\n", failures_10, failures_5);
    gl_device_destroy();
    return test_summary();
}
