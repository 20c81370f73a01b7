/* warp.c: see warp.h. */
#include "metrics/warp.h"

#include <math.h>
#include <stdlib.h>

#include "passes/taa_math.h"

/* Linear (view) depth of a window depth in [0, 1] for a perspective projection's clip planes. */
static float linear_depth(float window, float n, float f)
{
    float z = 2.0f * window - 1.0f;
    return 2.0f * n * f / (f + n - z * (f - n));
}

static float bilinear(const float *p, int w, int h, float x, float y)
{
    x = fminf(fmaxf(x, 0.0f), (float)(w - 1));
    y = fminf(fmaxf(y, 0.0f), (float)(h - 1));
    int x0 = (int)floorf(x), y0 = (int)floorf(y);
    int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0;
    float a = p[y0 * w + x0] + fx * (p[y0 * w + x1] - p[y0 * w + x0]);
    float b = p[y1 * w + x0] + fx * (p[y1 * w + x1] - p[y1 * w + x0]);
    return a + fy * (b - a);
}

long warp_build(const warp_desc *w, float *coords, unsigned char *valid)
{
    mat4 inv;
    if (!m4_invert(w->view_proj, &inv))
        return -1;
    const float tol = w->depth_tolerance > 0.0f ? w->depth_tolerance : WARP_DEPTH_TOLERANCE_DEFAULT;
    long n_valid = 0;
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
