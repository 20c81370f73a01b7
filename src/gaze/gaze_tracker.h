/* gaze_tracker.h: the gaze a real eye-tracking SYSTEM has at a time t, from the TRUE trace
 * (docs/latency.md). Pure C.
 *
 * The model, in order:
 *   - sampling: the tracker takes samples at times k / rate_hz (k = 0, 1, ...; from the trace start)
 *     and the system holds each until the next; rate_hz 0 = the trace's own samples, interpolated
 *     between them as gaze_at does (today's behaviour);
 *   - latency: frame t is drawn around the sample the system had at t - latency (before the first
 *     sample: the first one);
 *   - noise: Gaussian, per axis, standard deviation noise_deg degrees of visual angle, drawn once
 *     per tracker sample from a counter-based generator keyed by (seed, sample index, axis): the
 *     same seed gives the same delivered trace bit for bit at any frame rate and in any call order.
 *     The angles are those of frame_record's gaze_deg (atan of the offset from the principal point
 *     over the focal length, per axis), mapped exactly (tan), not with a small-angle guess;
 *     rate_hz 0: the noise of the trace sample at or before t - latency, held until the next;
 *   - loss: a tracker sample inside an invalid run of the trace (blink, missing value, low
 *     confidence) is lost. Policy hold: the last good sample stays (noise included); centre: the
 *     display centre; full: the frame is drawn without rings (full resolution) until the track
 *     returns. Past the trace's end the last sample is held and nothing is lost (as gaze_at).
 * With every option 0 and loss hold, gaze_tracker_at returns exactly gaze_at(trace, t).
 *
 * What it does NOT do: eye movement classification (it never reads the true trace's events), the
 * screen geometry of the recording (the trace is in display-normalised coordinates).
 */
#ifndef FOVSIM_GAZE_TRACKER_H
#define FOVSIM_GAZE_TRACKER_H

#include <stdbool.h>
#include <stdint.h>

#include "core/display.h"
#include "gaze/gaze.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gaze_loss { GAZE_LOSS_HOLD = 0, GAZE_LOSS_CENTRE, GAZE_LOSS_FULL, GAZE_LOSS_COUNT } gaze_loss;

/* Bounds of the options (the CLI, scene files and sweep manifests check against them). */
#define GAZE_TRACKER_MAX_LATENCY_MS 10000.0
#define GAZE_TRACKER_MAX_RATE_HZ 100000.0
#define GAZE_TRACKER_MAX_NOISE_DEG 30.0

typedef struct gaze_tracker_desc {
    float latency_ms; /* >= 0; 0 = the sample of time t */
    float rate_hz;    /* > 0: samples at k / rate_hz, held; 0 = the trace's own samples */
    float noise_deg;  /* standard deviation per axis, degrees of visual angle; 0 = none */
    uint32_t seed;    /* of the noise */
    gaze_loss loss;   /* default hold */
} gaze_tracker_desc;

/* Tracker options as a command line or a scene file gives them: each with whether it was given,
 * so the command line wins option by option over the scene file. */
typedef struct gaze_tracker_opts {
    gaze_tracker_desc desc;
    bool latency_set, rate_set, noise_set, seed_set, loss_set;
} gaze_tracker_opts;
/* Each option from `first` where given there, else from `second` where given there, else 0/hold. */
gaze_tracker_desc gaze_tracker_merge(const gaze_tracker_opts *first, const gaze_tracker_opts *second);

/* What the system has at one time. */
typedef struct gaze_delivery {
    float x, y;       /* normalised display coordinates, origin top-left, clamped to [0, 1] */
    bool lost;        /* the sample in use at t - latency is lost (the policy chose x, y) */
    bool full;        /* loss policy full and lost: draw this frame without rings */
    long sample;      /* the delivered sample: tracker sample index (rate > 0) or trace sample index
                         (rate 0); what the noise is keyed by */
} gaze_delivery;

/* "hold", "centre", "full"; NULL for an out-of-range value. */
const char *gaze_loss_name(gaze_loss l);
/* GAZE_LOSS_COUNT for an unknown name ("center" is taken for "centre"). */
gaze_loss gaze_loss_parse(const char *name);
/* "latency 50 ms, rate 120 Hz, noise 0.5 deg seed 7, loss hold" (rate 0: "rate trace"). */
void gaze_tracker_format(const gaze_tracker_desc *td, char *buf, int size);
/* Whether the tracker changes nothing (gaze_tracker_at == gaze_at). */
bool gaze_tracker_is_ideal(const gaze_tracker_desc *td);

/* The gaze the system has at `time` seconds for true trace `t` on display `d`. `beyond_end` (may be
 * NULL): whether t - latency was past the trace's last sample. */
gaze_delivery gaze_tracker_at(const gaze_trace *t, const gaze_tracker_desc *td, const display_desc *d, double time,
                              bool *beyond_end);

/* The noise of one sample: a standard normal deviate from (seed, sample, axis) alone. */
double gaze_tracker_normal(uint32_t seed, long sample, int axis);
/* Adds `dx_deg`, `dy_deg` (x right, y up) to the angles of normalised gaze (x, y) on display `d`
 * and returns the normalised result through x, y (not clamped). Exact: atan out, tan back. */
void gaze_offset_deg(const display_desc *d, double dx_deg, double dy_deg, double *x, double *y);

#ifdef __cplusplus
}
#endif

#endif
