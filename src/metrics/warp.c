/* warp.c: see warp.h. */
#include "metrics/warp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "passes/taa_math.h"

/* Linear (view) depth of a window depth in [0, 1] for a perspective projection's clip planes. */
static float linear_depth(float window, float n, float f)
{
    float z = 2.0f * window - 1.0f;
    return 2.0f * n * f / (f + n - z * (f - n));
}

/* Bilinear sample, taps clamped to the image; at integer coordinates the texel itself, exactly
 * (no 0 * (b - a) term, which is NaN next to an infinite texel). The clamp and floor are written
 * as comparisons and a truncation, which are the same here (NaN and -Inf clamp to 0, +Inf to the
 * last texel, and x >= 0 truncates to its floor): as libm calls they were most of the warp's time. */
static float bilinear(const float *p, int w, int h, float x, float y)
{
    x = x > 0.0f ? x : 0.0f;
    x = x < (float)(w - 1) ? x : (float)(w - 1);
    y = y > 0.0f ? y : 0.0f;
    y = y < (float)(h - 1) ? y : (float)(h - 1);
    int x0 = (int)x, y0 = (int)y;
    int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0;
    float a = p[y0 * w + x0];
    if (fx != 0.0f)
        a += fx * (p[y0 * w + x1] - a);
    if (fy == 0.0f)
        return a;
    float b = p[y1 * w + x0];
    if (fx != 0.0f)
        b += fx * (p[y1 * w + x1] - b);
    return a + fy * (b - a);
}

/* Inverse of a column-major 4x4 matrix in double (Gauss-Jordan, partial pivoting); false when
 * singular or not finite. */
static bool invert_d(const mat4 *a, double inv[16])
{
    double m[4][8];
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            m[r][c] = (double)a->m[c * 4 + r];
            m[r][c + 4] = r == c ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int r = c + 1; r < 4; r++)
            if (fabs(m[r][c]) > fabs(m[piv][c]))
                piv = r;
        if (!(fabs(m[piv][c]) > 1e-300) || !isfinite(m[piv][c]))
            return false;
        for (int k = 0; k < 8; k++) {
            double t = m[c][k];
            m[c][k] = m[piv][k];
            m[piv][k] = t;
        }
        double d = m[c][c];
        for (int k = 0; k < 8; k++)
            m[c][k] /= d;
        for (int r = 0; r < 4; r++) {
            if (r == c)
                continue;
            double f = m[r][c];
            for (int k = 0; k < 8; k++)
                m[r][k] -= f * m[c][k];
        }
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            inv[c * 4 + r] = m[r][c + 4];
    return true;
}

float warp_min_depth(const float *depth, int width, int height)
{
    float m = 1.0f;
    const size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; i++)
        if (depth[i] < m) /* false for NaN */
            m = depth[i];
    return m > 0.0f ? m : 0.0f;
}

bool warp_camera_still(const mat4 *prev, const mat4 *cur, int width, int height, float near_depth)
{
    if (memcmp(prev, cur, sizeof *cur) == 0)
        return true;
    double inv[16];
    if (!invert_d(cur, inv))
        return false;
    const double zn = isfinite(near_depth) ? 2.0 * fmin(fmax((double)near_depth, 0.0), 1.0) - 1.0 : -1.0;
    for (int c = 0; c < 8; c++) {
        const double ndc[4] = {c & 1 ? 1.0 : -1.0, c & 2 ? 1.0 : -1.0, c & 4 ? 1.0 : zn, 1.0};
        double world[4] = {0, 0, 0, 0}, clip[4] = {0, 0, 0, 0};
        for (int r = 0; r < 4; r++)
            for (int k = 0; k < 4; k++)
                world[r] += inv[k * 4 + r] * ndc[k];
        for (int r = 0; r < 4; r++)
            for (int k = 0; k < 4; k++)
                clip[r] += (double)prev->m[k * 4 + r] * world[k];
        /* The point is world / world[3]: in front of the previous camera when its clip w there,
         * clip[3] / world[3], is positive. */
        if (!(clip[3] * world[3] > 0.0))
            return false;
        double dx = (clip[0] / clip[3] - ndc[0]) * 0.5 * width, dy = (clip[1] / clip[3] - ndc[1]) * 0.5 * height;
        if (!(fabs(dx) <= WARP_STILL_TOLERANCE_PX && fabs(dy) <= WARP_STILL_TOLERANCE_PX))
            return false;
    }
    return true;
}

