// taa.glsl: the math of temporal antialiasing (docs/design.md "Temporal antialiasing"). C twin:
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

// C twin: taa_sparse_coverage. The history's coverage, kept where this frame's samples cannot refute
// it: clamped to the union of the neighbourhood's coverage range [cov_min, cov_max] and `slack`
// (clamped to [0, 1]; NaN -> 0) around the pixel's own sample `current`. `margin` is how far the
// result lies outside [cov_min, cov_max]; the caller widens the colour box by TAA_SPARSE_COLOR times
// it and the alpha range by it. slack 0 is the plain clamp to [cov_min, cov_max]. Inputs through
// taa_sanitize; a NaN history or sample counts as cov_min; NaN range ends as 0 and 1.
float taa_sparse_coverage(float history_coverage, float current, float cov_min, float cov_max, float slack,
                          out float margin)
{
    float lo = taa_is_nan(cov_min) ? 0.0 : taa_sanitize(cov_min), hi = taa_is_nan(cov_max) ? 1.0 : taa_sanitize(cov_max);
    float h = taa_is_nan(history_coverage) ? lo : taa_sanitize(history_coverage);
    float c = taa_is_nan(current) ? lo : taa_sanitize(current);
    float s = taa_is_nan(slack) ? 0.0 : clamp(slack, 0.0, 1.0);
    precise float a = c - s, b = c + s;
    float r = clamp(h, min(lo, a), max(hi, b));
    precise float below = lo - r, above = r - hi;
    margin = max(max(below, above), 0.0);
    return r;
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

// >>neighbourhood

// Variance-clipping box of the current frame's neighbourhood (YCoCg mean and standard deviation)
// and the range of its alpha and coverage. C twin: taa_box.
struct taa_box {
    vec3 mean;
    vec3 sigma;
    vec2 alpha;    // min, max
    vec2 coverage; // min, max
};

// C twin: taa_neighbourhood. Statistics of the first n (clamped to [1, TAA_MAX_TAPS]) taps, taps[0]
// the centre. per_tap: every tap through taa_sanitize4 / taa_sanitize (a NaN tap counts as 0, the
// others still count). Otherwise the taps are used raw and checked once: where the sum of every
// Y, alpha, coverage and squared Y, Co, Cg is not finite (a tap held NaN or Inf), the box says
// nothing: mean 0, sigma and ranges open to +-TAA_MAX_VALUE, so history passes unclipped (the
// caller sanitizes it).
taa_box taa_neighbourhood(vec4 taps[TAA_MAX_TAPS], float cov[TAA_MAX_TAPS], int n, bool per_tap)
{
    int count = clamp(n, 1, TAA_MAX_TAPS);
    precise vec3 m1 = vec3(0.0), m2 = vec3(0.0);
    precise float check = 0.0;
    vec4 s0 = per_tap ? taa_sanitize4(taps[0]) : taps[0];
    float c0 = per_tap ? taa_sanitize(cov[0]) : cov[0];
    vec2 ar = vec2(s0.a), cr = vec2(c0);
    for (int k = 0; k < TAA_MAX_TAPS; k++) {
        if (k >= count)
            break;
        vec4 s = per_tap ? taa_sanitize4(taps[k]) : taps[k];
        float cv = per_tap ? taa_sanitize(cov[k]) : cov[k];
        vec3 y = taa_rgb_to_ycocg(s.rgb);
        m1 = m1 + y;
        m2 = m2 + y * y;
        check = check + s.a + cv;
        ar = vec2(min(ar.x, s.a), max(ar.y, s.a));
        cr = vec2(min(cr.x, cv), max(cr.y, cv));
    }
    precise vec3 mean = m1 / float(count);
    precise vec3 var = m2 / float(count) - mean * mean;
    taa_box b;
    b.mean = mean;
    b.sigma = sqrt(max(var, vec3(0.0)));
    b.alpha = ar;
    b.coverage = cr;
    precise float all_sums = check + m1.x + m2.x + m2.y + m2.z;
    if (!per_tap && !taa_is_finite(all_sums)) {
        b.mean = vec3(0.0);
        b.sigma = vec3(float(TAA_MAX_VALUE));
        b.alpha = vec2(-float(TAA_MAX_VALUE), float(TAA_MAX_VALUE));
        b.coverage = vec2(-float(TAA_MAX_VALUE), float(TAA_MAX_VALUE));
    }
    return b;
}

// >>history

// C twin: taa_catmull_rom_taps. The 5 bilinear taps of the Catmull-Rom history fetch at position p
// (ring pixels) of a footprint of `size` ring pixels: xy the tap's position (clamped to the
// rendered texels' centres), z its weight. The 4x4 kernel's inner 2x2 taps are merged into one
// bilinear fetch per row and column and the four corner taps, whose weights are tiny, dropped
// (Jimenez's approximation).
void taa_catmull_rom_taps(vec2 p, vec2 size, out vec3 taps[5])
{
    vec2 q = vec2(taa_sanitize(p.x), taa_sanitize(p.y));
    vec2 t1 = floor(q - 0.5) + 0.5;
    precise vec2 f = q - t1;
    vec4 wx = taa_catmull_rom_weights(f.x), wy = taa_catmull_rom_weights(f.y);
    precise vec2 w12 = vec2(wx.y + wx.z, wy.y + wy.z);
    precise vec2 t12 = t1 + vec2(wx.z, wy.z) / max(w12, vec2(1e-6));
    vec2 lo = vec2(0.5), hi = max(vec2(taa_sanitize(size.x), taa_sanitize(size.y)) - 0.5, lo);
    vec2 t0 = clamp(t1 - 1.0, lo, hi), t3 = clamp(t1 + 2.0, lo, hi);
    t12 = clamp(t12, lo, hi);
    precise float w_top = w12.x * wy.x, w_left = wx.x * w12.y, w_mid = w12.x * w12.y, w_right = wx.w * w12.y,
                  w_bottom = w12.x * wy.w;
    taps[0] = vec3(t12.x, t0.y, w_top);
    taps[1] = vec3(t0.x, t12.y, w_left);
    taps[2] = vec3(t12.x, t12.y, w_mid);
    taps[3] = vec3(t3.x, t12.y, w_right);
    taps[4] = vec3(t12.x, t3.y, w_bottom);
}

// C twin: taa_history_sum. sum(w[k] * taps[k]) / sum(w[k]) over the first n (clamped to [1, 5])
// fetched history taps, through taa_sanitize4: finite, in [0, TAA_MAX_VALUE] (Catmull-Rom
// undershoots below 0 at sharp edges), whatever the inputs. per_tap: every tap through
// taa_sanitize4 first (a NaN tap counts as 0, the others still count); otherwise only the result
// is checked (a NaN tap makes the whole fetch 0, which the neighbourhood clip then pulls into its
// box).
vec4 taa_history_sum(vec4 taps[5], float w[5], int n, bool per_tap)
{
    int count = clamp(n, 1, 5);
    precise vec4 c = vec4(0.0);
    precise float wsum = 0.0;
    for (int k = 0; k < 5; k++) {
        if (k >= count)
            break;
        c = c + w[k] * (per_tap ? taa_sanitize4(taps[k]) : taps[k]);
        wsum = wsum + w[k];
    }
    precise vec4 r = c / wsum;
    return taa_sanitize4(r);
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

// >>disocclusion

// C twin: taa_history_surface_here. Is the nearest surface of the history fetched for this pixel
// still on it? hist_ndc is where the history was fetched, in the previous frame's NDC of this ring
// (xy), with the window depth of the nearest surface the history holds there as NDC (z). It is
// carried into this frame through prev_inv_view_proj and view_proj (unjittered), moved by -motion
// (the pixel's own per-object motion, last frame - now), and must land within max_px ring pixels
// (Chebyshev) of here_ndc, this pixel's centre (footprint: size ring pixels). keep: the window depth
// the history records for this pixel now: the nearer of this frame's sample (depth_cur, through
// taa_sanitize, clamped to [0, 1]) and the carried surface, or the sample alone where the result is
// false. offset: where the surface landed minus here_ndc, in ring pixels ((0, 0) where it cannot
// be carried: behind either camera, not finite), for the caller's look for the history whose
// surface does land here.
bool taa_history_surface_here(vec3 hist_ndc, vec3 motion, mat4 prev_inv_view_proj, mat4 view_proj, vec2 here_ndc,
                              vec2 size, float depth_cur, float max_px, out float keep, out vec2 offset)
{
    vec3 now;
    keep = clamp(taa_sanitize(depth_cur), 0.0, 1.0);
    offset = vec2(0.0);
    if (!taa_reproject_moving(hist_ndc, -taa_sanitize3(motion), prev_inv_view_proj, view_proj, now))
        return false;
    precise vec2 d = (now.xy - here_ndc) * 0.5 * size;
    offset = vec2(taa_sanitize(d.x), taa_sanitize(d.y));
    float far = max(abs(d.x), abs(d.y));
    if (!taa_is_finite(far) || far > max_px)
        return false;
    precise float z = now.z * 0.5 + 0.5;
    keep = min(keep, clamp(z, 0.0, 1.0));
    return true;
}

#endif
