/* gen_textures.c: the alpha-mapped textures of the generators (leaf cards, grass blades, chain-link
 * wire, fern fronds) and the opaque bark, see generators.h.
 *
 * Textures are painted analytically: every stroke and leaf is a signed distance d (texels) and a
 * texel gets coverage clamp(0.5 - d, 0, 1), which gives 1-texel soft edges. Shapes are added until
 * the texture reaches its target share of transparent texels (alpha byte 0), so the share holds
 * for every seed and texture size. Transparent texels then take the colour of the nearest
 * visible texel (chamfer distance transform), the usual dilation of production foliage textures.
 */
#include "scene/generators_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
bool gen_tex_leaves(uint32_t seed, int n, image_rgba8 *img)
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
bool gen_tex_blades(uint32_t seed, int n, image_rgba8 *img)
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
bool gen_tex_wire(int n, int wire, image_rgba8 *img)
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
bool gen_tex_fern(uint32_t seed, int n, image_rgba8 *img)
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
bool gen_tex_bark(uint32_t seed, image_rgba8 *img)
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
