/* annotate.c: rectangles, circles, crosses, bitmap text, region borders and a diverging legend
 * on a float RGB canvas (annotate.h). Every write goes through put(), which checks the clip. */
#include "output/annotate.h"

#include <math.h>
#include <string.h>

/* stb_easy_font is a header of static functions; its own code is not held to our warnings. */
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wconversion"
#endif
#include <stb/stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#define ANNOT_TEXT_MAX 255      /* characters drawn of one text */
#define ANNOT_QUAD_BYTES 64     /* stb_easy_font: 4 vertices of 16 bytes */
#define ANNOT_GLYPH_QUADS 32    /* room for one glyph's quads */
#define ANNOT_DASH 3            /* region borders: dash length in pixels */

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

annot_canvas annot_canvas_make(float *r, float *g, float *b, int width, int height, int x, int y, int w, int h)
{
    annot_canvas c = {{r, g, b}, width > 0 ? width : 0, height > 0 ? height : 0, {0, 0, 0, 0}};
    /* x + w in long long: no overflow for any int arguments */
    long long x1 = (long long)x + (w > 0 ? w : 0), y1 = (long long)y + (h > 0 ? h : 0);
    c.clip[0] = clampi(x, 0, c.width);
    c.clip[1] = clampi(y, 0, c.height);
    c.clip[2] = (int)(x1 < c.clip[0] ? c.clip[0] : x1 > c.width ? c.width : x1);
    c.clip[3] = (int)(y1 < c.clip[1] ? c.clip[1] : y1 > c.height ? c.height : y1);
    return c;
}

static void put(const annot_canvas *c, long long x, long long y, const float rgb[3])
{
    if (x < c->clip[0] || y < c->clip[1] || x >= c->clip[2] || y >= c->clip[3])
        return;
    size_t i = (size_t)y * (size_t)c->width + (size_t)x;
    for (int k = 0; k < 3; k++)
        if (c->plane[k])
            c->plane[k][i] = rgb[k];
}

/* The pixels whose centres lie in [a, b), as [*i0, *i1) clamped to [lo, hi]; false when none
 * (also for NaN). */
static bool span(double a, double b, int lo, int hi, int *i0, int *i1)
{
    if (!(a < b))
        return false;
    double p = ceil(a - 0.5), q = ceil(b - 0.5);
    p = p < lo ? lo : p > hi ? hi : p;
    q = q < lo ? lo : q > hi ? hi : q;
    *i0 = (int)p;
    *i1 = (int)q;
    return *i0 < *i1;
}

