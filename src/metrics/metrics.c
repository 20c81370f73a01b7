/* metrics.c: per-ring coverage, error and flicker metrics against the reference. See metrics.h
 * and docs/metrics.md. */
#include "metrics/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/config.h"
#include "core/log.h"

// >>ring mask

fs_status ring_mask_build(const display_desc *d, const fov_layout *l, float gx_px, float gy_px,
                          ring_mask *out)
{
    FS_ASSERT(d && l && out);
    memset(out, 0, sizeof *out);
    if (d->width <= 0 || d->height <= 0 || d->width > MAX_DISPLAY_SIZE ||
        d->height > MAX_DISPLAY_SIZE || l->count < 1 || l->count > MAX_FOV_RINGS)
        return FS_ERR_USAGE;
    const size_t n = (size_t)d->width * (size_t)d->height;
    out->ring = malloc(n);
    if (!out->ring)
        return FS_ERR_NOMEM;
    out->width = d->width;
    out->height = d->height;
    out->ring_count = l->count;
    /* The composite measures eccentricity from the clamped gaze; so must the mask, or a pixel
     * would be scored in a ring other than the one it was drawn from. */
    fov_gaze_clamp(d, &gx_px, &gy_px);
    for (int y = 0; y < d->height; y++) {
        unsigned char *row = out->ring + (size_t)y * (size_t)d->width;
        for (int x = 0; x < d->width; x++) {
            float e = fov_eccentricity_deg(d, gx_px, gy_px, (float)x + 0.5f, (float)y + 0.5f);
            int ring = fov_composite_weight(l, e).ring;
            /* fov_composite_weight returns a ring of the layout; the clamp only guards the
             * unsigned char store against a future change there. */
            row[x] = (unsigned char)(ring < 0 ? 0 : ring >= l->count ? l->count - 1 : ring);
        }
    }
    return FS_OK;
}

void ring_mask_free(ring_mask *m)
{
    if (!m)
        return;
    free(m->ring);
    memset(m, 0, sizeof *m);
}

// >>metrics

/* A sample as the EXR file would store it (exr_write.c's float_to_half without the rounding):
 * NaN 0, clamped to +-65504. Keeps every sum finite and makes metrics of an in-memory frame
 * agree with metrics of the same frame read back. */
static double sample(float v)
{
    if (v != v)
        return 0.0;
    if (v > 65504.0f)
        return 65504.0;
    if (v < -65504.0f)
        return -65504.0;
    return (double)v;
}

/* num / den for two non-negative means: 1 when both are ~0 (nothing there, nothing added),
 * otherwise den is floored at METRICS_EPS so the result stays finite. */
static double safe_ratio(double num, double den)
{
    if (num < METRICS_EPS && den < METRICS_EPS)
        return 1.0;
    return num / (den > METRICS_EPS ? den : METRICS_EPS);
}

typedef struct acc {
    long long pixels;
    double cov, ref_cov, sq_err, band_sq_err, flip, change;
} acc;

static bool same_size(const metrics_view *v, const ring_mask *m)
{
    return v && v->width == m->width && v->height == m->height && v->r && v->g && v->b &&
           v->coverage;
}

static void finish(const acc *a, bool has_prev, ring_metrics *o)
{
    memset(o, 0, sizeof *o);
    o->temporal_error = o->disoccluded = -1.0; /* not measured unless metrics_temporal runs */
    o->pixels = a->pixels;
    o->has_prev = has_prev;
    if (a->pixels == 0) {
        o->coverage_ratio = 1.0;
        o->psnr = METRICS_PSNR_CAP_DB;
        return;
    }
    const double n = (double)a->pixels;
    o->coverage = a->cov / n;
    o->ref_coverage = a->ref_cov / n;
    o->coverage_ratio = safe_ratio(o->coverage, o->ref_coverage);
    /* Coverage may be negative only through broken input; the ratio of two means is still
     * finite (den floored), just meaningless, which the test of |ratio - 1| will flag. */
    const double mse = a->sq_err / (3.0 * n);
    o->rmse = sqrt(mse);
    o->alpha_rmse = sqrt(a->band_sq_err / (3.0 * n));
    o->flip = a->flip / n;
    /* 10 log10(1 / mse) >= cap exactly when mse <= 10^(-cap / 10): no log of 0. */
    o->psnr = mse <= pow(10.0, -METRICS_PSNR_CAP_DB / 10.0) ? METRICS_PSNR_CAP_DB
                                                            : -10.0 * log10(mse);
    if (has_prev)
        o->change = a->change / n;
}

