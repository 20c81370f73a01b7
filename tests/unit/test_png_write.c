/* test_png_write.c: the sRGB PNG export (src/output/png_write.c) reproduces, bit for bit, the
 * FovVideoVDP and FLIP fixtures of ../shared/fixtures (made from the same half-float frames by
 * scripts/prep.py with numpy), and its quantisation's edge cases. */
#include <stdint.h>

#include "output/exr_write.h"
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
    RUN(reproduces_the_fixtures_bit_for_bit);
    RUN(unwritable_path_fails_cleanly);
    return test_summary();
}
