/* generators.c: procedural foliage assets (tree, grass, fence, fern), see generators.h.
 *
 * Textures are painted analytically: every stroke and leaf is a signed distance d (texels) and a
 * texel gets coverage clamp(0.5 - d, 0, 1), which gives 1-texel soft edges. Shapes are added until
 * the texture reaches its target share of transparent texels (alpha byte 0), so the share holds
 * for every seed and texture size. Transparent texels then take the colour of the nearest
 * visible texel (chamfer distance transform), the usual dilation of production foliage textures.
 *
 * Every generator draws from its own PCG32 streams (one for the texture, one for the geometry),
 * so the same desc gives byte-identical output, and changing card_count leaves the texture alone.
 */
#include "scene/generators.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

/* >>rng */

/* PCG32 (O'Neill 2014, pcg32_random_r). */
typedef struct gen_rng {
    uint64_t state, inc;
} gen_rng;

static uint32_t rng_u32(gen_rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xs >> rot) | (xs << ((32u - rot) & 31u));
}

static gen_rng rng_make(uint32_t seed, uint64_t stream)
{
    gen_rng r = {0u, (stream << 1u) | 1u};
    rng_u32(&r);
    r.state += seed;
    rng_u32(&r);
    return r;
}

/* Uniform in [0, 1). */
static float rng_float(gen_rng *r) { return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f); }
static float rng_range(gen_rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }
static int rng_int(gen_rng *r, int lo, int hi) { return lo + (int)(rng_u32(r) % (uint32_t)(hi - lo + 1)); }

/* Streams: one per generator and purpose. */
enum { STREAM_TEXTURE = 1, STREAM_GEOMETRY = 2, STREAM_BARK = 3 };

static float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* >>canvas: analytic painting of alpha-mapped textures */

typedef struct canvas {
    int n;            /* edge in texels */
    float *a;         /* coverage (straight alpha) per texel */
    float *rgb;       /* sRGB colour on a 0..255 scale, 3 per texel */
    long transparent; /* texels whose 8-bit alpha is still 0 */
} canvas;

static int alpha_byte(float a) { return (int)(clampf(a, 0.0f, 1.0f) * 255.0f + 0.5f); }

static bool canvas_init(canvas *c, int n)
{
    size_t t = (size_t)n * (size_t)n;
    c->n = n;
    c->a = calloc(t, sizeof *c->a);
    c->rgb = calloc(t * 3, sizeof *c->rgb);
    c->transparent = (long)t;
    return c->a && c->rgb;
}

static void canvas_clear(canvas *c)
{
    size_t t = (size_t)c->n * (size_t)c->n;
    memset(c->a, 0, t * sizeof *c->a);
    memset(c->rgb, 0, t * 3 * sizeof *c->rgb);
    c->transparent = (long)t;
}

static void canvas_free(canvas *c)
{
    free(c->a);
    free(c->rgb);
    memset(c, 0, sizeof *c);
}

static double canvas_transparent_fraction(const canvas *c)
{
    return (double)c->transparent / ((double)c->n * (double)c->n);
}

/* Paints coverage `cov` of colour `col` at a texel. Alpha takes the maximum (so strokes built from
 * several segments do not double their soft edges where the segments meet); colour moves towards
 * `col` by the new coverage. With `tint_only` only visible texels change colour (veins). */
static void canvas_put(canvas *c, int x, int y, float cov, const float col[3], bool tint_only)
{
    if (!(cov > 0.0f) || x < 0 || y < 0 || x >= c->n || y >= c->n)
        return;
    if (cov > 1.0f)
        cov = 1.0f;
    size_t i = (size_t)y * (size_t)c->n + (size_t)x;
    float old = c->a[i], *rgb = &c->rgb[3 * i];
    if (tint_only) {
        if (old <= 0.0f)
            return;
    } else if (cov > old) {
        if (alpha_byte(old) == 0 && alpha_byte(cov) > 0)
            c->transparent--;
        c->a[i] = cov;
    }
    float t = old > 0.0f ? cov : 1.0f;
    for (int k = 0; k < 3; k++)
        rgb[k] += (col[k] - rgb[k]) * t;
}

/* A tapered stroke from (x0,y0) to (x1,y1), width w0 -> w1 texels (full width), colour col0 ->
 * col1. Coordinates are continuous texel units (texel centres at +0.5). Visits only the rows and
 * column spans the stroke can touch. */
static void canvas_stroke(canvas *c, float x0, float y0, float x1, float y1, float w0, float w1,
                          const float col0[3], const float col1[3], bool tint_only)
{
    float dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    float r0 = 0.5f * w0, r1 = 0.5f * w1, R = fmaxf(r0, r1) + 0.5f; /* reach incl. soft edge */
    int ya = (int)floorf(fminf(y0, y1) - R), yb = (int)ceilf(fmaxf(y0, y1) + R);
    if (ya < 0)
        ya = 0;
    if (yb > c->n - 1)
        yb = c->n - 1;
    for (int y = ya; y <= yb; y++) {
        float yc = (float)y + 0.5f;
        /* Segment parameters whose y lies within R of this row. */
        float ta = 0.0f, tb = 1.0f;
        if (fabsf(dy) > 1e-6f) {
            ta = (yc - R - y0) / dy;
            tb = (yc + R - y0) / dy;
            if (ta > tb) {
                float s = ta;
                ta = tb;
                tb = s;
            }
            ta = fmaxf(ta, 0.0f);
            tb = fminf(tb, 1.0f);
            if (ta > tb)
                continue;
        } else if (fabsf(yc - y0) > R) {
            continue;
        }
        float xa = fminf(x0 + dx * ta, x0 + dx * tb) - R, xb = fmaxf(x0 + dx * ta, x0 + dx * tb) + R;
        int ia = (int)floorf(xa), ib = (int)ceilf(xb);
        if (ia < 0)
            ia = 0;
        if (ib > c->n - 1)
            ib = c->n - 1;
        for (int x = ia; x <= ib; x++) {
            float px = (float)x + 0.5f - x0, py = yc - y0;
            float t = len2 > 0.0f ? clampf((px * dx + py * dy) / len2, 0.0f, 1.0f) : 0.0f;
            float ex = px - dx * t, ey = py - dy * t;
            float d = sqrtf(ex * ex + ey * ey) - (r0 + (r1 - r0) * t);
            float cov = 0.5f - d;
            if (cov <= 0.0f)
                continue;
            float col[3];
            for (int k = 0; k < 3; k++)
                col[k] = col0[k] + (col1[k] - col0[k]) * t;
            canvas_put(c, x, y, cov, col, tint_only);
        }
    }
}