fs_status metrics_compute(const metrics_view *img, const metrics_view *ref, const metrics_view *band,
                          const float *flip, const metrics_view *prev, const ring_mask *mask,
                          ring_metrics *out)
{
    FS_ASSERT(mask && out);
    const int rings = mask->ring_count;
    const bool has_prev = prev != NULL;
    if (!band)
        band = ref;
    bool ok = mask->ring && rings >= 1 && rings <= MAX_FOV_RINGS && same_size(img, mask) &&
              same_size(ref, mask) && same_size(band, mask) &&
              (!has_prev || same_size(prev, mask));
    if (!ok) {
        if (rings >= 1 && rings <= MAX_FOV_RINGS)
            memset(out, 0, (size_t)(rings + 1) * sizeof *out);
        log_error("METRICS: image, reference, previous frames and ring mask differ in size");
        return FS_ERR_INTERNAL;
    }

    acc a[MAX_FOV_RINGS + 1];
    memset(a, 0, sizeof a);
    const size_t n = (size_t)mask->width * (size_t)mask->height;
    for (size_t i = 0; i < n; i++) {
        acc *r = &a[mask->ring[i] < rings ? mask->ring[i] : rings - 1];
        r->pixels++;
        r->cov += sample(img->coverage[i]);
        r->ref_cov += sample(ref->coverage[i]);
        const double ir = sample(img->r[i]), ig = sample(img->g[i]), ib = sample(img->b[i]);
        const double fr = sample(ref->r[i]), fg = sample(ref->g[i]), fb = sample(ref->b[i]);
        r->sq_err += (ir - fr) * (ir - fr) + (ig - fg) * (ig - fg) + (ib - fb) * (ib - fb);
        const double br = sample(band->r[i]), bg = sample(band->g[i]), bb = sample(band->b[i]);
        r->band_sq_err += (ir - br) * (ir - br) + (ig - bg) * (ig - bg) + (ib - bb) * (ib - bb);
        if (flip)
            r->flip += sample(flip[i]);
        if (has_prev) {
            r->change += (fabs(ir - sample(prev->r[i])) + fabs(ig - sample(prev->g[i])) +
                          fabs(ib - sample(prev->b[i]))) / 3.0;
        }
    }
    /* The whole display: the sums of the rings (every pixel is in exactly one). */
    acc *all = &a[rings];
    for (int k = 0; k < rings; k++) {
        all->pixels += a[k].pixels;
        all->cov += a[k].cov;
        all->ref_cov += a[k].ref_cov;
        all->sq_err += a[k].sq_err;
        all->band_sq_err += a[k].band_sq_err;
        all->flip += a[k].flip;
        all->change += a[k].change;
    }
    for (int k = 0; k <= rings; k++)
        finish(&a[k], has_prev, &out[k]);
    return FS_OK;
}

bool metrics_coverage_ratio_rests(double ref_px, int block)
{
    const double b = block > 1 ? (double)block : 1.0;
    return ref_px / (b * b) >= METRICS_MIN_REF_TEXELS; /* false for NaN */
}

double metrics_coverage_ratio_of_sums(double cov_px, double ref_px, int block)
{
    return metrics_coverage_ratio_rests(ref_px, block) ? cov_px / ref_px : -1.0;
}

// >>temporal error

fs_status metrics_temporal(const metrics_view *img, const metrics_view *wprev, const metrics_view *ref,
                           const metrics_view *wref, const unsigned char *valid, const ring_mask *mask,
                           ring_metrics *out)
{
    const int rings = mask->ring_count;
    if (!mask->ring || rings < 1 || rings > MAX_FOV_RINGS || !valid || !same_size(img, mask) ||
        !same_size(wprev, mask) || !same_size(ref, mask) || !same_size(wref, mask)) {
        log_error("METRICS: temporal error: images and ring mask differ in size");
        return FS_ERR_INTERNAL;
    }
    double sq[MAX_FOV_RINGS + 1] = {0};
    long long n[MAX_FOV_RINGS + 1] = {0}, warped[MAX_FOV_RINGS + 1] = {0};
    const size_t np = (size_t)mask->width * (size_t)mask->height;
    for (size_t i = 0; i < np; i++) {
        int k = mask->ring[i] < rings ? mask->ring[i] : rings - 1;
        n[k]++;
        if (!valid[i])
            continue;
        warped[k]++;
        const float *a[4] = {img->r, img->g, img->b}, *b[4] = {wprev->r, wprev->g, wprev->b};
        const float *f[4] = {ref->r, ref->g, ref->b}, *g[4] = {wref->r, wref->g, wref->b};
        for (int c = 0; c < 3; c++) {
            double d = (sample(a[c][i]) - sample(b[c][i])) - (sample(f[c][i]) - sample(g[c][i]));
            sq[k] += d * d;
        }
    }
    for (int k = 0; k < rings; k++) {
        sq[rings] += sq[k];
        n[rings] += n[k];
        warped[rings] += warped[k];
    }
    for (int k = 0; k <= rings; k++) {
        out[k].temporal_error = warped[k] ? sqrt(sq[k] / (3.0 * (double)warped[k])) : 0.0;
        out[k].disoccluded = n[k] ? 1.0 - (double)warped[k] / (double)n[k] : 1.0;
    }
    return FS_OK;
}

