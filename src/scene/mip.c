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
#include <stdbool.h>
#include <stdint.h>
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
    for (int l = 0; l < MIP_MAX_LEVELS; l++)
        out->alpha_scale[l] = 1.0f;
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

double mip_level_coverage(const mip_chain *c, int level, float cutoff)
{
    if (!c || level < 0 || level >= c->level_count || !c->rgba[level])
        return 0.0;
    size_t n = (size_t)c->width[level] * (size_t)c->height[level], pass = 0;
    const float *p = c->rgba[level];
    for (size_t i = 0; i < n; i++)
        pass += p[4 * i + 3] >= cutoff;
    return (double)pass / (double)n;
}

/* ---- Coverage-preserving chains (Castano) ----
 *
 * For a level with n texels, count(s) = #{texels: fl(alpha*s) >= cutoff} is non-decreasing in s
 * (float multiplication rounds monotonically), and so is s as a function of its bit pattern for
 * s >= 0. The level's alpha values are sorted once (radix sort on their bit patterns, which order
 * like the values for alpha >= 0); count(s) is then a binary search, and the smallest s with
 * count(s) >= K is a bisection over the bit patterns 0 .. FLT_MAX (at most 32 steps, exact). So a
 * level costs one sort and about 32 * log2(n) multiplications, not one scan per step. Storing
 * min(1, alpha*s) does not change the test for cutoff <= 1, so the counts are those of the result.
 */

#define MIP_S_MAX 0x7F7FFFFFu /* bit pattern of FLT_MAX */

static float mip_bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static uint32_t mip_float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static int mip_cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Sorts keys[0..n) ascending; tmp holds n more. Two LSD passes of 16 bits (qsort when small). */
static void mip_sort_keys(uint32_t *keys, uint32_t *tmp, size_t n, size_t *hist /* 65536 */)
{
    if (n < 4096) {
        qsort(keys, n, sizeof *keys, mip_cmp_u32);
        return;
    }
    for (int pass = 0; pass < 2; pass++) {
        int shift = 16 * pass;
        memset(hist, 0, 65536 * sizeof *hist);
        for (size_t i = 0; i < n; i++)
            hist[(keys[i] >> shift) & 0xFFFFu]++;
        size_t sum = 0;
        for (size_t b = 0; b < 65536; b++) {
            size_t c = hist[b];
            hist[b] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            tmp[hist[(keys[i] >> shift) & 0xFFFFu]++] = keys[i];
        uint32_t *t = keys;
        keys = tmp;
        tmp = t;
    }
    /* Two passes: the result is back in the caller's `keys`. */
}

typedef struct mip_level_alpha {
    const float *v; /* sorted ascending, >= 0 */
    size_t n;
    float cutoff;   /* in (0, 1] */
} mip_level_alpha;

/* Texels passing fl(v*s) >= cutoff, s given by its bit pattern. */
static size_t mip_count(const mip_level_alpha *la, uint32_t s_bits)
{
    float s = mip_bits_float(s_bits);
    size_t lo = 0, hi = la->n; /* first index that passes */
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        float x = la->v[mid] * s;
        if (x >= la->cutoff)
            hi = mid;
        else
            lo = mid + 1;
    }
    return la->n - lo;
}

