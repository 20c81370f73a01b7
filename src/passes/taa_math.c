/* taa_math.c: temporal antialiasing math, the C twin of shaders/common/taa.glsl (taa_math.h
 * documents each function). Same float operations in the same order as the GLSL, all in float (no
 * double, no FMA: C11 without -ffp-contract=fast does not contract). NaN and infinity tests look at
 * the bit pattern, as the GLSL does. tests/gpu/test_taa_twin.c compares the two.
 */
#include "passes/taa_math.h"

#include <math.h>
#include <string.h>

#include "common/shared_defs.h"

/* >>helpers */

static uint32_t float_bits(float x)
{
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    return b;
}

/* GLSL twin: taa_is_nan. */
static bool is_nan_bits(float x)
{
    return (float_bits(x) & 0x7fffffffu) > 0x7f800000u;
}

/* GLSL twin: taa_is_finite. */
static bool is_finite_bits(float x)
{
    return (float_bits(x) & 0x7f800000u) != 0x7f800000u;
}

/* GLSL clamp for a non-NaN x (min(max(x, lo), hi)). */
static float clampf(float x, float lo, float hi)
{
    float y = x > lo ? x : lo;
    return y < hi ? y : hi;
}

/* >>jitter */

float taa_halton(uint32_t index, uint32_t base)
{
    if (base < 2u)
        return 0.0f;
    /* Mirrored digits n / d, exactly, while 2 * d fits in 32 bits. */
    uint32_t n = 0u, d = 1u, limit = 0x7fffffffu / base;
    while (index > 0u && d <= limit) {
        n = n * base + index % base;
        d *= base;
        index /= base;
    }
    /* Long division: the first TAA_HALTON_BITS bits of n / d (n < d, so 2n < 2^32). */
    uint32_t bits = 0u;
    for (int k = 0; k < TAA_HALTON_BITS; k++) {
        n *= 2u;
        bits *= 2u;
        if (n >= d) {
            n -= d;
            bits |= 1u;
        }
    }
    return ldexpf((float)bits, -TAA_HALTON_BITS);
}

void taa_jitter(uint32_t frame, uint32_t length, float out[2])
{
    uint32_t len = length == 0u ? (uint32_t)TAA_JITTER_LENGTH_DEFAULT : length;
    if (len > (uint32_t)TAA_JITTER_LENGTH_MAX)
        len = (uint32_t)TAA_JITTER_LENGTH_MAX;
    uint32_t i = frame % len + 1u;
    out[0] = taa_halton(i, 2u) - 0.5f;
    out[1] = taa_halton(i, 3u) - 0.5f;
}

/* >>colour */

vec3 taa_rgb_to_ycocg(vec3 c)
{
    vec3 r;
    r.x = 0.25f * c.x + 0.5f * c.y + 0.25f * c.z;
    r.y = 0.5f * c.x - 0.5f * c.z;
    r.z = -0.25f * c.x + 0.5f * c.y - 0.25f * c.z;
    return r;
}

vec3 taa_ycocg_to_rgb(vec3 c)
{
    float t = c.x - c.z;
    return v3(t + c.y, c.x + c.z, t - c.y);
}

/* >>sanitize */

float taa_sanitize(float v)
{
    if (is_nan_bits(v))
        return 0.0f;
    return clampf(v, -(float)TAA_MAX_VALUE, (float)TAA_MAX_VALUE);
}

vec3 taa_sanitize_color(vec3 c)
{
    return v3(clampf(taa_sanitize(c.x), 0.0f, (float)TAA_MAX_VALUE), clampf(taa_sanitize(c.y), 0.0f, (float)TAA_MAX_VALUE),
              clampf(taa_sanitize(c.z), 0.0f, (float)TAA_MAX_VALUE));
}

void taa_sanitize4(const float c[4], float out[4])
{
    for (int k = 0; k < 4; k++)
        out[k] = clampf(taa_sanitize(c[k]), 0.0f, (float)TAA_MAX_VALUE);
}

/* GLSL twin: taa_sanitize3. */
static vec3 sanitize3(vec3 v)
{
    return v3(taa_sanitize(v.x), taa_sanitize(v.y), taa_sanitize(v.z));
}

/* >>clip */