// >>band-limited reference

/* Ring i's image: the mean of the reference's display pixels in each ring pixel's block that lie
 * on the display. Rows top first (ring row 0 at the rect's top), w * h values per plane. */
static void box_down(const metrics_view *ref, const fov_ring_rect *rr, float *const ring[4])
{
    const float *src[4] = {ref->r, ref->g, ref->b, ref->coverage};
    for (int ty = 0; ty < rr->height; ty++)
        for (int tx = 0; tx < rr->width; tx++) {
            double s[4] = {0, 0, 0, 0};
            int n = 0;
            for (int y = rr->y0 + ty * rr->block; y < rr->y0 + (ty + 1) * rr->block; y++)
                for (int x = rr->x0 + tx * rr->block; x < rr->x0 + (tx + 1) * rr->block; x++) {
                    if (x < 0 || y < 0 || x >= ref->width || y >= ref->height)
                        continue;
                    size_t i = (size_t)y * (size_t)ref->width + (size_t)x;
                    for (int c = 0; c < 4; c++)
                        s[c] += sample(src[c][i]);
                    n++;
                }
            size_t o = (size_t)ty * (size_t)rr->width + (size_t)tx;
            for (int c = 0; c < 4; c++)
                ring[c][o] = n ? (float)(s[c] / n) : 0.0f;
        }
}

/* Bilinear sample of a ring image at display point (px, py) as composite.frag's ring_uvw does:
 * ring texel coordinates clamped to the rendered texel centres. */
static void ring_sample(const fov_ring_rect *rr, float *const ring[4], float px, float py, float out[4])
{
    float tx = (px - (float)rr->x0) / (float)rr->block, ty = (py - (float)rr->y0) / (float)rr->block;
    tx = fminf(fmaxf(tx, 0.5f), (float)rr->width - 0.5f) - 0.5f;
    ty = fminf(fmaxf(ty, 0.5f), (float)rr->height - 0.5f) - 0.5f;
    int x0 = (int)floorf(tx), y0 = (int)floorf(ty);
    float fx = tx - (float)x0, fy = ty - (float)y0;
    int x1 = x0 + 1 < rr->width ? x0 + 1 : x0, y1 = y0 + 1 < rr->height ? y0 + 1 : y0;
    size_t w = (size_t)rr->width;
    for (int c = 0; c < 4; c++) {
        const float *p = ring[c];
        float a = p[(size_t)y0 * w + (size_t)x0] + fx * (p[(size_t)y0 * w + (size_t)x1] - p[(size_t)y0 * w + (size_t)x0]);
        float b = p[(size_t)y1 * w + (size_t)x0] + fx * (p[(size_t)y1 * w + (size_t)x1] - p[(size_t)y1 * w + (size_t)x0]);
        out[c] = a + fy * (b - a);
    }
}

fs_status metrics_band_limit(const metrics_view *ref, const display_desc *d, const fov_layout *l,
                             const fov_ring_rect *rects, float gx_px, float gy_px, float *const out[4],
                             metrics_view *band)
{
    FS_ASSERT(ref && d && l && rects && out && band);
    if (l->count < 1 || l->count > MAX_FOV_RINGS || d->width != ref->width || d->height != ref->height) {
        log_error("METRICS: band limit: bad layout (%d rings) or display size", l->count);
        return FS_ERR_USAGE;
    }
    float *rings[MAX_FOV_RINGS][4] = {{NULL}};
    fs_status st = FS_OK;
    for (int i = 0; i < l->count && st == FS_OK; i++) {
        size_t n = (size_t)rects[i].width * (size_t)rects[i].height;
        for (int c = 0; c < 4 && st == FS_OK; c++)
            if (!(rings[i][c] = malloc(sizeof(float) * (n ? n : 1))))
                st = FS_ERR_NOMEM;
        if (st == FS_OK)
            box_down(ref, &rects[i], rings[i]);
    }
    float gx = gx_px, gy = gy_px;
    fov_gaze_clamp(d, &gx, &gy);
    for (int y = 0; y < d->height && st == FS_OK; y++)
        for (int x = 0; x < d->width; x++) {
            float px = (float)x + 0.5f, py = (float)y + 0.5f, a[4], b[4];
            fov_blend w = fov_composite_weight(l, fov_eccentricity_deg(d, gx, gy, px, py));
            int k = w.ring < l->count ? w.ring : l->count - 1;
            ring_sample(&rects[k], rings[k], px, py, a);
            if (w.next > 0.0f && k + 1 < l->count) {
                ring_sample(&rects[k + 1], rings[k + 1], px, py, b);
                for (int c = 0; c < 4; c++)
                    a[c] += w.next * (b[c] - a[c]);
            }
            size_t i = (size_t)y * (size_t)d->width + (size_t)x;
            for (int c = 0; c < 4; c++)
                out[c][i] = a[c];
        }
    for (int i = 0; i < l->count; i++)
        for (int c = 0; c < 4; c++)
            free(rings[i][c]);
    *band = (metrics_view){d->width, d->height, out[0], out[1], out[2], out[3]};
    return st;
}

