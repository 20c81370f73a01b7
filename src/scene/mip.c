/* mip.c: premultiplied-alpha mip chains with an exact-area box filter (see mip.h).
 *
 * Each level has size max(1, floor(w/2)) x max(1, floor(h/2)) of the previous one. Destination
 * texel i of a row covers the source interval [i*sw/dw, (i+1)*sw/dw); it takes every source
 * texel it overlaps, weighted by the overlap length over sw/dw. Overlaps are computed in integer
 * units of 1/dw source texel, so the weights of a destination texel sum to 1 and every source
 * texel hands out exactly its own area: the mean of each level equals the mean of the level above
 * (up to float rounding). The filter is separable (rows, then columns) with at most 4 taps per
 * axis, since sw/dw <= 3.
 */
#include "scene/mip.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

/* Inputs are clamped to [0,1] (NaN gives 0): every caller stores the result in a texture or an
 * 8-bit image, and the GLSL twin (texture hardware sRGB decode) saturates the same way. */
float srgb_to_linear(float c)
{
    if (!(c > 0.0f))
        return 0.0f;
    if (c >= 1.0f)
        return 1.0f;
    return c <= 0.04045f ? c / 12.92f : (float)pow((c + 0.055) / 1.055, 2.4);
}

float linear_to_srgb(float c)
{
    if (!(c > 0.0f))
        return 0.0f;
    if (c >= 1.0f)
        return 1.0f;
    return c <= 0.0031308f ? c * 12.92f : (float)(1.055 * pow(c, 1.0 / 2.4) - 0.055);
}

#define MIP_MAX_TAPS 4

typedef struct mip_taps {
    int first, count;
    float w[MIP_MAX_TAPS];
} mip_taps;

/* Weights of the exact-area box filter from sw source texels down to dw (dw <= sw). */
static void mip_make_taps(int sw, int dw, mip_taps *t)
{
    for (int i = 0; i < dw; i++) {
        /* In units of 1/dw source texel: destination i spans [lo, hi), source j spans
         * [j*dw, (j+1)*dw). */
        long long lo = (long long)i * sw, hi = lo + sw;
        int j0 = (int)(lo / dw), j1 = (int)((hi - 1) / dw);
        FS_ASSERT(j1 - j0 + 1 <= MIP_MAX_TAPS);
        t[i].first = j0;
        t[i].count = j1 - j0 + 1;
        for (int j = j0; j <= j1; j++) {
            long long a = (long long)j * dw, b = a + dw;
            if (a < lo)
                a = lo;
            if (b > hi)
                b = hi;
            t[i].w[j - j0] = (float)((double)(b - a) / (double)sw);
        }
    }
}

/* One level down: src (sw x sh) -> dst (dw x dh) through tmp (dw x sh). */
static void mip_downsample(const float *src, int sw, int sh, float *dst, int dw, int dh, float *tmp,
                           const mip_taps *tx, const mip_taps *ty)
{
    for (int y = 0; y < sh; y++) {
        const float *row = src + (size_t)y * sw * 4;
        float *out = tmp + (size_t)y * dw * 4;
        for (int x = 0; x < dw; x++) {
            const mip_taps *t = &tx[x];
            const float *s = row + (size_t)t->first * 4;
            float r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f;
            for (int k = 0; k < t->count; k++) {
                float w = t->w[k];
                r += w * s[4 * k];
                g += w * s[4 * k + 1];
                b += w * s[4 * k + 2];
                a += w * s[4 * k + 3];
            }
            out[4 * x] = r;
            out[4 * x + 1] = g;
            out[4 * x + 2] = b;
            out[4 * x + 3] = a;
        }
    }
    size_t n = (size_t)dw * 4;
    for (int y = 0; y < dh; y++) {
        const mip_taps *t = &ty[y];
        float *out = dst + (size_t)y * n;
        memset(out, 0, n * sizeof *out);
        for (int k = 0; k < t->count; k++) {
            const float *s = tmp + (size_t)(t->first + k) * n;
            float w = t->w[k];
            for (size_t i = 0; i < n; i++)
                out[i] += w * s[i];
        }
    }
}

static int mip_next(int s) { return s / 2 > 1 ? s / 2 : 1; }

fs_status mip_chain_build(const image_rgba8 *img, mip_chain *out)
{
    memset(out, 0, sizeof *out);
    FS_ASSERT(img && img->rgba && img->width >= 1 && img->height >= 1);
    if (!img || !img->rgba || img->width < 1 || img->height < 1)
        return FS_ERR_INTERNAL;

    int levels = 1;
    for (int w = img->width, h = img->height; (w > 1 || h > 1) && levels < MIP_MAX_LEVELS; levels++) {
        w = mip_next(w);
        h = mip_next(h);
    }

    int w = img->width, h = img->height;
    float *tmp = NULL;
    mip_taps *tx = NULL, *ty = NULL;
    if (levels > 1) {
        tmp = malloc((size_t)mip_next(w) * (size_t)h * 4 * sizeof *tmp);
        tx = malloc((size_t)mip_next(w) * sizeof *tx);
        ty = malloc((size_t)mip_next(h) * sizeof *ty);
        if (!tmp || !tx || !ty)
            goto nomem;
    }

    for (int l = 0; l < levels; l++) {
        out->rgba[l] = malloc((size_t)w * (size_t)h * 4 * sizeof(float));
        if (!out->rgba[l])
            goto nomem;
        out->width[l] = w;
        out->height[l] = h;
        out->level_count = l + 1;
        if (l == 0) {
            float lut[256];
            for (int i = 0; i < 256; i++)
                lut[i] = srgb_to_linear((float)i / 255.0f);
            const uint8_t *s = img->rgba;
            float *d = out->rgba[0];
            for (size_t i = 0, n = (size_t)w * (size_t)h; i < n; i++) {
                float a = (float)s[4 * i + 3] / 255.0f;
                d[4 * i] = lut[s[4 * i]] * a;
                d[4 * i + 1] = lut[s[4 * i + 1]] * a;
                d[4 * i + 2] = lut[s[4 * i + 2]] * a;
                d[4 * i + 3] = a;
            }
        } else {
            int pw = out->width[l - 1], ph = out->height[l - 1];
            mip_make_taps(pw, w, tx);
            mip_make_taps(ph, h, ty);
            mip_downsample(out->rgba[l - 1], pw, ph, out->rgba[l], w, h, tmp, tx, ty);
        }
        w = mip_next(w);
        h = mip_next(h);
    }
    free(tmp);
    free(tx);
    free(ty);
    return FS_OK;

nomem:
    free(tmp);
    free(tx);
    free(ty);
    mip_chain_free(out);
    log_error("MIP: [%s] out of memory building the mip chain of a %dx%d image", img->name,
              img->width, img->height);
    return FS_ERR_NOMEM;
}

void mip_chain_free(mip_chain *c)
{
    if (!c)
        return;
    for (int l = 0; l < MIP_MAX_LEVELS; l++)
        free(c->rgba[l]);
    memset(c, 0, sizeof *c);
}

double mip_level_mean_alpha(const mip_chain *c, int level)
{
    if (!c || level < 0 || level >= c->level_count || !c->rgba[level])
        return 0.0;
    size_t n = (size_t)c->width[level] * (size_t)c->height[level];
    const float *p = c->rgba[level];
    double sum = 0.0;
    for (size_t i = 0; i < n; i++)
        sum += p[4 * i + 3];
    return sum / (double)n;
}
