/* measure.h: what compare (compare.c) and bench --accuracy (bench_accuracy.c) share to measure
 * each alpha mode against the reference: a mode's renderer and per-ring sums over frames, and the
 * motion-compensated temporal error's per-frame state (docs/metrics.md). */
#ifndef FOVSIM_MEASURE_H
#define FOVSIM_MEASURE_H

#include <stdbool.h>

#include "metrics/metrics.h"
#include "output/exr_write.h"
#include "passes/renderer.h"
#include "reference/reference.h"
#include "session/session.h"

/* The reference of demo and bench --accuracy unless given: supersampling and samples per pixel. */
#define DEMO_SUPERSAMPLE 2
#define DEMO_SAMPLES 16

/* One alpha mode's renderer and what it measured. */
typedef struct mode_run {
    alpha_mode mode;
    plan pl;
    renderer *r;
    exr_image img, prev;   /* this frame's and the previous frame's image */
    bool have_prev;
    double *frame_ms;      /* per frame: draw to glFinish */
    /* Sums over frames, per measurement ring (+1: the whole display). cov_px, ref_px: the method's
     * and the reference's coverage summed over the ring's pixels and the frames (display pixels of
     * coverage), whose ratio is the coverage ratio over frames (measure_coverage_ratio). */
    double cov_px[MAX_FOV_RINGS + 1], ref_px[MAX_FOV_RINGS + 1];
    double rmse_sum[MAX_FOV_RINGS + 1], psnr_sum[MAX_FOV_RINGS + 1];
    double alpha_rmse_sum[MAX_FOV_RINGS + 1]; /* against the band-limited reference */
    double flip_sum[MAX_FOV_RINGS + 1];       /* mean LDR-FLIP */
    double te_sum[MAX_FOV_RINGS + 1];         /* motion-compensated temporal error */
    int te_n[MAX_FOV_RINGS + 1];
    float *flip;                              /* this frame's FLIP map against the reference */
    double still_sum[MAX_FOV_RINGS + 1]; /* static-view flicker: change on frames with a still camera */
    int err_n[MAX_FOV_RINGS + 1], still_n[MAX_FOV_RINGS + 1];
} mode_run;

/* The motion-compensated temporal error's per-frame state (docs/metrics.md "Temporal error"): a
 * depth pass that method and reference share (the traditional test at full resolution, no TAA),
 * this frame's and the previous frame's depth, and the previous reference warped into this frame. */
typedef struct temporal {
    plan pl;
    renderer *probe;
    int width, height;
    float *buf;              /* 2 depths, 4 warped reference planes, 4 warped method planes, the
                              * warp's positions (2 per pixel) */
    float *coords;
    unsigned char *valid;
    float *depth[2];         /* this frame's, the previous frame's */
    frame_record prev;       /* the previous frame (valid when have_prev) */
    bool have_prev, warped;  /* a previous frame exists; this frame's reference was warped */
    float near_depth;        /* this frame's smallest depth (warp_camera_still) */
} temporal;

/* The rings metrics are reported in: the run's own layout when it is foveated, else the acuity
 * model's (so a full-resolution run is still measured where its periphery would be). */
fov_layout measure_layout(const plan *pl);
/* The colour and coverage planes of an image (its channels R, G, B, coverage). */
metrics_view measure_view(const exr_image *img);
/* The LDR-FLIP map of img against ref at the display's pixels per degree at its centre. */
fs_status measure_flip(const metrics_view *img, const metrics_view *ref, const display_desc *d, float *out);
/* Adds one frame's per-ring metrics (count rings + the whole display) to mr's sums. still: the
 * camera did not move since the previous frame (the static-view flicker counts). */
void measure_accumulate(mode_run *mr, const ring_metrics *rm, int count, bool still);
/* sum / n, or none when n is 0. */
double measure_mean_or(double sum, int n, double none);
/* Display pixels per texel of measurement ring k of layout l (1 << scale_log2); 1 for the whole
 * display (k == l->count) and when l is NULL (a run at full resolution everywhere). */
int measure_block(const fov_layout *l, int k);
/* Measurement ring k's coverage ratio over the frames: the ratio of sums cov_px / ref_px, or -1
 * (not reported: n/a) when the reference's coverage is below METRICS_MIN_REF_TEXELS texels of
 * `block` (metrics_coverage_ratio_rests, the rule of fovsim check). */