/* Lowers t to extent / |d| where |d| > extent. GLSL twin: taa_clip_axis. */
static float clip_axis(float t, float d, float extent)
{
    float ad = fabsf(d);
    if (ad > extent) {
        float s = extent / ad;
        t = s < t ? s : t;
    }
    return t;
}

vec3 taa_clip_to_box(vec3 history, vec3 mean, vec3 sigma, float gamma, float margin)
{
    vec3 h = sanitize3(history), m = sanitize3(mean), s = sanitize3(sigma);
    float g = is_nan_bits(gamma) ? (float)TAA_GAMMA_DEFAULT : clampf(gamma, 0.0f, (float)TAA_MAX_VALUE);
    float mg = is_nan_bits(margin) ? 0.0f : clampf(margin, 0.0f, (float)TAA_MAX_VALUE);
    vec3 e = v3(g * fabsf(s.x) + mg, g * fabsf(s.y) + mg, g * fabsf(s.z) + mg);
    vec3 d = v3(h.x - m.x, h.y - m.y, h.z - m.z);
    float t = 1.0f;
    t = clip_axis(t, d.x, e.x);
    t = clip_axis(t, d.y, e.y);
    t = clip_axis(t, d.z, e.z);
    if (t >= 1.0f)
        return h;
    return v3(m.x + d.x * t, m.y + d.y * t, m.z + d.z * t);
}

/* >>sparse */

float taa_sparse_coverage(float history_coverage, float current, float cov_min, float cov_max, float slack,
                          float *margin)
{
    float lo = is_nan_bits(cov_min) ? 0.0f : taa_sanitize(cov_min), hi = is_nan_bits(cov_max) ? 1.0f : taa_sanitize(cov_max);
    float h = is_nan_bits(history_coverage) ? lo : taa_sanitize(history_coverage);
    float c = is_nan_bits(current) ? lo : taa_sanitize(current);
    float s = is_nan_bits(slack) ? 0.0f : clampf(slack, 0.0f, 1.0f);
    float a = c - s, b = c + s;
    float r = clampf(h, fminf(lo, a), fmaxf(hi, b));
    float below = lo - r, above = r - hi;
    *margin = fmaxf(fmaxf(below, above), 0.0f);
    return r;
}

/* >>resolve */

void taa_catmull_rom_weights(float frac, float w[4])
{
    float t = clampf(taa_sanitize(frac), 0.0f, 1.0f);
    w[0] = t * (-0.5f + t * (1.0f - 0.5f * t));
    w[1] = 1.0f + t * t * (-2.5f + 1.5f * t);
    w[2] = t * (0.5f + t * (2.0f - 1.5f * t));
    w[3] = t * t * (-0.5f + 0.5f * t);
}

/* GLSL twin: taa_resolve_blend. */
static float resolve_blend(float blend)
{
    return is_nan_bits(blend) ? (float)TAA_BLEND_DEFAULT : clampf(blend, 0.0f, 1.0f);
}

vec3 taa_resolve(vec3 current, vec3 history, bool history_valid, float blend)
{
    vec3 c = taa_sanitize_color(current);
    if (!history_valid)
        return c;
    vec3 h = taa_sanitize_color(history);
    float b = resolve_blend(blend);
    return v3(h.x + (c.x - h.x) * b, h.y + (c.y - h.y) * b, h.z + (c.z - h.z) * b);
}

void taa_resolve4(const float current[4], const float history[4], bool history_valid, float blend, float out[4])
{
    float c[4], h[4];
    taa_sanitize4(current, c);
    if (!history_valid) {
        memcpy(out, c, sizeof c);
        return;
    }
    taa_sanitize4(history, h);
    float b = resolve_blend(blend);
    for (int k = 0; k < 4; k++)
        out[k] = h[k] + (c[k] - h[k]) * b;
}

float taa_resolve1(float current, float history, bool history_valid, float blend)
{
    float c[4] = {current, current, current, current}, h[4] = {history, history, history, history}, r[4];
    taa_resolve4(c, h, history_valid, blend, r);
    return r[0];
}

/* >>neighbourhood */

