/* test_annotate.c: the CPU drawing of the comparison grid's annotation (src/output/annotate.c)
 * and the grid itself (src/commands/compare_grid.c): labels stay inside their tile, a circle of
 * radius r lies at distance r from its centre, nothing is ever written outside the picture
 * (guard floats around every plane), NaN and huge coordinates draw nothing, the colour maps'
 * ends, and the grid's tiles, swatches and gaze marker. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "commands/compare_grid.h"
#include "output/annotate.h"
#include "test.h"

#define GUARD 64 /* floats before and after every plane */
#define SENTINEL -7.0f

typedef struct pic {
    float *mem[3], *p[3];
    int w, h;
} pic;

static pic pic_make(int w, int h)
{
    pic q = {.w = w, .h = h};
    size_t n = (size_t)w * (size_t)h + 2 * GUARD;
    for (int c = 0; c < 3; c++) {
        q.mem[c] = malloc(n * sizeof(float));
        for (size_t i = 0; i < n; i++)
            q.mem[c][i] = SENTINEL;
        q.p[c] = q.mem[c] + GUARD;
    }
    return q;
}

static void pic_free(pic *q)
{
    for (int c = 0; c < 3; c++)
        free(q->mem[c]);
}

static bool guards_intact(const pic *q)
{
    size_t n = (size_t)q->w * (size_t)q->h;
    for (int c = 0; c < 3; c++)
        for (size_t i = 0; i < GUARD; i++)
            if (q->mem[c][i] != SENTINEL || q->p[c][n + i] != SENTINEL)
                return false;
    return true;
}

static bool written(const pic *q, int x, int y)
{
    return q->p[0][(size_t)y * (size_t)q->w + (size_t)x] != SENTINEL;
}

static int count_written(const pic *q)
{
    int n = 0;
    for (int y = 0; y < q->h; y++)
        for (int x = 0; x < q->w; x++)
            n += written(q, x, y);
    return n;
}

static annot_canvas whole(pic *q)
{
    return annot_canvas_make(q->p[0], q->p[1], q->p[2], q->w, q->h, 0, 0, q->w, q->h);
}

static const float k_white[3] = {1, 1, 1};

TEST(a_label_lands_inside_its_tile)
{
    pic q = pic_make(120, 60);
    /* tile (1, 1) of 40 x 20 tiles; the text is longer than the tile is wide */
    annot_canvas c = annot_canvas_make(q.p[0], q.p[1], q.p[2], q.w, q.h, 40, 20, 40, 20);
    int w = annot_text(&c, 42.0f, 22.0f, 1, "traditional: coverage - reference", k_white);
    CHECK(w == annot_text_width("traditional: coverage - reference", 1) && w > 40);
    int inside = 0, outside = 0;
    for (int y = 0; y < q.h; y++)
        for (int x = 0; x < q.w; x++)
            if (written(&q, x, y))
                (x >= 40 && x < 80 && y >= 20 && y < 40) ? inside++ : outside++;
    CHECK(inside > 20 && outside == 0);
    /* the glyphs lie below and right of the text's corner, within the text's height */
    for (int y = 0; y < q.h; y++)
        for (int x = 0; x < q.w; x++)
            if (written(&q, x, y))
                CHECK(x >= 42 && y >= 22 && y < 22 + annot_text_height(1));
    CHECK(guards_intact(&q));
    pic_free(&q);
}

TEST(text_scales_by_whole_factors)
{
    CHECK(annot_text_width("hashed", 2) == 2 * annot_text_width("hashed", 1));
    CHECK(annot_text_height(3) == 3 * annot_text_height(1));
    CHECK(annot_text_width("", 1) == 0);
    pic a = pic_make(200, 40), b = pic_make(200, 40);
    annot_canvas ca = whole(&a), cb = whole(&b);
    annot_text(&ca, 0, 0, 1, "Ag", k_white);
    annot_text(&cb, 0, 0, 2, "Ag", k_white);
    CHECK(count_written(&b) == 4 * count_written(&a) && count_written(&a) > 0);
    pic_free(&a);
    pic_free(&b);
}

