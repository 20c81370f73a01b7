/* annotate.h: drawing on a float RGB picture on the CPU, for the labels, gaze marker, region
 * borders and legend of the comparison grid (docs/compare.md "The grid"). Pure C, no GL.
 *
 * A canvas is three float planes (linear R, G, B; rows top first) and a clip rectangle: nothing
 * is ever written outside the clip, which itself is clamped to the planes, so any coordinate
 * (negative, huge, NaN, infinite) is safe and draws at most the part that lands inside.
 * Coordinates are pixels, top-left origin; pixel (x, y) covers [x, x+1) x [y, y+1).
 *
 * Text uses stb_easy_font (public domain, Debian's libstb-dev; header only): its glyphs are
 * axis-aligned quads, filled here as rectangles, scaled by a whole factor.
 *
 * What it does NOT do: blending beyond annot_shade, antialiasing, fonts other than the one.
 */
#ifndef FOVSIM_ANNOTATE_H
#define FOVSIM_ANNOTATE_H

#include <stdbool.h>

typedef struct annot_canvas {
    float *plane[3];  /* R, G, B: width * height floats each */
    int width, height;
    int clip[4];      /* x0, y0, x1, y1 (half-open) that may be written; clamped to the planes */
} annot_canvas;

/* A canvas over whole planes, clipped to rectangle (x, y, w, h) of them (e.g. one grid tile). */
annot_canvas annot_canvas_make(float *r, float *g, float *b, int width, int height, int x, int y, int w, int h);

/* Linear RGB of a 0xRRGGBB sRGB colour (alpha_mode's colours are written so). */
void annot_hex_colour(unsigned hex, float rgb[3]);
/* The diverging colour of t in [-1, 1] (clamped; NaN as 0): blue at -1, white at 0, red at +1,
 * interpolated in sRGB and returned linear. Blue against red stays apart for the common
 * colour-vision deficiencies. */
void annot_diverging(float t, float rgb[3]);

/* Pixels whose centre lies in [x0, x1) x [y0, y1) set to rgb. */
void annot_fill_rect(const annot_canvas *c, float x0, float y0, float x1, float y1, const float rgb[3]);
/* The same pixels darkened: multiplied by (1 - amount), amount in [0, 1] (a backdrop for text). */
void annot_shade_rect(const annot_canvas *c, float x0, float y0, float x1, float y1, float amount);
/* A 1-pixel outline: every pixel whose centre is within half a pixel of distance r from (cx, cy). */
void annot_circle(const annot_canvas *c, float cx, float cy, float r, const float rgb[3]);
/* A plus sign centred on the pixel holding (cx, cy), arms `arm` pixels long, 1 pixel wide. */
void annot_cross(const annot_canvas *c, float cx, float cy, int arm, const float rgb[3]);

/* Text size in pixels at a whole scale (>= 1) for one line of text. */
int annot_text_width(const char *text, int scale);
int annot_text_height(int scale);
/* Draws one line of ASCII text with its top-left corner at (x, y); characters beyond 255 of
 * them are dropped. Returns the width drawn (annot_text_width). */
int annot_text(const annot_canvas *c, float x, float y, int scale, const char *text, const float rgb[3]);

/* Borders between regions: `region` is a w x h map of region ids (rows top first) placed with
 * its top-left at (ox, oy) on the canvas; a pixel whose id differs from its right or lower
 * neighbour is drawn, in dashes of `a` and `b` (3 pixels each) so the line shows on any
 * background. */
void annot_region_borders(const annot_canvas *c, int ox, int oy, const unsigned char *region, int w, int h,
                          const float a[3], const float b[3]);

/* The legend of annot_diverging, filling the canvas's clip: `title` on top, a colour bar from -1
 * to +1 across the middle, and under it `lo` at its left end, "0" at its middle and `hi` at its
 * right end, in white on black. */
void annot_diverging_legend(const annot_canvas *c, int scale, const char *title, const char *lo, const char *hi);

#endif
