/* test_mip.c: premultiplied-alpha mip chains (src/scene/mip.c): sRGB, level sizes, area-exact
 * filtering (mean alpha preserved), premultiplication, and the coverage drift of traditional
 * alpha testing with distance on a real texture (MegaKit Leaves.png) and the generated fence. */
#include <stdint.h>
#include <time.h>

#include "core/log.h"
#include "scene/generators.h"
#include "scene/mip.h"
#include "test.h"

#include "stb_png.h"

static uint32_t rng_state = 12345u;
static uint32_t next_u32(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 17;
    rng_state ^= rng_state << 5;
    return rng_state;
}

/* A random image; `alpha_mode` 0 = uniform alpha, 1 = mostly 0 or 255 (foliage-like). */
static image_rgba8 make_image(int w, int h, int alpha_mode)
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
        im.rgba[4 * i + 3] = a;
    }
    return im;
}

/* Share of texels of a level whose alpha passes a traditional test (alpha >= cutoff). */
static double level_pass_fraction(const mip_chain *c, int level, float cutoff)
{
    size_t n = (size_t)c->width[level] * c->height[level], pass = 0;
    for (size_t i = 0; i < n; i++)
        pass += c->rgba[level][4 * i + 3] >= cutoff;
    return (double)pass / (double)n;
}

TEST(srgb_known_values)
{
    CHECK_NEAR(srgb_to_linear(0.5f), 0.2140411, 1e-5);
    CHECK_NEAR(srgb_to_linear(0.0f), 0.0, 0.0);
    CHECK_NEAR(srgb_to_linear(1.0f), 1.0, 0.0);
    CHECK_NEAR(srgb_to_linear(0.04045f), 0.04045 / 12.92, 1e-7);
    CHECK_NEAR(srgb_to_linear(10.0f / 255.0f), 0.0030353, 1e-6);
    CHECK_NEAR(linear_to_srgb(0.5f), 0.7353570, 1e-5);
    CHECK_NEAR(linear_to_srgb(0.0031308f), 0.04045, 1e-5);
    CHECK_NEAR(linear_to_srgb(0.2140411f), 0.5, 1e-5);
    /* Out of range and NaN saturate. */
    CHECK(srgb_to_linear(-1.0f) == 0.0f && srgb_to_linear(2.0f) == 1.0f);
    CHECK(linear_to_srgb(NAN) == 0.0f && linear_to_srgb(7.0f) == 1.0f);
}

TEST(srgb_round_trip_all_bytes)
{
    float prev = -1.0f;
    for (int i = 0; i < 256; i++) {
        float lin = srgb_to_linear((float)i / 255.0f);
        CHECK(lin > prev); /* strictly increasing */
        prev = lin;
        int back = (int)(linear_to_srgb(lin) * 255.0f + 0.5f);
        CHECK(back == i);
    }
}

static void check_sizes(int w, int h, int levels, const int *ws, const int *hs)
{
    image_rgba8 im = make_image(w, h, 0);
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    CHECK(c.level_count == levels);
    for (int l = 0; l < levels && l < c.level_count; l++) {
        CHECK(c.width[l] == ws[l]);
        CHECK(c.height[l] == hs[l]);
    }
    for (int l = c.level_count; l < MIP_MAX_LEVELS; l++)
        CHECK(c.rgba[l] == NULL);
    mip_chain_free(&c);
    free(im.rgba);
}

TEST(level_sizes)
{
    const int p[] = {256, 128, 64, 32, 16, 8, 4, 2, 1};
    check_sizes(256, 256, 9, p, p);
    const int w1008[] = {1008, 504, 252, 126, 63, 31, 15, 7, 3, 1};
    const int h981[] = {981, 490, 245, 122, 61, 30, 15, 7, 3, 1};
    check_sizes(1008, 981, 10, w1008, h981);
    const int one[] = {1, 1, 1}, seven[] = {7, 3, 1};
    check_sizes(1, 7, 3, one, seven);
    const int three[] = {3, 1};
    check_sizes(3, 3, 2, three, three);
    const int single[] = {1};
    check_sizes(1, 1, 1, single, single);
    const int w2[] = {2, 1, 1}, h5[] = {5, 2, 1}; /* the narrow side stops at 1 */
    check_sizes(2, 5, 3, w2, h5);
}