TEST(a_circle_of_radius_r_lies_at_distance_r)
{
    for (float r = 1.0f; r <= 20.0f; r += 1.5f) {
        pic q = pic_make(64, 64);
        annot_canvas c = whole(&q);
        float cx = 31.5f, cy = 32.5f; /* a pixel centre */
        annot_circle(&c, cx, cy, r, k_white);
        int n = 0;
        for (int y = 0; y < q.h; y++)
            for (int x = 0; x < q.w; x++)
                if (written(&q, x, y)) {
                    double d = hypot(x + 0.5 - cx, y + 0.5 - cy);
                    CHECK(fabs(d - r) <= 0.5 + 1e-9);
                    n++;
                }
        /* a closed outline: about 2 pi r pixels, and (whole r: they are pixel centres) the four
         * compass points */
        CHECK(n >= (int)(2 * 3.14159265 * r * 0.8) && n <= (int)(2 * 3.14159265 * r * 1.6) + 4);
        if (r == floorf(r))
            CHECK(written(&q, (int)floorf(cx + r), (int)floorf(cy)) && written(&q, (int)floorf(cx - r), (int)floorf(cy)));
        if (r == floorf(r))
            CHECK(written(&q, (int)floorf(cx), (int)floorf(cy + r)) && written(&q, (int)floorf(cx), (int)floorf(cy - r)));
        CHECK(guards_intact(&q));
        pic_free(&q);
    }
}

TEST(nothing_is_written_outside_the_picture)
{
    pic q = pic_make(37, 23);
    annot_canvas c = whole(&q);
    const char *texts[] = {"gaze", "coverage - reference", "\x01\x7f\xff odd bytes", ""};
    for (int t = 0; t < 4; t++)
        for (int y = -30; y <= 30; y += 3)
            for (int x = -200; x <= 60; x += 7) {
                annot_text(&c, (float)x, (float)y, 1 + (x & 1), texts[t], k_white);
                annot_circle(&c, (float)x, (float)y, 9.0f, k_white);
                annot_cross(&c, (float)x, (float)y, 4, k_white);
                annot_fill_rect(&c, (float)x, (float)y, (float)x + 50.0f, (float)y + 3.0f, k_white);
            }
    CHECK(guards_intact(&q));
    /* a canvas asked for beyond the planes is clipped to them */
    annot_canvas big = annot_canvas_make(q.p[0], q.p[1], q.p[2], q.w, q.h, -100, -100, INT_MAX, INT_MAX);
    CHECK(big.clip[0] == 0 && big.clip[1] == 0 && big.clip[2] == q.w && big.clip[3] == q.h);
    annot_fill_rect(&big, -1e9f, -1e9f, 1e9f, 1e9f, k_white);
    CHECK(count_written(&q) == q.w * q.h && guards_intact(&q));
    pic_free(&q);
}

TEST(nan_and_huge_coordinates_are_safe)
{
    pic q = pic_make(32, 32);
    annot_canvas c = whole(&q);
    float bad[] = {NAN, INFINITY, -INFINITY, 1e30f, -1e30f, 3e9f, -3e9f};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        float v = bad[i];
        annot_text(&c, v, 5.0f, 1, "x", k_white);
        annot_text(&c, 5.0f, v, 1, "x", k_white);
        annot_circle(&c, v, v, 5.0f, k_white);
        annot_circle(&c, 16.0f, 16.0f, fabsf(v), k_white); /* far beyond the picture, or NaN */
        annot_cross(&c, v, 16.0f, 3, k_white);
        annot_fill_rect(&c, v, v, v, v, k_white);
        annot_fill_rect(&c, 0.0f, 0.0f, v == v && v > 0 ? NAN : v, 4.0f, k_white);
        annot_fill_rect(&c, v, 0.0f, v, 32.0f, k_white);
    }
    annot_shade_rect(&c, 0, 0, 32, 32, NAN);
    CHECK(count_written(&q) == 0);
    unsigned char region[4] = {0, 1, 0, 1};
    annot_region_borders(&c, INT_MAX, INT_MIN, region, 2, 2, k_white, k_white);
    annot_region_borders(&c, INT_MIN, INT_MAX, region, 2, 2, k_white, k_white);
    annot_region_borders(&c, 0, 0, NULL, 2, 2, k_white, k_white);
    CHECK(count_written(&q) == 0 && guards_intact(&q));
    /* a rectangle from -huge to +huge fills what it covers, no more */
    annot_fill_rect(&c, -INFINITY, 10.0f, INFINITY, 11.0f, k_white);
    CHECK(count_written(&q) == 32 && guards_intact(&q));
    pic_free(&q);
}

