/* alpha_hash.h: hashed and stochastic alpha-test thresholds (Wyman & McGuire 2017, seed 000 §4-6),
 * the C twin of shaders/common/alpha_hash.glsl.
 *
 * Every function here has a GLSL function of the same name and the same float operations in the
 * same order, so the GPU twin test (tests/gpu/test_alpha_twin.c) can compare them input by input.
 * Constants (hash kinds, defaults, clamps) come from common/shared_defs.h, shared with the GLSL.
 * docs/hashed-alpha.md explains the choices (hash, anisotropy, NaN and overflow handling).
 *
 *   alpha_hash_sine / alpha_hash_pcg      vec3 -> [0, 1): the paper's nested sine hash; pcg3d on
 *                                         the floored coordinates (ALPHA_HASH_SINE / _PCG)
 *   alpha_hashed_threshold                seed 000 Listing 1: pixel-scale, log2-interpolated,
 *                                         CDF-corrected threshold in (0, 1]
 *   alpha_hashed_fade                     seed 000 §5.5.1 fade-in around the material cutoff
 *   alpha_texture_lod                     the LOD of a texture footprint (trilinear)
 *   alpha_lod_clamp                       the level the alpha test reads under --alpha-lod-max
 *   alpha_stochastic_threshold            seed 000 §4: uniform in (0, 1], new per pixel and frame
 *   alpha_hashed_a2c_threshold / _mask    seed 000 §6: per-sample thresholds of hashed A2C
 *
 * Usage (what the forward shader does per fragment):
 *   float t = alpha_hashed_threshold(obj, dFdx(obj), dFdy(obj), 1.0f, ALPHA_HASH_PCG, false);
 *   t = alpha_hashed_fade(cutoff, t, lod, ALPHA_FADE_N_DEFAULT);
 *   pass = alpha >= t;
 *
 * Guarantees: every threshold is finite and in [ALPHA_THRESHOLD_MIN, 1] for every input, NaN and
 * infinities included, so alpha = 1 always passes and alpha = 0 never does.
 *
 * What it does NOT do: sample textures, compute derivatives (the caller passes dFdx/dFdy of the
 * object-space position), or decide which strategy a material uses (plan.c).
 */
#ifndef FOVSIM_ALPHA_HASH_H
#define FOVSIM_ALPHA_HASH_H

#include <stdbool.h>
#include <stdint.h>

#include "core/fmath.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct alpha_uvec3 {
    uint32_t x, y, z;
} alpha_uvec3;

/* pcg3d of Jarzynski & Olano 2020 ("Hash Functions for GPU Rendering", JCGT 9(3)).
 * GLSL twin: uvec3 alpha_hash_pcg3d(uvec3). */
alpha_uvec3 alpha_hash_pcg3d(alpha_uvec3 v);

/* Seed 000 §5.1: hash2(v) = fract(1e4 sin(17 v.x + 0.1 v.y) (0.1 + |sin(13 v.y + v.x)|)),
 * hash3(p) = hash2(hash2(p.xy), p.z). Result in [0, 1) (NaN -> 0). GLSL twin: alpha_hash_sine. */
float alpha_hash_sine(vec3 p);

/* The 2D hash inside alpha_hash_sine (McGuire's hash2 above), in [0, 1). GLSL twin: alpha_hash_sine2. */
float alpha_hash_sine2(float x, float y);

/* pcg3d of floor(p), each axis converted to int32 (non-finite -> 0, clamped to the int32 range,
 * -0 -> 0), output ((x ^ y ^ z) >> 8) * 2^-24 in [0, 1). GLSL twin: alpha_hash_pcg. */
float alpha_hash_pcg(vec3 p);

/* ALPHA_HASH_SINE -> alpha_hash_sine, anything else -> alpha_hash_pcg. GLSL twin: alpha_hash_kind. */
float alpha_hash_kind(vec3 p, int hash_kind);

/* The hashes of one layer's lattice (docs/hashed-alpha.md, "Layers"): alpha_hash_pcg with `layer`
 * XORed into the x key (a bijection of the lattice, so each layer stays uniform; GLSL twin:
 * alpha_hash_pcg_cell), alpha_hash_sine with the inner 2D hash rotated by the layer's top 24 bits,
 * fract(hash2(p.xy) + (layer >> 8) 2^-24) (GLSL twin: alpha_hash_sine_layer), and the choice
 * between them (GLSL twin: alpha_hash_kind_layer). Layer 0 gives the hashes above exactly. */
