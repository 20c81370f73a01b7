/* compare_grid.c: part 0 of a comparison frame, its tiles and their annotation (compare_grid.h). */
#include "commands/compare_grid.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "output/annotate.h"

/* Heat colour of t in [0, 1]: black, red, yellow, white (linear). */
static void heat(float t, float rgb[3])
{
    t = isfinite(t) ? fminf(fmaxf(t, 0.0f), 1.0f) : 1.0f;
    rgb[0] = fminf(3.0f * t, 1.0f);
    rgb[1] = fminf(fmaxf(3.0f * t - 1.0f, 0.0f), 1.0f);
    rgb[2] = fminf(fmaxf(3.0f * t - 2.0f, 0.0f), 1.0f);
}

/* What a tile shows, per pixel. */
typedef enum tile_kind { TILE_IMAGE, TILE_HEAT, TILE_GREY, TILE_DIFF, TILE_BLACK } tile_kind;

typedef struct grid {
    float *p[4]; /* R, G, B, A of the grid */
    int stride;  /* grid width */
    int w, h;    /* tile size */
    const float (*lut)[3]; /* diff_lut */
} grid;

/* annot_diverging at DIFF_STEPS + 1 points over [-1, 1], made per grid (no shared state): its three
 * powf per pixel were a third of the grid's time (62 ms at 640x360 with two modes before);
 * steps of 1/1024 are below half-float's resolution near 1. */
#define DIFF_STEPS 2048
typedef float diff_lut[DIFF_STEPS + 1][3];

static void diff_lut_fill(diff_lut lut)
{
    for (int i = 0; i <= DIFF_STEPS; i++)
        annot_diverging(-1.0f + 2.0f * (float)i / DIFF_STEPS, lut[i]);
}

static const float *diff_colour(const float (*lut)[3], float t)
{
    t = isnan(t) ? 0.0f : fminf(fmaxf(t, -1.0f), 1.0f);
    return lut[(int)lrintf((t + 1.0f) * 0.5f * DIFF_STEPS)];
}

/* Fills tile (col, row) from a, b (w x h planes): TILE_IMAGE a = R, G, B planes; TILE_HEAT
 * heat(a[0]); TILE_GREY a[0] as grey; TILE_DIFF annot_diverging(a[0] - b[0]). */
static void put_tile(const grid *g, int col, int row, tile_kind kind, const float *const a[3], const float *b)
{
    for (int y = 0; y < g->h; y++)
        for (int x = 0; x < g->w; x++) {
            size_t s = (size_t)y * (size_t)g->w + (size_t)x;
            size_t d = ((size_t)row * (size_t)g->h + (size_t)y) * (size_t)g->stride + (size_t)col * (size_t)g->w + (size_t)x;
            float rgb[3] = {0, 0, 0};
            switch (kind) {
            case TILE_IMAGE:
                for (int c = 0; c < 3; c++)
                    rgb[c] = a[c][s];
                break;
            case TILE_HEAT: heat(a[0][s], rgb); break;
            case TILE_GREY: rgb[0] = rgb[1] = rgb[2] = a[0][s]; break;
            case TILE_DIFF: memcpy(rgb, diff_colour(g->lut, a[0][s] - b[s]), sizeof rgb); break;
            case TILE_BLACK: break;
            }
            for (int c = 0; c < 3; c++)
                g->p[c][d] = rgb[c];
            g->p[3][d] = 1.0f;
        }
}

int compare_grid_text_scale(int w, int h)
{
    (void)w;
    return 1 + (h > 0 ? h : 0) / 300;
}

/* The label at the top-left corner of a tile: a square of `colour` (linear RGB), then the text,
 * on a darkened backdrop. */
static void label(const annot_canvas *c, int scale, const float colour[3], const char *text)
{
    static const float white[3] = {1, 1, 1}, black[3] = {0, 0, 0};
    int pad = 2 * scale, th = annot_text_height(scale);
    float x = (float)c->clip[0], y = (float)c->clip[1];
    float tw = (float)annot_text_width(text, scale);
    annot_shade_rect(c, x, y, x + (float)(3 * pad + th) + tw + (float)pad, y + (float)(2 * pad + th), 0.7f);
    annot_fill_rect(c, x + (float)pad - 1.0f, y + (float)pad - 1.0f, x + (float)(pad + th) + 1.0f,
                    y + (float)(pad + th) + 1.0f, black);
    annot_fill_rect(c, x + (float)pad, y + (float)pad, x + (float)(pad + th), y + (float)(pad + th), colour);
    annot_text(c, x + (float)(2 * pad + th), y + (float)pad + (float)scale, scale, text, white);
}

/* The gaze marker: a magenta ring with a black edge either side and a magenta cross at its
 * centre, the cross's centre on the display pixel holding the gaze (as --overlay draws it). */
static void gaze_marker(const annot_canvas *c, int scale, float gx, float gy)
{
    static const float magenta[3] = {1, 0, 1}, black[3] = {0, 0, 0};
    float cx = floorf(gx) + 0.5f, cy = floorf(gy) + 0.5f, r = (float)(6 * scale);
    annot_circle(c, cx, cy, r - 1.0f, black);
    annot_circle(c, cx, cy, r + 1.0f, black);
    annot_circle(c, cx, cy, r, magenta);
    annot_cross(c, gx, gy, 2 * scale, magenta);
}