TEST(region_borders_follow_the_map)
{
    enum { W = 20, H = 10 };
    unsigned char region[W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            region[y * W + x] = x < 12 ? 0 : 1;
    pic q = pic_make(40, 20);
    /* only the tile at (20, 10) may be written; the map placed there */
    annot_canvas c = annot_canvas_make(q.p[0], q.p[1], q.p[2], q.w, q.h, 20, 10, W, H);
    static const float a[3] = {1, 1, 0}, b[3] = {0, 0, 0};
    annot_region_borders(&c, 20, 10, region, W, H, a, b);
    for (int y = 0; y < q.h; y++)
        for (int x = 0; x < q.w; x++)
            CHECK(written(&q, x, y) == (x == 20 + 11 && y >= 10));
    /* dashes: both colours appear along the border */
    int yellow = 0, black = 0;
    for (int y = 10; y < 20; y++) {
        float g = q.p[1][(size_t)y * 40 + 31];
        yellow += g == 1.0f;
        black += g == 0.0f;
    }
    CHECK(yellow > 0 && black > 0 && yellow + black == H);
    CHECK(guards_intact(&q));
    pic_free(&q);
}

TEST(colour_maps)
{
    float rgb[3], lo[3], hi[3], mid[3];
    annot_hex_colour(0xffffff, rgb);
    CHECK(rgb[0] == 1.0f && rgb[1] == 1.0f && rgb[2] == 1.0f);
    annot_hex_colour(0x000000, rgb);
    CHECK(rgb[0] == 0.0f && rgb[1] == 0.0f && rgb[2] == 0.0f);
    annot_hex_colour(0x80ff00, rgb); /* sRGB 128/255 is linear 0.2158 */
    CHECK_NEAR(rgb[0], 0.2158f, 1e-3f);
    CHECK(rgb[1] == 1.0f && rgb[2] == 0.0f);
    annot_diverging(0.0f, mid);
    CHECK(mid[0] == 1.0f && mid[1] == 1.0f && mid[2] == 1.0f);
    annot_diverging(NAN, rgb);
    CHECK(rgb[0] == 1.0f && rgb[1] == 1.0f && rgb[2] == 1.0f);
    annot_diverging(-1.0f, lo);
    annot_diverging(1.0f, hi);
    CHECK(lo[2] > lo[0] && lo[2] > 0.3f && hi[0] > hi[2] && hi[0] > 0.3f); /* blue lost, red extra */
    annot_diverging(-5.0f, rgb);
    CHECK(rgb[0] == lo[0] && rgb[2] == lo[2]);
    annot_diverging(-0.5f, rgb); /* between white and the end */
    CHECK(rgb[0] < 1.0f && rgb[0] > lo[0]);
}

TEST(the_legend_fills_its_cell_and_shows_both_ends)
{
    pic q = pic_make(200, 100);
    annot_canvas c = annot_canvas_make(q.p[0], q.p[1], q.p[2], q.w, q.h, 100, 50, 100, 50);
    annot_diverging_legend(&c, 1, "coverage - reference", "-1 lost", "+1 extra");
    for (int y = 0; y < q.h; y++)
        for (int x = 0; x < q.w; x++)
            CHECK(written(&q, x, y) == (x >= 100 && y >= 50));
    /* the bar across the middle row: blue at its left end, red at its right */
    size_t row = (size_t)75 * 200;
    CHECK(q.p[2][row + 112] > q.p[0][row + 112] && q.p[0][row + 188] > q.p[2][row + 188]);
    CHECK(guards_intact(&q));
    pic_free(&q);
}

/* >>the grid */

static void plane_fill(exr_image *img, const char *ch, float v)
{
    float *p = exr_image_add_channel(img, ch);
    for (int i = 0; i < img->width * img->height; i++)
        p[i] = v;
}

static float grid_at(const exr_image *g, const char *ch, int x, int y)
{
    return exr_image_channel(g, ch)[(size_t)y * (size_t)g->width + (size_t)x];
}

TEST(the_grid_tiles_swatches_and_gaze)
{
    enum { W = 160, H = 90 };
    exr_image a, b, ref;
    CHECK(exr_image_init(&a, W, H) && exr_image_init(&b, W, H) && exr_image_init(&ref, W, H));
    const char *ch[4] = {"R", "G", "B", "coverage"};
    for (int c = 0; c < 4; c++) {
        plane_fill(&a, ch[c], c == 3 ? 1.0f : 0.25f); /* extra coverage */
        plane_fill(&b, ch[c], c == 3 ? 0.0f : 0.5f);  /* lost coverage */
        plane_fill(&ref, ch[c], c == 3 ? 0.5f : 0.125f);
    }
    float *flip = calloc((size_t)W * H, sizeof *flip);
    unsigned char *rings = calloc((size_t)W * H, 1);
    for (int i = 0; i < W * H; i++)
        rings[i] = i % W >= 100;
    alpha_mode modes[2] = {ALPHA_MODE_HASHED, ALPHA_MODE_TRADITIONAL};
    const exr_image *images[2] = {&a, &b};
    const float *flips[2] = {flip, flip};
    compare_grid_desc d = {.mode_count = 2, .modes = modes, .images = images, .flip = flips, .ref = &ref,
                           .rings = rings, .gaze_px = {40.3f, 60.7f}, .annotate = false};
    exr_image off, on;
    CHECK(compare_grid_build(&d, &off) == FS_OK);
    d.annotate = true;
    CHECK(compare_grid_build(&d, &on) == FS_OK);
    CHECK(off.width == 3 * W && off.height == COMPARE_GRID_ROWS * H && !strcmp(off.part_name, "compare"));
    /* clean grid: tiles as they are; the coverage row red where a mode adds, blue where it loses */
    CHECK(grid_at(&off, "R", 5, 5) == 0.25f && grid_at(&off, "G", W + 5, 5) == 0.5f && grid_at(&off, "A", 7, 7) == 1.0f);
    CHECK(grid_at(&off, "G", 2 * W + 5, H + 5) == 0.5f); /* reference coverage, grey */
    float red[3], blue[3];
    annot_diverging(0.5f, red);
    annot_diverging(-0.5f, blue);
    CHECK(grid_at(&off, "R", 5, 2 * H + 5) == red[0] && grid_at(&off, "B", W + 5, 2 * H + 5) == blue[2]);
    CHECK(grid_at(&off, "R", 2 * W + 80, 2 * H + 45) == 0.0f); /* no legend */
    /* annotated: the swatch of each mode's colour at (2..10, 2..10) of its tiles, the gaze marker's
     * centre magenta in every tile, a ring border at column 99 */
    for (int m = 0; m < 2; m++) {
        char hex[8];
        float want[3];
        annot_hex_colour((unsigned)strtoul(alpha_mode_colour(modes[m], hex) + 1, NULL, 16), want);
        for (int row = 0; row < COMPARE_GRID_ROWS; row++) {
            CHECK(grid_at(&on, "R", m * W + 5, row * H + 5) == want[0]);
            CHECK(grid_at(&on, "G", m * W + 5, row * H + 5) == want[1]);
            CHECK(grid_at(&on, "B", m * W + 5, row * H + 5) == want[2]);
        }
    }
    for (int col = 0; col < 3; col++) {
        int x = col * W + 40, y = 60;
        CHECK(grid_at(&on, "R", x, y) == 1.0f && grid_at(&on, "G", x, y) == 0.0f && grid_at(&on, "B", x, y) == 1.0f);
        CHECK(grid_at(&off, "G", x, y) != 0.0f);
    }
    CHECK(grid_at(&on, "R", 99, 30) != grid_at(&off, "R", 99, 30) && grid_at(&on, "R", 98, 30) == 0.25f);
    CHECK(grid_at(&on, "R", 2 * W + 80, 2 * H + 45) != 0.0f); /* the legend's bar */
    char desc[512];
    compare_grid_describe(&d, desc, sizeof desc);
    CHECK(strstr(desc, "3 columns x 3 rows of 160x90 tiles; row 0: hashed | traditional | reference") != NULL);
    /* a missing channel is refused, *out zeroed */
    exr_image_free(&off);
    exr_image bad;
    CHECK(exr_image_init(&bad, W, H));
    images[1] = &bad;
    CHECK(compare_grid_build(&d, &off) == FS_ERR_USAGE && off.planes[0] == NULL);
    exr_image_free(&bad);
    exr_image_free(&on);
    exr_image_free(&a);
    exr_image_free(&b);
    exr_image_free(&ref);
    free(flip);
    free(rings);
}

int main(void)
{
    RUN(a_label_lands_inside_its_tile);
    RUN(text_scales_by_whole_factors);
    RUN(a_circle_of_radius_r_lies_at_distance_r);
    RUN(nothing_is_written_outside_the_picture);
    RUN(nan_and_huge_coordinates_are_safe);
    RUN(region_borders_follow_the_map);
    RUN(colour_maps);
    RUN(the_legend_fills_its_cell_and_shows_both_ends);
    RUN(the_grid_tiles_swatches_and_gaze);
    return test_summary();
}
