/* taa_math.h: the math of temporal antialiasing (docs/design.md "Temporal antialiasing"), the C twin of
 * shaders/common/taa.glsl.
 *
 * Every function has a GLSL function of the same name and the same float operations in the same
 * order (no FMA on either side: C11 does not contract, the GLSL marks its results `precise`), so
 * tests/gpu/test_taa_twin.c can compare them input by input. Constants (TAA_*) come from
 * common/shared_defs.h, shared with the GLSL.
 *
 *   taa_halton / taa_jitter         Halton(2,3) sub-pixel jitter, offsets in (-0.5, 0.5) ring pixels
 *   taa_rgb_to_ycocg / _to_rgb      the colour space of the neighbourhood clip
 *   taa_clip_to_box                 variance clipping (Salvi 2016, Karis 2014): AABB clip of the
 *                                   history towards the neighbourhood mean
 *   taa_sparse_coverage             the history coverage that this frame's samples cannot refute
 *   taa_history_surface_here        disocclusion: does the history's nearest surface still lie on
 *                                   this pixel
 *   taa_neighbourhood               the clip box's statistics from the 3x3 or cross taps
 *   taa_catmull_rom_weights         4-tap cubic weights of one axis, for the history fetch
 *   taa_catmull_rom_taps            the 5 bilinear taps of the Catmull-Rom history fetch
 *   taa_history_sum                 the history from its fetched taps (Catmull-Rom or bilinear)
 *   taa_resolve / 4 / 1             exponential blend of history and current sample (RGB, RGBA, one
 *                                   channel)
 *   taa_sanitize / _color / 4       NaN -> 0, +-Inf -> +-TAA_MAX_VALUE (colours also clamped >= 0)
 *   taa_reproject                   current NDC + depth -> previous frame's NDC
 *   taa_reproject_moving            the same for a point with its own world-space motion
 *
 * Usage, per ring pixel (what the resolve shader does):
 *   taa_reproject(ndc, inv_vp_jittered, prev_vp, &prev, &valid);      // -> history uv
 *   vec3 c = taa_rgb_to_ycocg(taa_sanitize_color(current));
 *   vec3 h = taa_rgb_to_ycocg(taa_sanitize_color(history_catmull_rom));
 *   valid = valid && taa_history_surface_here(hist_ndc, motion, prev_inv_vp, vp, here, size, depth,
 *                                             TAA_PARALLAX_PX, &keep, offset); // keep -> history depth
 *   float m;
 *   history_coverage = taa_sparse_coverage(history_coverage, cur_cov, cov_min, cov_max, TAA_SPARSE_SLACK, &m);
 *   h = taa_clip_to_box(h, mean, sigma, TAA_GAMMA_DEFAULT, TAA_SPARSE_COLOR * m); // YCoCg
 *   out = taa_resolve(current, taa_ycocg_to_rgb(h), valid && inside, TAA_BLEND_DEFAULT);
 *
 * Guarantees: taa_sanitize, taa_sanitize_color, taa_clip_to_box, taa_catmull_rom_weights and
 * taa_resolve return finite values for every input (NaN and infinities included), so NaN/Inf never
 * enters history. taa_reproject returns finite NDC with valid = false where it cannot reproject.
 *
 * What it does NOT do: fetch textures, compute the neighbourhood statistics, choose the fallback
 * ring after a saccade, or detect camera cuts (the TAA pass does).
 */
#ifndef FOVSIM_TAA_MATH_H
#define FOVSIM_TAA_MATH_H

#include <stdbool.h>
#include <stdint.h>

#include "core/fmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Radical inverse of index in base (>= 2; other bases -> 0), in [0, 1): the digits of index
 * mirrored about the radix point, computed exactly in integers and truncated to TAA_HALTON_BITS
 * fraction bits (so the GPU gives the same bits). Digits beyond base^k > 2^31 / base are dropped
 * (they are below 2^-29). GLSL twin: float taa_halton(uint, uint). */
float taa_halton(uint32_t index, uint32_t base);

/* Jitter of a frame: i = frame % length + 1 (index 0 is skipped), out = (halton(i, 2) - 0.5,
 * halton(i, 3) - 0.5) in (-0.5, 0.5) pixels of the ring. length 0 -> TAA_JITTER_LENGTH_DEFAULT,
 * clamped to TAA_JITTER_LENGTH_MAX. Exact. GLSL twin: vec2 taa_jitter(uint, uint). */
void taa_jitter(uint32_t frame, uint32_t length, float out[2]);

/* Y = R/4 + G/2 + B/4, Co = R/2 - B/2, Cg = -R/4 + G/2 - B/4, and its inverse (R = Y - Cg + Co,
 * G = Y + Cg, B = Y - Cg - Co): inverse up to float rounding. GLSL twins: same names. */
