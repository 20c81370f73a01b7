/* test_castano.c: coverage-preserving mip chains (Castano; src/scene/mip.c
 * mip_chain_build_castano, mip_level_coverage). On the real MegaKit textures Leaves.png and
 * Leaves_TwistedTree_C.png (cutoff 0.2, their glTF alphaCutoff), Flowers.png (1008x981) and the
 * generated chain-link fence (cutoff 0.5), every level of the castano chain keeps level 0's share
 * of passing texels while the plain chain drifts (Leaves bloats towards 1, the fence erodes to 0);
 * the unpremultiplied colour is untouched; edge cases (opaque, transparent, cutoff 0, 1, > 1, NaN,
 * 1x1, thin and NPOT images) and build speed.
 *
 * Tolerance on a level's coverage: |c_l - c_0| <= max(0.02, 1/texels of the level) — one texel
 * of quantisation for small levels. Texels of equal alpha pass or fail together, so a level whose
 * alphas come in large groups of equal values (the fence is one periodic, symmetric tile; the
 * synthetic random images mix few alpha values) may not be able to get that close: independently
 * of the implementation, the test computes from the level's sorted alpha values the best share any
 * single threshold can give and requires the castano chain to reach it (optimality); the 0.02
 * tolerance is then max(0.02, 1/texels, that best). The real MegaKit textures meet the plain
 * tolerance at every level.
 */
#include <stdint.h>
#include <time.h>

#include "core/log.h"
#include "scene/generators.h"
#include "scene/mip.h"
#include "test.h"

#include "stb_png.h"

static uint32_t rng_state = 987654321u;
static uint32_t next_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

/* A random image; `alpha_mode` 0 = uniform alpha, 1 = mostly 0 or 255 with a soft band
 * (foliage-like), 2 = alpha given by `fixed_alpha`. */
static image_rgba8 make_image(int w, int h, int alpha_mode, uint8_t fixed_alpha)
{
    image_rgba8 im = {.width = w, .height = h};
    im.rgba = malloc((size_t)w * h * 4);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        uint32_t r = next_u32();
        im.rgba[4 * i] = (uint8_t)r;
        im.rgba[4 * i + 1] = (uint8_t)(r >> 8);
        im.rgba[4 * i + 2] = (uint8_t)(r >> 16);
        uint8_t a = (uint8_t)(r >> 24);
        if (alpha_mode == 1)
            a = a < 150 ? 0 : (a < 160 ? a : 255);
        else if (alpha_mode == 2)
            a = fixed_alpha;
        im.rgba[4 * i + 3] = a;
    }
    return im;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Smallest |count/n - target| any threshold on this level's (unscaled) alpha can give: the
 * passing sets are "every texel with alpha >= v" for a value v of the level, or none. Values
 * within 4 ulps of the next lower one count as equal: they are the same average up to float
 * rounding, and no float scale separates them reliably (alpha * s rounds). */
static double best_reachable_error(const float *rgba, size_t n, double target)
{
    float *v = malloc(n * sizeof *v);
    for (size_t i = 0; i < n; i++)
        v[i] = rgba[4 * i + 3];
    qsort(v, n, sizeof *v, cmp_float);
    double best = target; /* nothing passes */
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && v[i] <= v[i - 1] * (1.0f + 0x1p-21f))
            continue;
        if (!(v[i] > 0.0f))
            continue; /* alpha 0 never passes a positive cutoff */
        double e = fabs((double)(n - i) / (double)n - target);
        if (e < best)
            best = e;
    }
    free(v);
    return best;
}

/* Checks that the castano chain of `im` keeps level 0's coverage at every level, that it differs
 * from the plain chain only by the recorded alpha scales, and that colour/alpha is unchanged.
 * Prints the per-level table. Returns the plain chain's largest |c_l - c_0| (its drift). */
static int quiet_tables; /* the random-image sweep prints only failures */

