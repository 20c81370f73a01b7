#include "fmath.h"

#include <math.h>
#include <string.h>

vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
vec3 v3_lerp(vec3 a, vec3 b, float t) { return v3_add(a, v3_scale(v3_sub(b, a), t)); }
float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
float v3_len(vec3 a) { return sqrtf(v3_dot(a, a)); }
vec3 v3_norm_or(vec3 a, vec3 fallback)
{
    float l = v3_len(a);
    if (!(l > 0.0f) || !isfinite(l))
        return fallback;
    return v3_scale(a, 1.0f / l);
}
vec3 v3_min(vec3 a, vec3 b) { return v3(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z)); }
vec3 v3_max(vec3 a, vec3 b) { return v3(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z)); }

mat4 m4_identity(void)
{
    mat4 r = {{0}};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0f;
    return r;
}

mat4 m4_mul(mat4 a, mat4 b)
{
    mat4 r;
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++)
                s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

mat4 m4_translate(vec3 t)
{
    mat4 r = m4_identity();
    r.m[12] = t.x;
    r.m[13] = t.y;
    r.m[14] = t.z;
    return r;
}

mat4 m4_scale(vec3 s)
{
    mat4 r = m4_identity();
    r.m[0] = s.x;
    r.m[5] = s.y;
    r.m[10] = s.z;
    return r;
}

mat4 m4_quat(const float q[4])
{
    float x = q[0], y = q[1], z = q[2], w = q[3];
    mat4 r = m4_identity();
    r.m[0] = 1 - 2 * (y * y + z * z);
    r.m[1] = 2 * (x * y + z * w);
    r.m[2] = 2 * (x * z - y * w);
    r.m[4] = 2 * (x * y - z * w);
    r.m[5] = 1 - 2 * (x * x + z * z);
    r.m[6] = 2 * (y * z + x * w);
    r.m[8] = 2 * (x * z + y * w);
    r.m[9] = 2 * (y * z - x * w);
    r.m[10] = 1 - 2 * (x * x + y * y);
    return r;
}

mat4 m4_rotate_y(float a)
{
    float q[4] = {0.0f, sinf(a * 0.5f), 0.0f, cosf(a * 0.5f)};
    return m4_quat(q);
}

mat4 m4_trs(const float t[3], const float q[4], const float s[3])
{
    return m4_mul(m4_translate(v3(t[0], t[1], t[2])), m4_mul(m4_quat(q), m4_scale(v3(s[0], s[1], s[2]))));
}

mat4 m4_look_at(vec3 eye, vec3 target, vec3 up)
{
    vec3 f = v3_norm_or(v3_sub(target, eye), v3(0, 0, -1));
    if (fabsf(v3_dot(f, v3_norm_or(up, v3(0, 1, 0)))) > 0.9999f)
        up = v3(0, 0, f.y > 0 ? 1.0f : -1.0f); /* looking straight up or down */
    vec3 s = v3_norm_or(v3_cross(f, up), v3(1, 0, 0));
    vec3 u = v3_cross(s, f);
    mat4 r = m4_identity();
    r.m[0] = s.x;  r.m[4] = s.y;  r.m[8] = s.z;
    r.m[1] = u.x;  r.m[5] = u.y;  r.m[9] = u.z;
    r.m[2] = -f.x; r.m[6] = -f.y; r.m[10] = -f.z;
    r.m[12] = -v3_dot(s, eye);
    r.m[13] = -v3_dot(u, eye);
    r.m[14] = v3_dot(f, eye);
    return r;
}

mat4 m4_perspective_hfov(float hfov, float aspect, float n, float f)
{
    float sx = 1.0f / tanf(hfov * 0.5f);
    float sy = sx * aspect;
    mat4 r = {{0}};
    r.m[0] = sx;
    r.m[5] = sy;
    r.m[10] = (f + n) / (n - f);
    r.m[11] = -1.0f;
    r.m[14] = 2.0f * f * n / (n - f);
    return r;
}

mat4 m4_perspective_offaxis(float hfov, float aspect, float cx, float cy, float n, float f)
{
    mat4 r = m4_perspective_hfov(hfov, aspect, n, f);
    if (cx == 0.0f && cy == 0.0f)
        return r; /* no -0 entries: the centred matrix stays bit-identical */
    /* clip w = -z, so x_ndc = sx x / -z + cx needs the z column entry -cx (glFrustum's (r+l)/(r-l)). */
    r.m[8] = -cx;
    r.m[9] = -cy;
    return r;
}

bool m4_invert(mat4 a, mat4 *out)
{
    const float *m = a.m;
    float inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    float det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0f || !isfinite(det)) {
        *out = m4_identity();
        return false;
    }
    det = 1.0f / det;
    for (int i = 0; i < 16; i++)
        out->m[i] = inv[i] * det;
    return true;
}

vec3 m4_point(mat4 a, vec3 p)
{
    const float *m = a.m;
    return v3(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12],
              m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
              m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]);
}

vec3 m4_dir(mat4 a, vec3 d)
{
    const float *m = a.m;
    return v3(m[0] * d.x + m[4] * d.y + m[8] * d.z,
              m[1] * d.x + m[5] * d.y + m[9] * d.z,
              m[2] * d.x + m[6] * d.y + m[10] * d.z);
}

mat4 m4_normal_matrix(mat4 a)
{
    mat4 upper = a, inv, r = m4_identity();
    upper.m[12] = upper.m[13] = upper.m[14] = 0.0f;
    m4_invert(upper, &inv);
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            r.m[c * 4 + row] = inv.m[row * 4 + c];
    return r;
}

bool m4_box_outside_clip(mat4 mvp, vec3 lo, vec3 hi)
{
    /* Bit k of `out` set for a corner outside plane k; the box is culled when some plane has all
     * eight corners outside it. */
    unsigned all = 0x3f;
    for (int c = 0; c < 8; c++) {
        float p[3] = {c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z};
        float v[4];
        for (int r = 0; r < 4; r++)
            v[r] = mvp.m[r] * p[0] + mvp.m[4 + r] * p[1] + mvp.m[8 + r] * p[2] + mvp.m[12 + r];
        unsigned out = (v[0] < -v[3]) | (v[0] > v[3]) << 1 | (v[1] < -v[3]) << 2 | (v[1] > v[3]) << 3 |
                       (v[2] < -v[3]) << 4 | (v[2] > v[3]) << 5;
        all &= out;
        if (!all)
            return false;
    }
    return all != 0;
}

bool m4_box_screen_rect(mat4 mvp, vec3 lo, vec3 hi, float w, float h, float rect[4])
{
    float r[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 8; c++) {
        float p[3] = {c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z};
        float v[4];
        for (int k = 0; k < 4; k++)
            v[k] = mvp.m[k] * p[0] + mvp.m[4 + k] * p[1] + mvp.m[8 + k] * p[2] + mvp.m[12 + k];
        if (!(v[3] > 1e-6f))
            return false;
        float x = (0.5f + 0.5f * v[0] / v[3]) * w, y = (0.5f - 0.5f * v[1] / v[3]) * h;
        if (!isfinite(x) || !isfinite(y))
            return false;
        r[0] = fminf(r[0], x);
        r[1] = fminf(r[1], y);
        r[2] = fmaxf(r[2], x);
        r[3] = fmaxf(r[3], y);
    }
    memcpy(rect, r, sizeof r);
    return true;
}