vec3 taa_rgb_to_ycocg(vec3 rgb);
vec3 taa_ycocg_to_rgb(vec3 ycocg);

/* NaN -> 0, then clamped to [-TAA_MAX_VALUE, TAA_MAX_VALUE] (+Inf -> 65504, -Inf -> -65504; finite
 * values beyond the half-float range would turn into Inf in the RGBA16F history). Denormals pass
 * through (GPUs may flush them to 0). GLSL twin: taa_sanitize. */
float taa_sanitize(float v);
/* taa_sanitize per channel, then clamped to [0, TAA_MAX_VALUE]. GLSL twin: taa_sanitize_color. */
vec3 taa_sanitize_color(vec3 c);

/* taa_sanitize_color for RGBA (alpha / coverage included). GLSL twin: vec4 taa_sanitize4(vec4). */
void taa_sanitize4(const float c[4], float out[4]);

/* Variance clipping in YCoCg. Box = mean +- (gamma * |sigma| + margin) (inputs sanitized; gamma NaN
 * -> TAA_GAMMA_DEFAULT, negative -> 0; margin NaN or negative -> 0). History inside the box is returned unchanged; outside, it moves
 * along the segment to the mean until it meets the box: mean + (history - mean) * t, t = min over
 * the axes where |d| > extent of extent / |d|. A zero extent on such an axis gives t = 0: the mean.
 * GLSL twin: taa_clip_to_box. */
vec3 taa_clip_to_box(vec3 history, vec3 mean, vec3 sigma, float gamma, float margin);

/* Sparse coverage (docs/taa.md, "Sparse coverage"). A pixel's coverage sample is one binary draw of
 * its expected coverage (an alpha test of a surface thinner than the pixel, or a jittered edge), and
 * its neighbours' samples are draws of other expectations: nothing this frame can refute a history
 * coverage h except the pixel's own sample, and that only where P(sample | h) < alpha, i.e. a miss
 * under h > 1 - alpha or a hit under h < alpha. So the history's coverage is clamped to the union of
 * the neighbourhood's range [cov_min, cov_max] (what the usual clip allows) and [current - slack,
 * current + slack], slack = 1 - alpha (clamped to [0, 1], NaN -> 0; default TAA_SPARSE_SLACK, alpha
 * = 0.05). Returns the clamped coverage; *margin = how far it lies outside [cov_min, cov_max], by
 * which the caller widens the alpha range and, times TAA_SPARSE_COLOR, the colour box. slack 0 is
 * the plain clamp (margin 0). Inputs through taa_sanitize (so the results are finite); NaN history
 * or current count as cov_min, NaN range ends as 0 and 1.
 * GLSL twin: taa_sparse_coverage. */
float taa_sparse_coverage(float history_coverage, float current, float cov_min, float cov_max, float slack,
                          float *margin);

/* Catmull-Rom weights of the taps at -1, 0, 1, 2 for a sample at frac in [0, 1] (clamped, NaN -> 0)
 * past tap 0. They sum to 1 (up to rounding) and reproduce linear functions.
 * GLSL twin: vec4 taa_catmull_rom_weights(float). */
void taa_catmull_rom_weights(float frac, float w[4]);

/* Variance-clipping box of the current frame's neighbourhood: YCoCg mean and standard deviation,
 * range (min, max) of alpha and of coverage. GLSL twin: struct taa_box. */
typedef struct taa_box {
    vec3 mean, sigma;
    float alpha[2], coverage[2];
} taa_box;

/* Statistics of the first n taps (n clamped to [1, TAA_MAX_TAPS]; taps[0] is the centre; RGBA and
 * coverage). mean = sum(Y) / n, sigma = sqrt(max(sum(Y^2) / n - mean^2, 0)) per YCoCg axis.
 * per_tap: every tap goes through taa_sanitize4 / taa_sanitize first, so a NaN tap counts as 0
 * and the others still count (today's resolve). Otherwise the taps are used raw and checked once:
 * where the sum of every Y, alpha, coverage and squared Y, Co, Cg is not finite (a tap held NaN or
 * Inf, or values so large their squares overflow; the current frame is half float, so real taps
 * cannot) the box says nothing: mean 0, sigma and both ranges open to +-TAA_MAX_VALUE, and the
 * history passes unclipped (it is sanitized on its own). Either way every field is finite. GLSL
 * twin: taa_neighbourhood. */
taa_box taa_neighbourhood(const float taps[][4], const float cov[], int n, bool per_tap);

/* The 5 bilinear taps of the Catmull-Rom history fetch at position p (ring pixels, sanitized) of a
 * footprint of size ring pixels: taps[k] = {x, y, weight}, positions clamped to the rendered
 * texels' centres [0.5, size - 0.5]. The 4x4 kernel's inner 2x2 taps are merged into one bilinear
 * fetch per row and column, the four corner taps (tiny weights) dropped (Jimenez's approximation):
 * top, left, centre, right, bottom. GLSL twin: taa_catmull_rom_taps. */