float alpha_hash_pcg_layer(vec3 p, uint32_t layer);
float alpha_hash_sine_layer(vec3 p, uint32_t layer);
float alpha_hash_kind_layer(vec3 p, int hash_kind, uint32_t layer);

/* pcg's 32-bit RXS-M-XS step (Jarzynski & Olano 2020), a bijection of uint32. GLSL twin:
 * alpha_hash_pcg1. */
uint32_t alpha_hash_pcg1(uint32_t v);

/* The layer key of a fragment, pcg1(pcg1(instance) + primitive): `instance` a stable id of the
 * instance (its slot in the scene, not its place in the frame's draws), `primitive` the triangle's
 * index within the instance's asset. GLSL twin: alpha_hash_layer. */
uint32_t alpha_hash_layer(uint32_t instance, uint32_t primitive);

/* The key of noise level `level` of Listing 1 (the isotropic exponent floor(l) or ceil(l)),
 * (level + ALPHA_HASH_LEVEL_BIAS) * ALPHA_HASH_LEVEL_MUL mod 2^32: distinct and nonzero for every
 * level in [-60, 60]. alpha_hashed_threshold_layer XORs it into the layer key of each of its two
 * hashes, so the two levels hash different lattices and stay independent where their cells are the
 * same cell, within a pixel of the object origin (docs/hashed-alpha.md "Assets a pixel or two wide").
 * GLSL twin: alpha_hash_level_key. */
uint32_t alpha_hash_level_key(int level);

/* Seed 000 Eq. 1: maps x = (1 - f) u1 + f u2 (u1, u2 independent uniform in [0, 1)) back to a
 * uniform value, a = min(f, 1 - f). Only the needed branch is evaluated and its denominator is
 * kept >= FLT_MIN, so f = 0 or 1 (a = 0) and a within 1e-7 of 0 are finite. Result in [0, 1].
 * GLSL twin: alpha_hash_cdf. */
float alpha_hash_cdf(float x, float lerp_factor);

/* log2(pixScale) of Listing 1, pixScale = 1 / (hash_scale * max(|dx|, |dy|)) with 3D lengths,
 * clamped to [-ALPHA_HASH_LOG2_CLAMP, +ALPHA_HASH_LOG2_CLAMP]. Zero derivatives give +60 (finest),
 * infinite ones -60; a NaN derivative vector counts as zero; hash_scale <= 0 or non-finite uses
 * ALPHA_HASH_SCALE_DEFAULT. GLSL twin: alpha_hash_log2_scale. */
float alpha_hash_log2_scale(vec3 dx, vec3 dy, float hash_scale);

/* Seed 000 Listing 1: the hashed threshold in [ALPHA_THRESHOLD_MIN, 1]. `obj` is the object-space
 * position (anchored to the whole instance), dx/dy its screen derivatives (dFdx/dFdy), hash_scale
 * the noise cell size in pixels (default 1), hash_kind ALPHA_HASH_*. `anisotropic` refines the
 * noise cells per object axis by a power of two (at most 2^ALPHA_MAX_ANISO_LOG2) where the footprint along
 * that axis is shorter than the longest one (docs/hashed-alpha.md). Non-finite obj components hash
 * as 0. Departing from the listing, each of the two levels hashes its own lattice
 * (alpha_hash_level_key), so the threshold stays uniform within a pixel of the object origin, where
 * the listing's two cells coincide. GLSL twin: alpha_hashed_threshold. */
float alpha_hashed_threshold(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic);

/* alpha_hashed_threshold with both hashes on the lattice of `layer` (alpha_hash_layer): surfaces
 * with different layer keys get independent thresholds even inside one noise cell; each layer's
 * thresholds are as uniform as the unlayered ones. Layer 0 is alpha_hashed_threshold, bit for bit.
 * Each of the two hashes uses `layer ^ alpha_hash_level_key(its level)`, for layer 0 too.
 * GLSL twin: alpha_hashed_threshold_layer. */
float alpha_hashed_threshold_layer(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic,
                                   uint32_t layer);

