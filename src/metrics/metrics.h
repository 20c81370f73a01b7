/* metrics.h: image metrics of a foveated method against the reference, per foveation ring and
 * over the whole display (docs/design.md "Ground truth and metrics"; formulas in docs/metrics.md).
 *
 * Per ring and for the whole display: mean coverage of the method and of the reference and their
 * ratio (peripheral coverage preservation), RMSE and PSNR of linear RGB against the reference (and
 * against the band-limited reference: alpha_rmse), mean FLIP, the method's mean frame-to-frame
 * change, and (metrics_temporal) the motion-compensated temporal error.
 *
 * Usage:
 *   ring_mask m;  ring_mask_build(&display, &layout, gx_px, gy_px, &m);   (per gaze)
 *   ring_metrics out[MAX_FOV_RINGS + 1];
 *   metrics_compute(&img, &ref, band_or_NULL, flip_or_NULL, prev_or_NULL, &m, out);
 *   metrics_csv_header(f);  metrics_csv_row(f, frame, time, "hashed", ring_or_-1, &out[k], ms);
 *   ring_mask_free(&m);
 *
 * Every number it produces is finite (they end up in CSV and JSON):
 *   - a non-finite or huge input sample counts as the EXR file would store it: NaN as 0, and
 *     values clamped to +-65504 (no half rounding otherwise);
 *   - the ratio of two means (coverage_ratio) is 1 when both are below METRICS_EPS (nothing to
 *     preserve and nothing added: no difference) and otherwise num / max(den, METRICS_EPS), a
 *     large number when only the reference is ~0 (bloat out of nothing);
 *   - PSNR is capped at METRICS_PSNR_CAP_DB (identical images);
 *   - a ring with no display pixels for this gaze (pixels == 0) reports the neutral values
 *     (means 0, ratios 1, rmse 0, psnr at the cap): skip it by its pixel count;
 *   - without a previous frame (first frame, after a cut) change is 0 and has_prev 0.
 *
 * What it does NOT do: GL, reading EXR files, choosing frames or modes, aggregating frames into a
 * summary (the caller does, skipping rows with pixels == 0 and change rows with has_prev == 0).
 */
#ifndef FOVSIM_METRICS_H
#define FOVSIM_METRICS_H

#include <stdbool.h>
#include <stdio.h>

#include "core/status.h"
#include "fov/fov_ring.h"
#include "scene/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Means below this count as zero in a ratio's denominator (coverage and mean change, both in
 * linear units where visible values are 1e-3..1): a ring whose reference holds a single
 * 1e-3-coverage pixel in a million is still a real, if tiny, reference. */
#ifndef METRICS_EPS
#define METRICS_EPS 1e-6
#endif
/* A coverage ratio rests on the reference's coverage: below this many ring texels of it (the sum of
 * the reference's coverage over the ring's display pixels, divided by block^2 display pixels per
 * texel) a ratio is not reported, per frame (metrics.csv writes -1) nor over frames (summaries
 * write -1 and print n/a), and `fovsim check` does not judge it. A ratio of a few texels' coverage
 * jumps with every flipped texel: 1 texel of method coverage over 1/4 texel of reference reads 4.
 * One definition for compare, bench --accuracy, merge and check (docs/metrics.md "Coverage ratio
 * over frames"). */
#ifndef METRICS_MIN_REF_TEXELS
#define METRICS_MIN_REF_TEXELS 4.0
#endif
/* PSNR of identical images, in dB: 10 log10(1 / MSE) reaches it at MSE = 1e-10, far below the
 * error of a half-float frame (ulp 2^-11 at 1.0 gives MSE ~ 1e-7 at worst). */
#ifndef METRICS_PSNR_CAP_DB
#define METRICS_PSNR_CAP_DB 100.0
#endif

/* A borrowed view of one frame: linear, premultiplied, rows top first, width * height floats per
 * plane. All four planes are required. */
typedef struct metrics_view {
    int width, height;
    const float *r, *g, *b, *coverage;
} metrics_view;

/* The ring each display pixel belongs to for one gaze. */
typedef struct ring_mask {
    int width, height; /* display pixels */
    int ring_count;    /* the layout's ring count */
    unsigned char *ring; /* width * height ring indices, rows top first; owned */
} ring_mask;

/* Ring of each display pixel for gaze (gx_px, gy_px) in display pixels:
 * fov_composite_weight(l, fov_eccentricity_deg(d, gx, gy, x + 0.5, y + 0.5)).ring, the gaze first
 * clamped with fov_gaze_clamp (the gaze the composite uses). A pixel in the blend band of a
 * border counts for the inner ring (the one it mostly shows). FS_ERR_USAGE for a bad display
 * (size outside 1..MAX_DISPLAY_SIZE) or layout (count outside 1..MAX_FOV_RINGS), FS_ERR_NOMEM
 * when out of memory; *out is zeroed then. Costs one eccentricity per pixel (~30 ms at 1280x720
 * on one core): build it when the gaze moves, not per mode. */