/* Borders, gaze and label of tile (col, row). */
static void annotate_tile(const grid *g, const compare_grid_desc *d, int col, int row, const float colour[3],
                          const char *text)
{
    static const float yellow[3] = {1.0f, 0.9f, 0.1f}, black[3] = {0, 0, 0};
    annot_canvas c = annot_canvas_make(g->p[0], g->p[1], g->p[2], g->stride, g->h * COMPARE_GRID_ROWS, col * g->w,
                                       row * g->h, g->w, g->h);
    int scale = compare_grid_text_scale(g->w, g->h);
    annot_region_borders(&c, col * g->w, row * g->h, d->rings, g->w, g->h, yellow, black);
    if (isfinite(d->gaze_px[0]) && isfinite(d->gaze_px[1]))
        gaze_marker(&c, scale, (float)(col * g->w) + d->gaze_px[0], (float)(row * g->h) + d->gaze_px[1]);
    label(&c, scale, colour, text);
}

static const char *const k_rgbc[4] = {"R", "G", "B", "coverage"};

/* Whether img has R, G, B and coverage planes of w x h. */
static bool has_planes(const exr_image *img, int w, int h)
{
    if (!img || img->width != w || img->height != h)
        return false;
    for (int c = 0; c < 4; c++)
        if (!exr_image_channel(img, k_rgbc[c]))
            return false;
    return true;
}

fs_status compare_grid_build(const compare_grid_desc *d, exr_image *out)
{
    memset(out, 0, sizeof *out);
    int nm = d->mode_count, w = d->ref ? d->ref->width : 0, h = d->ref ? d->ref->height : 0;
    bool fine = nm >= 1 && nm <= ALPHA_MODE_COUNT && has_planes(d->ref, w, h);
    for (int m = 0; fine && m < nm; m++)
        fine = has_planes(d->images[m], w, h) && d->flip[m];
    if (!fine)
        return FS_ERR_USAGE;
    if (!exr_image_init(out, w * (nm + 1), h * COMPARE_GRID_ROWS))
        return FS_ERR_NOMEM;
    exr_image_set_part_name(out, "compare");
    float (*lut)[3] = malloc(sizeof(diff_lut));
    if (!lut) {
        exr_image_free(out);
        return FS_ERR_NOMEM;
    }
    diff_lut_fill(lut);
    grid g = {.stride = out->width, .w = w, .h = h, .lut = (const float (*)[3])lut};
    static const char *const names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++)
        if (!(g.p[c] = exr_image_add_channel(out, names[c]))) {
            free(lut);
            exr_image_free(out);
            return FS_ERR_NOMEM;
        }
    const float *ref_cov[3] = {exr_image_channel(d->ref, "coverage")};
    for (int m = 0; m <= nm; m++) {
        const exr_image *src = m < nm ? d->images[m] : d->ref;
        const float *pic[3] = {exr_image_channel(src, "R"), exr_image_channel(src, "G"), exr_image_channel(src, "B")};
        put_tile(&g, m, 0, TILE_IMAGE, pic, NULL);
        if (m == nm) {
            put_tile(&g, m, 1, TILE_GREY, ref_cov, NULL);
            put_tile(&g, m, 2, TILE_BLACK, NULL, NULL);
            break;
        }
        const float *fl[3] = {d->flip[m]}, *cov[3] = {exr_image_channel(src, "coverage")};
        put_tile(&g, m, 1, TILE_HEAT, fl, NULL);
        put_tile(&g, m, 2, TILE_DIFF, cov, ref_cov[0]);
    }
    free(lut);
    if (!d->annotate)
        return FS_OK;
    for (int m = 0; m <= nm; m++) {
        const char *name = m < nm ? alpha_mode_name(d->modes[m]) : "reference";
        float colour[3] = {0.5f, 0.5f, 0.5f}; /* the reference's: grey */
        char hex[8], text[96];
        if (m < nm)
            annot_hex_colour((unsigned)strtoul(alpha_mode_colour(d->modes[m], hex) + 1, NULL, 16), colour);
        snprintf(text, sizeof text, "%s: image", name);
        annotate_tile(&g, d, m, 0, colour, text);
        snprintf(text, sizeof text, m < nm ? "%s: FLIP (white = 1)" : "%s: coverage", name);
        annotate_tile(&g, d, m, 1, colour, text);
        if (m < nm) {
            snprintf(text, sizeof text, "%s: coverage - reference", name);
            annotate_tile(&g, d, m, 2, colour, text);
        }
    }
    annot_canvas legend = annot_canvas_make(g.p[0], g.p[1], g.p[2], g.stride, out->height, nm * w, 2 * h, w, h);
    annot_diverging_legend(&legend, compare_grid_text_scale(w, h), "coverage - reference", "-1 lost", "+1 extra");
    return FS_OK;
}

void compare_grid_describe(const compare_grid_desc *d, char *buf, size_t size)
{
    int nm = d->mode_count;
    size_t o = 0;
#define PUT(...) (o += (size_t)snprintf(buf + o, o < size ? size - o : 0, __VA_ARGS__), o = o < size ? o : size)
    PUT("%d columns x %d rows of %dx%d tiles; row 0:", nm + 1, COMPARE_GRID_ROWS, d->ref ? d->ref->width : 0,
        d->ref ? d->ref->height : 0);
    for (int m = 0; m < nm; m++)
        PUT(" %s |", alpha_mode_name(d->modes[m]));
    PUT(" reference; row 1: the LDR-FLIP map of each mode against the reference (black 0, white 1) | reference "
        "coverage (grey); row 2: each mode's coverage minus the reference's (blue -1 lost, white 0, red +1 extra) | "
        "%s; annotation %s", d->annotate ? "its legend" : "black",
        d->annotate ? "on: labels (a square of the mode's colour), measurement-ring borders (yellow/black), "
                      "gaze marker (magenta)" : "off");
#undef PUT
}