void taa_catmull_rom_taps(float px, float py, float size_x, float size_y, float taps[5][3]);

/* History from the first n (clamped to [1, 5]) fetched taps with weights w: sum(w * tap) /
 * sum(w), through taa_sanitize4, so finite and in [0, TAA_MAX_VALUE] for any input (Catmull-Rom
 * undershoots below 0 at sharp edges). per_tap: each tap through taa_sanitize4 first (a NaN tap
 * counts as 0); otherwise only the result is sanitized (a NaN in a tap makes that channel of the
 * fetch 0, which the clip then pulls into the box). GLSL twin: taa_history_sum. */
void taa_history_sum(const float taps[][4], const float w[], int n, bool per_tap, float out[4]);

/* Exponential blend: history + (current - history) * blend, both colours through
 * taa_sanitize_color first; blend NaN -> TAA_BLEND_DEFAULT, clamped to [0, 1]. history_valid false
 * -> the sanitized current. GLSL twin: taa_resolve. */
vec3 taa_resolve(vec3 current, vec3 history, bool history_valid, float blend);

/* taa_resolve for RGBA through taa_sanitize4. GLSL twin: vec4 taa_resolve4(vec4, vec4, bool, float). */
void taa_resolve4(const float current[4], const float history[4], bool history_valid, float blend, float out[4]);
/* taa_resolve of one channel (coverage). GLSL twin: float taa_resolve(float, float, bool, float). */
float taa_resolve1(float current, float history, bool history_valid, float blend);

/* Reprojection of a current-frame point (ndc.xy in [-1, 1], ndc.z = depth in [-1, 1]) through
 * inv_view_proj_jittered (the inverse of the matrix the frame was rendered with) and
 * prev_view_proj (the previous frame's, with or without its jitter as the caller wants) into the
 * previous frame's NDC (*out: x, y, depth). *valid is true when the previous clip w is > 0, the
 * homogeneous world point has a w of the same sign, and everything is finite. Where invalid, *out
 * is taa_sanitize of ndc. The world point is kept homogeneous (prev * (inv * ndc)): one division.
 * GLSL twin: bool taa_reproject(vec3, mat4, mat4, out vec3 prev_ndc) (returns valid; an overload
 * with out vec2 gives xy only). */
void taa_reproject(vec3 ndc, const mat4 *inv_view_proj_jittered, const mat4 *prev_view_proj, vec3 *out, bool *valid);
/* taa_reproject of a point that itself moved: `motion` is where it was last frame minus where it
 * is now, in world units (a swaying leaf's per-object motion). The motion, through sanitize3
 * (NaN -> 0, clamped to +-TAA_MAX_VALUE), is added to the homogeneous world point as
 * motion * w, so there is still one division. Zero motion gives taa_reproject's result wherever
 * the world point's w is finite. GLSL twin: bool taa_reproject_moving(vec3, vec3, mat4, mat4,
 * out vec3 prev_ndc) (and an out vec2 overload). */
void taa_reproject_moving(vec3 ndc, vec3 motion, const mat4 *inv_view_proj_jittered, const mat4 *prev_view_proj,
                          vec3 *out, bool *valid);

/* Disocclusion (docs/taa.md, "Sparse coverage and disocclusion"): is the history fetched for a pixel
 * still of the surfaces that lie on it? The history records, per pixel, the window depth of the
 * nearest surface it holds. hist_ndc is that surface in the previous frame's NDC of this ring (xy
 * where the history was fetched, z its depth as NDC). It is carried into this frame through
 * prev_inv_view_proj and view_proj (unjittered), moved by -motion (the pixel's own per-object
 * motion, last frame - now), with taa_reproject_moving. True when it lands within max_px ring pixels
 * (Chebyshev distance, for a footprint of size_x x size_y ring pixels) of (here_x, here_y), the
 * pixel's centre in this frame's NDC. *keep = what the history records for the pixel now: the
 * nearer of the pixel's own sample (depth_cur through taa_sanitize, clamped to [0, 1]) and the
 * carried surface (its window depth, clamped to [0, 1]); the sample alone where the result is
 * false. offset[] = where the surface landed minus the pixel's centre, in ring pixels, through
 * taa_sanitize ((0, 0) where it cannot be carried: behind either camera, not finite): the resolve
 * looks for the history whose surface lands here at the fetch position minus it. A still camera
 * and no motion land every surface on its own pixel. GLSL twin: taa_history_surface_here. */
bool taa_history_surface_here(vec3 hist_ndc, vec3 motion, const mat4 *prev_inv_view_proj, const mat4 *view_proj,
                              float here_x, float here_y, float size_x, float size_y, float depth_cur, float max_px,
                              float *keep, float offset[2]);

#ifdef __cplusplus
}
#endif

#endif