TEST(mean_alpha_and_colour_preserved)
{
    const int sizes[][2] = {{256, 256}, {1008, 981}, {1, 7}, {3, 3}, {5, 3}, {37, 1}, {100, 63}, {17, 129}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (int mode = 0; mode < 2; mode++) {
            image_rgba8 im = make_image(sizes[s][0], sizes[s][1], mode);
            mip_chain c;
            CHECK(mip_chain_build(&im, &c) == FS_OK);
            double a0 = mip_level_mean_alpha(&c, 0);
            /* Level 0 is the image itself. */
            double direct = 0.0;
            for (size_t i = 0; i < (size_t)im.width * im.height; i++)
                direct += im.rgba[4 * i + 3] / 255.0;
            CHECK_NEAR(a0, direct / ((double)im.width * im.height), 1e-7);
            double r0 = 0.0;
            for (size_t i = 0; i < (size_t)im.width * im.height; i++)
                r0 += c.rgba[0][4 * i];
            r0 /= (double)im.width * im.height;
            for (int l = 1; l < c.level_count; l++) {
                double al = mip_level_mean_alpha(&c, l);
                CHECK(fabs(al - a0) <= 1e-5 * a0);
                double rl = 0.0;
                size_t n = (size_t)c.width[l] * c.height[l];
                for (size_t i = 0; i < n; i++)
                    rl += c.rgba[l][4 * i];
                rl /= (double)n;
                CHECK(fabs(rl - r0) <= 1e-5 * r0);
            }
            CHECK(c.width[c.level_count - 1] == 1 && c.height[c.level_count - 1] == 1);
            mip_chain_free(&c);
            free(im.rgba);
        }
}

TEST(opaque_stays_opaque)
{
    const int sizes[][2] = {{64, 64}, {1008, 981}, {3, 3}, {1, 7}, {5, 2}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        image_rgba8 im = make_image(sizes[s][0], sizes[s][1], 0);
        for (size_t i = 0; i < (size_t)im.width * im.height; i++)
            im.rgba[4 * i + 3] = 255;
        mip_chain c;
        CHECK(mip_chain_build(&im, &c) == FS_OK);
        for (int l = 0; l < c.level_count; l++) {
            size_t n = (size_t)c.width[l] * c.height[l];
            float lo = 2.0f, hi = -1.0f;
            for (size_t i = 0; i < n; i++) {
                float a = c.rgba[l][4 * i + 3];
                lo = fminf(lo, a);
                hi = fmaxf(hi, a);
            }
            CHECK(lo >= 1.0f - 1e-6f && hi <= 1.0f + 1e-6f);
        }
        mip_chain_free(&c);
        free(im.rgba);
    }
}

TEST(premultiplied_no_colour_bleed)
{
    uint8_t px[8] = {255, 0, 0, 255, /* opaque red */ 0, 255, 0, 0 /* transparent green */};
    image_rgba8 im = {.width = 2, .height = 1, .rgba = px};
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    CHECK(c.level_count == 2);
    /* Level 0: the transparent texel's green is gone after premultiplication. */
    CHECK_NEAR(c.rgba[0][4 + 1], 0.0, 0.0);
    const float *t = c.rgba[1];
    CHECK_NEAR(t[0], 0.5 * srgb_to_linear(1.0f), 1e-6);
    CHECK_NEAR(t[1], 0.0, 0.0);
    CHECK_NEAR(t[2], 0.0, 0.0);
    CHECK_NEAR(t[3], 0.5, 1e-6);
    mip_chain_free(&c);
    /* A half-transparent mid-grey texel: colour is decoded from sRGB before the multiply. */
    uint8_t g[4] = {128, 128, 128, 51};
    image_rgba8 gi = {.width = 1, .height = 1, .rgba = g};
    CHECK(mip_chain_build(&gi, &c) == FS_OK);
    CHECK_NEAR(c.rgba[0][0], srgb_to_linear(128.0f / 255.0f) * 0.2, 1e-6);
    CHECK_NEAR(c.rgba[0][3], 0.2, 1e-6);
    mip_chain_free(&c);
}

TEST(exact_area_weights_odd_size)
{
    /* 3x1 alpha (0, 255, 0) -> 1x1: every source texel weighs 1/3. 5x1 -> 2x1: destination 0
     * covers texels 0, 1 and half of 2. */
    uint8_t a3[12] = {0, 0, 0, 0, 0, 0, 0, 255, 0, 0, 0, 0};
    image_rgba8 im = {.width = 3, .height = 1, .rgba = a3};
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    CHECK_NEAR(c.rgba[1][3], 1.0 / 3.0, 1e-6);
    mip_chain_free(&c);
    uint8_t a5[20] = {0};
    a5[4 * 2 + 3] = 255; /* the middle texel, shared by both destinations */
    a5[4 * 0 + 3] = 255;
    image_rgba8 im5 = {.width = 5, .height = 1, .rgba = a5};
    CHECK(mip_chain_build(&im5, &c) == FS_OK);
    CHECK(c.width[1] == 2);
    CHECK_NEAR(c.rgba[1][3], (1.0 + 0.5) / 2.5, 1e-6);
    CHECK_NEAR(c.rgba[1][4 + 3], 0.5 / 2.5, 1e-6);
    mip_chain_free(&c);
}

TEST(empty_chain_free_is_noop)
{
    mip_chain c;
    memset(&c, 0, sizeof c);
    mip_chain_free(&c);
    mip_chain_free(NULL);
    CHECK(mip_level_mean_alpha(&c, 0) == 0.0);
}

TEST(build_speed_2048)
{
    image_rgba8 im = make_image(2048, 2048, 1);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double s = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    printf("mip: 2048x2048 chain (%d levels) built in %.3f s\n", c.level_count, s);
    CHECK(c.level_count == 12);
    /* Generous: the -O2 build takes ~0.1 s; sanitizer builds are several times slower. */
    CHECK(s < 5.0);
    mip_chain_free(&c);
    free(im.rgba);
}

/* docs/design.md "Ground truth and metrics": Leaves.png has mean alpha 0.44; with its glTF cutoff 0.2
 * a traditional test keeps 0.44 of texels at mip 0 and everything at mip 10 (bloat). */
TEST(megakit_leaves_coverage_bloats)
{
    const char *path = test_shared_path("assets/quaternius_megakit_set_a/Leaves.png");
    int w = 0, h = 0, comp = 0;
    uint8_t *px = stbi_load(path, &w, &h, &comp, 4);
    CHECK(px != NULL);
    if (!px) {
        fprintf(stderr, "cannot load %s (set FOVSIM_SHARED)\n", path);
        return;
    }
    image_rgba8 im = {.width = w, .height = h, .rgba = px};
    mip_chain c;
    CHECK(mip_chain_build(&im, &c) == FS_OK);
    CHECK(c.level_count == 12);
    double a0 = mip_level_mean_alpha(&c, 0);
    CHECK_NEAR(a0, 0.44, 0.01);
    double pass[MIP_MAX_LEVELS];
    printf("Leaves.png %dx%d mean alpha %.4f; share with alpha >= 0.2 per level:", w, h, a0);
    for (int l = 0; l < c.level_count; l++) {
        pass[l] = level_pass_fraction(&c, l, 0.2f);
        CHECK(fabs(mip_level_mean_alpha(&c, l) - a0) <= 1e-5 * a0);
        printf(" %d:%.3f", l, pass[l]);
    }
    printf("\n");
    CHECK_NEAR(pass[0], 0.44, 0.02);
    CHECK(pass[10] >= 0.999);
    CHECK(pass[10] / pass[0] > 2.0);
    /* Coverage only grows once the filter starts mixing leaves and gaps. */
    for (int l = 3; l < c.level_count; l++)
        CHECK(pass[l] >= pass[l - 1] - 0.01);
    mip_chain_free(&c);
    stbi_image_free(px);
}

/* The generated fence (mean alpha ~0.13 < cutoff 0.5) erodes to nothing at coarse mips. */
TEST(fence_coverage_erodes)
{
    asset a;
    CHECK(gen_fence(&(gen_fence_desc){0}, &a) == FS_OK);
    if (a.image_count < 1)
        return;
    const image_rgba8 *im = &a.images[0];
    size_t n = (size_t)im->width * im->height, transparent = 0;
    for (size_t i = 0; i < n; i++)
        transparent += im->rgba[4 * i + 3] == 0;
    double tf = (double)transparent / (double)n;
    mip_chain c;
    CHECK(mip_chain_build(im, &c) == FS_OK);
    double a0 = mip_level_mean_alpha(&c, 0);
    double pass[MIP_MAX_LEVELS];
    printf("fence wire %dx%d transparent %.4f mean alpha %.4f; share with alpha >= 0.5 per level:",
           im->width, im->height, tf, a0);
    for (int l = 0; l < c.level_count; l++) {
        pass[l] = level_pass_fraction(&c, l, 0.5f);
        printf(" %d:%.3f", l, pass[l]);
    }
    printf("\n");
    CHECK(a0 < 0.25);
    /* Mip 0 keeps about the non-transparent share (minus the soft edges below 0.5). */
    CHECK(pass[0] <= 1.0 - tf + 1e-9);
    CHECK(pass[0] >= 0.6 * (1.0 - tf));
    /* ...and the coarse mips keep nothing: the fence vanishes with distance. */
    CHECK(pass[c.level_count - 1] == 0.0);
    CHECK(pass[c.level_count - 2] == 0.0);
    CHECK(pass[3] < 0.5 * pass[0]);
    mip_chain_free(&c);
    asset_free(&a);
}

int main(void)
{
    log_set_quiet_errors(false);
    RUN(srgb_known_values);
    RUN(srgb_round_trip_all_bytes);
    RUN(level_sizes);
    RUN(mean_alpha_and_colour_preserved);
    RUN(opaque_stays_opaque);
    RUN(premultiplied_no_colour_bleed);
    RUN(exact_area_weights_odd_size);
    RUN(empty_chain_free_is_noop);
    RUN(build_speed_2048);
    RUN(megakit_leaves_coverage_bloats);
    RUN(fence_coverage_erodes);
    return test_summary();
}
