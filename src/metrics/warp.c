/* warp.c: see warp.h. */
#include "metrics/warp.h"

#include <math.h>

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

long warp_previous(const warp_desc *w, const metrics_view *prev, float *const out[4], unsigned char *valid)
{
    mat4 inv;
    if (!m4_invert(w->view_proj, &inv))
        return -1;
    const float tol = w->depth_tolerance > 0.0f ? w->depth_tolerance : WARP_DEPTH_TOLERANCE_DEFAULT;
    const float *src[4] = {prev->r, prev->g, prev->b, prev->coverage};
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
            n_valid += ok;
            for (int c = 0; c < 4; c++)
                out[c][i] = ok ? bilinear(src[c], w->width, w->height, px, py) : 0.0f;
        }
    return n_valid;
}