/* A filled ellipse, semi-axes ra (along angle `ang`) and rb, colour lighter at the centre. Uses
 * the usual first-order distance approximation d = k0 (k0 - 1) / k1. */
static void canvas_ellipse(canvas *c, float cx, float cy, float ra, float rb, float ang,
                           const float col[3])
{
    float ca = cosf(ang), sa = sinf(ang), R = ra + 1.0f;
    int ya = (int)floorf(cy - R), yb = (int)ceilf(cy + R), xa = (int)floorf(cx - R), xb = (int)ceilf(cx + R);
    if (ya < 0)
        ya = 0;
    if (xa < 0)
        xa = 0;
    if (yb > c->n - 1)
        yb = c->n - 1;
    if (xb > c->n - 1)
        xb = c->n - 1;
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++) {
            float px = (float)x + 0.5f - cx, py = (float)y + 0.5f - cy;
            float u = px * ca + py * sa, v = -px * sa + py * ca;
            float k0 = sqrtf((u * u) / (ra * ra) + (v * v) / (rb * rb));
            float k1 = sqrtf((u * u) / (ra * ra * ra * ra) + (v * v) / (rb * rb * rb * rb));
            float d = k1 > 0.0f ? k0 * (k0 - 1.0f) / k1 : -rb;
            float cov = 0.5f - d;
            if (cov <= 0.0f)
                continue;
            float shade = 1.08f - 0.16f * fminf(k0, 1.0f), cc[3];
            for (int k = 0; k < 3; k++)
                cc[k] = fminf(col[k] * shade, 255.0f);
            canvas_put(c, x, y, cov, cc, false);
        }
}

/* Fills the colour of transparent texels with the colour of the nearest visible one (two-pass
 * chamfer distance transform, 8-neighbourhood), so filtering straight-alpha data or a consumer
 * that ignores alpha never sees black fringes. */