taa_box taa_neighbourhood(const float taps[][4], const float cov[], int n, bool per_tap)
{
    int count = n < 1 ? 1 : n > TAA_MAX_TAPS ? TAA_MAX_TAPS : n;
    float m1[3] = {0, 0, 0}, m2[3] = {0, 0, 0}, check = 0.0f;
    float s0[4], c0 = per_tap ? taa_sanitize(cov[0]) : cov[0];
    if (per_tap)
        taa_sanitize4(taps[0], s0);
    else
        memcpy(s0, taps[0], sizeof s0);
    float ar[2] = {s0[3], s0[3]}, cr[2] = {c0, c0};
    for (int k = 0; k < count; k++) {
        float s[4], cv = per_tap ? taa_sanitize(cov[k]) : cov[k];
        if (per_tap)
            taa_sanitize4(taps[k], s);
        else
            memcpy(s, taps[k], sizeof s);
        vec3 y = taa_rgb_to_ycocg(v3(s[0], s[1], s[2]));
        const float yv[3] = {y.x, y.y, y.z};
        for (int c = 0; c < 3; c++) {
            m1[c] = m1[c] + yv[c];
            m2[c] = m2[c] + yv[c] * yv[c];
        }
        check = check + s[3] + cv;
        ar[0] = ar[0] < s[3] ? ar[0] : s[3];
        ar[1] = ar[1] > s[3] ? ar[1] : s[3];
        cr[0] = cr[0] < cv ? cr[0] : cv;
        cr[1] = cr[1] > cv ? cr[1] : cv;
    }
    taa_box b;
    float mean[3], sigma[3];
    for (int c = 0; c < 3; c++) {
        mean[c] = m1[c] / (float)count;
        float var = m2[c] / (float)count - mean[c] * mean[c];
        sigma[c] = sqrtf(var > 0.0f ? var : 0.0f);
    }
    b.mean = v3(mean[0], mean[1], mean[2]);
    b.sigma = v3(sigma[0], sigma[1], sigma[2]);
    b.alpha[0] = ar[0];
    b.alpha[1] = ar[1];
    b.coverage[0] = cr[0];
    b.coverage[1] = cr[1];
    float all_sums = check + m1[0] + m2[0] + m2[1] + m2[2];
    if (!per_tap && !is_finite_bits(all_sums)) {
        const float mx = (float)TAA_MAX_VALUE;
        b.mean = v3(0, 0, 0);
        b.sigma = v3(mx, mx, mx);
        b.alpha[0] = b.coverage[0] = -mx;
        b.alpha[1] = b.coverage[1] = mx;
    }
    return b;
}

/* >>history */

void taa_catmull_rom_taps(float px, float py, float size_x, float size_y, float taps[5][3])
{
    const float p[2] = {taa_sanitize(px), taa_sanitize(py)}, size[2] = {taa_sanitize(size_x), taa_sanitize(size_y)};
    float t0[2], t12[2], t3[2], w0[2], w12[2], w3[2];
    for (int a = 0; a < 2; a++) {
        float t1 = floorf(p[a] - 0.5f) + 0.5f, f = p[a] - t1, w[4];
        taa_catmull_rom_weights(f, w);
        w0[a] = w[0];
        w12[a] = w[1] + w[2];
        w3[a] = w[3];
        float lo = 0.5f, hi = size[a] - 0.5f;
        hi = hi > lo ? hi : lo;
        float t = t1 + w[2] / (w12[a] > 1e-6f ? w12[a] : 1e-6f);
        t12[a] = clampf(t, lo, hi);
        t0[a] = clampf(t1 - 1.0f, lo, hi);
        t3[a] = clampf(t1 + 2.0f, lo, hi);
    }
    const float out[5][3] = {{t12[0], t0[1], w12[0] * w0[1]},
                             {t0[0], t12[1], w0[0] * w12[1]},
                             {t12[0], t12[1], w12[0] * w12[1]},
                             {t3[0], t12[1], w3[0] * w12[1]},
                             {t12[0], t3[1], w12[0] * w3[1]}};
    memcpy(taps, out, sizeof out);
}

void taa_history_sum(const float taps[][4], const float w[], int n, bool per_tap, float out[4])
{
    int count = n < 1 ? 1 : n > 5 ? 5 : n;
    float c[4] = {0, 0, 0, 0}, wsum = 0.0f;
    for (int k = 0; k < count; k++) {
        float t[4];
        if (per_tap)
            taa_sanitize4(taps[k], t);
        else
            memcpy(t, taps[k], sizeof t);
        for (int e = 0; e < 4; e++)
            c[e] = c[e] + w[k] * t[e];
        wsum = wsum + w[k];
    }
    float r[4];
    for (int e = 0; e < 4; e++)
        r[e] = c[e] / wsum;
    taa_sanitize4(r, out);
}

