/* test_png_write.c: the sRGB PNG export (src/output/png_write.c) reproduces, bit for bit, the
 * FovVideoVDP and FLIP fixtures of ../shared/fixtures (made from the same half-float frames by
 * scripts/prep.py with numpy), and its quantisation's edge cases. */
#include <float.h>
#include <stdint.h>

#include "output/exr_write.h"
#include "output/grid_video.h"
#include "output/png_write.h"
#include "stb_png.h"
#include "test.h"

TEST(quantisation_edges)
{
    CHECK(png_srgb_quantise(0.0f, 16) == 0 && png_srgb_quantise(-1.0f, 16) == 0 && png_srgb_quantise(NAN, 16) == 0);
    CHECK(png_srgb_quantise(1.0f, 16) == 65535 && png_srgb_quantise(7.0f, 16) == 65535);
    CHECK(png_srgb_quantise(1.0f, 8) == 255);
    /* The linear segment: 12.92 * 0.001 * 65535 = 846.7 -> 847. */
    CHECK(png_srgb_quantise(0.001f, 16) == 847);
    /* Mid-grey: linear 0.214041 is sRGB 0.5 (to 6 digits): 32767.5 rounds to an even 32768 or
     * its neighbour; either way within one step of the middle. */
    uint16_t q = png_srgb_quantise(0.2140411f, 16);
    CHECK(q == 32767 || q == 32768);
}

/* The video's rgb24 conversion (grid_video_to_rgb24, without libm calls) gives the bytes of the
 * plain formula it replaced, on every edge: ties of the 65536 levels, 0 and 1 and their
 * neighbours, negatives, NaN, infinities, huge values and a dense sweep of [-0.01, 1.01]. */
static uint8_t plain_rgb24(float l, const uint8_t *lut)
{
    l = isfinite(l) ? fminf(fmaxf(l, 0.0f), 1.0f) : 0.0f;
    return lut[(int)lrintf(l * (GRID_VIDEO_LUT - 1))];
}

TEST(video_rgb24_matches_plain_formula)
{
    static uint8_t lut[GRID_VIDEO_LUT];
    for (int i = 0; i < GRID_VIDEO_LUT; i++) /* a LUT whose bytes tell neighbouring levels apart */
        lut[i] = (uint8_t)(i * 7 + i / 256);
    enum { N = 600000 };
    float *v = malloc(sizeof(float) * N);
    unsigned char *out = malloc(3 * N);
    CHECK(v && out);
    if (!v || !out)
        return;
    size_t n = 0;
    const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, 2.0f, NAN, -NAN, INFINITY, -INFINITY, FLT_MAX, -FLT_MAX,
                             FLT_MIN, 1e-30f, nextafterf(1.0f, 0.0f), nextafterf(1.0f, 2.0f), nextafterf(0.0f, 1.0f)};
    for (size_t i = 0; i < sizeof special / sizeof special[0]; i++)
        v[n++] = special[i];
    for (int k = 0; k < 65535 && n + 3 < N; k += 7) { /* k + 1/2 of a level, and its neighbours */
        float t = ((float)k + 0.5f) / 65535.0f;
        v[n++] = t;
        v[n++] = nextafterf(t, 0.0f);
        v[n++] = nextafterf(t, 1.0f);
    }
    for (int i = 0; n < N; i++)
        v[n++] = -0.01f + 1.02f * (float)i / (float)(N / 2);
    float *pl[3] = {v, v + N / 3, v + 2 * (N / 3)};
    grid_video_to_rgb24((const float *const *)pl, N / 3, lut, out);
    int bad = 0;
    for (size_t i = 0; i < N / 3; i++)
        for (int c = 0; c < 3; c++)
            bad += out[3 * i + (size_t)c] != plain_rgb24(pl[c][i], lut);
    CHECK(bad == 0);
    /* Not vacuous: the sweep reaches many levels. */
    CHECK(plain_rgb24(0.25f, lut) != plain_rgb24(0.75f, lut));
    free(v);
    free(out);
}

/* Frame 6 of the fixtures: the linear half-float frame through png_write_srgb, read back with
 * stb_image, against the fixture's PNG of the same frame. */
static void same_as_fixture(const char *name, int bits)
{
    char path[512], out[1400];
    snprintf(path, sizeof path, "fixtures/sequences/forest_256x144_12f/linear_frame6/%s.0006.linear.exr", name);
    exr_image img;
    CHECK(exr_read_file(test_shared_path(path), &img) == FS_OK);
    const float *rgb[3] = {exr_image_channel(&img, "R"), exr_image_channel(&img, "G"), exr_image_channel(&img, "B")};
    CHECK(rgb[0] && rgb[1] && rgb[2]);
    snprintf(out, sizeof out, "%s/%s.%d.png", test_out_dir(), name, bits);
    CHECK(png_write_srgb(out, img.width, img.height, rgb, bits) == FS_OK);
    if (bits == 16)
        snprintf(path, sizeof path, "fixtures/sequences/forest_256x144_12f/%s/%s.0006.png", name, name);
    else
        snprintf(path, sizeof path, "fixtures/flip/inputs/%s.0006.srgb8.png", name);
    int w, h, c, w2, h2, c2;
    void *want = bits == 16 ? (void *)stbi_load_16(test_shared_path(path), &w, &h, &c, 3)
                            : (void *)stbi_load(test_shared_path(path), &w, &h, &c, 3);
    void *got = bits == 16 ? (void *)stbi_load_16(out, &w2, &h2, &c2, 3) : (void *)stbi_load(out, &w2, &h2, &c2, 3);
    CHECK(want && got && w == img.width && h == img.height && w2 == w && h2 == h && c2 == 3);
    if (want && got && w2 == w && h2 == h) {
        size_t n = (size_t)w * (size_t)h * 3 * (size_t)(bits / 8);
        size_t differ = 0;
        for (size_t i = 0; i < n; i++)
            differ += ((unsigned char *)want)[i] != ((unsigned char *)got)[i];
        if (differ)
            fprintf(stderr, "%s, %d bit: %zu bytes differ\n", name, bits, differ);
        CHECK(differ == 0);
    }
    stbi_image_free(want);
    stbi_image_free(got);
    exr_image_free(&img);
}

TEST(reproduces_the_fixtures_bit_for_bit)
{
    static const char *const names[] = {"reference", "traditional", "hashed"};
    for (int i = 0; i < 3; i++) {
        same_as_fixture(names[i], 16);
        same_as_fixture(names[i], 8);
    }
}

TEST(unwritable_path_fails_cleanly)
{
    float px[3] = {0.5f, 0.5f, 0.5f};
    const float *rgb[3] = {&px[0], &px[1], &px[2]};
    CHECK(png_write_srgb("/nonexistent-dir/x.png", 1, 1, rgb, 16) == FS_ERR_IO);
}

int main(void)
{
    RUN(quantisation_edges);
    RUN(video_rgb24_matches_plain_formula);
    RUN(reproduces_the_fixtures_bit_for_bit);
    RUN(unwritable_path_fails_cleanly);
    return test_summary();
}