static float srgb_to_linear(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

void annot_hex_colour(unsigned hex, float rgb[3])
{
    for (int k = 0; k < 3; k++)
        rgb[k] = srgb_to_linear((float)((hex >> (16 - 8 * k)) & 0xffu) / 255.0f);
}

void annot_diverging(float t, float rgb[3])
{
    /* ColorBrewer RdBu's ends (sRGB): #2166ac (lost) and #b2182b (extra) */
    static const float lost[3] = {0x21 / 255.0f, 0x66 / 255.0f, 0xac / 255.0f};
    static const float extra[3] = {0xb2 / 255.0f, 0x18 / 255.0f, 0x2b / 255.0f};
    t = isnan(t) ? 0.0f : fminf(fmaxf(t, -1.0f), 1.0f);
    const float *end = t < 0.0f ? lost : extra;
    float a = fabsf(t);
    for (int k = 0; k < 3; k++)
        rgb[k] = srgb_to_linear(1.0f + (end[k] - 1.0f) * a);
}

void annot_fill_rect(const annot_canvas *c, float x0, float y0, float x1, float y1, const float rgb[3])
{
    int a, b, p, q;
    if (!span(x0, x1, c->clip[0], c->clip[2], &a, &b) || !span(y0, y1, c->clip[1], c->clip[3], &p, &q))
        return;
    for (int y = p; y < q; y++)
        for (int x = a; x < b; x++)
            put(c, x, y, rgb);
}

void annot_shade_rect(const annot_canvas *c, float x0, float y0, float x1, float y1, float amount)
{
    int a, b, p, q;
    if (!(amount >= 0.0f) || !span(x0, x1, c->clip[0], c->clip[2], &a, &b) ||
        !span(y0, y1, c->clip[1], c->clip[3], &p, &q))
        return;
    float keep = 1.0f - fminf(amount, 1.0f);
    for (int y = p; y < q; y++)
        for (int x = a; x < b; x++)
            for (int k = 0; k < 3; k++)
                if (c->plane[k])
                    c->plane[k][(size_t)y * (size_t)c->width + (size_t)x] *= keep;
}

void annot_circle(const annot_canvas *c, float cx, float cy, float r, const float rgb[3])
{
    if (!isfinite(cx) || !isfinite(cy) || !isfinite(r) || r < 0.0f)
        return;
    int a, b, p, q;
    if (!span((double)cx - r - 1.0, (double)cx + r + 1.0, c->clip[0], c->clip[2], &a, &b) ||
        !span((double)cy - r - 1.0, (double)cy + r + 1.0, c->clip[1], c->clip[3], &p, &q))
        return;
    for (int y = p; y < q; y++)
        for (int x = a; x < b; x++) {
            double d = hypot(x + 0.5 - (double)cx, y + 0.5 - (double)cy);
            if (fabs(d - (double)r) <= 0.5)
                put(c, x, y, rgb);
        }
}

void annot_cross(const annot_canvas *c, float cx, float cy, int arm, const float rgb[3])
{
    if (!isfinite(cx) || !isfinite(cy) || arm < 0)
        return;
    float x = floorf(cx), y = floorf(cy);
    annot_fill_rect(c, x - (float)arm, y, x + (float)arm + 1.0f, y + 1.0f, rgb);
    annot_fill_rect(c, x, y - (float)arm, x + 1.0f, y + (float)arm + 1.0f, rgb);
}

/* text cut to ANNOT_TEXT_MAX characters of one line, anything but printable ASCII as '?' (the
 * font's table covers ' ' to '~' only) */
static void text_copy(const char *text, char buf[ANNOT_TEXT_MAX + 1])
{
    size_t n = 0;
    for (; text && text[n] && text[n] != '\n' && n < ANNOT_TEXT_MAX; n++)
        buf[n] = text[n] >= ' ' && text[n] <= '~' ? text[n] : '?';
    buf[n] = '\0';
}

int annot_text_width(const char *text, int scale)
{
    char buf[ANNOT_TEXT_MAX + 1];
    text_copy(text, buf);
    return stb_easy_font_width(buf) * (scale < 1 ? 1 : scale);
}

int annot_text_height(int scale)
{
    /* stb_easy_font's glyphs span rows 0..6 above the baseline and 2 below (g, p, y) */
    return 9 * (scale < 1 ? 1 : scale);
}

int annot_text(const annot_canvas *c, float x, float y, int scale, const char *text, const float rgb[3])
{
    char buf[ANNOT_TEXT_MAX + 1];
    scale = scale < 1 ? 1 : scale;
    text_copy(text, buf);
    int width = stb_easy_font_width(buf) * scale;
    if (!isfinite(x) || !isfinite(y))
        return width;
    /* One character at a time: its quads fit a small buffer (a glyph has at most a dozen). */
    float pen = 0.0f, s = (float)scale;
    for (size_t i = 0; buf[i]; i++) {
        char ch[2] = {buf[i], '\0'}, quads[ANNOT_GLYPH_QUADS * ANNOT_QUAD_BYTES];
        int n = stb_easy_font_print(pen, 0.0f, ch, NULL, quads, (int)sizeof quads);
        pen += (float)stb_easy_font_width(ch);
        for (int q = 0; q < n; q++) {
            float v[4][4]; /* x, y, z, colour bytes per vertex */
            memcpy(v, quads + (size_t)q * ANNOT_QUAD_BYTES, sizeof v);
            float x0 = v[0][0], x1 = v[0][0], y0 = v[0][1], y1 = v[0][1];
            for (int k = 1; k < 4; k++) {
                x0 = fminf(x0, v[k][0]);
                x1 = fmaxf(x1, v[k][0]);
                y0 = fminf(y0, v[k][1]);
                y1 = fmaxf(y1, v[k][1]);
            }
            annot_fill_rect(c, x + x0 * s, y + y0 * s, x + x1 * s, y + y1 * s, rgb);
        }
    }
    return width;
}

void annot_region_borders(const annot_canvas *c, int ox, int oy, const unsigned char *region, int w, int h,
                          const float a[3], const float b[3])
{
    if (!region || w <= 0 || h <= 0)
        return;
    /* only the map's pixels that land inside the clip */
    long long i0 = (long long)c->clip[0] - ox, i1 = (long long)c->clip[2] - ox;
    long long j0 = (long long)c->clip[1] - oy, j1 = (long long)c->clip[3] - oy;
    i0 = i0 < 0 ? 0 : i0;
    j0 = j0 < 0 ? 0 : j0;
    i1 = i1 > w ? w : i1;
    j1 = j1 > h ? h : j1;
    for (long long j = j0; j < j1; j++)
        for (long long i = i0; i < i1; i++) {
            size_t k = (size_t)j * (size_t)w + (size_t)i;
            bool edge = (i + 1 < w && region[k] != region[k + 1]) || (j + 1 < h && region[k] != region[k + (size_t)w]);
            if (edge)
                put(c, ox + i, oy + j, ((i + j) / ANNOT_DASH) % 2 ? b : a);
        }
}

void annot_diverging_legend(const annot_canvas *c, int scale, const char *title, const char *lo, const char *hi)
{
    static const float black[3] = {0, 0, 0}, white[3] = {1, 1, 1};
    int x0 = c->clip[0], y0 = c->clip[1], w = c->clip[2] - x0, h = c->clip[3] - y0;
    if (w <= 0 || h <= 0)
        return;
    scale = scale < 1 ? 1 : scale;
    annot_fill_rect(c, (float)x0, (float)y0, (float)(x0 + w), (float)(y0 + h), black);
    int th = annot_text_height(scale), bh = h / 8 > 2 * scale ? h / 8 : 2 * scale;
    float bx0 = (float)x0 + 0.1f * (float)w, bx1 = (float)x0 + 0.9f * (float)w;
    float by0 = (float)y0 + 0.5f * (float)(h - bh), by1 = by0 + (float)bh;
    int a, b;
    if (span(bx0, bx1, c->clip[0], c->clip[2], &a, &b))
        for (int x = a; x < b; x++) {
            float rgb[3];
            annot_diverging(-1.0f + 2.0f * ((float)x + 0.5f - bx0) / (bx1 - bx0), rgb);
            annot_fill_rect(c, (float)x, by0, (float)x + 1.0f, by1, rgb);
        }
    float mid = 0.5f * (bx0 + bx1), tick = (float)(2 * scale);
    annot_fill_rect(c, bx0, by1, bx0 + 1.0f, by1 + tick, white);
    annot_fill_rect(c, floorf(mid), by1, floorf(mid) + 1.0f, by1 + tick, white);
    annot_fill_rect(c, bx1 - 1.0f, by1, bx1, by1 + tick, white);
    float ly = by1 + tick + (float)scale;
    annot_text(c, bx0, by0 - (float)(th + 2 * scale), scale, title, white);
    annot_text(c, bx0, ly, scale, lo, white);
    annot_text(c, floorf(mid - 0.5f * (float)annot_text_width("0", scale)), ly, scale, "0", white);
    annot_text(c, bx1 - (float)annot_text_width(hi, scale), ly, scale, hi, white);
}