fs_status ring_mask_build(const display_desc *d, const fov_layout *l, float gx_px, float gy_px,
                          ring_mask *out);
/* No-op on a zeroed mask. */
void ring_mask_free(ring_mask *m);

/* Metrics of one ring (or of the whole display) of one frame of one method. */
typedef struct ring_metrics {
    long long pixels;      /* display pixels in the ring; 0: off screen for this gaze (the rest
                              then holds the neutral values, see above) */
    double coverage;       /* mean coverage of the method */
    double ref_coverage;   /* mean coverage of the reference */
    double coverage_ratio; /* coverage / ref_coverage (see the header for ~0); 1 = preserved */
    double rmse;           /* sqrt(mean over pixels and R, G, B of (img - ref)^2) */
    double alpha_rmse;     /* the same against the band-limited reference (metrics_band_limit):
                              the part of the error the rings' resolution does not explain; equals
                              rmse when no band-limited reference is given */
    double psnr;           /* 10 log10(1 / MSE), peak 1.0, capped at METRICS_PSNR_CAP_DB */
    double flip;           /* mean LDR-FLIP error (metrics/flip.h) over the ring's pixels; 0 when no
                              FLIP map is given */
    double temporal_error; /* metrics_temporal: motion-compensated; -1 when not measured */
    double disoccluded;    /* metrics_temporal: share of pixels not warped; -1 when not measured */
    double change;         /* mean over pixels of (|dR| + |dG| + |dB|) / 3, frame - previous, not
                              motion-compensated: the static-view flicker when the camera is still */
    int has_prev;          /* 1 when previous frames were given (change is measured) */
} ring_metrics;

/* Fills out[0 .. ring_count - 1] (per ring) and out[ring_count] (whole display). prev may be
 * NULL (first frame, after a cut): no change measured.
 * band (may be NULL) is the band-limited reference, for alpha_rmse; flip (may be NULL) the
 * image's FLIP error map against the reference (the mask's size), for flip. Every view must have
 * the mask's size: FS_ERR_INTERNAL otherwise (a bug in the caller, out[] is then zeroed), else
 * FS_OK. Sums in double. */
fs_status metrics_compute(const metrics_view *img, const metrics_view *ref, const metrics_view *band,
                          const float *flip, const metrics_view *prev, const ring_mask *mask,
                          ring_metrics *out);

/* Motion-compensated temporal error of one frame (docs/metrics.md "Temporal error"), per ring
 * (out[0 .. ring_count - 1]) and over the whole display (out[ring_count]):
 *   temporal_error = sqrt(mean over warped pixels and R, G, B of ((I - W I') - (F - W F'))^2)
 *   disoccluded    = share of the ring's pixels that were not warped (valid[i] == 0)
 * img/ref: this frame's method and reference; wprev/wref: the previous frames warped into this one
 * (warp_previous, with one warp for both). A ring with no warped pixel gets 0 and disoccluded 1.
 * Fills only those two fields. FS_ERR_INTERNAL for mismatched sizes. */
fs_status metrics_temporal(const metrics_view *img, const metrics_view *wprev, const metrics_view *ref,
                           const metrics_view *wref, const unsigned char *valid, const ring_mask *mask,
                           ring_metrics *out);

/* The band-limited reference: the reference as the rings of layout `l` would show it if each had
 * drawn it exactly. Each ring's footprint rects[i] (the frame's ring_rect) is box-filtered down to
 * the ring's grid (the display pixels of each ring pixel that lie on the display, averaged), and
 * every display pixel is reconstructed as the composite does (shaders/composite.frag): the ring of
 * its eccentricity for gaze (gx_px, gy_px) (clamped as fov_gaze_clamp), sampled bilinearly with
 * taps clamped to the rendered texel centres, mixed with the next ring inside the blend band.
 * With one full-resolution ring it is the reference itself. out: four planes (R, G, B, coverage)
 * of the reference's size, written here; *band views them. FS_ERR_NOMEM when out of memory,
 * FS_ERR_USAGE for a bad layout. */
fs_status metrics_band_limit(const metrics_view *ref, const display_desc *d, const fov_layout *l,
                             const fov_ring_rect *rects, float gx_px, float gy_px, float *const out[4],
                             metrics_view *band);

/* Whether a coverage ratio resting on ref_px display pixels of reference coverage (the sum of the
 * reference's coverage over the pixels, e.g. ref_coverage * pixels, or its sum over frames) in a ring
 * of block x block display pixels per texel is reported: ref_px / block^2 >= METRICS_MIN_REF_TEXELS.
 * block < 1 counts as 1 (a full-resolution ring, the whole display). */
bool metrics_coverage_ratio_rests(double ref_px, int block);
/* The ratio of sums cov_px / ref_px (coverage summed over pixels and frames) when
 * metrics_coverage_ratio_rests(ref_px, block), else -1 (not reported). */
