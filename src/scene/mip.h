/* mip.h: mip chains built with premultiplied alpha (CPU, no GL).
 *
 * An sRGB RGBA8 image becomes a chain of linear, premultiplied float RGBA levels: level 0 is the
 * image itself (colour decoded from sRGB, then multiplied by alpha), each further level is an
 * exact-area box filter of the previous one (odd and non-power-of-two sizes included), down to
 * 1x1. Filtering premultiplied colour keeps transparent texels' colour from bleeding into visible
 * ones (seed 000 §5.5.2, seed 001 "premultiplied alpha"); because the filter is area-exact, the mean
 * alpha of every level equals level 0's (to float rounding) — the property that makes traditional
 * alpha testing lose (or gain) coverage with distance.
 *
 * What it does NOT do: upload, coverage-preserving (Castano) chains (a later issue).
 */
#ifndef FOVSIM_MIP_H
#define FOVSIM_MIP_H

#include "core/status.h"
#include "scene/scene.h"

#define MIP_MAX_LEVELS 16

typedef struct mip_chain {
    int level_count;
    int width[MIP_MAX_LEVELS], height[MIP_MAX_LEVELS];
    float *rgba[MIP_MAX_LEVELS]; /* linear premultiplied RGBA, 4 floats per texel, rows top first */
} mip_chain;

/* sRGB-encoded value in [0,1] (an 8-bit value divided by 255) to linear [0,1] (IEC 61966-2-1);
 * clamps, NaN gives 0. */
float srgb_to_linear(float c);
float linear_to_srgb(float c);

/* Builds the full chain of `img`; FS_ERR_NOMEM on allocation failure (chain left empty). */
fs_status mip_chain_build(const image_rgba8 *img, mip_chain *out);
/* Frees the levels; no-op on a zeroed chain. */
void mip_chain_free(mip_chain *c);
/* Mean alpha of one level (for tests and `fovsim plan`). */
double mip_level_mean_alpha(const mip_chain *c, int level);

#endif