static bool canvas_dilate(canvas *c)
{
    int n = c->n;
    size_t t = (size_t)n * (size_t)n;
    float *dist = malloc(t * sizeof *dist);
    uint32_t *src = malloc(t * sizeof *src);
    if (!dist || !src) {
        free(dist);
        free(src);
        return false;
    }
    bool any = false;
    for (size_t i = 0; i < t; i++) {
        bool vis = alpha_byte(c->a[i]) > 0;
        dist[i] = vis ? 0.0f : INFINITY;
        src[i] = (uint32_t)i;
        any = any || vis;
    }
    if (any) {
        static const int off[4][2] = {{-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
        static const float w[4] = {1.0f, 1.41421356f, 1.0f, 1.41421356f};
        for (int pass = 0; pass < 2; pass++) {
            int s = pass == 0 ? 1 : -1;
            for (int yy = 0; yy < n; yy++)
                for (int xx = 0; xx < n; xx++) {
                    int y = pass == 0 ? yy : n - 1 - yy, x = pass == 0 ? xx : n - 1 - xx;
                    size_t i = (size_t)y * n + x;
                    for (int k = 0; k < 4; k++) {
                        int nx = x + s * off[k][0], ny = y + s * off[k][1];
                        if (nx < 0 || ny < 0 || nx >= n || ny >= n)
                            continue;
                        size_t j = (size_t)ny * n + nx;
                        if (dist[j] + w[k] < dist[i]) {
                            dist[i] = dist[j] + w[k];
                            src[i] = src[j];
                        }
                    }
                }
        }
        for (size_t i = 0; i < t; i++)
            if (src[i] != i)
                memcpy(&c->rgb[3 * i], &c->rgb[3 * (size_t)src[i]], 3 * sizeof(float));
    }
    free(dist);
    free(src);
    return true;
}

/* Moves the canvas into an RGBA8 image (dilating first). */
static bool canvas_to_image(canvas *c, const char *name, image_rgba8 *img)
{
    if (!canvas_dilate(c))
        return false;
    size_t t = (size_t)c->n * (size_t)c->n;
    img->rgba = malloc(t * 4);
    if (!img->rgba)
        return false;
    img->width = img->height = c->n;
    snprintf(img->name, sizeof img->name, "%s", name);
    for (size_t i = 0; i < t; i++) {
        for (int k = 0; k < 3; k++)
            img->rgba[4 * i + k] = (uint8_t)(clampf(c->rgb[3 * i + k], 0.0f, 255.0f) + 0.5f);
        img->rgba[4 * i + 3] = (uint8_t)alpha_byte(c->a[i]);
    }
    return true;
}

/* >>textures */

static void rgb_jitter(gen_rng *r, const float base[3], float amount, float out[3])
{
    float s = rng_range(r, 1.0f - amount, 1.0f + amount);
    for (int k = 0; k < 3; k++)
        out[k] = clampf(base[k] * s * rng_range(r, 0.95f, 1.05f), 0.0f, 255.0f);
}

/* Leaf card: a branching twig with elliptic leaves on 1-3 texel stems, transparent padding
 * around, painted until 55-70 % of texels are transparent (target 64 %). */
static bool tex_leaves(uint32_t seed, int n, image_rgba8 *img)
{
    canvas c;
    if (!canvas_init(&c, n)) {
        canvas_free(&c);
        return false;
    }
    gen_rng r = rng_make(seed, STREAM_TEXTURE);
    const float pad = fmaxf(1.0f, (float)n / 32.0f), lo = pad, hi = (float)n - pad;
    const float twig_col[3] = {92, 70, 44}, twig_tip[3] = {96, 110, 50};
    const float leaf_cols[3][3] = {{62, 118, 40}, {88, 140, 48}, {50, 98, 36}};
    const float vein[3] = {120, 160, 70};

    /* Twigs: a main twig up the middle and alternate side twigs, as (x0,y0,x1,y1,w0,w1). */
    float tw[8][6];
    int ntw = 0;
    float bx = (float)n * 0.5f + rng_range(&r, -0.05f, 0.05f) * (float)n, by = hi - 1.0f;
    float tx = (float)n * 0.5f + rng_range(&r, -0.1f, 0.1f) * (float)n, ty = lo + 0.12f * (float)n;
    tw[ntw][0] = bx, tw[ntw][1] = by, tw[ntw][2] = tx, tw[ntw][3] = ty, tw[ntw][4] = 3.0f, tw[ntw][5] = 1.5f;
    ntw++;
    int sides = 5;
    for (int i = 0; i < sides; i++) {
        float t = 0.18f + 0.14f * (float)i + rng_range(&r, -0.03f, 0.03f);
        float sx = bx + (tx - bx) * t, sy = by + (ty - by) * t;
        float side = (i & 1) ? 1.0f : -1.0f;
        float ang = side * rng_range(&r, 0.6f, 1.0f); /* from vertical */
        float len = (float)n * rng_range(&r, 0.22f, 0.34f) * (1.0f - 0.5f * t);
        float ex = clampf(sx + sinf(ang) * len, lo + 2.0f, hi - 2.0f);
        float ey = clampf(sy - cosf(ang) * len, lo + 2.0f, hi - 2.0f);
        tw[ntw][0] = sx, tw[ntw][1] = sy, tw[ntw][2] = ex, tw[ntw][3] = ey, tw[ntw][4] = 2.0f, tw[ntw][5] = 1.0f;
        ntw++;
    }
    for (int i = 0; i < ntw; i++)
        canvas_stroke(&c, tw[i][0], tw[i][1], tw[i][2], tw[i][3], tw[i][4], tw[i][5], twig_col, twig_tip, false);

    /* Leaves: best of 4 candidate placements (most still-transparent texels under the leaf),
     * which spreads them over the card instead of piling them on the twigs. */
    const double target = 0.64;
    for (int attempt = 0; attempt < 4000 && canvas_transparent_fraction(&c) > target; attempt++) {
        float best[7] = {0}; /* attach x, y, centre x, y, ra, rb, angle */
        int best_score = -1;
        for (int cand = 0; cand < 4; cand++) {
            const float *w = tw[rng_int(&r, 0, ntw - 1)];
            float t = rng_range(&r, 0.15f, 1.0f);
            float px = w[0] + (w[2] - w[0]) * t, py = w[1] + (w[3] - w[1]) * t;
            float ang = atan2f(w[3] - w[1], w[2] - w[0]) +
                        (rng_float(&r) < 0.5f ? -1.0f : 1.0f) * rng_range(&r, 0.5f, 1.2f);
            float ra = (float)n * rng_range(&r, 0.055f, 0.09f), rb = ra * rng_range(&r, 0.36f, 0.5f);
            float stem = (float)n * rng_range(&r, 0.015f, 0.045f) + 1.0f;
            float ca = cosf(ang), sa = sinf(ang);
            float cx = px + ca * (stem + ra), cy = py + sa * (stem + ra);
            if (cx - ra - 1.0f < lo || cx + ra + 1.0f > hi || cy - ra - 1.0f < lo || cy + ra + 1.0f > hi)
                continue;
            int score = 0;
            for (int k = 0; k < 9; k++) {
                float su = k == 0 ? 0.0f : 0.6f * ra * cosf((float)k * 0.785398f);
                float sv = k == 0 ? 0.0f : 0.6f * rb * sinf((float)k * 0.785398f);
                int qx = (int)(cx + su * ca - sv * sa), qy = (int)(cy + su * sa + sv * ca);
                if (qx >= 0 && qy >= 0 && qx < n && qy < n && c.a[(size_t)qy * n + qx] <= 0.0f)
                    score++;
            }
            if (score > best_score) {
                best_score = score;
                float b[7] = {px, py, cx, cy, ra, rb, ang};
                memcpy(best, b, sizeof b);
            }
        }
        if (best_score < 0)
            continue;
        float px = best[0], py = best[1], cx = best[2], cy = best[3], ra = best[4], rb = best[5], ang = best[6];
        float col[3];
        rgb_jitter(&r, leaf_cols[rng_int(&r, 0, 2)], 0.12f, col);
        float sw = rng_range(&r, 1.0f, 3.0f);
        float sx = cx - cosf(ang) * ra * 0.7f, sy = cy - sinf(ang) * ra * 0.7f;
        canvas_stroke(&c, px, py, sx, sy, sw, fmaxf(1.0f, sw * 0.7f), twig_tip, col, false);
        canvas_ellipse(&c, cx, cy, ra, rb, ang, col);
        /* Midrib: colour only, the leaf outline stays the ellipse. */
        canvas_stroke(&c, sx, sy, cx + cosf(ang) * ra * 0.8f, cy + sinf(ang) * ra * 0.8f, 1.0f, 1.0f,
                      vein, vein, true);
    }
    bool ok = canvas_to_image(&c, "tree_leaves", img);
    canvas_free(&c);
    return ok;
}

/* Grass tuft: thin curved blades (1-4 texels at the base, 1 at the tip) rising from the bottom
 * edge, side padding, painted until 60-75 % of texels are transparent (target 70 %). */
static bool tex_blades(uint32_t seed, int n, image_rgba8 *img)
{
    canvas c;
    if (!canvas_init(&c, n)) {
        canvas_free(&c);
        return false;
    }
    gen_rng r = rng_make(seed, STREAM_TEXTURE);
    const float pad = fmaxf(1.0f, (float)n / 32.0f), lo = pad + 1.0f, hi = (float)n - pad - 1.0f;
    const float base_col[3] = {58, 92, 30}, tip_col[3] = {150, 176, 80};
    const double target = 0.70;
    for (int blade = 0; blade < 100000 && canvas_transparent_fraction(&c) > target; blade++) {
        float x0 = rng_range(&r, lo + 2.0f, hi - 2.0f), y0 = (float)n;
        float h = (float)n * rng_range(&r, 0.4f, 0.92f);
        float lean = h * rng_range(&r, -0.35f, 0.35f);
        float x2 = clampf(x0 + lean, lo, hi), y2 = (float)n - h;
        float x1 = x0 + lean * rng_range(&r, 0.0f, 0.3f), y1 = (float)n - h * 0.6f; /* bend */
        float w0 = rng_range(&r, 1.5f, 4.0f);
        float cb[3], ct[3];
        rgb_jitter(&r, base_col, 0.15f, cb);
        rgb_jitter(&r, tip_col, 0.12f, ct);
        const int segs = 8;
        float px = x0, py = y0;
        for (int s = 1; s <= segs; s++) {
            float t = (float)s / (float)segs, u = 1.0f - t;
            float qx = u * u * x0 + 2.0f * u * t * x1 + t * t * x2;
            float qy = u * u * y0 + 2.0f * u * t * y1 + t * t * y2;
            float t0 = (float)(s - 1) / (float)segs;
            float ca[3], cz[3];
            for (int k = 0; k < 3; k++) {
                ca[k] = cb[k] + (ct[k] - cb[k]) * t0;
                cz[k] = cb[k] + (ct[k] - cb[k]) * t;
            }
            canvas_stroke(&c, px, py, qx, qy, w0 + (1.0f - w0) * t0, w0 + (1.0f - w0) * t, ca, cz, false);
            px = qx;
            py = qy;
        }
    }
    bool ok = canvas_to_image(&c, "grass_blades", img);
    canvas_free(&c);
    return ok;
}

/* Share of a unit texel inside the band |x| <= r around a 45-degree line whose axis is `delta`
 * texels (perpendicular) from the texel centre. The texel's projection on the line's normal has a
 * triangular density on [-h, h], h = sqrt(2)/2, so this is exact area coverage, not an
 * approximation. */
static float diag_band_coverage(float delta, float r)
{
    const float h = 0.70710678f;
    float hi = r - delta, lo = -r - delta, F[2];
    for (int k = 0; k < 2; k++) {
        float t = clampf(k == 0 ? hi : lo, -h, h);
        F[k] = t < 0.0f ? (t + h) * (t + h) : 2.0f * h * h - (h - t) * (h - t); /* 2h^2 = 1 */
    }
    return clampf(F[0] - F[1], 0.0f, 1.0f);
}

/* One chain-link cell: wires along both diagonals, `wire` texels thick (measured across the
 * wire), joining seamlessly when the tile repeats; exact area coverage gives the soft edges. No
 * padding (the tile must wrap). Metallic grey, brighter along the wire axis. */
static bool tex_wire(int n, int wire, image_rgba8 *img)
{
    img->rgba = malloc((size_t)n * (size_t)n * 4);
    if (!img->rgba)
        return false;
    img->width = img->height = n;
    snprintf(img->name, sizeof img->name, "%s", "fence_wire");
    const float grey[3] = {150, 156, 162}, r = 0.5f * (float)wire, fn = (float)n;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            float px = (float)x + 0.5f, py = (float)y + 0.5f, cov = 0.0f, best = INFINITY;
            for (int k = 0; k < 2; k++) {
                /* Offset along x to the nearest wire of this family, then across the wire. */
                float u = fmodf(k == 0 ? px - py + fn : px + py, fn);
                float dist = fminf(u, fn - u) * 0.70710678f;
                cov = fmaxf(cov, diag_band_coverage(dist, r));
                best = fminf(best, dist);
            }
            float shade = 1.15f - 0.35f * clampf(best / (r + 0.7f), 0.0f, 1.0f);
            uint8_t *p = &img->rgba[4 * ((size_t)y * n + x)];
            for (int k = 0; k < 3; k++)
                p[k] = (uint8_t)(clampf(grey[k] * (cov > 0.0f ? shade : 1.0f), 0.0f, 255.0f) + 0.5f);
            p[3] = (uint8_t)alpha_byte(cov);
        }
    return true;
}

/* Fern frond along the card's vertical axis: a 2-texel rachis and many 1-2 texel pinnae whose
 * length follows the frond outline (widest a third of the way up). */
static void fern_paint(canvas *c, uint32_t seed, float spacing)
{
    gen_rng r = rng_make(seed, STREAM_TEXTURE);
    int n = c->n;
    const float pad = fmaxf(1.0f, (float)n / 32.0f), fn = (float)n;
    const float rach_col[3] = {70, 96, 36}, pin_base[3] = {52, 104, 38}, pin_tip[3] = {96, 150, 56};
    float cx = fn * 0.5f, y_base = fn - pad, y_tip = pad + 1.0f, len = y_base - y_tip;
    float max_l = fn * 0.5f - pad - 2.0f;
    canvas_stroke(c, cx, y_base, cx, y_tip, 2.0f, 2.0f, rach_col, rach_col, false);
    int pairs = (int)(len / spacing);
    for (int i = 0; i < pairs; i++) {
        for (int side = -1; side <= 1; side += 2) {
            /* Alternate sides are offset by half a spacing, as in real fronds. */
            float t = ((float)i + (side > 0 ? 0.5f : 0.0f)) * spacing / len + 0.04f;
            if (t > 0.985f)
                continue;
            float prof = sinf((float)FS_PI * (0.1f + 0.9f * powf(t, 0.8f)));
            float l = max_l * prof * rng_range(&r, 0.85f, 1.05f);
            float ang = rng_range(&r, 0.95f, 1.15f); /* from the rachis, pointing up and out */
            float y0 = y_base - t * len, x0 = cx + (float)side * 1.0f;
            float x1 = clampf(x0 + (float)side * sinf(ang) * l, pad + 1.0f, fn - pad - 1.0f);
            float y1 = clampf(y0 - cosf(ang) * l, pad + 1.0f, fn - pad - 1.0f);
            float w0 = rng_range(&r, 1.6f, 2.0f);
            canvas_stroke(c, x0, y0, x1, y1, w0, 1.0f, pin_base, pin_tip, false);
        }
    }
}

/* Picks the pinna spacing that brings the transparent share near 66 % (range 55-75 %): the
 * opaque area is close to proportional to 1/spacing, so a few secant steps converge. */
static bool tex_fern(uint32_t seed, int n, image_rgba8 *img)
{
    canvas c;
    if (!canvas_init(&c, n)) {
        canvas_free(&c);
        return false;
    }
    const double target = 0.66;
    float spacing = 4.5f, best_spacing = spacing;
    double best_err = INFINITY;
    for (int it = 0; it < 6; it++) {
        canvas_clear(&c);
        fern_paint(&c, seed, spacing);
        double tf = canvas_transparent_fraction(&c), err = fabs(tf - target);
        if (err < best_err) {
            best_err = err;
            best_spacing = spacing;
        }
        if (err < 0.02)
            break;
        spacing = clampf(spacing * (float)((1.0 - tf) / (1.0 - target)), 2.0f, (float)n);
    }
    canvas_clear(&c);
    fern_paint(&c, seed, best_spacing);
    bool ok = canvas_to_image(&c, "fern_fronds", img);
    canvas_free(&c);
    return ok;
}

/* Opaque bark: vertical streaks and darker cracks, 64 x 64, tiles horizontally. */
static bool tex_bark(uint32_t seed, image_rgba8 *img)
{
    const int n = 64;
    img->rgba = malloc((size_t)n * n * 4);
    if (!img->rgba)
        return false;
    img->width = img->height = n;
    snprintf(img->name, sizeof img->name, "%s", "tree_bark");
    gen_rng r = rng_make(seed, STREAM_BARK);
    float colv[64];
    for (int x = 0; x < n; x++)
        colv[x] = rng_range(&r, 0.75f, 1.15f);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            float s = 0.5f * colv[x] + 0.25f * colv[(x + 1) % n] + 0.25f * colv[(x + n - 1) % n];
            s *= rng_range(&r, 0.9f, 1.1f);
            if (rng_float(&r) < 0.04f)
                s *= 0.6f;
            uint8_t *p = &img->rgba[4 * ((size_t)y * n + x)];
            p[0] = (uint8_t)clampf(96.0f * s, 0.0f, 255.0f);
            p[1] = (uint8_t)clampf(72.0f * s, 0.0f, 255.0f);
            p[2] = (uint8_t)clampf(50.0f * s, 0.0f, 255.0f);
            p[3] = 255;
        }
    return true;
}