long warp_build(const warp_desc *w, float *coords, unsigned char *valid)
{
    mat4 inv;
    if (!m4_invert(w->view_proj, &inv))
        return -1;
    const float tol = w->depth_tolerance > 0.0f ? w->depth_tolerance : WARP_DEPTH_TOLERANCE_DEFAULT;
    long n_valid = 0;
    if (warp_camera_still(&w->prev_view_proj, &w->view_proj, w->width, w->height,
                          warp_min_depth(w->depth, w->width, w->height))) {
        /* The identity: each pixel at its own position, copied by warp_apply. */
        for (int y = 0; y < w->height; y++)
            for (int x = 0; x < w->width; x++) {
                size_t i = (size_t)y * (size_t)w->width + (size_t)x;
                bool ok = true;
                if (w->prev_depth) {
                    float ls = linear_depth(w->prev_depth[i], w->prev_znear, w->prev_zfar);
                    float lh = linear_depth(w->depth[i], w->prev_znear, w->prev_zfar);
                    ok = !(ls < lh * (1.0f - tol));
                }
                valid[i] = (unsigned char)ok;
                coords[2 * i] = (float)x;
                coords[2 * i + 1] = (float)y;
                n_valid += ok;
            }
        return n_valid;
    }
    for (int y = 0; y < w->height; y++)
        for (int x = 0; x < w->width; x++) {
            size_t i = (size_t)y * (size_t)w->width + (size_t)x;
            float d = w->depth[i];
            vec3 ndc = v3(2.0f * ((float)x + 0.5f) / (float)w->width - 1.0f,
                          1.0f - 2.0f * ((float)y + 0.5f) / (float)w->height, 2.0f * d - 1.0f);
            vec3 p;
            bool ok;
            taa_reproject(ndc, &inv, &w->prev_view_proj, &p, &ok);
            /* The previous frame's pixel coordinates (centres at integers, rows top first). */
            float px = (p.x + 1.0f) * 0.5f * (float)w->width - 0.5f, py = (1.0f - p.y) * 0.5f * (float)w->height - 0.5f;
            ok = ok && px >= -0.5f && px <= (float)w->width - 0.5f && py >= -0.5f && py <= (float)w->height - 0.5f;
            if (ok && w->prev_depth) {
                /* Disoccluded: something nearer covered this point in the previous frame. */
                float seen = bilinear(w->prev_depth, w->width, w->height, px, py);
                float here = 0.5f * (p.z + 1.0f);
                float ls = linear_depth(seen, w->prev_znear, w->prev_zfar);
                float lh = linear_depth(here, w->prev_znear, w->prev_zfar);
                ok = !(ls < lh * (1.0f - tol));
            }
            valid[i] = (unsigned char)ok;
            coords[2 * i] = px;
            coords[2 * i + 1] = py;
            n_valid += ok;
        }
    return n_valid;
}

void warp_apply(const float *coords, const unsigned char *valid, const metrics_view *prev, float *const out[4])
{
    const float *src[4] = {prev->r, prev->g, prev->b, prev->coverage};
    size_t n = (size_t)prev->width * (size_t)prev->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 4; c++)
            out[c][i] = valid[i] ? bilinear(src[c], prev->width, prev->height, coords[2 * i], coords[2 * i + 1]) : 0.0f;
}

long warp_previous(const warp_desc *w, const metrics_view *prev, float *const out[4], unsigned char *valid)
{
    float *coords = malloc(sizeof(float) * 2 * (size_t)w->width * (size_t)w->height);
    long n = coords ? warp_build(w, coords, valid) : -1;
    if (n >= 0)
        warp_apply(coords, valid, prev, out);
    free(coords);
    return n;
}