// >>csv

typedef struct column_row {
    const char *name, *format;
    unsigned flags;
} column_row;

#define METRICS_COL_ROW(ID, name, format, flags) {#name, format, flags},
static const column_row k_columns[METRICS_COL_COUNT] = {METRICS_CSV_COLUMNS(METRICS_COL_ROW)};
#undef METRICS_COL_ROW

/* The header line, ",frame,time,...": metrics_csv_header skips the first comma. */
#define METRICS_COL_HEADER(ID, name, format, flags) "," #name
static const char k_header[] = METRICS_CSV_COLUMNS(METRICS_COL_HEADER) "\n";
#undef METRICS_COL_HEADER

const char *metrics_column_name(metrics_column c)
{
    return (unsigned)c < METRICS_COL_COUNT ? k_columns[c].name : "";
}

unsigned metrics_column_flags(metrics_column c)
{
    return (unsigned)c < METRICS_COL_COUNT ? k_columns[c].flags : 0u;
}

metrics_column metrics_column_of(const char *name)
{
    int c = 0;
    while (c < METRICS_COL_COUNT && strcmp(name, k_columns[c].name) != 0)
        c++;
    return (metrics_column)c;
}

bool metrics_csv_header(FILE *f)
{
    FS_ASSERT(f);
    fputs(k_header + 1, f);
    return !ferror(f);
}

/* `s` as one CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, quote or
 * line break. */
static void csv_field(FILE *f, const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

bool metrics_csv_row(FILE *f, int frame, float time, const char *mode, int ring,
                     const ring_metrics *m, bool still, double frame_ms, const char *gaze_event)
{
    FS_ASSERT(f && mode && m && gaze_event);
    if (!isfinite(time))
        time = 0.0f;
    if (!isfinite(frame_ms) || frame_ms < 0.0)
        frame_ms = -1.0;
    /* Every value as a double (whole numbers below 2^53 print exactly with %.0f); the mode and the
     * gaze event are the strings. %.9g keeps 9 significant digits: more than the half-float inputs carry. */
    const double v[METRICS_COL_COUNT] = {
        [METRICS_COL_FRAME] = frame,
        [METRICS_COL_TIME] = (double)time,
        [METRICS_COL_RING] = ring,
        [METRICS_COL_PIXELS] = (double)m->pixels,
        [METRICS_COL_COVERAGE] = m->coverage,
        [METRICS_COL_REF_COVERAGE] = m->ref_coverage,
        [METRICS_COL_COVERAGE_RATIO] = m->coverage_ratio,
        [METRICS_COL_RMSE] = m->rmse,
        [METRICS_COL_ALPHA_RMSE] = m->alpha_rmse,
        [METRICS_COL_FLIP] = m->flip,
        [METRICS_COL_PSNR] = m->psnr,
        [METRICS_COL_TEMPORAL_ERROR] = m->temporal_error,
        [METRICS_COL_DISOCCLUDED] = m->disoccluded,
        [METRICS_COL_STATIC_FLICKER] = still && m->has_prev ? m->change : -1.0,
        [METRICS_COL_FRAME_MS] = frame_ms,
    };
    for (int c = 0; c < METRICS_COL_COUNT; c++) {
        if (c)
            fputc(',', f);
        if (k_columns[c].format)
            fprintf(f, k_columns[c].format, v[c]);
        else
            csv_field(f, c == METRICS_COL_MODE ? mode : gaze_event);
    }
    fputc('\n', f);
    return !ferror(f);
}
