/* alpha_hash.c: C twin of shaders/common/alpha_hash.glsl (see alpha_hash.h).
 *
 * Every function mirrors its GLSL namesake operation by operation, in float, in the same order
 * (no double, no FMA: C11 without -ffp-contract=fast does not contract). NaN and infinity tests use
 * the bit pattern (as the GLSL does with floatBitsToUint), because GLSL compilers may assume that
 * comparisons never see NaN and rewrite `!(x > 0)` to `x <= 0`.
 */
#include "passes/alpha_hash.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "common/shared_defs.h"

/* >>helpers */

static uint32_t float_bits(float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* GLSL twin: alpha_hash_is_finite (exponent bits not all ones). */
static bool is_finite_bits(float x)
{
    return (float_bits(x) & 0x7f800000u) != 0x7f800000u;
}

/* GLSL twin: alpha_hash_is_nan. */
static bool is_nan_bits(float x)
{
    return (float_bits(x) & 0x7fffffffu) > 0x7f800000u;
}

/* GLSL twin: alpha_hash_nan_to_zero. */
static float nan_to_zero(float x)
{
    return is_nan_bits(x) ? 0.0f : x;
}

/* GLSL min/max for operands that are never NaN here (inlined, unlike libm's fminf/fmaxf). */
static float minf(float a, float b)
{
    return b < a ? b : a;
}

static float maxf(float a, float b)
{
    return a < b ? b : a;
}

/* GLSL clamp(x, lo, hi) = min(max(x, lo), hi) for non-NaN x; NaN -> nan_value.
 * GLSL twin: alpha_hash_clamp. */
static float clamp_nan(float x, float lo, float hi, float nan_value)
{
    if (is_nan_bits(x))
        return nan_value;
    return x < lo ? lo : x > hi ? hi : x;
}

/* Largest float below 1: hash outputs stay in [0, 1) even when fract() rounds up to 1.0. */
#define ONE_MINUS_ULP 0x1.fffffep-1f

/* GLSL twin: alpha_hash_unit. */
static float unit_interval(float h)
{
    return clamp_nan(h, 0.0f, ONE_MINUS_ULP, 0.0f);
}

/* 2^e for |e| <= 126, built from the exponent bits: exactly ldexp(1, e) (ldexpf is an out-of-line
 * libm call, a third of the cost of a threshold). GLSL twin: alpha_hash_pow2. */
static float pow2i(int e)
{
    uint32_t u = (uint32_t)(e + 127) << 23;
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* GLSL twin: alpha_hash_fract. */
static float fractf(float x)
{
    return x - floorf(x);
}

/* GLSL twin: alpha_hash_dot (the squared length, summed left to right). */
static float dot3(vec3 v)
{
    return v.x * v.x + v.y * v.y + v.z * v.z;
}

/* maxDeriv^2 of Listing 1 with 3D lengths; a NaN vector counts as zero length.
 * GLSL twin: alpha_hash_max_deriv2. */
static float max_deriv2(vec3 dx, vec3 dy)
{
    return maxf(nan_to_zero(dot3(dx)), nan_to_zero(dot3(dy)));
}

/* >>hashes */

/* GLSL twin: alpha_hash_pcg3d (the uvec3 statements, one lane at a time). */
alpha_uvec3 alpha_hash_pcg3d(alpha_uvec3 v)
{
    v.x = v.x * 1664525u + 1013904223u;
    v.y = v.y * 1664525u + 1013904223u;
    v.z = v.z * 1664525u + 1013904223u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.x ^= v.x >> 16u;
    v.y ^= v.y >> 16u;
    v.z ^= v.z >> 16u;
    v.x += v.y * v.z;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    return v;
}

/* Seed 000 §5.1 (McGuire's hash). GLSL twin: alpha_hash_sine2. */
float alpha_hash_sine2(float x, float y)
{
    float s1 = sinf(17.0f * x + 0.1f * y);
    float s2 = sinf(13.0f * y + x);
    float h = 1.0e4f * s1 * (0.1f + fabsf(s2));
    return unit_interval(fractf(h));
}

float alpha_hash_sine(vec3 p)
{
    return alpha_hash_sine2(alpha_hash_sine2(p.x, p.y), p.z);
}

float alpha_hash_sine_layer(vec3 p, uint32_t layer)
{
    float h = alpha_hash_sine2(p.x, p.y) + (float)(layer >> 8u) * (1.0f / 16777216.0f);
    return alpha_hash_sine2(fractf(h), p.z);
}

/* One floored coordinate as the int32 key of pcg3d: non-finite -> 0, denormal -> 0 (GPUs may flush
 * them), floor, clamp to [-2^31, 2^31 - 128] (the largest float below 2^31), int, bit pattern as
 * uint (-0 becomes 0). GLSL twin: alpha_hash_key. */
static uint32_t hash_key(float v)
{
    if (!is_finite_bits(v) || fabsf(v) < FLT_MIN)
        v = 0.0f;
    float q = floorf(v);
    q = q < -2147483648.0f ? -2147483648.0f : q > 2147483520.0f ? 2147483520.0f : q;
    return (uint32_t)(int32_t)q;
}

float alpha_hash_pcg_layer(vec3 p, uint32_t layer)
{
    alpha_uvec3 h = alpha_hash_pcg3d((alpha_uvec3){hash_key(p.x) ^ layer, hash_key(p.y), hash_key(p.z)});
    return (float)((h.x ^ h.y ^ h.z) >> 8u) * (1.0f / 16777216.0f);
}

float alpha_hash_pcg(vec3 p)
{
    return alpha_hash_pcg_layer(p, 0u);
}

float alpha_hash_kind_layer(vec3 p, int hash_kind, uint32_t layer)
{
    return hash_kind == ALPHA_HASH_SINE ? alpha_hash_sine_layer(p, layer) : alpha_hash_pcg_layer(p, layer);
}

float alpha_hash_kind(vec3 p, int hash_kind)
{
    return alpha_hash_kind_layer(p, hash_kind, 0u);
}

uint32_t alpha_hash_pcg1(uint32_t v)
{
    uint32_t state = v * 747796405u + 2891336453u;
    uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

uint32_t alpha_hash_layer(uint32_t instance, uint32_t primitive)
{
    return alpha_hash_pcg1(alpha_hash_pcg1(instance) + primitive);
}

uint32_t alpha_hash_level_key(int level)
{
    return (uint32_t)(level + ALPHA_HASH_LEVEL_BIAS) * ALPHA_HASH_LEVEL_MUL;
}

/* >>threshold */

/* Eq. 1 without the guard, for x and lerp_factor in [0, 1] (result in [0, 1]); straight-line.
 * Eq. 1 is symmetric, cdf(1 - x) = 1 - cdf(x): the lower half at z = min(x, 1 - x) (exact for
 * x in [0, 1]), mirrored. GLSL twin: alpha_hash_cdf_core. */
static float cdf_core(float x, float lerp_factor)
{
    float a = minf(lerp_factor, 1.0f - lerp_factor);
    float z = minf(x, 1.0f - x);
    float lo = z * z / maxf(2.0f * a * (1.0f - a), FLT_MIN);
    float mid = (z - 0.5f * a) / (1.0f - a);
    float f = z < a ? lo : mid;
    return x < 0.5f ? f : 1.0f - f;
}

float alpha_hash_cdf(float x, float lerp_factor)
{
    return clamp_nan(cdf_core(x, lerp_factor), 0.0f, 1.0f, 0.5f);
}

float alpha_hash_log2_scale(vec3 dx, vec3 dy, float hash_scale)
{
    float hs = is_finite_bits(hash_scale) && hash_scale > 0.0f ? hash_scale : (float)ALPHA_HASH_SCALE_DEFAULT;
    /* log2(1 / (hs * maxDeriv)) = -0.5 * log2(hs^2 * maxDeriv^2): no square root, no division.
     * hs * (hs * m2) is never NaN: hs is finite and > 0, m2 >= 0 or inf. */
    float y2 = hs * (hs * max_deriv2(dx, dy));
    const float lim = (float)ALPHA_HASH_LOG2_CLAMP;
    /* 2^-120 and 2^120 (pixScale 2^60 and 2^-60) decide the ends without log2 of 0 or inf, which
     * GLSL leaves undefined. */
    if (y2 <= 0x1p-120f)
        return lim;
    if (y2 >= 0x1p120f)
        return -lim;
    float l = -0.5f * log2f(y2);
    return l < -lim ? -lim : l > lim ? lim : l;
}

/* Anisotropic option: 2^e per object axis, e = floor(log2(max_deriv / deriv_axis)) limited to
 * [0, ALPHA_MAX_ANISO_LOG2], by exact comparisons with power-of-two multiples (no log2 rounding).
 * GLSL twin: alpha_hash_aniso_level. */
static int aniso_level(float deriv_axis, float max_deriv)
{
    int e = 0;
    for (int j = 1; j <= ALPHA_MAX_ANISO_LOG2; j++)
        e += deriv_axis * pow2i(j) <= max_deriv ? 1 : 0;
    return e;
}

/* An object coordinate as the cells see it: |o| in [2^-62, 2^63) unchanged, anything else (0,
 * tinier, larger, NaN, inf) 0, by one unsigned test of the exponent bits. The cells 2^level * o
 * (level in [-60, 64]) are then finite and exact, and either 0 or normal (>= 2^-122: a GPU that
 * flushes denormals floors them the same way). GLSL twin: alpha_hash_coord. */
static float hash_coord(float o)
{
    return (float_bits(o) & 0x7f800000u) - (65u << 23) < (125u << 23) ? o : 0.0f;
}

float alpha_hashed_threshold_layer(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic,
                                   uint32_t layer)
{
    float l = alpha_hash_log2_scale(dx, dy, hash_scale);
    float lo = floorf(l), hi = ceilf(l);
    float lerp_factor = l - lo; /* fract(l) */
    int ilo = (int)lo, ihi = (int)hi;
    int ex = 0, ey = 0, ez = 0;
    if (anisotropic) {
        float m = sqrtf(max_deriv2(dx, dy)); /* max of the lengths (sqrt is monotonic) */
        ex = aniso_level(maxf(nan_to_zero(fabsf(dx.x)), nan_to_zero(fabsf(dy.x))), m);
        ey = aniso_level(maxf(nan_to_zero(fabsf(dx.y)), nan_to_zero(fabsf(dy.y))), m);
        ez = aniso_level(maxf(nan_to_zero(fabsf(dx.z)), nan_to_zero(fabsf(dy.z))), m);
    }
    vec3 o = {hash_coord(obj.x), hash_coord(obj.y), hash_coord(obj.z)};
    vec3 c_lo = {floorf(pow2i(ilo + ex) * o.x), floorf(pow2i(ilo + ey) * o.y), floorf(pow2i(ilo + ez) * o.z)};
    vec3 c_hi = {floorf(pow2i(ihi + ex) * o.x), floorf(pow2i(ihi + ey) * o.y), floorf(pow2i(ihi + ez) * o.z)};
    /* Each level on its own lattice, keyed by the level (not by lo / hi: a cell keeps its hash when
     * l crosses an integer). GLSL twin: the same lines. */
    float h_lo = alpha_hash_kind_layer(c_lo, hash_kind, layer ^ alpha_hash_level_key(ilo));
    float h_hi = alpha_hash_kind_layer(c_hi, hash_kind, layer ^ alpha_hash_level_key(ihi));
    float x = (1.0f - lerp_factor) * h_lo + lerp_factor * h_hi;
    /* x and lerp_factor are in [0, 1], so no NaN guard (the hard-case tests check every input). */
    float t = cdf_core(x, lerp_factor);
    return t < (float)ALPHA_THRESHOLD_MIN ? (float)ALPHA_THRESHOLD_MIN : t > 1.0f ? 1.0f : t;
}

float alpha_hashed_threshold(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic)
{
    return alpha_hashed_threshold_layer(obj, dx, dy, hash_scale, hash_kind, anisotropic, 0u);
}

/* >>fade */

float alpha_hashed_fade(float cutoff, float threshold, float lod, float fade_n)
{
    const float tmin = (float)ALPHA_THRESHOLD_MIN;
    float c = clamp_nan(cutoff, tmin, 1.0f, 0.5f);
    float t = clamp_nan(threshold, tmin, 1.0f, c);
    if (is_nan_bits(fade_n) || fade_n <= 0.0f)
        return t;
    /* b = clamp(x / n, 0, 1)^2, straight-line: x <= 0 -> 0, x >= n -> 1, NaN -> 1 (full noise). */
    float q = clamp_nan(lod / fade_n, 0.0f, 1.0f, 1.0f);
    float b = q * q;
    /* c and t are in [tmin, 1] and b in [0, 1]: never NaN, a plain clamp (rounding only). */
    float f = c + (t - c) * b;
    return f < tmin ? tmin : f > 1.0f ? 1.0f : f;
}

float alpha_texture_lod(const float duv_dx[2], const float duv_dy[2], const float tex_size[2])
{
    float tx0 = duv_dx[0] * tex_size[0], tx1 = duv_dx[1] * tex_size[1];
    float ty0 = duv_dy[0] * tex_size[0], ty1 = duv_dy[1] * tex_size[1];
    float px = sqrtf(tx0 * tx0 + tx1 * tx1), py = sqrtf(ty0 * ty0 + ty1 * ty1);
    float lod = 0.0f;
    if (!is_nan_bits(px) && !is_nan_bits(py)) {
        float pmax = maxf(px, py);
        if (pmax > 0.0f) {
            const float lim = (float)ALPHA_HASH_LOG2_CLAMP;
            lod = pmax >= 0x1p60f ? lim : clamp_nan(log2f(pmax), -lim, lim, 0.0f);
        }
    }
    return lod;
}

float alpha_texture_fade_level(const float duv_dx[2], const float duv_dy[2], const float tex_size[2], float mip_scale)
{
    float tx0 = duv_dx[0] * tex_size[0], tx1 = duv_dx[1] * tex_size[1];
    float ty0 = duv_dy[0] * tex_size[0], ty1 = duv_dy[1] * tex_size[1];
    float px2 = tx0 * tx0 + tx1 * tx1, py2 = ty0 * ty0 + ty1 * ty1;
    const float big = 0x1p120f;
    float p2max = maxf(minf(nan_to_zero(px2), big), minf(nan_to_zero(py2), big));
    /* max(log2(pmax) + bias, 0) = 0.5 log2(max(pmax^2 4^bias, 1)) */
    float s2 = mip_scale * mip_scale;
    float v = maxf(p2max * s2, 1.0f);
    return 0.5f * log2f(minf(v, big));
}

float alpha_lod_clamp(float level, float lod_max)
{
    return lod_max >= 0.0f && level > lod_max ? lod_max : level;
}

/* >>stochastic */

float alpha_stochastic_threshold(uint32_t pixel_x, uint32_t pixel_y, uint32_t frame, uint32_t salt)
{
    alpha_uvec3 h = alpha_hash_pcg3d((alpha_uvec3){pixel_x, pixel_y, frame ^ salt});
    return (float)(((h.x ^ h.y ^ h.z) >> 8u) + 1u) * (1.0f / 16777216.0f);
}

/* >>a2c */

/* n rounded down to a power of two in [1, ALPHA_A2C_MAX_SAMPLES]. GLSL twin: alpha_hash_a2c_n. */
static int a2c_n(int n)
{
    int p = 1;
    while (p * 2 <= n && p * 2 <= ALPHA_A2C_MAX_SAMPLES)
        p *= 2;
    return p;
}

float alpha_hashed_a2c_threshold(int i, int n, float xi1, float xi2, float chi)
{
    int nn = a2c_n(n);
    float fn = (float)nn;
    float x1 = clamp_nan(xi1, 0.0f, 1.0f, 0.0f), x2 = clamp_nan(xi2, 0.0f, 1.0f, 0.0f);
    float c = clamp_nan(chi, (float)ALPHA_THRESHOLD_MIN, 1.0f, 1.0f);
    uint32_t a_o = (uint32_t)(int32_t)floorf(fn * x1);
    uint32_t a_plus = 2u * (uint32_t)(int32_t)floorf(0.5f * fn * x2) + 1u;
    uint32_t k = (a_o + (uint32_t)i * a_plus) & (uint32_t)(nn - 1);
    return (c + (float)k) / fn;
}

uint32_t alpha_hashed_a2c_mask(float alpha, int n, float xi1, float xi2, float chi)
{
    int nn = a2c_n(n);
    uint32_t m = 0;
    for (int i = 0; i < nn; i++)
        if (alpha >= alpha_hashed_a2c_threshold(i, nn, xi1, xi2, chi))
            m |= 1u << (uint32_t)i;
    return m;
}

float alpha_hashed_frame_offset(float t, uint32_t frame)
{
    /* The offset is reduced modulo 1 in float from the frame's fractional multiple, computed on
     * the frame modulo 2^16 so it stays exact in float: the same steps as the GLSL twin. */
    float k = (float)(frame & 0xffffu);
    float off = k * (float)ALPHA_FRAME_OFFSET_STEP;
    off = off - floorf(off);
    float u = t + off;
    u = u - floorf(u);
    return u > 0.0f ? u : 1.0f; /* (0, 1]: 0 wraps to 1 */
}