/* `strict`: every level within max(0.02, 1/texels), whatever the ties. */
static double check_preserves(const image_rgba8 *im, float cutoff, const char *label, int strict)
{
    mip_chain p, c;
    CHECK(mip_chain_build(im, &p) == FS_OK);
    CHECK(mip_chain_build_castano(im, cutoff, &c) == FS_OK);
    CHECK(c.level_count == p.level_count);
    if (c.level_count != p.level_count || c.level_count < 1) {
        mip_chain_free(&p);
        mip_chain_free(&c);
        return 0.0;
    }
    double c0 = mip_level_coverage(&c, 0, cutoff);
    CHECK(c0 == mip_level_coverage(&p, 0, cutoff));
    CHECK(c.alpha_scale[0] == 1.0f);
    if (!quiet_tables)
        printf("%s %dx%d cutoff %.2f: level texels plain castano (scale)\n", label, im->width,
               im->height, (double)cutoff);
    double drift = 0.0, worst = 0.0, max_colour_err = 0.0;
    for (int l = 0; l < c.level_count; l++) {
        size_t n = (size_t)c.width[l] * c.height[l];
        double cp = mip_level_coverage(&p, l, cutoff), cc = mip_level_coverage(&c, l, cutoff);
        double best = best_reachable_error(p.rgba[l], n, c0);
        double tol = fmax(0.02, 1.0 / (double)n);
        if (!strict)
            tol = fmax(tol, best + 1e-9);
        if (!quiet_tables)
            printf("  %2d %8zu %.4f %.4f (%.4f)%s\n", l, n, cp, cc, (double)c.alpha_scale[l],
                   best > 1e-12 + 0.5 / (double)n ? " [ties]" : "");
        drift = fmax(drift, fabs(cp - c0));
        worst = fmax(worst, fabs(cc - c0));
        CHECK(fabs(cc - c0) <= tol);
        /* Optimal: no threshold on this level could do better (a texel's worth of slack). */
        CHECK(fabs(cc - c0) <= best + 1e-9);
        if (fabs(cc - c0) > tol || fabs(cc - c0) > best + 1e-9)
            fprintf(stderr, "%s level %d: coverage %.6f vs level 0 %.6f (tol %.4f, best %.6f)\n",
                    label, l, cc, c0, tol, best);
        float s = c.alpha_scale[l];
        CHECK(s > 0.0f && isfinite(s));
        if (s == 1.0f)
            CHECK(memcmp(c.rgba[l], p.rgba[l], n * 4 * sizeof(float)) == 0);
        for (size_t i = 0; i < n; i++) {
            const float *q = p.rgba[l] + 4 * i, *t = c.rgba[l] + 4 * i;
            float na = q[3] * s;
            if (!(q[3] > 0.0f))
                na = q[3];
            else if (na > 1.0f)
                na = 1.0f;
            CHECK(t[3] == na); /* alpha' = min(1, alpha * s) */
            for (int ch = 0; ch < 3; ch++) {
                CHECK(t[ch] >= 0.0f && t[ch] <= t[3]); /* premultiplied stays <= alpha */
                if (q[3] > 0.0f) {
                    double before = fmin(1.0, (double)q[ch] / q[3]), after = (double)t[ch] / t[3];
                    double e = fabs(after - before);
                    max_colour_err = fmax(max_colour_err, e);
                    if (e > 1.0 / 255.0) {
                        CHECK(e <= 1.0 / 255.0);
                        break;
                    }
                }
            }
        }
    }
    if (!quiet_tables)
        printf("  plain max |dc| %.4f, castano max |dc| %.4f, max unpremultiplied colour change %.2g\n",
               drift, worst, max_colour_err);
    mip_chain_free(&p);
    mip_chain_free(&c);
    return drift;
}

static double elapsed_s(const struct timespec *t0, const struct timespec *t1)
{
    return (double)(t1->tv_sec - t0->tv_sec) + 1e-9 * (double)(t1->tv_nsec - t0->tv_nsec);
}

static uint8_t *load_png(const char *rel, int *w, int *h)
{
    const char *path = test_shared_path(rel);
    int comp = 0;
    uint8_t *px = stbi_load(path, w, h, &comp, 4);
    CHECK(px != NULL);
    if (!px)
        fprintf(stderr, "cannot load %s (set FOVSIM_SHARED)\n", path);
    return px;
}