double metrics_coverage_ratio_of_sums(double cov_px, double ref_px, int block);

/* >>columns: the columns of metrics.csv, in order: the one list of them. One row per column,
 * X(ID, name, FORMAT, FLAGS):
 *   ID      METRICS_COL_<ID>, its index in a row
 *   name    its name in the header, by which merge and check find it; fovsim check's metric of
 *           the same name (check_metric_name), if any, judges it as its flags say
 *   FORMAT  how metrics_csv_row writes its value (NULL: a string, the mode or the gaze event)
 *   FLAGS   METRICS_COLF_* or'ed
 * docs/metrics.md defines each; docs/design-notes.md "Adding a metrics.csv column" lists what else a
 * new measurement touches. */
#define METRICS_COLF_KEY 1         /* names the row (frame, time, mode, ring), not a measurement */
#define METRICS_COLF_WHOLE 2       /* a whole number (merge refuses anything else) */
#define METRICS_COLF_GROWTH 4      /* an error: fovsim check fails its growth, now - baseline */
#define METRICS_COLF_EITHER_WAY 8  /* fovsim check fails a change either way, |now - baseline|
                                    * (coverage: erosion and bloat) */
#define METRICS_COLF_UNMEASURED 16 /* negative (-1) = not measured or not reported: check skips it */
#define METRICS_COLF_RESTS 32      /* judged only where both runs' reference holds enough coverage
                                    * (metrics_coverage_ratio_rests) */
#define METRICS_CSV_COLUMNS(X)                                                                    \
    X(FRAME, frame, "%.0f", METRICS_COLF_KEY | METRICS_COLF_WHOLE)                               \
    X(TIME, time, "%.9g", METRICS_COLF_KEY)                                                      \
    X(MODE, mode, NULL, METRICS_COLF_KEY)                                                        \
    X(RING, ring, "%.0f", METRICS_COLF_KEY | METRICS_COLF_WHOLE)                                 \
    X(PIXELS, pixels, "%.0f", METRICS_COLF_WHOLE)                                                \
    X(COVERAGE, coverage, "%.9g", 0)                                                             \
    X(REF_COVERAGE, ref_coverage, "%.9g", 0)                                                     \
    X(COVERAGE_RATIO, coverage_ratio, "%.9g",                                                    \
      METRICS_COLF_EITHER_WAY | METRICS_COLF_UNMEASURED | METRICS_COLF_RESTS)                    \
    X(RMSE, rmse, "%.9g", METRICS_COLF_GROWTH)                                                   \
    X(ALPHA_RMSE, alpha_rmse, "%.9g", METRICS_COLF_GROWTH)                                       \
    X(FLIP, flip, "%.9g", METRICS_COLF_GROWTH)                                                   \
    X(PSNR, psnr, "%.9g", 0)                                                                     \
    X(TEMPORAL_ERROR, temporal_error, "%.9g", METRICS_COLF_GROWTH | METRICS_COLF_UNMEASURED)     \
    X(DISOCCLUDED, disoccluded, "%.9g", METRICS_COLF_UNMEASURED)                                 \
    X(STATIC_FLICKER, static_flicker, "%.9g", METRICS_COLF_UNMEASURED)                           \
    X(GAZE_EVENT, gaze_event, NULL, 0)                                                           \
    X(FRAME_MS, frame_ms, "%.3f", METRICS_COLF_UNMEASURED)

#define METRICS_COL_ENUM(ID, name, format, flags) METRICS_COL_##ID,
typedef enum metrics_column { METRICS_CSV_COLUMNS(METRICS_COL_ENUM) METRICS_COL_COUNT } metrics_column;
#undef METRICS_COL_ENUM

/* The column's name ("coverage_ratio"), its METRICS_COLF_* flags; the column of a name, or
 * METRICS_COL_COUNT. */
const char *metrics_column_name(metrics_column c);
unsigned metrics_column_flags(metrics_column c);
metrics_column metrics_column_of(const char *name);

/* CSV: one row per frame x mode x ring (ring -1 = the whole display), the columns above;
 * gaze_event is the true gaze's eye-movement event at the frame (gaze_events.h: "fixation",
 * "saccade", "pursuit", "lost");
 * static_flicker is `change` on frames with a
 * still camera (the caller says: still) and -1 otherwise. coverage_ratio is written as given: compare
 * sets it to -1 first where the reference holds too little (measure_gate_ratios,
 * metrics_coverage_ratio_rests). `mode` is quoted when it holds a comma, quote or line break. frame_ms < 0 or
 * not finite means "not measured" and is written as -1; a non-finite time as 0. Both return
 * false when the stream reports an error. */
bool metrics_csv_header(FILE *f);
bool metrics_csv_row(FILE *f, int frame, float time, const char *mode, int ring,
                     const ring_metrics *m, bool still, double frame_ms, const char *gaze_event);

#ifdef __cplusplus
}
#endif

#endif