/* >>mesh builder */

typedef struct mesh_b {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    uint32_t nv, ni, cap_v, cap_i;
    bool oom;
} mesh_b;

static bool mb_reserve(mesh_b *m, uint32_t add_v, uint32_t add_i)
{
    if (m->oom)
        return false;
    if (m->nv + add_v > m->cap_v) {
        uint32_t cap = m->cap_v ? m->cap_v : 64;
        while (cap < m->nv + add_v)
            cap *= 2;
        float *p = realloc(m->pos, sizeof(float) * 3 * cap);
        if (p)
            m->pos = p;
        float *q = realloc(m->nrm, sizeof(float) * 3 * cap);
        if (q)
            m->nrm = q;
        float *u = realloc(m->uv, sizeof(float) * 2 * cap);
        if (u)
            m->uv = u;
        if (!p || !q || !u)
            return !(m->oom = true);
        m->cap_v = cap;
    }
    if (m->ni + add_i > m->cap_i) {
        uint32_t cap = m->cap_i ? m->cap_i : 96;
        while (cap < m->ni + add_i)
            cap *= 2;
        uint32_t *p = realloc(m->idx, sizeof(uint32_t) * cap);
        if (!p)
            return !(m->oom = true);
        m->idx = p;
        m->cap_i = cap;
    }
    return true;
}

