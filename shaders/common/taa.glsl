// taa.glsl: the math of temporal antialiasing (DESIGN.md "Temporal antialiasing"). C twin:
// src/passes/taa_math.c (declared in src/passes/taa_math.h, which documents each function); both
// take their constants from common/shared_defs.h and evaluate the same float operations in the same
// order. `precise` stops the compiler from fusing multiply-adds the C side does not fuse. NaN and
// infinity tests look at the bit pattern, because compilers may assume that comparisons never see
// NaN. tests/gpu/test_taa_twin.c checks this file against the C twin.
#ifndef FOVSIM_TAA_GLSL
#define FOVSIM_TAA_GLSL

#include "common/shared_defs.h"

// >>helpers

// C twin: is_nan_bits.
bool taa_is_nan(float x)
{
    return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u;
}

// C twin: is_finite_bits.
bool taa_is_finite(float x)
{
    return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

// >>jitter

// C twin: taa_halton. Exact integer radical inverse, truncated to TAA_HALTON_BITS bits.
float taa_halton(uint index, uint base)
{
    if (base < 2u)
        return 0.0;
    uint n = 0u, d = 1u, limit = 0x7fffffffu / base;
    while (index > 0u && d <= limit) {
        n = n * base + index % base;
        d *= base;
        index /= base;
    }
    uint bits = 0u;
    for (int k = 0; k < TAA_HALTON_BITS; k++) {
        n *= 2u;
        bits *= 2u;
        if (n >= d) {
            n -= d;
            bits |= 1u;
        }
    }
    return ldexp(float(bits), -TAA_HALTON_BITS);
}

// C twin: taa_jitter (its `length`; the name would hide GLSL's length()). Offsets in (-0.5, 0.5)
// ring pixels.
vec2 taa_jitter(uint frame, uint period)
{
    uint len = period == 0u ? uint(TAA_JITTER_LENGTH_DEFAULT) : period;
    len = min(len, uint(TAA_JITTER_LENGTH_MAX));
    uint i = frame % len + 1u;
    return vec2(taa_halton(i, 2u) - 0.5, taa_halton(i, 3u) - 0.5);
}

// >>colour

// C twin: taa_rgb_to_ycocg.
vec3 taa_rgb_to_ycocg(vec3 c)
{
    precise vec3 r;
    r.x = 0.25 * c.x + 0.5 * c.y + 0.25 * c.z;
    r.y = 0.5 * c.x - 0.5 * c.z;
    r.z = -0.25 * c.x + 0.5 * c.y - 0.25 * c.z;
    return r;
}

// C twin: taa_ycocg_to_rgb.
vec3 taa_ycocg_to_rgb(vec3 c)
{
    precise float t = c.x - c.z;
    precise vec3 r = vec3(t + c.y, c.x + c.z, t - c.y);
    return r;
}

// >>sanitize

// C twin: taa_sanitize. NaN -> 0, clamped to +-TAA_MAX_VALUE.
float taa_sanitize(float v)
{
    if (taa_is_nan(v))
        return 0.0;
    return clamp(v, -float(TAA_MAX_VALUE), float(TAA_MAX_VALUE));
}

// C twin: taa_sanitize_color. taa_sanitize, then clamped to [0, TAA_MAX_VALUE].
vec3 taa_sanitize_color(vec3 c)
{
    return clamp(vec3(taa_sanitize(c.x), taa_sanitize(c.y), taa_sanitize(c.z)), 0.0, float(TAA_MAX_VALUE));
}

// C twin: taa_sanitize4. taa_sanitize_color for RGBA (alpha / coverage included).
vec4 taa_sanitize4(vec4 c)
{
    return clamp(vec4(taa_sanitize(c.x), taa_sanitize(c.y), taa_sanitize(c.z), taa_sanitize(c.w)), 0.0,
                 float(TAA_MAX_VALUE));
}

// C twin: sanitize3.
vec3 taa_sanitize3(vec3 v)
{
    return vec3(taa_sanitize(v.x), taa_sanitize(v.y), taa_sanitize(v.z));
}

// >>clip

// C twin: clip_axis.
float taa_clip_axis(float t, float d, float extent)
{
    float ad = abs(d);
    if (ad > extent) {
        precise float s = extent / ad;
        t = s < t ? s : t;
    }
    return t;
}

// C twin: taa_clip_to_box. Variance clipping towards the mean (YCoCg); the box's half-extent is
// gamma * sigma + margin on every axis.
vec3 taa_clip_to_box(vec3 history, vec3 mean, vec3 sigma, float gamma, float margin)
{
    vec3 h = taa_sanitize3(history), m = taa_sanitize3(mean), s = taa_sanitize3(sigma);
    float g = taa_is_nan(gamma) ? float(TAA_GAMMA_DEFAULT) : clamp(gamma, 0.0, float(TAA_MAX_VALUE));
    float mg = taa_is_nan(margin) ? 0.0 : clamp(margin, 0.0, float(TAA_MAX_VALUE));
    precise vec3 e = g * abs(s) + mg;
    precise vec3 d = h - m;
    float t = 1.0;
    t = taa_clip_axis(t, d.x, e.x);
    t = taa_clip_axis(t, d.y, e.y);
    t = taa_clip_axis(t, d.z, e.z);
    if (t >= 1.0)
        return h;
    precise vec3 r = m + d * t;
    return r;
}

// >>sparse

// C twin: taa_sparse_margin. min(|history_coverage - c|, slack) where the neighbourhood's coverage
// samples all equal c (cov_min == cov_max); 0 otherwise. slack NaN -> 0, clamped to [0, 1].
float taa_sparse_margin(float history_coverage, float cov_min, float cov_max, float slack)
{
    if (taa_is_nan(history_coverage) || taa_is_nan(cov_min) || taa_is_nan(cov_max) || taa_is_nan(slack) ||
        cov_min != cov_max)
        return 0.0;
    precise float d = abs(history_coverage - cov_min);
    return min(d, clamp(slack, 0.0, 1.0));
}

// >>resolve

// C twin: taa_catmull_rom_weights. Weights of the taps at -1, 0, 1, 2.
vec4 taa_catmull_rom_weights(float frac)
{
    float t = clamp(taa_sanitize(frac), 0.0, 1.0);
    precise vec4 w;
    w.x = t * (-0.5 + t * (1.0 - 0.5 * t));
    w.y = 1.0 + t * t * (-2.5 + 1.5 * t);
    w.z = t * (0.5 + t * (2.0 - 1.5 * t));
    w.w = t * t * (-0.5 + 0.5 * t);
    return w;
}

// C twin: taa_resolve_blend. blend NaN -> TAA_BLEND_DEFAULT, clamped to [0, 1].
float taa_resolve_blend(float blend)
{
    return taa_is_nan(blend) ? float(TAA_BLEND_DEFAULT) : clamp(blend, 0.0, 1.0);
}

// C twin: taa_resolve. history + (current - history) * blend; invalid history -> current.
vec3 taa_resolve(vec3 current, vec3 history, bool history_valid, float blend)
{
    vec3 c = taa_sanitize_color(current);
    if (!history_valid)
        return c;
    vec3 h = taa_sanitize_color(history);
    float b = taa_resolve_blend(blend);
    precise vec3 r = h + (c - h) * b;
    return r;
}

// C twin: taa_resolve4. taa_resolve for RGBA, through taa_sanitize4.
vec4 taa_resolve4(vec4 current, vec4 history, bool history_valid, float blend)
{
    vec4 c = taa_sanitize4(current);
    if (!history_valid)
        return c;
    vec4 h = taa_sanitize4(history);
    float b = taa_resolve_blend(blend);
    precise vec4 r = h + (c - h) * b;
    return r;
}

// C twin: taa_resolve1. taa_resolve of one non-negative channel (coverage).
float taa_resolve(float current, float history, bool history_valid, float blend)
{
    return taa_resolve4(vec4(current), vec4(history), history_valid, blend).x;
}

// >>reproject

// C twin: mul_m4_v4 (column by column, left to right).
vec4 taa_mul_m4_v4(mat4 m, vec4 v)
{
    precise vec4 r = m[0] * v.x + m[1] * v.y + m[2] * v.z + m[3] * v.w;
    return r;
}

// C twin: reproject_world. The homogeneous world point into the previous frame's NDC.
bool taa_reproject_world(vec3 ndc, vec4 world, mat4 prev_view_proj, out vec3 prev_ndc)
{
    prev_ndc = taa_sanitize3(ndc);
    vec4 prev = taa_mul_m4_v4(prev_view_proj, world);
    bool same_side = (prev.w > 0.0 && world.w > 0.0) || (prev.w < 0.0 && world.w < 0.0);
    if (!same_side || !taa_is_finite(prev.w))
        return false;
    precise vec3 r = vec3(prev.x / prev.w, prev.y / prev.w, prev.z / prev.w);
    if (!taa_is_finite(r.x) || !taa_is_finite(r.y) || !taa_is_finite(r.z))
        return false;
    prev_ndc = r;
    return true;
}

// C twin: taa_reproject. Current NDC (xy, depth) -> previous frame's NDC (xy, depth) in prev_ndc;
// returns valid. Where invalid, prev_ndc = taa_sanitize3(ndc).
bool taa_reproject(vec3 ndc, mat4 inv_view_proj_jittered, mat4 prev_view_proj, out vec3 prev_ndc)
{
    prev_ndc = taa_sanitize3(ndc);
    if (!taa_is_finite(ndc.x) || !taa_is_finite(ndc.y) || !taa_is_finite(ndc.z))
        return false;
    vec4 world = taa_mul_m4_v4(inv_view_proj_jittered, vec4(ndc, 1.0));
    return taa_reproject_world(ndc, world, prev_view_proj, prev_ndc);
}

// C twin: taa_reproject_moving. The same for a point that moved by `motion` (world, last frame -
// now) on its own: added to the homogeneous world point as motion * w.
bool taa_reproject_moving(vec3 ndc, vec3 motion, mat4 inv_view_proj_jittered, mat4 prev_view_proj, out vec3 prev_ndc)
{
    prev_ndc = taa_sanitize3(ndc);
    if (!taa_is_finite(ndc.x) || !taa_is_finite(ndc.y) || !taa_is_finite(ndc.z))
        return false;
    vec4 world = taa_mul_m4_v4(inv_view_proj_jittered, vec4(ndc, 1.0));
    vec3 m = taa_sanitize3(motion);
    precise vec3 moved = world.xyz + m * world.w;
    return taa_reproject_world(ndc, vec4(moved, world.w), prev_view_proj, prev_ndc);
}

// C twin: taa_reproject_moving (xy only).
bool taa_reproject_moving(vec3 ndc, vec3 motion, mat4 inv_view_proj_jittered, mat4 prev_view_proj, out vec2 prev_ndc_xy)
{
    vec3 p;
    bool valid = taa_reproject_moving(ndc, motion, inv_view_proj_jittered, prev_view_proj, p);
    prev_ndc_xy = p.xy;
    return valid;
}

// C twin: taa_reproject (its out->x, out->y). The same, for callers that only need xy.
bool taa_reproject(vec3 ndc, mat4 inv_view_proj_jittered, mat4 prev_view_proj, out vec2 prev_ndc_xy)
{
    vec3 p;
    bool valid = taa_reproject(ndc, inv_view_proj_jittered, prev_view_proj, p);
    prev_ndc_xy = p.xy;
    return valid;
}

#endif
