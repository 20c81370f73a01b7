/* image_diff.h: how far one image is from another of the same size, per channel plane: the
 * squared differences (for an RMSE) and the largest difference of block means (the "max over
 * 2x2" guard), optionally over one region of the image (a foveation ring). Pure C.
 *
 * The block guard: a render that differs from its baseline only by rounding (llvmpipe against a
 * GPU driver, or two llvmpipe builds) flips a few alpha-tested pixels along edges, each a full
 * difference of up to 1 in one pixel. The largest per-pixel difference would call that a failure;
 * the largest difference of the means of bs x bs blocks counts a lone flipped pixel of a 2x2
 * block as 1/4, while a shape that moved or vanished (every pixel of a block changed) still counts
 * fully. In a ring drawn at 1/b resolution one ring texel covers b x b display pixels (bilinearly
 * upsampled), so the same guard there takes blocks of 2b x 2b display pixels: a flipped ring texel
 * then also counts at most 1/4 (the upsampled texel's weights sum to b^2 display pixels).
 * tests/gpu/test_golden.c and `fovsim check` (docs/check.md) use it.
 *
 * Blocks are aligned to multiples of bs from the top-left corner (ring footprints are aligned to
 * their block grid: fov_ring_rect); a block cut by the right or bottom edge is the mean of the
 * pixels it has.
 *
 * What it does NOT do: read files, weigh channels, or decide what is too far (callers do). */
#ifndef FOVSIM_IMAGE_DIFF_H
#define FOVSIM_IMAGE_DIFF_H

#ifdef __cplusplus
extern "C" {
#endif

typedef struct image_diff {
    double sq_sum;   /* sum over compared samples of (a - b)^2 */
    long count;      /* samples compared */
    double max_block; /* largest |mean(a) - mean(b)| over the blocks compared */
} image_diff;

/* Adds planes a and b (w x h floats, rows top first) to *d: every pixel whose region[i] == r to
 * the squared sums, and every bs x bs block holding at least one such pixel to max_block (the
 * block's mean over all its pixels, whatever their region). region NULL: the whole image (r is
 * ignored). Non-finite differences count as 65504 (the largest half, what an EXR would hold). */
void image_diff_add(image_diff *d, const float *a, const float *b, int w, int h, int bs, const int *region, int r);

/* sqrt(sq_sum / count); 0 when nothing was compared. */
double image_diff_rmse(const image_diff *d);

#ifdef __cplusplus
}
#endif

#endif