static uint32_t mb_vertex(mesh_b *m, vec3 p, vec3 n, float u, float v)
{
    uint32_t i = m->nv++;
    m->pos[3 * i] = p.x, m->pos[3 * i + 1] = p.y, m->pos[3 * i + 2] = p.z;
    m->nrm[3 * i] = n.x, m->nrm[3 * i + 1] = n.y, m->nrm[3 * i + 2] = n.z;
    m->uv[2 * i] = u, m->uv[2 * i + 1] = v;
    return i;
}

static void mb_tri(mesh_b *m, uint32_t a, uint32_t b, uint32_t c)
{
    m->idx[m->ni++] = a;
    m->idx[m->ni++] = b;
    m->idx[m->ni++] = c;
}

/* A quad p0 p1 p2 p3 (around its edge) with UVs uv[0..3], wound so its geometric normal agrees
 * with `n` (stored on all four vertices). */
static void mb_quad(mesh_b *m, const vec3 p[4], const float uv[4][2], vec3 n)
{
    if (!mb_reserve(m, 4, 6))
        return;
    uint32_t b = m->nv;
    for (int k = 0; k < 4; k++)
        mb_vertex(m, p[k], n, uv[k][0], uv[k][1]);
    vec3 g = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
    if (v3_dot(g, n) >= 0.0f) {
        mb_tri(m, b, b + 1, b + 2);
        mb_tri(m, b, b + 2, b + 3);
    } else {
        mb_tri(m, b, b + 2, b + 1);
        mb_tri(m, b, b + 3, b + 2);
    }
}

/* A card centred at c spanning `up` (texture top at +up) and `side` (texture left at -side),
 * each a full-edge vector. Normal = side x up. */
static void mb_card(mesh_b *m, vec3 c, vec3 side, vec3 up)
{
    vec3 hs = v3_scale(side, 0.5f), hu = v3_scale(up, 0.5f);
    vec3 p[4] = {v3_sub(v3_sub(c, hs), hu), v3_sub(v3_add(c, hs), hu), v3_add(v3_add(c, hs), hu),
                 v3_add(v3_sub(c, hs), hu)};
    const float uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    mb_quad(m, p, uv, v3_norm_or(v3_cross(side, up), v3(0, 0, 1)));
}

/* An axis-aligned box [lo, hi] with outward face normals; UVs span each face. */
static void mb_box(mesh_b *m, vec3 lo, vec3 hi)
{
    const float uv[4][2] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (int axis = 0; axis < 3; axis++)
        for (int sgn = 0; sgn < 2; sgn++) {
            float f = sgn ? (&hi.x)[axis] : (&lo.x)[axis];
            int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            vec3 p[4], n = v3(0, 0, 0);
            (&n.x)[axis] = sgn ? 1.0f : -1.0f;
            for (int k = 0; k < 4; k++) {
                float *q = &p[k].x;
                q[axis] = f;
                q[a1] = (k == 1 || k == 2) ? (&hi.x)[a1] : (&lo.x)[a1];
                q[a2] = (k >= 2) ? (&hi.x)[a2] : (&lo.x)[a2];
            }
            mb_quad(m, p, uv, n);
        }
}

