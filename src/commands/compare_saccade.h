/* compare_saccade.h: what compare measures around the true gaze's eye movements (docs/latency.md
 * "After a saccade"): each frame's event (metrics.csv's gaze_event), and the foveal error after a
 * saccade lands: RMSE, FLIP and coverage ratio within FOVEA_DEG of the true gaze, frame by frame
 * for the first POST_SACCADE_MS after each landing, per mode. That is the number the eye
 * tracker's latency moves: until the rings follow, the true fovea is drawn by a coarse ring.
 * And the latency study's latency.csv and latency.png across compare runs at several latencies.
 *
 * What it does NOT do: classify (gaze_events.h), draw or measure images (compare.c gives it each
 * frame's foveal metrics, computed on its threads).
 */
#ifndef FOVSIM_COMPARE_SACCADE_H
#define FOVSIM_COMPARE_SACCADE_H

#include <stdbool.h>
#include <stdio.h>

#include "core/strbuf.h"
#include "gaze/gaze_events.h"
#include "metrics/metrics.h"
#include "passes/plan.h"
#include "session/session.h"

#define POST_SACCADE_MS 150.0
#define FOVEA_DEG 5.0f
/* Frames after a landing told apart (at most; 150 ms is 4 frames at 24 fps, 14 at 90). */
#define MAX_POST_FRAMES 64

/* One frame's place among the true gaze's events. */
typedef struct saccade_frame {
    gaze_event event;
    int post;        /* frames since the last landing (0: the first frame at or after it), when this
                        frame is within POST_SACCADE_MS of it and not itself in a saccade; else -1 */
    int saccade;     /* which saccade landed (index into the events' saccades), -1 without */
    double ms_after; /* ms since that landing */
} saccade_frame;

/* Per mode, sums over the post-saccade frames: per frame after the landing [0, MAX_POST_FRAMES),
 * and over all of them [MAX_POST_FRAMES]. Coverage as display pixels (summed), so the ratio is the
 * ratio of sums, as everywhere (docs/metrics.md). */
typedef struct post_sums {
    double rmse[MAX_POST_FRAMES + 1], flip[MAX_POST_FRAMES + 1];
    double cov_px[MAX_POST_FRAMES + 1], ref_px[MAX_POST_FRAMES + 1];
    int n[MAX_POST_FRAMES + 1];
} post_sums;

typedef struct saccade_study {
    bool on;          /* a gaze trace: its events were classified */
    gaze_events ev;
    float fps;
    int frames_after; /* frames told apart after a landing: ceil(POST_SACCADE_MS * fps), capped */
    post_sums mode[ALPHA_MODE_COUNT];
    int event_frames[GAZE_EVENT_COUNT]; /* measured frames per event */
    int landings;     /* saccades with at least one measured post-saccade frame */
    int last_saccade; /* the last one counted there */
    sbuf csv;         /* post_saccade.csv */
} saccade_study;

/* The events of session s's true trace (none without a trace) on the scene's display. */
fs_status saccade_study_begin(saccade_study *ss, const session *s, float fps);
void saccade_study_end(saccade_study *ss);
/* Frame at `time` (seconds) of the trace. */
saccade_frame saccade_study_frame(const saccade_study *ss, const gaze_trace *t, double time);
/* The mask whose ring 0 is the disc of FOVEA_DEG around the true gaze (ring 1 the rest). */
fs_status saccade_fovea_mask(const display_desc *d, const float true_gaze_px[2], ring_mask *out);
/* A measured frame: its event counted (once per frame, not per mode). */
void saccade_study_count(saccade_study *ss, const saccade_frame *sf);
/* Mode m's foveal metrics of a measured post-saccade frame (fovea: ring 0 of the fovea mask). */
void saccade_study_add(saccade_study *ss, int m, const char *mode, int frame, float time, const saccade_frame *sf,
                       const ring_metrics *fovea);

/* Mode m's figures over the post-saccade frames (`after` -1) or the `after`-th frame after the
 * landings. frames 0: nothing measured (the rest then -1). */
typedef struct post_result {
    int frames;
    double rmse, flip, coverage_ratio; /* coverage_ratio -1 when the reference holds too little */
} post_result;
post_result saccade_study_result(const saccade_study *ss, int m, int after);

/* OUT/post_saccade.csv (atomically), when the study is on. */
fs_status saccade_study_write(const saccade_study *ss, const char *out);
/* summary.json: the run's "gaze_events" member (with its trailing comma), and mode m's
 * "post_saccade" member (with its trailing ", "). */
void saccade_study_json_events(const saccade_study *ss, FILE *f);
void saccade_study_json_mode(const saccade_study *ss, FILE *f, int m);
/* The table's lines. */
void saccade_study_print(const saccade_study *ss, const alpha_mode *modes, int nm);

/* >>latency study: compare at several latencies (compare --gaze-latency MS,MS,...) */
typedef struct latency_row {
    float latency_ms;
    alpha_mode mode;
    post_result post;       /* after saccades */
    double frame_ms_median; /* the mode's */
} latency_row;
/* What one compare run of a latency study hands back. */
typedef struct latency_run {
    latency_row rows[ALPHA_MODE_COUNT]; /* one per mode */
    int count;
    char scene[512], rings[256];
} latency_run;
/* OUT/latency.csv (atomically) and OUT/latency.png (gnuplot, when on PATH) from the rows, and the
 * table on stdout. `rings`: the run's ring layout, written in every row. */
fs_status latency_study_write(const char *out, const char *scene, const char *rings, const latency_row *rows, int n);

#endif
