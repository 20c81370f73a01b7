/* image_diff (metrics/image_diff.h): the squared differences and the block guard that fovsim check
 * and the golden test compare images with. */
#include "metrics/image_diff.h"

#include "test.h"

#define W 8
#define H 6

TEST(identical_images_differ_by_nothing)
{
    float a[W * H];
    for (int i = 0; i < W * H; i++)
        a[i] = (float)i / 7.0f;
    image_diff d = {0};
    image_diff_add(&d, a, a, W, H, 2, NULL, 0);
    CHECK(d.count == W * H);
    CHECK(image_diff_rmse(&d) == 0.0 && d.max_block == 0.0);
}

TEST(one_flipped_pixel_counts_a_quarter_in_a_2x2_block)
{
    float a[W * H] = {0}, b[W * H] = {0};
    b[3 * W + 5] = 1.0f; /* pixel (5, 3): block (4..5, 2..3) */
    image_diff d = {0};
    image_diff_add(&d, b, a, W, H, 2, NULL, 0);
    CHECK_NEAR(d.max_block, 0.25, 1e-12);
    CHECK_NEAR(image_diff_rmse(&d), sqrt(1.0 / (W * H)), 1e-12);
    /* Per pixel (bs 1) it is the full difference; a whole block changed counts fully. */
    image_diff p = {0};
    image_diff_add(&p, b, a, W, H, 1, NULL, 0);
    CHECK_NEAR(p.max_block, 1.0, 1e-12);
    b[2 * W + 4] = b[2 * W + 5] = b[3 * W + 4] = 1.0f;
    image_diff q = {0};
    image_diff_add(&q, b, a, W, H, 2, NULL, 0);
    CHECK_NEAR(q.max_block, 1.0, 1e-12);
}

TEST(opposite_differences_in_a_block_cancel)
{
    /* The guard looks at block means: a feature that moved by one pixel inside its block is a
     * rounding, not a change of shape. */
    float a[W * H] = {0}, b[W * H] = {0};
    a[0] = 1.0f;
    b[1] = 1.0f;
    image_diff d = {0};
    image_diff_add(&d, b, a, W, H, 2, NULL, 0);
    CHECK(d.max_block == 0.0);
    CHECK_NEAR(image_diff_rmse(&d), sqrt(2.0 / (W * H)), 1e-12);
}

TEST(regions_select_pixels_and_blocks)
{
    /* Left half region 0, right half region 1; a difference only on the right. */
    float a[W * H] = {0}, b[W * H] = {0};
    int region[W * H];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            region[y * W + x] = x >= W / 2;
    for (int y = 0; y < 4; y++)
        for (int x = 4; x < 8; x++)
            b[y * W + x] = 0.5f;
    image_diff r0 = {0}, r1 = {0};
    image_diff_add(&r0, b, a, W, H, 4, region, 0);
    image_diff_add(&r1, b, a, W, H, 4, region, 1);
    CHECK(r0.count == W * H / 2 && r1.count == W * H / 2);
    CHECK(image_diff_rmse(&r0) == 0.0 && r0.max_block == 0.0);
    CHECK_NEAR(r1.max_block, 0.5, 1e-12); /* the 4x4 block (4..7, 0..3) */
    CHECK_NEAR(image_diff_rmse(&r1), sqrt(16 * 0.25 / (W * H / 2)), 1e-12);
}

TEST(edge_blocks_and_non_finite_values)
{
    /* 5 x 3 with 2 x 2 blocks: the last column and row are blocks of the pixels they have. */
    float a[15] = {0}, b[15] = {0};
    b[14] = 1.0f; /* (4, 2): a block of one pixel */
    image_diff d = {0};
    image_diff_add(&d, b, a, 5, 3, 2, NULL, 0);
    CHECK_NEAR(d.max_block, 1.0, 1e-12);
    /* NaN counts as the largest half: never as "no difference". */
    b[14] = NAN;
    image_diff n = {0};
    image_diff_add(&n, b, a, 5, 3, 2, NULL, 0);
    CHECK(isfinite(image_diff_rmse(&n)) && n.max_block == 65504.0);
    image_diff none = {0};
    CHECK(image_diff_rmse(&none) == 0.0);
}

int main(void)
{
    RUN(identical_images_differ_by_nothing);
    RUN(one_flipped_pixel_counts_a_quarter_in_a_2x2_block);
    RUN(opposite_differences_in_a_block_cancel);
    RUN(regions_select_pixels_and_blocks);
    RUN(edge_blocks_and_non_finite_values);
    return test_summary();
}