/* Moves the builder into a prim (colours 1). */
static bool mb_finish(mesh_b *m, int material_index, prim *out)
{
    memset(out, 0, sizeof *out);
    if (m->oom || m->nv == 0)
        return false;
    out->colors = malloc(sizeof(float) * 4 * m->nv);
    if (!out->colors)
        return false;
    for (uint32_t i = 0; i < 4 * m->nv; i++)
        out->colors[i] = 1.0f;
    out->vertex_count = m->nv;
    out->index_count = m->ni;
    out->positions = m->pos;
    out->normals = m->nrm;
    out->uvs = m->uv;
    out->indices = m->idx;
    out->material = material_index;
    memset(m, 0, sizeof *m);
    return true;
}

static void mb_free(mesh_b *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

/* >>asset assembly */

static bool asset_alloc(asset *a, const char *name, int prims, int materials, int images)
{
    memset(a, 0, sizeof *a);
    snprintf(a->name, sizeof a->name, "%s", name);
    a->source = ASSET_SOURCE_GENERATOR;
    a->prims = calloc((size_t)prims, sizeof *a->prims);
    a->materials = calloc((size_t)materials, sizeof *a->materials);
    a->images = images ? calloc((size_t)images, sizeof *a->images) : NULL;
    if (!a->prims || !a->materials || (images && !a->images)) {
        asset_free(a);
        return false;
    }
    a->prim_count = prims;
    a->material_count = materials;
    a->image_count = images;
    return true;
}

static material mat_foliage(const char *name, int image, float cutoff, tex_wrap wrap)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    for (int k = 0; k < 4; k++)
        m.base_color[k] = 1.0f;
    m.base_color_image = image;
    m.wrap_s = m.wrap_t = wrap;
    m.mag_filter = TEX_FILTER_LINEAR;
    m.alpha_kind = ALPHA_KIND_MASK;
    m.alpha_cutoff = cutoff;
    m.double_sided = true;
    m.alpha_mode = ALPHA_MODE_DEFAULT;
    return m;
}

static material mat_opaque(const char *name, int image, float r, float g, float b)
{
    material m;
    memset(&m, 0, sizeof m);
    snprintf(m.name, sizeof m.name, "%s", name);
    m.base_color[0] = r, m.base_color[1] = g, m.base_color[2] = b, m.base_color[3] = 1.0f;
    m.base_color_image = image;
    m.wrap_s = m.wrap_t = TEX_WRAP_REPEAT;
    m.mag_filter = TEX_FILTER_LINEAR;
    m.alpha_kind = ALPHA_KIND_OPAQUE;
    m.alpha_cutoff = 0.5f;
    m.double_sided = false;
    return m;
}

static fs_status gen_fail_nomem(const char *gen, asset *out, mesh_b *m1, mesh_b *m2)
{
    if (m1)
        mb_free(m1);
    if (m2)
        mb_free(m2);
    asset_free(out);
    log_error("generator %s: out of memory", gen);
    return FS_ERR_NOMEM;
}

/* >>validation */

static bool check_pow2(const char *gen, const char *field, int v)
{
    if (v >= 8 && v <= 4096 && (v & (v - 1)) == 0)
        return true;
    log_error("generator %s: %s: expected a power of two in [8, 4096], got %d", gen, field, v);
    return false;
}

static bool check_int(const char *gen, const char *field, int v, int lo, int hi)
{
    if (v >= lo && v <= hi)
        return true;
    log_error("generator %s: %s: expected an integer in [%d, %d], got %d", gen, field, lo, hi, v);
    return false;
}

/* World sizes: finite, > 0 and at most 100 km (beyond that float positions lose the texel). */
static bool check_size(const char *gen, const char *field, float v)
{
    if (isfinite(v) && v > 0.0f && v <= 1e5f)
        return true;
    log_error("generator %s: %s: expected a finite size in (0, 100000] metres, got %g", gen, field, (double)v);
    return false;
}

static bool check_cutoff(const char *gen, float v)
{
    if (isfinite(v) && v > 0.0f && v <= 1.0f)
        return true;
    log_error("generator %s: alpha_cutoff: expected a number in (0, 1], got %g", gen, (double)v);
    return false;
}

/* >>defaults */