/* Seed 000 Eq. 2-3 with the material cutoff c in place of 0.5: c + (threshold - c) b(lod),
 * b(x) = clamp(x / fade_n, 0, 1)^2, where lod is the mip level the alpha lookup reads (mip bias
 * included, clamped at 0: alpha_texture_fade_level). There is no anisotropy term: the paper adds
 * log2(anisotropy) to x because an anisotropic filter reads finer levels than the footprint's long
 * axis, but fovsim's sampler is trilinear, whose level already follows the long axis
 * (docs/hashed-alpha.md "The fade and anisotropy"). fade_n <= 0 (or NaN) disables the fade:
 * returns the threshold. NaN lod -> b = 1 (full noise); NaN threshold -> the cutoff; cutoff clamped
 * to [ALPHA_THRESHOLD_MIN, 1] (NaN -> 0.5). Result in [ALPHA_THRESHOLD_MIN, 1].
 * GLSL twin: alpha_hashed_fade. */
float alpha_hashed_fade(float cutoff, float threshold, float lod, float fade_n);

/* Threshold t in (0, 1] shifted by frame * ALPHA_FRAME_OFFSET_STEP modulo 1, kept in (0, 1]: the
 * per-frame variation TAA averages (used only when TAA is on). A uniform t stays uniform.
 * GLSL twin: alpha_hashed_frame_offset in alpha_hash.glsl. */
float alpha_hashed_frame_offset(float t, uint32_t frame);

/* The LOD a trilinear lookup selects, log2(pmax), pmax = max(|duv_dx * size|, |duv_dy * size|)
 * (the GL spec's isotropic approximation: the footprint's long axis; not clamped to the mip range;
 * clamped to [-60, 60]). Zero or NaN derivatives -> 0. GLSL twin: alpha_texture_lod (the forward
 * shader itself uses textureQueryLod). */
float alpha_texture_lod(const float duv_dx[2], const float duv_dy[2], const float tex_size[2]);

/* The level a trilinear lookup with mip bias b reads, max(alpha_texture_lod + b, 0), as one log2:
 * 0.5 log2(max(pmax^2 4^b, 1)); mip_scale = 2^b. The x of alpha_hashed_fade, which the forward
 * shader's hashed test computes instead of calling textureQueryLod (docs/hashed-alpha.md "Cost").
 * NaN squared lengths count as 0 and squared lengths are kept <= 2^120: for a finite mip_scale the
 * result is in [0, 60] (zero derivatives give 0).
 * GLSL twin: alpha_texture_fade_level. */
float alpha_texture_fade_level(const float duv_dx[2], const float duv_dy[2], const float tex_size[2], float mip_scale);

/* The alpha LOD clamp (docs/hashed-alpha.md "Alpha LOD clamp"): the level the alpha test of a
 * clamped material reads, min(level, lod_max), where level is alpha_texture_fade_level's. lod_max
 * < 0 (ALPHA_LOD_OFF) or NaN: no clamp, level itself. The forward shader re-reads alpha at lod_max
 * only where the result is below level (textureLod), and the hashed fade and mip scaling take the
 * clamped level. GLSL twin: alpha_lod_clamp. */
float alpha_lod_clamp(float level, float lod_max);

/* Seed 000 §4: ((pcg3d(x, y, frame ^ salt) reduced to 24 bits) + 1) * 2^-24, uniform in (0, 1]
 * (0 impossible, 1 possible). GLSL twin: alpha_stochastic_threshold. */
float alpha_stochastic_threshold(uint32_t pixel_x, uint32_t pixel_y, uint32_t frame, uint32_t salt);

/* Seed 000 §6: threshold of sample i, (chi + ((a_o + i a_+) mod n)) / n with a_o = floor(n xi1),
 * a_+ = 2 floor(0.5 n xi2) + 1. n is rounded down to a power of two in [1, ALPHA_A2C_MAX_SAMPLES];
 * xi1, xi2 are clamped to [0, 1] (NaN -> 0), chi to [ALPHA_THRESHOLD_MIN, 1] (NaN -> 1).
 * GLSL twin: alpha_hashed_a2c_threshold. */
float alpha_hashed_a2c_threshold(int i, int n, float xi1, float xi2, float chi);

/* Bit i (i < n) set when alpha >= alpha_hashed_a2c_threshold(i, ...): alpha = 1 sets all n bits,
 * alpha = 0 none, alpha = k/n exactly k. GLSL twin: alpha_hashed_a2c_mask. */
uint32_t alpha_hashed_a2c_mask(float alpha, int n, float xi1, float xi2, float chi);

#ifdef __cplusplus
}
#endif

#endif
