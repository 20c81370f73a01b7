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
 * mip_chain_build_castano builds the same chain and then rescales the alpha of every level l >= 1
 * so that a traditional test (alpha >= cutoff) passes the same share of texels as at level 0
 * (Castano's coverage-preserving mipmaps, seed 001; docs/design.md "Alpha-test strategies", castano).
 *
 * What it does NOT do: upload (passes/renderer_upload.c).
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
    /* Factor the alpha of each level was multiplied by (before clamping to 1): 1 for level 0, for
     * every level of a mip_chain_build chain, and for levels beyond level_count. */
    float alpha_scale[MIP_MAX_LEVELS];
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

/* Coverage-preserving chain (Castano). Builds mip_chain_build's chain; c0 = share of level-0
 * texels with alpha >= cutoff. For every level l >= 1 a scale s_l is found by exact bisection
 * (over the float bit patterns of s, counting texels on a sorted copy of the level's alpha), such
 * that the count of texels with min(1, alpha*s_l) >= cutoff is the achievable count closest to
 * c0 * texels (ties of equal alpha may make the exact count unreachable; a level with one texel
 * passes or fails as a whole). Among the scales giving that count it takes 1 if it is one of them
 * (the level is left untouched), else the one halfway (in threshold cutoff/s) between the two
 * alphas that bracket the boundary, else (one-sided range) the end nearest 1 moved inwards by a
 * factor 1 +- 2^-10, so the RGBA16 upload's rounding cannot flip the boundary texel (for cutoffs
 * above 1/128).
 * Alpha becomes min(1, alpha*s_l) and the premultiplied colour is scaled by the factor alpha
 * actually changed by (and clamped to [0, alpha]), so colour/alpha is unchanged where alpha > 0.
 * alpha_scale[l] records s_l.
 * Scales stay 1 when: c0 is 0 (nothing to preserve: a level may not pass more than level 0);
 * c0 is 1 and the level already passes everywhere (an all-opaque image; only float rounding of
 * the average below a cutoff of 1 could need a scale, and then it restores full cover); cutoff
 * <= 0 (every texel passes everywhere) or > 1 (none does); a level whose alpha is all 0 (no scale
 * helps: it stays 0; through this API only an all-transparent image has one). A NaN cutoff is
 * rejected: FS_ERR_SCENE, logged, chain left empty (zeroed) — a NaN here is a bad material.
 * A 2048x2048 image builds in about 0.05 s at -O2 (one radix sort per level, no rescans).
 * FS_ERR_NOMEM on allocation failure (chain left empty). */
fs_status mip_chain_build_castano(const image_rgba8 *img, float cutoff, mip_chain *out);
/* Share of the texels of a level with alpha >= cutoff (the traditional test); 0 for a bad level
 * or a NaN cutoff. */
double mip_level_coverage(const mip_chain *c, int level, float cutoff);
/* The first mip level l >= 1 at which the traditional test's coverage (alpha >= cutoff) departs
 * from level 0's by more than `tolerance` (relative to level 0's, at least 1/texels of level l);
 * level_count when it never does. Used to fade hashed noise in before the traditional test
 * erodes a texture (docs/hashed-alpha.md, "Fade-in"). */
int mip_coverage_drift_level(const mip_chain *c, float cutoff, double tolerance);

#endif