gen_tree_desc gen_tree_defaults(const gen_tree_desc *d)
{
    gen_tree_desc r = d ? *d : (gen_tree_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.height == 0.0f) r.height = 6.0f;
    if (r.crown_radius == 0.0f) r.crown_radius = 2.0f;
    if (r.card_count == 0) r.card_count = 60;
    if (r.card_size == 0.0f) r.card_size = 1.2f;
    if (r.texture_size == 0) r.texture_size = 256;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_grass_desc gen_grass_defaults(const gen_grass_desc *d)
{
    gen_grass_desc r = d ? *d : (gen_grass_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.extent == 0.0f) r.extent = 10.0f;
    if (r.card_count == 0) r.card_count = 400;
    if (r.blade_height == 0.0f) r.blade_height = 0.5f;
    if (r.texture_size == 0) r.texture_size = 128;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_fence_desc gen_fence_defaults(const gen_fence_desc *d)
{
    gen_fence_desc r = d ? *d : (gen_fence_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.length == 0.0f) r.length = 10.0f;
    if (r.height == 0.0f) r.height = 2.0f;
    if (r.cell_size == 0.0f) r.cell_size = 0.1f;
    if (r.texture_size == 0) r.texture_size = 64;
    if (r.wire_texels == 0) r.wire_texels = 3;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

gen_fern_desc gen_fern_defaults(const gen_fern_desc *d)
{
    gen_fern_desc r = d ? *d : (gen_fern_desc){0};
    if (r.seed == 0) r.seed = 1;
    if (r.size == 0.0f) r.size = 1.0f;
    if (r.frond_count == 0) r.frond_count = 8;
    if (r.texture_size == 0) r.texture_size = 128;
    if (r.alpha_cutoff == 0.0f) r.alpha_cutoff = 0.5f;
    return r;
}

/* >>tree */

/* A random unit vector (uniform on the sphere). */
static vec3 rng_dir(gen_rng *r)
{
    float z = rng_range(r, -1.0f, 1.0f), phi = rng_range(r, 0.0f, 2.0f * (float)FS_PI);
    float s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return v3(s * cosf(phi), z, s * sinf(phi));
}

/* Any unit vector perpendicular to unit vector a. */
static vec3 perp(vec3 a)
{
    vec3 t = fabsf(a.y) < 0.9f ? v3(0, 1, 0) : v3(1, 0, 0);
    return v3_norm_or(v3_cross(a, t), v3(1, 0, 0));
}

fs_status gen_tree(const gen_tree_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_tree_desc d = gen_tree_defaults(desc);
    const char *g = "tree";
    if (!check_size(g, "height", d.height) || !check_size(g, "crown_radius", d.crown_radius) ||
        !check_int(g, "card_count", d.card_count, 1, 100000) || !check_size(g, "card_size", d.card_size) ||
        !check_pow2(g, "texture_size", d.texture_size) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "tree", 2, 2, 2))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!tex_leaves(d.seed, d.texture_size, &out->images[0]) || !tex_bark(d.seed, &out->images[1]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("leaves", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);
    out->materials[1] = mat_opaque("bark", 1, 1.0f, 1.0f, 1.0f);

    /* Crown: an ellipsoid (R, Rv, R) whose top touches `height`; leaf clusters inside it, shrunk
     * by half a card so cards stay near the crown's surface. */
    float H = d.height, R = d.crown_radius, s = d.card_size;
    float Rv = fminf(1.2f * R, 0.45f * H), cy = H - Rv;
    float ir = fmaxf(R - 0.5f * s, 0.3f * R), irv = fmaxf(Rv - 0.5f * s, 0.3f * Rv);
    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);

    mesh_b leaves = {0}, trunk = {0};
    for (int i = 0; i < d.card_count; i++) {
        /* Radius u^(1/4): clusters favour the outer shell, as foliage on a real crown does. */
        vec3 dir = rng_dir(&r);
        float rad = powf(rng_float(&r), 0.25f);
        vec3 c = v3(dir.x * ir * rad, cy + dir.y * irv * rad, dir.z * ir * rad);
        /* Card "up" points away from the crown centre, jittered: twig base inwards. */
        vec3 up = v3_norm_or(v3_add(dir, v3_scale(rng_dir(&r), 0.6f)), v3(0, 1, 0));
        vec3 b0 = perp(up), b1 = v3_cross(up, b0);
        float roll = rng_range(&r, 0.0f, (float)FS_PI);
        int quads = rng_int(&r, 2, 3);
        float sc = s * rng_range(&r, 0.85f, 1.15f);
        for (int q = 0; q < quads; q++) {
            float a = roll + (float)FS_PI * (float)q / (float)quads;
            vec3 side = v3_add(v3_scale(b0, cosf(a)), v3_scale(b1, sinf(a)));
            mb_card(&leaves, c, v3_scale(side, sc), v3_scale(up, sc));
        }
    }

    /* Trunk: 8-sided tapered cylinder from the ground into the crown centre, radial normals
     * (tilted by the taper), bark UVs wrapping twice around. */
    const int sides = 8, rings = 4;
    float top = cy + 0.3f * Rv, r0 = fmaxf(0.04f * H, 0.02f), r1 = 0.45f * r0;
    float slope = (r0 - r1) / fmaxf(top, 1e-6f);
    if (mb_reserve(&trunk, (uint32_t)((sides + 1) * (rings + 1)), (uint32_t)(sides * rings * 6))) {
        for (int j = 0; j <= rings; j++) {
            float t = (float)j / (float)rings, y = top * t, rr = r0 + (r1 - r0) * t;
            for (int k = 0; k <= sides; k++) {
                float a = 2.0f * (float)FS_PI * (float)k / (float)sides;
                vec3 n = v3_norm_or(v3(cosf(a), slope, sinf(a)), v3(1, 0, 0));
                mb_vertex(&trunk, v3(rr * cosf(a), y, rr * sinf(a)), n, 2.0f * (float)k / (float)sides,
                          (1.0f - t) * top / (2.0f * (float)FS_PI * r0 / 2.0f));
            }
        }
        for (int j = 0; j < rings; j++)
            for (int k = 0; k < sides; k++) {
                uint32_t a = (uint32_t)(j * (sides + 1) + k), b = a + 1, c = a + (uint32_t)(sides + 1), e = c + 1;
                /* Outward-facing (counter-clockwise seen from outside). */
                mb_tri(&trunk, a, c, b);
                mb_tri(&trunk, b, c, e);
            }
    }
    if (!mb_finish(&leaves, 0, &out->prims[0]) || !mb_finish(&trunk, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &leaves, &trunk);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>grass */

fs_status gen_grass(const gen_grass_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_grass_desc d = gen_grass_defaults(desc);
    const char *g = "grass";
    if (!check_size(g, "extent", d.extent) || !check_int(g, "card_count", d.card_count, 1, 100000) ||
        !check_size(g, "blade_height", d.blade_height) || !check_pow2(g, "texture_size", d.texture_size) ||
        !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "grass", 2, 2, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!tex_blades(d.seed, d.texture_size, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("blades", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);
    out->materials[1] = mat_opaque("ground", -1, 0.11f, 0.14f, 0.05f);

    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);
    mesh_b blades = {0}, ground = {0};
    float half = 0.5f * d.extent;
    for (int i = 0; i < d.card_count; i++) {
        float h = d.blade_height * rng_range(&r, 0.7f, 1.3f), w = h * rng_range(&r, 1.0f, 1.4f);
        float m = fminf(0.5f * w, half);
        float x = rng_range(&r, -half + m, half - m), z = rng_range(&r, -half + m, half - m);
        float yaw = rng_range(&r, 0.0f, (float)FS_PI);
        for (int q = 0; q < 2; q++) {
            float a = yaw + 0.5f * (float)FS_PI * (float)q;
            mb_card(&blades, v3(x, 0.5f * h, z), v3(w * cosf(a), 0, w * sinf(a)), v3(0, h, 0));
        }
    }
    {
        vec3 p[4] = {v3(-half, 0, -half), v3(half, 0, -half), v3(half, 0, half), v3(-half, 0, half)};
        float k = d.extent; /* UVs in metres, for whoever textures the ground later */
        const float uv[4][2] = {{0, 0}, {k, 0}, {k, k}, {0, k}};
        mb_quad(&ground, p, uv, v3(0, 1, 0));
    }
    if (!mb_finish(&blades, 0, &out->prims[0]) || !mb_finish(&ground, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &blades, &ground);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>fence */

fs_status gen_fence(const gen_fence_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_fence_desc d = gen_fence_defaults(desc);
    const char *g = "fence";
    if (!check_size(g, "length", d.length) || !check_size(g, "height", d.height) ||
        !check_size(g, "cell_size", d.cell_size) || !check_pow2(g, "texture_size", d.texture_size) ||
        !check_int(g, "wire_texels", d.wire_texels, 1, 5) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "fence", 2, 2, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!tex_wire(d.texture_size, d.wire_texels, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("wire", 0, d.alpha_cutoff, TEX_WRAP_REPEAT);
    out->materials[1] = mat_opaque("posts", -1, 0.33f, 0.34f, 0.36f);

    mesh_b wire = {0}, posts = {0};
    float L = d.length, H = d.height;
    {
        /* One quad; the sampler repeats the cell tile L/cell x H/cell times. */
        vec3 p[4] = {v3(0, 0, 0), v3(L, 0, 0), v3(L, H, 0), v3(0, H, 0)};
        float u = L / d.cell_size, v = H / d.cell_size;
        const float uv[4][2] = {{0, v}, {u, v}, {u, 0}, {0, 0}};
        mb_quad(&wire, p, uv, v3(0, 0, 1));
    }
    /* Posts every ~2.5 m, the end posts flush with x = 0 and x = length; a top rail above the
     * mesh. Thin parts shrink with a short fence so they never exceed it. */
    float pw = fminf(0.06f, 0.1f * L), rail = fminf(0.05f, 0.1f * H);
    int count = (int)ceilf(L / 2.5f) + 1;
    if (count < 2)
        count = 2;
    for (int i = 0; i < count; i++) {
        float x = 0.5f * pw + (L - pw) * (float)i / (float)(count - 1);
        mb_box(&posts, v3(x - 0.5f * pw, 0, -0.5f * pw), v3(x + 0.5f * pw, H + rail, 0.5f * pw));
    }
    mb_box(&posts, v3(0, H, -0.4f * rail), v3(L, H + rail, 0.4f * rail));
    if (!mb_finish(&wire, 0, &out->prims[0]) || !mb_finish(&posts, 1, &out->prims[1]))
        return gen_fail_nomem(g, out, &wire, &posts);
    asset_compute_bounds(out);
    return FS_OK;
}

/* >>fern */

fs_status gen_fern(const gen_fern_desc *desc, asset *out)
{
    memset(out, 0, sizeof *out);
    gen_fern_desc d = gen_fern_defaults(desc);
    const char *g = "fern";
    if (!check_size(g, "size", d.size) || !check_int(g, "frond_count", d.frond_count, 1, 100000) ||
        !check_pow2(g, "texture_size", d.texture_size) || !check_cutoff(g, d.alpha_cutoff))
        return FS_ERR_SCENE;

    if (!asset_alloc(out, "fern", 1, 1, 1))
        return gen_fail_nomem(g, out, NULL, NULL);
    if (!tex_fern(d.seed, d.texture_size, &out->images[0]))
        return gen_fail_nomem(g, out, NULL, NULL);
    out->materials[0] = mat_foliage("fronds", 0, d.alpha_cutoff, TEX_WRAP_CLAMP);

    gen_rng r = rng_make(d.seed, STREAM_GEOMETRY);
    mesh_b fr = {0};
    const int segs_max = 6;
    for (int i = 0; i < d.frond_count; i++) {
        float az = 2.0f * (float)FS_PI * ((float)i + rng_range(&r, -0.3f, 0.3f)) / (float)d.frond_count;
        float len = d.size * rng_range(&r, 0.8f, 1.1f), width = 0.5f * len;
        float elev = rng_range(&r, 0.9f, 1.3f), bend = rng_range(&r, 1.0f, 1.7f); /* radians */
        float roll = rng_range(&r, -0.25f, 0.25f);
        int segs = rng_int(&r, 4, segs_max);
        vec3 fwd = v3(cosf(az), 0, sinf(az));
        vec3 lat = v3(-sinf(az) * cosf(roll), sinf(roll), cosf(az) * cosf(roll)); /* across the frond */
        if (!mb_reserve(&fr, (uint32_t)(2 * (segs + 1)), (uint32_t)(6 * segs)))
            break;
        uint32_t base = fr.nv;
        vec3 p = v3_scale(fwd, 0.03f * d.size);
        for (int k = 0; k <= segs; k++) {
            float t = (float)k / (float)segs;
            /* Frond base (texture bottom, v = 1) at the clump centre, tip at v = 0. */
            vec3 hl = v3_scale(lat, 0.5f * width);
            vec3 a = v3_sub(p, hl), b = v3_add(p, hl);
            a.y = fmaxf(a.y, 0.0f);
            b.y = fmaxf(b.y, 0.0f);
            mb_vertex(&fr, a, v3(0, 1, 0), 0.0f, 1.0f - t);
            mb_vertex(&fr, b, v3(0, 1, 0), 1.0f, 1.0f - t);
            /* Arch: elevation falls linearly along the frond, so it rises, then droops. */
            float e = elev - bend * (t + 0.5f / (float)segs);
            p = v3_add(p, v3_add(v3_scale(fwd, cosf(e) * len / (float)segs), v3(0, sinf(e) * len / (float)segs, 0)));
        }
        for (int k = 0; k < segs; k++) {
            uint32_t a = base + 2u * (uint32_t)k;
            mb_tri(&fr, a, a + 1, a + 3);
            mb_tri(&fr, a, a + 3, a + 2);
        }
    }
    if (!mb_finish(&fr, 0, &out->prims[0]))
        return gen_fail_nomem(g, out, &fr, NULL);
    prim_compute_normals(&out->prims[0]); /* smooth along each arched strip */
    asset_compute_bounds(out);
    return FS_OK;
}