/* Leaves.png (mean alpha 0.44, cutoff 0.2): the plain chain bloats to full cover at mip 10. */
TEST(leaves_coverage_preserved)
{
    int w = 0, h = 0;
    uint8_t *px = load_png("assets/quaternius_megakit_set_a/Leaves.png", &w, &h);
    if (!px)
        return;
    image_rgba8 im = {.width = w, .height = h, .rgba = px};
    double drift = check_preserves(&im, 0.2f, "Leaves.png", 1);
    CHECK(drift > 0.5); /* 0.44 -> 1.00 */
    mip_chain p;
    CHECK(mip_chain_build(&im, &p) == FS_OK);
    CHECK(mip_level_coverage(&p, 10, 0.2f) >= 0.999);
    mip_chain_free(&p);

    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    mip_chain c;
    CHECK(mip_chain_build_castano(&im, 0.2f, &c) == FS_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double tc = elapsed_s(&t0, &t1);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK(mip_chain_build(&im, &p) == FS_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("Leaves.png castano chain built in %.3f s (plain chain %.3f s)\n", tc, elapsed_s(&t0, &t1));
    /* -O2 takes a few hundredths of a second; sanitizer builds are several times slower. */
    CHECK(tc < 5.0);
    /* Bloat is corrected by scaling alpha down at the coarse levels. */
    CHECK(c.alpha_scale[10] < 1.0f);
    mip_chain_free(&c);
    mip_chain_free(&p);
    stbi_image_free(px);
}

TEST(twisted_tree_leaves_coverage_preserved)
{
    int w = 0, h = 0;
    uint8_t *px = load_png("assets/quaternius_megakit_set_a/Leaves_TwistedTree_C.png", &w, &h);
    if (!px)
        return;
    image_rgba8 im = {.width = w, .height = h, .rgba = px};
    double drift = check_preserves(&im, 0.2f, "Leaves_TwistedTree_C.png", 1);
    CHECK(drift > 0.2);
    stbi_image_free(px);
}

/* Flowers.png: 1008x981, non-power-of-two with odd sizes. */
TEST(flowers_npot_coverage_preserved)
{
    int w = 0, h = 0;
    uint8_t *px = load_png("assets/quaternius_megakit_set_a/Flowers.png", &w, &h);
    if (!px)
        return;
    CHECK(w == 1008 && h == 981);
    image_rgba8 im = {.width = w, .height = h, .rgba = px};
    check_preserves(&im, 0.2f, "Flowers.png", 1);
    stbi_image_free(px);
}

/* The generated chain-link fence (mean alpha 0.13, cutoff 0.5) erodes to nothing on the plain
 * chain; castano scales alpha up and keeps it. */
TEST(fence_coverage_preserved)
{
    asset a;
    CHECK(gen_fence(&(gen_fence_desc){0}, &a) == FS_OK);
    CHECK(a.image_count >= 1);
    if (a.image_count < 1)
        return;
    const image_rgba8 *im = &a.images[0];
    double drift = check_preserves(im, 0.5f, "fence", 0);
    mip_chain p, c;
    CHECK(mip_chain_build(im, &p) == FS_OK);
    CHECK(mip_chain_build_castano(im, 0.5f, &c) == FS_OK);
    double c0 = mip_level_coverage(&p, 0, 0.5f);
    CHECK(c0 > 0.1);
    CHECK(mip_level_coverage(&p, 3, 0.5f) == 0.0); /* 8x8: the wire is gone */
    CHECK(drift >= c0 - 1e-12);
    CHECK(mip_level_coverage(&c, 3, 0.5f) > 0.1);
    CHECK(c.alpha_scale[3] > 1.0f);
    mip_chain_free(&p);
    mip_chain_free(&c);
    asset_free(&a);
}

TEST(random_images_coverage_preserved)
{
    const int sizes[][2] = {{1008, 981}, {256, 256}, {100, 63}, {17, 129}, {37, 1}, {1, 7}, {2, 1}, {3, 3}};
    const float cutoffs[] = {0.2f, 0.5f, 0.69f, 1.0f};
    quiet_tables = 1;
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (int mode = 0; mode < 2; mode++)
            for (size_t k = 0; k < sizeof cutoffs / sizeof cutoffs[0]; k++) {
                image_rgba8 im = make_image(sizes[s][0], sizes[s][1], mode, 0);
                char label[64];
                snprintf(label, sizeof label, "random mode %d", mode);
                check_preserves(&im, cutoffs[k], label, 0);
                free(im.rgba);
            }
    quiet_tables = 0;
}

/* Every scale 1 and the chain identical to the plain one. */
static void check_unchanged(const image_rgba8 *im, float cutoff, double expect_c0)
{
    mip_chain p, c;
    CHECK(mip_chain_build(im, &p) == FS_OK);
    CHECK(mip_chain_build_castano(im, cutoff, &c) == FS_OK);
    CHECK(c.level_count == p.level_count);
    for (int l = 0; l < MIP_MAX_LEVELS; l++)
        CHECK(c.alpha_scale[l] == 1.0f);
    for (int l = 0; l < c.level_count && l < p.level_count; l++) {
        size_t n = (size_t)c.width[l] * c.height[l];
        CHECK(memcmp(c.rgba[l], p.rgba[l], n * 4 * sizeof(float)) == 0);
        if (expect_c0 >= 0.0)
            CHECK(mip_level_coverage(&c, l, cutoff) == expect_c0);
    }
    mip_chain_free(&p);
    mip_chain_free(&c);
}

TEST(edge_cases_scale_one)
{
    /* All opaque: coverage 1 at every level, already. */
    image_rgba8 op = make_image(64, 48, 2, 255);
    check_unchanged(&op, 0.5f, 1.0);
    check_unchanged(&op, 1.0f, 1.0);
    free(op.rgba);
    image_rgba8 op2 = make_image(1008, 981, 2, 255);
    check_unchanged(&op2, 0.2f, 1.0);
    free(op2.rgba);
    /* All transparent: nothing to preserve; alpha stays 0 everywhere. */
    image_rgba8 tr = make_image(1008, 981, 2, 0);
    check_unchanged(&tr, 0.5f, 0.0);
    check_unchanged(&tr, 1.0f, 0.0);
    free(tr.rgba);
    /* Uniform alpha below the cutoff: nothing passes at level 0, nor anywhere. */
    image_rgba8 lo = make_image(40, 40, 2, 100);
    check_unchanged(&lo, 0.5f, 0.0);
    free(lo.rgba);
    /* Cutoff 0 (and below): every texel passes everywhere. Cutoff > 1: none does. */
    image_rgba8 im = make_image(1008, 981, 1, 0);
    check_unchanged(&im, 0.0f, 1.0);
    check_unchanged(&im, -0.5f, 1.0);
    check_unchanged(&im, 1.0001f, 0.0);
    check_unchanged(&im, 7.0f, 0.0);
    check_unchanged(&im, INFINITY, 0.0);
    check_unchanged(&im, -INFINITY, 1.0);
    free(im.rgba);
    /* 1x1: only level 0. */
    uint8_t px[4] = {10, 200, 30, 128};
    image_rgba8 one = {.width = 1, .height = 1, .rgba = px};
    check_unchanged(&one, 0.5f, 1.0);
    check_unchanged(&one, 0.6f, 0.0);
    mip_chain c;
    CHECK(mip_chain_build_castano(&one, 0.5f, &c) == FS_OK);
    CHECK(c.level_count == 1);
    mip_chain_free(&c);
}

TEST(cutoff_one)
{
    /* Binary alpha in 4x4 blocks on a 1008x981 image: with cutoff 1 only fully opaque texels pass;
     * the plain chain loses every block edge, castano scales the best up to exactly 1. */
    image_rgba8 im = make_image(1008, 981, 0, 0);
    for (int y = 0; y < im.height; y++)
        for (int x = 0; x < im.width; x++) {
            uint32_t h = (uint32_t)(x / 4) * 73856093u ^ (uint32_t)(y / 4) * 19349663u;
            h ^= h >> 13;
            h *= 0x5bd1e995u;
            h ^= h >> 15;
            im.rgba[4 * ((size_t)y * im.width + x) + 3] = (h & 3u) == 0 ? 255 : 0;
        }
    check_preserves(&im, 1.0f, "blocks", 0);
    mip_chain c;
    CHECK(mip_chain_build_castano(&im, 1.0f, &c) == FS_OK);
    for (int l = 0; l < c.level_count; l++) {
        size_t n = (size_t)c.width[l] * c.height[l];
        for (size_t i = 0; i < n; i++)
            CHECK(c.rgba[l][4 * i + 3] <= 1.0f);
    }
    mip_chain_free(&c);
    free(im.rgba);
}

TEST(nan_cutoff_rejected)
{
    image_rgba8 im = make_image(16, 16, 1, 0);
    mip_chain c;
    log_set_quiet_errors(true);
    CHECK(mip_chain_build_castano(&im, NAN, &c) == FS_ERR_SCENE);
    log_set_quiet_errors(false);
    CHECK(c.level_count == 0);
    for (int l = 0; l < MIP_MAX_LEVELS; l++)
        CHECK(c.rgba[l] == NULL);
    mip_chain_free(&c);
    free(im.rgba);
}

TEST(plain_chain_scales_one_and_coverage_api)
{
    image_rgba8 im = make_image(33, 20, 0, 0);
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    for (int l = 0; l < MIP_MAX_LEVELS; l++)
        CHECK(c.alpha_scale[l] == 1.0f);
    size_t n = (size_t)im.width * im.height, pass = 0;
    for (size_t i = 0; i < n; i++)
        pass += im.rgba[4 * i + 3] >= 128; /* 128/255 >= 0.5 */
    CHECK_NEAR(mip_level_coverage(&c, 0, 0.5f), (double)pass / (double)n, 1e-12);
    CHECK(mip_level_coverage(&c, 0, 0.0f) == 1.0);
    CHECK(mip_level_coverage(&c, 0, 2.0f) == 0.0);
    CHECK(mip_level_coverage(&c, 0, NAN) == 0.0);
    CHECK(mip_level_coverage(&c, -1, 0.5f) == 0.0);
    CHECK(mip_level_coverage(&c, c.level_count, 0.5f) == 0.0);
    CHECK(mip_level_coverage(NULL, 0, 0.5f) == 0.0);
    mip_chain_free(&c);
    memset(&c, 0, sizeof c);
    CHECK(mip_level_coverage(&c, 0, 0.5f) == 0.0);
    free(im.rgba);
}

TEST(build_speed_2048)
{
    image_rgba8 im = make_image(2048, 2048, 1, 0);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    mip_chain c;
    CHECK(mip_chain_build_castano(&im, 0.5f, &c) == FS_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double s = elapsed_s(&t0, &t1);
    printf("castano: 2048x2048 chain (%d levels) built in %.3f s\n", c.level_count, s);
    CHECK(c.level_count == 12);
    /* Generous: -O2 takes well under 0.1 s; sanitizer builds are several times slower. */
    CHECK(s < 5.0);
    mip_chain_free(&c);
    free(im.rgba);
}

/* The level where the traditional test's coverage drifts (renderer: end of the hashed fade-in). */
TEST(coverage_drift_level)
{
    asset a;
    CHECK(gen_fence(&(gen_fence_desc){0}, &a) == FS_OK);
    mip_chain p;
    CHECK(mip_chain_build(&a.images[0], &p) == FS_OK);
    /* Fence coverage per level: 0.150, 0.180 (+20 %), 0.125 (-17 %), 0 at level 3. */
    CHECK(mip_coverage_drift_level(&p, 0.5f, 0.25) == 3);
    CHECK(mip_coverage_drift_level(&p, 0.5f, 0.10) == 1);
    CHECK(mip_coverage_drift_level(&p, 0.0f, 0.25) == p.level_count); /* everything always passes */
    mip_chain_free(&p);
    asset_free(&a);
    int w = 0, h = 0;
    uint8_t *px = load_png("assets/quaternius_megakit_set_a/Leaves.png", &w, &h);
    if (!px)
        return;
    image_rgba8 im = {.width = w, .height = h, .rgba = px};
    CHECK(mip_chain_build(&im, &p) == FS_OK);
    /* Leaves at 0.2: +11 % at level 5, +22 % at 6, +41 % at 7. */
    int l = mip_coverage_drift_level(&p, 0.2f, 0.25);
    fprintf(stderr, "Leaves.png drifts by a quarter at mip %d\n", l);
    CHECK(l == 7);
    mip_chain_free(&p);
    stbi_image_free(px);
}

int main(void)
{
    log_set_quiet_errors(false);
    RUN(leaves_coverage_preserved);
    RUN(twisted_tree_leaves_coverage_preserved);
    RUN(flowers_npot_coverage_preserved);
    RUN(fence_coverage_preserved);
    RUN(random_images_coverage_preserved);
    RUN(edge_cases_scale_one);
    RUN(cutoff_one);
    RUN(nan_cutoff_rejected);
    RUN(plain_chain_scales_one_and_coverage_api);
    RUN(build_speed_2048);
    RUN(coverage_drift_level);
    return test_summary();
}