/* >>reproject */

/* m * (x, y, z, w), column by column, left to right (the GLSL writes m[0]*x + m[1]*y + ...).
 * GLSL twin: taa_mul_m4_v4. */
static void mul_m4_v4(const mat4 *m, const float v[4], float out[4])
{
    for (int r = 0; r < 4; r++)
        out[r] = m->m[0 + r] * v[0] + m->m[4 + r] * v[1] + m->m[8 + r] * v[2] + m->m[12 + r] * v[3];
}

/* The shared tail of both reprojections: the homogeneous world point into the previous frame. */
static void reproject_world(vec3 ndc, const float world[4], const mat4 *prev_view_proj, vec3 *out, bool *valid)
{
    float prev[4];
    *out = sanitize3(ndc);
    *valid = false;
    mul_m4_v4(prev_view_proj, world, prev);
    bool same_side = (prev[3] > 0.0f && world[3] > 0.0f) || (prev[3] < 0.0f && world[3] < 0.0f);
    if (!same_side || !is_finite_bits(prev[3]))
        return;
    /* prev[3] / world[3] > 0 is the previous clip w of the dehomogenized world point. */
    vec3 r = v3(prev[0] / prev[3], prev[1] / prev[3], prev[2] / prev[3]);
    if (!is_finite_bits(r.x) || !is_finite_bits(r.y) || !is_finite_bits(r.z))
        return;
    *out = r;
    *valid = true;
}

void taa_reproject(vec3 ndc, const mat4 *inv_view_proj_jittered, const mat4 *prev_view_proj, vec3 *out, bool *valid)
{
    *out = sanitize3(ndc);
    *valid = false;
    if (!is_finite_bits(ndc.x) || !is_finite_bits(ndc.y) || !is_finite_bits(ndc.z))
        return;
    float p[4] = {ndc.x, ndc.y, ndc.z, 1.0f}, world[4];
    mul_m4_v4(inv_view_proj_jittered, p, world);
    reproject_world(ndc, world, prev_view_proj, out, valid);
}

void taa_reproject_moving(vec3 ndc, vec3 motion, const mat4 *inv_view_proj_jittered, const mat4 *prev_view_proj,
                          vec3 *out, bool *valid)
{
    *out = sanitize3(ndc);
    *valid = false;
    if (!is_finite_bits(ndc.x) || !is_finite_bits(ndc.y) || !is_finite_bits(ndc.z))
        return;
    float p[4] = {ndc.x, ndc.y, ndc.z, 1.0f}, world[4];
    mul_m4_v4(inv_view_proj_jittered, p, world);
    vec3 m = sanitize3(motion);
    world[0] = world[0] + m.x * world[3];
    world[1] = world[1] + m.y * world[3];
    world[2] = world[2] + m.z * world[3];
    reproject_world(ndc, world, prev_view_proj, out, valid);
}

/* >>disocclusion */

bool taa_history_surface_here(vec3 hist_ndc, vec3 motion, const mat4 *prev_inv_view_proj, const mat4 *view_proj,
                              float here_x, float here_y, float size_x, float size_y, float depth_cur, float max_px,
                              float *keep, float offset[2])
{
    vec3 now, m = sanitize3(motion);
    bool valid;
    *keep = clampf(taa_sanitize(depth_cur), 0.0f, 1.0f);
    offset[0] = offset[1] = 0.0f;
    taa_reproject_moving(hist_ndc, v3(-m.x, -m.y, -m.z), prev_inv_view_proj, view_proj, &now, &valid);
    if (!valid)
        return false;
    float dx = (now.x - here_x) * 0.5f * size_x, dy = (now.y - here_y) * 0.5f * size_y;
    offset[0] = taa_sanitize(dx);
    offset[1] = taa_sanitize(dy);
    float far = fmaxf(fabsf(dx), fabsf(dy));
    if (!is_finite_bits(far) || far > max_px)
        return false;
    float z = now.z * 0.5f + 0.5f;
    *keep = fminf(*keep, clampf(z, 0.0f, 1.0f));
    return true;
}
