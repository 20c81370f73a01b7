// alpha_hash.glsl: hashed and stochastic alpha-test thresholds (Wyman & McGuire 2017, seed 000
// §4-6). C twin: src/passes/alpha_hash.c (declared in src/passes/alpha_hash.h, which documents each
// function); both take their constants from common/shared_defs.h and evaluate the same float
// operations in the same order. `precise` stops the compiler from fusing multiply-adds the C side
// does not fuse. NaN and infinity tests look at the bit pattern, because compilers may assume that
// comparisons never see NaN. tests/gpu/test_alpha_twin.c checks this file against the C twin;
// docs/hashed-alpha.md explains the choices.
#ifndef FOVSIM_ALPHA_HASH_GLSL
#define FOVSIM_ALPHA_HASH_GLSL

#include "common/shared_defs.h"

// >>helpers

// C twin: is_finite_bits.
bool alpha_hash_is_finite(float x)
{
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

// C twin: is_nan_bits.
bool alpha_hash_is_nan(float x)
{
    return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u;
}

// C twin: nan_to_zero.
float alpha_hash_nan_to_zero(float x)
{
    return alpha_hash_is_nan(x) ? 0.0 : x;
}

// C twin: clamp_nan (clamp, NaN -> nan_value).
float alpha_hash_clamp(float x, float lo, float hi, float nan_value)
{
    if (alpha_hash_is_nan(x))
        return nan_value;
    return x < lo ? lo : (x > hi ? hi : x);
}

// C twin: unit_interval ([0, 1), the largest float below 1 is 0x3f7fffff).
float alpha_hash_unit(float h)
{
    return alpha_hash_clamp(h, 0.0, uintBitsToFloat(0x3f7fffffu), 0.0);
}

// C twin: pow2i. 2^e for |e| <= 126 from the exponent bits: exactly ldexp(1.0, e), in two integer
// operations (llvmpipe lowers ldexp to about ten: clamps and two multiplies for denormal results).
float alpha_hash_pow2(int e)
{
    return uintBitsToFloat(uint(e + 127) << 23);
}

// C twin: fractf.
float alpha_hash_fract(float x)
{
    precise float f = x - floor(x);
    return f;
}

// C twin: dot3 (the squared length, summed left to right, no fused multiply-add).
float alpha_hash_dot(vec3 v)
{
    precise float d = v.x * v.x + v.y * v.y + v.z * v.z;
    return d;
}

// C twin: max_deriv2 (maxDeriv^2 of Listing 1 with 3D lengths; a NaN vector counts as zero length).
float alpha_hash_max_deriv2(vec3 dx, vec3 dy)
{
    return max(alpha_hash_nan_to_zero(alpha_hash_dot(dx)), alpha_hash_nan_to_zero(alpha_hash_dot(dy)));
}

// >>hashes

// C twin: alpha_hash_pcg3d (Jarzynski & Olano 2020).
uvec3 alpha_hash_pcg3d(uvec3 v)
{
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v ^= v >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

// C twin: alpha_hash_sine2 (seed 000 §5.1, McGuire's 2D hash).
float alpha_hash_sine2(vec2 v)
{
    precise float s1 = sin(17.0 * v.x + 0.1 * v.y);
    precise float s2 = sin(13.0 * v.y + v.x);
    precise float h = 1.0e4 * s1 * (0.1 + abs(s2));
    return alpha_hash_unit(alpha_hash_fract(h));
}

// C twin: alpha_hash_sine.
float alpha_hash_sine(vec3 p)
{
    return alpha_hash_sine2(vec2(alpha_hash_sine2(p.xy), p.z));
}

// C twin: hash_key (non-finite or denormal -> 0, floor, clamp to the int32 range, bits as uint).
uint alpha_hash_key(float v)
{
    if (!alpha_hash_is_finite(v) || abs(v) < uintBitsToFloat(0x00800000u))
        v = 0.0;
    float q = floor(v);
    q = q < -2147483648.0 ? -2147483648.0 : (q > 2147483520.0 ? 2147483520.0 : q);
    return uint(int(q));
}

// C twin: alpha_hash_pcg.
float alpha_hash_pcg(vec3 p)
{
    uvec3 h = alpha_hash_pcg3d(uvec3(alpha_hash_key(p.x), alpha_hash_key(p.y), alpha_hash_key(p.z)));
    return float((h.x ^ h.y ^ h.z) >> 8u) * (1.0 / 16777216.0);
}

// C twin: alpha_hash_pcg_layer.
// pcg of lattice cells that are already finite integers (the floored cells of alpha_hashed_threshold): the same
// value as alpha_hash_pcg(c) (layer 0), without re-checking for NaN, Inf, denormals and re-flooring, which
// alpha_hash_key does for arbitrary inputs (cost on llvmpipe: ~6 % of the hashed forest's frame).
// `layer` (alpha_hash_layer; 0 = none) is XORed into the x key: a bijection of the lattice for
// each layer, so each layer's hashes stay uniform, and layers with different keys hash different
// lattice points.
float alpha_hash_pcg_cell(vec3 c, uint layer)
{
    vec3 q = clamp(c, vec3(-2147483648.0), vec3(2147483520.0));
    uvec3 h = alpha_hash_pcg3d(uvec3(ivec3(q)) ^ uvec3(layer, 0u, 0u));
    // < 2^24, so float(int) gives the same exact value as float(uint), in one instruction where
    // the CPU has no unsigned conversion (AVX2: llvmpipe spends about six).
    return float(int((h.x ^ h.y ^ h.z) >> 8u)) * (1.0 / 16777216.0);
}

// C twin: alpha_hash_sine_layer (alpha_hash_sine with the inner hash rotated by the layer's top
// 24 bits; layer 0 gives alpha_hash_sine exactly).
float alpha_hash_sine_layer(vec3 p, uint layer)
{
    precise float h = alpha_hash_sine2(p.xy) + float(layer >> 8u) * (1.0 / 16777216.0);
    return alpha_hash_sine2(vec2(alpha_hash_fract(h), p.z));
}

// C twin: alpha_hash_kind_layer (alpha_hash_kind of a layer's lattice; layer 0 = alpha_hash_kind).
float alpha_hash_kind_layer(vec3 p, int hash_kind, uint layer)
{
#ifdef ALPHA_HASH_KIND
    // The plan compiles one hash per variant: a runtime choice costs both hashes on SIMD
    // rasterisers that evaluate both sides of a branch (measured on llvmpipe: 1.61x -> 1.41x
    // traditional's frame time for the hashed forest).
#if ALPHA_HASH_KIND == ALPHA_HASH_SINE
    return alpha_hash_sine_layer(p, layer);
#else
    return alpha_hash_pcg_cell(p, layer);
#endif
#else
    if (hash_kind == ALPHA_HASH_SINE)
        return alpha_hash_sine_layer(p, layer);
    return alpha_hash_pcg_cell(p, layer);
#endif
}

float alpha_hash_kind(vec3 p, int hash_kind)
{
    return alpha_hash_kind_layer(p, hash_kind, 0u);
}

// C twin: alpha_hash_pcg1 (pcg's 32-bit RXS-M-XS output step, Jarzynski & Olano 2020): a bijection.
uint alpha_hash_pcg1(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// C twin: alpha_hash_layer. The layer key of a fragment: a stable id of its instance and of its
// triangle within the instance's asset, mixed to 32 bits. Overlapping surfaces whose object-space
// positions fall in the same noise cell (far away: several leaves of one plant, or instances
// sharing the asset's object space) get independent thresholds instead of one shared threshold,
// so k layers of opacity a cover 1 - (1 - a)^k, not a (docs/hashed-alpha.md, "Layers").
uint alpha_hash_layer(uint instance, uint primitive)
{
    return alpha_hash_pcg1(alpha_hash_pcg1(instance) + primitive);
}

// C twin: alpha_hash_level_key. The key of noise level `level` (the isotropic exponent floor(l) or
// ceil(l), in [-60, 60]), XORed into the layer key of each of Listing 1's two hashes: the levels hash
// different lattices, so the two cells stay independent where they are the same cell (within a
// pixel of the object origin; docs/hashed-alpha.md). Distinct and nonzero for every level.
uint alpha_hash_level_key(int level)
{
    return uint(level + ALPHA_HASH_LEVEL_BIAS) * ALPHA_HASH_LEVEL_MUL;
}

// >>threshold

// C twin: cdf_core (seed 000 Eq. 1, denominators >= FLT_MIN). Eq. 1 is symmetric,
// cdf(1 - x) = 1 - cdf(x): the lower half is evaluated at z = min(x, 1 - x) (exact for x in [0, 1])
// and mirrored, straight-line (two cases and two selects instead of three branches). For x and
// lerp_factor in [0, 1], which is all alpha_hashed_threshold passes, the result is in [0, 1]
// without a guard: z < a gives z^2 / (2a(1 - a)) <= a / (2(1 - a)) <= 0.5, otherwise
// (z - a/2) / (1 - a) is in [0, 0.5].
float alpha_hash_cdf_core(float x, float lerp_factor)
{
    precise float a = min(lerp_factor, 1.0 - lerp_factor);
    precise float z = min(x, 1.0 - x);
    precise float lo = z * z / max(2.0 * a * (1.0 - a), uintBitsToFloat(0x00800000u));
    precise float mid = (z - 0.5 * a) / (1.0 - a);
    precise float f = z < a ? lo : mid;
    precise float t = x < 0.5 ? f : 1.0 - f;
    return t;
}

// C twin: alpha_hash_cdf (Eq. 1 for any input: clamped to [0, 1], NaN -> 0.5).
float alpha_hash_cdf(float x, float lerp_factor)
{
    return alpha_hash_clamp(alpha_hash_cdf_core(x, lerp_factor), 0.0, 1.0, 0.5);
}

// C twin: alpha_hash_log2_scale (Listing 1's log2(pixScale), clamped; ends decided without log2).
// log2(1 / (hs * maxDeriv)) = -0.5 * log2(hs^2 * maxDeriv^2): one log2 of the squared lengths, no
// square root and no division. hs * (hs * m2) cannot be NaN (hs is finite and > 0, m2 >= 0 or inf).
float alpha_hash_log2_scale(vec3 dx, vec3 dy, float hash_scale)
{
    float hs = (alpha_hash_is_finite(hash_scale) && hash_scale > 0.0) ? hash_scale : float(ALPHA_HASH_SCALE_DEFAULT);
    precise float y2 = hs * (hs * alpha_hash_max_deriv2(dx, dy));
    const float lim = float(ALPHA_HASH_LOG2_CLAMP);
    precise float l = -0.5 * log2(y2);
    // pixScale >= 2^60 <=> y2 <= 2^-120, pixScale <= 2^-60 <=> y2 >= 2^120: log2's result is not
    // used there (GLSL leaves log2 of 0 and inf undefined).
    return y2 <= ldexp(1.0, -120) ? lim : (y2 >= ldexp(1.0, 120) ? -lim : clamp(l, -lim, lim));
}

// C twin: aniso_level (per-axis refinement, exact power-of-two comparisons).
int alpha_hash_aniso_level(float deriv_axis, float max_deriv)
{
    int e = 0;
    for (int j = 1; j <= ALPHA_MAX_ANISO_LOG2; j++)
        e += deriv_axis * ldexp(1.0, j) <= max_deriv ? 1 : 0;
    return e;
}

// C twin: hash_coord. An object coordinate as the cells see it: |o| in [2^-62, 2^63) unchanged,
// anything else (0, tinier, larger, NaN, inf) 0, by one unsigned test of the exponent bits. Every
// cell 2^level * o (level in [-60, 64]) is then finite and exact, and either 0 or normal (>= 2^-122,
// so a GPU that flushes denormals floors it like C does), without a guard per cell.
float alpha_hash_coord(float o)
{
    return (floatBitsToUint(o) & 0x7f800000u) - (65u << 23) < (125u << 23) ? o : 0.0;
}

// C twin: alpha_hashed_threshold_layer (seed 000 Listing 1, each hash on the lattice of `layer`
// (alpha_hash_layer) and of its level (alpha_hash_level_key); layer 0 = alpha_hashed_threshold).
float alpha_hashed_threshold_layer(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic,
                                   uint layer)
{
    float l = alpha_hash_log2_scale(dx, dy, hash_scale);
    float lo = floor(l), hi = ceil(l);
    precise float lerp_factor = l - lo; // fract(l)
    int ilo = int(lo), ihi = int(hi);
    ivec3 e = ivec3(0);
#ifdef ALPHA_HASH_ANISO
    // As for ALPHA_HASH_KIND: the plan compiles the anisotropic refinement in or out.
    anisotropic = ALPHA_HASH_ANISO != 0;
    if (ALPHA_HASH_ANISO != 0) {
#else
    if (anisotropic) {
#endif
        float m = sqrt(alpha_hash_max_deriv2(dx, dy)); // max of the lengths (sqrt is monotonic)
        vec3 adx = abs(dx), ady = abs(dy);
        e.x = alpha_hash_aniso_level(max(alpha_hash_nan_to_zero(adx.x), alpha_hash_nan_to_zero(ady.x)), m);
        e.y = alpha_hash_aniso_level(max(alpha_hash_nan_to_zero(adx.y), alpha_hash_nan_to_zero(ady.y)), m);
        e.z = alpha_hash_aniso_level(max(alpha_hash_nan_to_zero(adx.z), alpha_hash_nan_to_zero(ady.z)), m);
    }
    vec3 o = vec3(alpha_hash_coord(obj.x), alpha_hash_coord(obj.y), alpha_hash_coord(obj.z));
    vec3 c_lo = floor(vec3(alpha_hash_pow2(ilo + e.x), alpha_hash_pow2(ilo + e.y), alpha_hash_pow2(ilo + e.z)) * o);
    vec3 c_hi = floor(vec3(alpha_hash_pow2(ihi + e.x), alpha_hash_pow2(ihi + e.y), alpha_hash_pow2(ihi + e.z)) * o);
    // Each level on its own lattice (a departure from Listing 1): keyed by the level itself, not by
    // lo / hi, so a cell keeps its hash when l crosses an integer and it turns from hi into lo.
    float h_lo = alpha_hash_kind_layer(c_lo, hash_kind, layer ^ alpha_hash_level_key(ilo));
    float h_hi = alpha_hash_kind_layer(c_hi, hash_kind, layer ^ alpha_hash_level_key(ihi));
    precise float x = (1.0 - lerp_factor) * h_lo + lerp_factor * h_hi;
    // x and lerp_factor are in [0, 1] (hashes in [0, 1), l clamped and never NaN), so the CDF needs
    // no NaN guard here: the hard-case tests check the result for every input.
    float t = alpha_hash_cdf_core(x, lerp_factor);
    return clamp(t, float(ALPHA_THRESHOLD_MIN), 1.0);
}

// C twin: alpha_hashed_threshold (seed 000 Listing 1).
float alpha_hashed_threshold(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic)
{
    return alpha_hashed_threshold_layer(obj, dx, dy, hash_scale, hash_kind, anisotropic, 0u);
}

// >>fade

// C twin: alpha_hashed_fade (seed 000 Eq. 2-3 around the material cutoff, at the mip level the
// trilinear lookup reads; straight-line: b = clamp(lod / n, 0, 1)^2, NaN -> 1). No anisotropy term:
// the paper's log2(anisotropy) is for anisotropic filters, which read finer levels than a trilinear
// one (docs/hashed-alpha.md "The fade and anisotropy").
float alpha_hashed_fade(float cutoff, float threshold, float lod, float fade_n)
{
    const float tmin = float(ALPHA_THRESHOLD_MIN);
    float c = alpha_hash_clamp(cutoff, tmin, 1.0, 0.5);
    float t = alpha_hash_clamp(threshold, tmin, 1.0, c);
    if (alpha_hash_is_nan(fade_n) || fade_n <= 0.0)
        return t;
    precise float q = lod / fade_n;
    float qc = alpha_hash_clamp(q, 0.0, 1.0, 1.0);
    precise float b = qc * qc;
    // c and t are in [tmin, 1] and b in [0, 1], so f is never NaN: a plain clamp (rounding only).
    precise float f = c + (t - c) * b;
    return clamp(f, tmin, 1.0);
}

// C twin: alpha_texture_lod (the GL spec's isotropic LOD, log2 of the footprint's long axis; the
// forward shader uses textureQueryLod).
float alpha_texture_lod(vec2 duv_dx, vec2 duv_dy, vec2 tex_size)
{
    precise vec2 tx = duv_dx * tex_size, ty = duv_dy * tex_size;
    precise float px2 = tx.x * tx.x + tx.y * tx.y, py2 = ty.x * ty.x + ty.y * ty.y;
    float px = sqrt(px2), py = sqrt(py2);
    float lod = 0.0;
    if (!alpha_hash_is_nan(px) && !alpha_hash_is_nan(py)) {
        float pmax = max(px, py);
        if (pmax > 0.0) {
            const float lim = float(ALPHA_HASH_LOG2_CLAMP);
            lod = pmax >= ldexp(1.0, 60) ? lim : alpha_hash_clamp(log2(pmax), -lim, lim, 0.0);
        }
    }
    return lod;
}

// C twin: alpha_texture_fade_level. The level a trilinear lookup with bias b reads,
// max(log2(pmax) + b, 0) = 0.5 log2(max(pmax^2 4^b, 1)): one log2 of squared lengths and no
// textureQueryLod. mip_scale = 2^b. NaN squared lengths count as 0; v is kept <= 2^120, so the
// level is in [0, 60].
float alpha_texture_fade_level(vec2 duv_dx, vec2 duv_dy, vec2 tex_size, float mip_scale)
{
    precise vec2 tx = duv_dx * tex_size, ty = duv_dy * tex_size;
    precise float px2 = tx.x * tx.x + tx.y * tx.y, py2 = ty.x * ty.x + ty.y * ty.y;
    const float big = uintBitsToFloat(0x7b800000u); // 2^120
    float p2max = max(min(alpha_hash_nan_to_zero(px2), big), min(alpha_hash_nan_to_zero(py2), big));
    precise float s2 = mip_scale * mip_scale;
    precise float v = max(p2max * s2, 1.0);
    precise float level = 0.5 * log2(min(v, big));
    return level;
}

// C twin: alpha_lod_clamp. The level the alpha test reads under a clamp lod_max: min(level,
// lod_max); lod_max < 0 or NaN: no clamp (level).
float alpha_lod_clamp(float level, float lod_max)
{
    return (lod_max >= 0.0 && level > lod_max) ? lod_max : level;
}

// >>stochastic

// C twin: alpha_stochastic_threshold (seed 000 §4), uniform in (0, 1].
float alpha_stochastic_threshold(uint pixel_x, uint pixel_y, uint frame, uint salt)
{
    uvec3 h = alpha_hash_pcg3d(uvec3(pixel_x, pixel_y, frame ^ salt));
    return float(((h.x ^ h.y ^ h.z) >> 8u) + 1u) * (1.0 / 16777216.0);
}

// >>a2c

// C twin: a2c_n (n rounded down to a power of two in [1, ALPHA_A2C_MAX_SAMPLES]).
int alpha_hash_a2c_n(int n)
{
    int p = 1;
    while (p * 2 <= n && p * 2 <= ALPHA_A2C_MAX_SAMPLES)
        p *= 2;
    return p;
}

// C twin: alpha_hashed_a2c_threshold (seed 000 §6).
float alpha_hashed_a2c_threshold(int i, int n, float xi1, float xi2, float chi)
{
    int nn = alpha_hash_a2c_n(n);
    float fn = float(nn);
    float x1 = alpha_hash_clamp(xi1, 0.0, 1.0, 0.0), x2 = alpha_hash_clamp(xi2, 0.0, 1.0, 0.0);
    float c = alpha_hash_clamp(chi, float(ALPHA_THRESHOLD_MIN), 1.0, 1.0);
    uint a_o = uint(int(floor(fn * x1)));
    uint a_plus = 2u * uint(int(floor(0.5 * fn * x2))) + 1u;
    uint k = (a_o + uint(i) * a_plus) & uint(nn - 1);
    return (c + float(k)) / fn;
}

// C twin: alpha_hashed_a2c_mask.
uint alpha_hashed_a2c_mask(float alpha, int n, float xi1, float xi2, float chi)
{
    int nn = alpha_hash_a2c_n(n);
    uint m = 0u;
    for (int i = 0; i < nn; i++)
        if (alpha >= alpha_hashed_a2c_threshold(i, nn, xi1, xi2, chi))
            m |= 1u << uint(i);
    return m;
}

// C twin: alpha_hashed_frame_offset in src/passes/alpha_hash.c (same steps).
float alpha_hashed_frame_offset(float t, uint frame)
{
    float k = float(frame & 0xffffu);
    precise float off = k * float(ALPHA_FRAME_OFFSET_STEP);
    off = off - floor(off);
    precise float u = t + off;
    u = u - floor(u);
    return u > 0.0 ? u : 1.0;
}

#endif