double measure_coverage_ratio(const mode_run *mr, int k, int block);
/* Per frame: sets each ring's coverage_ratio (count rings + the whole display) to -1 where the
 * frame's reference holds less coverage than a ratio needs (the same rule); blocks as
 * measure_block(l, k). */
void measure_gate_ratios(ring_metrics *rm, int count, const fov_layout *l);

/* The temporal error (measure.c documents each step): begin once, then per frame temporal_frame,
 * temporal_measure per mode, temporal_next; temporal_end frees it. */
fs_status temporal_begin(temporal *t, const session *s);
fs_status temporal_frame(temporal *t, const frame_record *fr, const metrics_view *prev_ref);
/* temporal_frame in two: the GL part (this frame's depth pass and the warp into it; have_prev_ref:
 * a previous reference will be warped), then the CPU part (the previous reference through the
 * warp), which compare's frame worker runs. */
fs_status temporal_depth(temporal *t, const frame_record *fr, bool have_prev_ref);
void temporal_warp_reference(temporal *t, const metrics_view *prev_ref);
fs_status temporal_measure(temporal *t, const metrics_view *img, const metrics_view *prev_img,
                           const metrics_view *ref, const ring_mask *mask, double noise2, ring_metrics *rm);
/* temporal_measure with the method's warped planes in `scratch` (4 * width * height floats) instead
 * of t's own: t is only read, so modes with their own scratch may be measured at once, on threads. */
fs_status temporal_measure_in(const temporal *t, float *scratch, const metrics_view *img, const metrics_view *prev_img,
                              const metrics_view *ref, const ring_mask *mask, double noise2, ring_metrics *rm);
double temporal_reference_noise2(const reference *rf, bool still, double e_now, double e_prev);
bool temporal_still(const temporal *t, const frame_record *fr);
void temporal_next(temporal *t, const frame_record *fr);
void temporal_end(temporal *t);

/* >>phase clock: where a run's time goes (--verbose prints it; docs/compare.md "Where the time
 * goes"). The main thread's phases sum their wall time, the process's CPU time (every thread:
 * llvmpipe's, the EXR writer's, the frame worker's, whatever they did meanwhile) and the main
 * thread's own CPU time. The frame worker's jobs (compare measures and writes frame i while the
 * main thread draws frame i + 1's reference) sum their wall time and their own threads' CPU time. */
typedef enum run_phase {
    PHASE_MODES,     /* every mode's draw and readback */
    PHASE_REFERENCE, /* the reference: drawn (passes, resolve, sums) or read from the cache, and stored */
    PHASE_PREPARE,   /* the temporal error's depth pass and warp (the GL the worker needs) */
    PHASE_WAIT,      /* waiting for the worker to finish the frame before */
    PHASE_FINISH,    /* after the frames: the EXR queue drained, the video finished, the reports */
    PHASE_COUNT
} run_phase;

typedef enum worker_job {
    JOB_METRICS, /* ring masks, band limit, the previous reference warped, every mode's FLIP and
                  * per-ring metrics */
    JOB_OUTPUTS, /* the grid, the layers, the video frame, the EXR queue (waits when it is full) */
    JOB_COUNT
} worker_job;

typedef struct phase_clock {
    double wall[PHASE_COUNT], cpu[PHASE_COUNT], own_cpu[PHASE_COUNT]; /* seconds */
    double job_wall[JOB_COUNT], job_cpu[JOB_COUNT];                     /* the worker's */
    double at_wall, at_cpu, at_own;
    int cur; /* the phase running, -1 for none */
} phase_clock;

/* The calling thread's CPU time in seconds (0 when it cannot be read). */
double measure_thread_cpu_s(void);
void phase_clock_begin(phase_clock *pc);
/* Ends the phase running (if any) and starts `phase` (-1: none). */
void phase_clock_switch(phase_clock *pc, int phase);
/* One line per phase and job on stderr (log_info: --verbose only), then the EXR writer threads'
 * own CPU time (writer_cpu_s; < 0: not known), which the phases' process CPU already holds. */
void phase_clock_print(const phase_clock *pc, const char *name, double writer_cpu_s);

#endif