/* Smallest bit pattern s in [0, MIP_S_MAX] with count(s) >= k; MIP_S_MAX + 1 if none. */
static uint32_t mip_first_scale(const mip_level_alpha *la, size_t k)
{
    uint32_t lo = 0, hi = MIP_S_MAX + 1u;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (mip_count(la, mid) >= k)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The scale for one level (see mip.h for the choice among equally good scales). */
static float mip_castano_scale(const mip_level_alpha *la, double target)
{
    const uint32_t one = mip_float_bits(1.0f);
    size_t k_up = (size_t)ceil(target);
    if (k_up > la->n)
        k_up = la->n;
    uint32_t u_up = mip_first_scale(la, k_up);
    bool have_up = u_up <= MIP_S_MAX;
    size_t c_up = have_up ? mip_count(la, u_up) : 0;
    bool have_dn = u_up > 0;
    size_t c_dn = have_dn ? mip_count(la, u_up - 1u) : 0;

    size_t c;
    uint32_t a, b; /* every s in [a, b] gives count c */
    if (have_up && (!have_dn || (double)c_up - target <= target - (double)c_dn)) {
        c = c_up;
        a = u_up;
        b = mip_first_scale(la, c_up + 1) - 1u;
    } else {
        c = c_dn;
        b = u_up - 1u;
        a = mip_first_scale(la, c_dn);
    }
    if (a <= one && one <= b)
        return 1.0f;
    double sa = mip_bits_float(a), sb = mip_bits_float(b);
    float s;
    if (b >= MIP_S_MAX) /* unbounded above: every texel that can pass passes; a > 1 */
        s = (float)(sa * (1.0 + 1.0 / 1024.0));
    else if (a == 0) /* unbounded below: count 0, b < 1 */
        s = (float)(sb * (1.0 - 1.0 / 1024.0));
    else /* halfway between the bracketing alphas: threshold (cutoff/sa + cutoff/sb) / 2 */
        s = (float)(2.0 * sa * sb / (sa + sb));
    if (!(s > 0.0f) || mip_count(la, mip_float_bits(s)) != c)
        s = mip_bits_float(a == 0 ? b : a);
    return s;
}

/* alpha' = min(1, alpha*s); premultiplied colour scaled by alpha'/alpha and clamped to [0, alpha']. */
static void mip_apply_scale(float *p, size_t n, float s)
{
    for (size_t i = 0; i < n; i++) {
        float *t = p + 4 * i;
        float a = t[3];
        if (!(a > 0.0f))
            continue;
        float na = a * s;
        if (na > 1.0f)
            na = 1.0f;
        float f = na / a;
        for (int ch = 0; ch < 3; ch++) {
            float c = t[ch] * f;
            t[ch] = c > 0.0f ? (c < na ? c : na) : 0.0f;
        }
        t[3] = na;
    }
}

fs_status mip_chain_build_castano(const image_rgba8 *img, float cutoff, mip_chain *out)
{
    if (isnan(cutoff)) {
        memset(out, 0, sizeof *out);
        log_error("MIP: [%s] alpha cutoff is NaN: cannot build a coverage-preserving mip chain",
                  img ? img->name : "");
        return FS_ERR_SCENE;
    }
    fs_status st = mip_chain_build(img, out);
    if (st != FS_OK || out->level_count < 2 || !(cutoff > 0.0f) || cutoff > 1.0f)
        return st;
    double c0 = mip_level_coverage(out, 0, cutoff);
    if (c0 <= 0.0)
        return FS_OK; /* nothing to preserve; no scale can make a level pass nothing either */

    size_t n1 = (size_t)out->width[1] * (size_t)out->height[1];
    uint32_t *keys = malloc(n1 * sizeof *keys), *tmp = malloc(n1 * sizeof *tmp);
    size_t *hist = malloc(65536 * sizeof *hist);
    if (!keys || !tmp || !hist) {
        free(keys);
        free(tmp);
        free(hist);
        mip_chain_free(out);
        log_error("MIP: [%s] out of memory building the coverage-preserving chain of a %dx%d image",
                  img->name, img->width, img->height);
        return FS_ERR_NOMEM;
    }
    for (int l = 1; l < out->level_count; l++) {
        size_t n = (size_t)out->width[l] * (size_t)out->height[l];
        float *p = out->rgba[l];
        for (size_t i = 0; i < n; i++) {
            float a = p[4 * i + 3];
            keys[i] = a > 0.0f ? mip_float_bits(a) : 0u; /* -0 and NaN (never produced) as 0 */
        }
        mip_sort_keys(keys, tmp, n, hist);
        /* keys now holds the sorted bit patterns; tmp (malloc'd, so untyped) becomes the floats. */
        float *v = (float *)(void *)tmp;
        for (size_t i = 0; i < n; i++)
            v[i] = mip_bits_float(keys[i]);
        mip_level_alpha la = {.v = v, .n = n, .cutoff = cutoff};
        float s = mip_castano_scale(&la, c0 * (double)n);
        out->alpha_scale[l] = s;
        if (s != 1.0f)
            mip_apply_scale(p, n, s);
    }
    free(keys);
    free(tmp);
    free(hist);
    return FS_OK;
}

int mip_coverage_drift_level(const mip_chain *c, float cutoff, double tolerance)
{
    double c0 = mip_level_coverage(c, 0, cutoff);
    for (int l = 1; l < c->level_count; l++) {
        double texels = (double)c->width[l] * (double)c->height[l];
        double slack = fmax(tolerance * c0, 1.0 / texels);
        if (fabs(mip_level_coverage(c, l, cutoff) - c0) > slack)
            return l;
    }
    return c->level_count;
}
