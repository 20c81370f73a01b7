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

/* 2^e for |e| <= 126, built from the exponent bits: exactly ldexp(1, e), which the GLSL calls
 * (ldexpf is an out-of-line libm call, a third of the cost of a threshold). */
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

/* GLSL twin: alpha_hash_length (length(): sqrt of the dot product, summed left to right). */
static float length3(vec3 v)
{
    return sqrtf(v.x * v.x + v.y * v.y + v.z * v.z);
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

float alpha_hash_pcg(vec3 p)
{
    alpha_uvec3 h = alpha_hash_pcg3d((alpha_uvec3){hash_key(p.x), hash_key(p.y), hash_key(p.z)});
    return (float)((h.x ^ h.y ^ h.z) >> 8u) * (1.0f / 16777216.0f);
}

float alpha_hash_kind(vec3 p, int hash_kind)
{
    return hash_kind == ALPHA_HASH_SINE ? alpha_hash_sine(p) : alpha_hash_pcg(p);
}

/* >>threshold */

float alpha_hash_cdf(float x, float lerp_factor)
{
    float a = minf(lerp_factor, 1.0f - lerp_factor);
    float t;
    if (x < a) {
        t = x * x / maxf(2.0f * a * (1.0f - a), FLT_MIN);
    } else if (x < 1.0f - a) {
        t = (x - 0.5f * a) / (1.0f - a);
    } else {
        float y = 1.0f - x;
        t = 1.0f - y * y / maxf(2.0f * a * (1.0f - a), FLT_MIN);
    }
    return clamp_nan(t, 0.0f, 1.0f, 0.5f);
}

float alpha_hash_log2_scale(vec3 dx, vec3 dy, float hash_scale)
{
    float hs = is_finite_bits(hash_scale) && hash_scale > 0.0f ? hash_scale : (float)ALPHA_HASH_SCALE_DEFAULT;
    float max_deriv = maxf(nan_to_zero(length3(dx)), nan_to_zero(length3(dy)));
    float pix_scale = 1.0f / (hs * max_deriv); /* in [0, inf]: never NaN */
    const float lim = (float)ALPHA_HASH_LOG2_CLAMP;
    /* 2^60 and 2^-60 decide the ends without log2 of 0 or inf, which GLSL leaves undefined. */
    if (pix_scale >= 0x1p60f)
        return lim;
    if (pix_scale <= 0x1p-60f)
        return -lim;
    return clamp_nan(log2f(pix_scale), -lim, lim, 0.0f);
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

/* Cell of obj at per-axis scale 2^(level + e): floor(scale * obj), non-finite -> 0.
 * GLSL twin: alpha_hash_cell. */
static float cell(float o, int level)
{
    float v = pow2i(level) * o;
    if (!is_finite_bits(v) || fabsf(v) < FLT_MIN)
        v = 0.0f;
    return floorf(v);
}

float alpha_hashed_threshold(vec3 obj, vec3 dx, vec3 dy, float hash_scale, int hash_kind, bool anisotropic)
{
    float l = alpha_hash_log2_scale(dx, dy, hash_scale);
    float lo = floorf(l), hi = ceilf(l);
    float lerp_factor = l - lo; /* fract(l) */
    int ilo = (int)lo, ihi = (int)hi;
    int ex = 0, ey = 0, ez = 0;
    if (anisotropic) {
        float m = maxf(nan_to_zero(length3(dx)), nan_to_zero(length3(dy)));
        ex = aniso_level(maxf(nan_to_zero(fabsf(dx.x)), nan_to_zero(fabsf(dy.x))), m);
        ey = aniso_level(maxf(nan_to_zero(fabsf(dx.y)), nan_to_zero(fabsf(dy.y))), m);
        ez = aniso_level(maxf(nan_to_zero(fabsf(dx.z)), nan_to_zero(fabsf(dy.z))), m);
    }
    vec3 c_lo = {cell(obj.x, ilo + ex), cell(obj.y, ilo + ey), cell(obj.z, ilo + ez)};
    vec3 c_hi = {cell(obj.x, ihi + ex), cell(obj.y, ihi + ey), cell(obj.z, ihi + ez)};
    float h_lo = alpha_hash_kind(c_lo, hash_kind);
    float h_hi = alpha_hash_kind(c_hi, hash_kind);
    float x = (1.0f - lerp_factor) * h_lo + lerp_factor * h_hi;
    float t = alpha_hash_cdf(x, lerp_factor);
    return clamp_nan(t, (float)ALPHA_THRESHOLD_MIN, 1.0f, 1.0f);
}

/* >>fade */

float alpha_hashed_fade(float cutoff, float threshold, float lod, float aniso_ratio, float fade_n)
{
    const float tmin = (float)ALPHA_THRESHOLD_MIN;
    float c = clamp_nan(cutoff, tmin, 1.0f, 0.5f);
    float t = clamp_nan(threshold, tmin, 1.0f, c);
    if (is_nan_bits(fade_n) || fade_n <= 0.0f)
        return t;
    float r = clamp_nan(aniso_ratio, 1.0f, (float)ALPHA_MAX_ANISO, 1.0f);
    float x = lod + log2f(r);
    float b;
    if (is_nan_bits(x)) {
        b = 1.0f;
    } else if (x <= 0.0f) {
        b = 0.0f;
    } else if (x >= fade_n) {
        b = 1.0f;
    } else {
        float q = x / fade_n;
        b = q * q;
    }
    return clamp_nan(c + (t - c) * b, tmin, 1.0f, c);
}

float alpha_texture_lod(const float duv_dx[2], const float duv_dy[2], const float tex_size[2], float *aniso_ratio)
{
    float tx0 = duv_dx[0] * tex_size[0], tx1 = duv_dx[1] * tex_size[1];
    float ty0 = duv_dy[0] * tex_size[0], ty1 = duv_dy[1] * tex_size[1];
    float px = sqrtf(tx0 * tx0 + tx1 * tx1), py = sqrtf(ty0 * ty0 + ty1 * ty1);
    float ratio = 1.0f, lod = 0.0f;
    if (!is_nan_bits(px) && !is_nan_bits(py)) {
        float pmax = maxf(px, py), pmin = minf(px, py);
        if (pmax > 0.0f) {
            const float lim = (float)ALPHA_HASH_LOG2_CLAMP;
            ratio = clamp_nan(pmax / pmin, 1.0f, (float)ALPHA_MAX_ANISO, 1.0f);
            lod = pmax >= 0x1p60f ? lim : clamp_nan(log2f(pmax), -lim, lim, 0.0f);
        }
    }
    if (aniso_ratio)
        *aniso_ratio = ratio;
    return lod;
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
