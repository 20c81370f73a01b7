/* bench_internal.h: what bench.c (the measured frames and their summaries), bench_report.c (the
 * JSON and Markdown reports) and bench_calibrate.c (--calibrate) share; not bench --accuracy. */
#ifndef FOVSIM_BENCH_INTERNAL_H
#define FOVSIM_BENCH_INTERNAL_H

#include "commands/commands.h"
#include "common/shared_defs.h"
#include "fov/fov_ring.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "session/session.h"

/* The layouts bench measures: full resolution, the run's rings without ring LOD, and (when the run
 * asks for ring LOD and its plan compiles it) the same rings with it. */
enum { BENCH_FULL, BENCH_RINGS, BENCH_RINGS_LOD, BENCH_LAYOUTS };

#define BENCH_COUNTS_MAX 8 /* work counts per stage (BENCH_COUNTS) */

/* One measured configuration of the bench (full resolution, or the run's ring layout). */
typedef struct bench_config {
    char name[64];
    alpha_mode mode;    /* the global alpha mode of this configuration */
    int layout;         /* BENCH_FULL, BENCH_RINGS or BENCH_RINGS_LOD */
    bool foveated;      /* drawn with `rings` (else full resolution) */
    bool msaa_only;     /* traditional test drawn through the MSAA targets (A2C cost split) */
    int width, height;  /* the display it is drawn at */
    bool taa;
    fov_layout rings;   /* its ring layout when foveated */
    /* bench --calibrate: only the draw with a glFinish per stage, whose statistics give the
     * counts (no separately timed draw, no covered fragments) */
    bool stages_only;
    bool held_out;      /* bench --calibrate: measures the fit instead of feeding it */
    plan pl;
    renderer *r;
    double *wall, *stage_wall, *stage_gl, *shaded; /* n, n * stages, n * stages, n */
    double *cpu, *faults; /* n each: process CPU time (ms) and minor page faults of the timed draw */
    double *instances;    /* n * MAX_FOV_RINGS: instances each ring drew (ring-major) */
    /* Work counts (BENCH_COUNTS order), -1 = unknown: per frame (n) and per stage (n * stages). */
    double *count[BENCH_COUNTS_MAX], *stage_count[BENCH_COUNTS_MAX];
    /* covered fragments of each ring's (rings off: the frame's) forward passes, summed over the frames */
    double ring_pass_covered[MAX_FOV_RINGS][PLAN_MAX_PASSES];
    renderer_stats names; /* stage names, and which stages draw the scene (pass_geometry) */
} bench_config;

/* The work counts bench reports (docs/benchmarks.md "Work counts"): names in the JSON and in the
 * text. The first four are the timed frame's pipeline statistics; covered fragments come from a
 * frame of their own drawn with the counting variant (renderer_set_counting); bytes from the
 * targets' footprints (passes/pass_bytes.h). */
enum { COUNT_VS, COUNT_PRIMS, COUNT_FS, COUNT_CLIPPED, COUNT_COVERED, COUNT_READ, COUNT_WRITTEN, COUNT_SHADED, BENCH_COUNTS };
_Static_assert(BENCH_COUNTS == BENCH_COUNTS_MAX, "BENCH_COUNTS_MAX sizes the count arrays");

typedef struct summary {
    double median, p10, p90, min, max;
} summary;


/* bench --calibrate's matrix (bench_calibrate.c): sizes x ring layouts x alpha modes x TAA. */
enum { CALIB_SIZES = 4, CALIB_LAYOUTS = 3, CALIB_CONFIGS = CALIB_SIZES * CALIB_LAYOUTS * ALPHA_MODE_COUNT * 2 };
enum { BENCH_MAX_CFG = BENCH_LAYOUTS * (ALPHA_MODE_COUNT + 1) > CALIB_CONFIGS ? BENCH_LAYOUTS * (ALPHA_MODE_COUNT + 1)
                                                                             : CALIB_CONFIGS };

/* What the bench measured, summarised per configuration (c) over the n frames: per stage (p),
 * per pipeline statistic (q) and per ring (i). */
typedef struct bench_summaries {
    summary wall[BENCH_MAX_CFG], shaded[BENCH_MAX_CFG], cpu[BENCH_MAX_CFG], faults[BENCH_MAX_CFG];
    summary count[BENCH_MAX_CFG][BENCH_COUNTS];
    summary stage_wall[BENCH_MAX_CFG][RENDERER_STATS_MAX], stage_gl[BENCH_MAX_CFG][RENDERER_STATS_MAX];
    summary stage_count[BENCH_MAX_CFG][RENDERER_STATS_MAX][BENCH_COUNTS];
    summary instances[BENCH_MAX_CFG][MAX_FOV_RINGS];
    /* sums over the frames, -1 = unknown */
    double count_all[BENCH_MAX_CFG][BENCH_COUNTS], stage_count_all[BENCH_MAX_CFG][RENDERER_STATS_MAX][BENCH_COUNTS];
    /* each configuration's median frame time / traditional's in the same layout (0: not measured) */
    double rel[BENCH_MAX_CFG];
    /* the stages that draw the scene (renderer_stats.pass_geometry), summed over the frames:
     * covered fragments and fragment-shader invocations, -1 = unknown */
    double geom_covered[BENCH_MAX_CFG], geom_fs[BENCH_MAX_CFG];
    /* foveation's speedup (the first mode, full resolution vs foveated) and its ideals: display
     * pixels / shaded pixels, and full resolution's covered fragments / the foveated frame's (the
     * stages that draw the scene, over the same frames; -1 = unknown) */
    double speedup, ideal, covered_ideal;
    /* the speedup with the composite's synced stage time taken off each foveated frame: what
     * foveation saves, without llvmpipe's full-screen pass (-1 = unknown) */
    double speedup_no_composite;
    bool has_fov;
} bench_summaries;

/* One bench run: the session, its configurations, their summaries and the report's text. */
typedef struct bench_run {
    const run_desc *d;
    session s;
    int n; /* measured frames */
    bench_config cfg[BENCH_MAX_CFG];
    int ncfg, nlayouts, per_layout;
    bool lod;   /* a ring LOD configuration per mode (BENCH_RINGS_LOD) */
    float span; /* seconds of camera path the frames spread over */
    double px;  /* display pixels */
    char rings[256], lod_text[200];
    bench_summaries sum;
    char *report;
    int o; /* bytes of report asked for (report_printf) */
} bench_run;

/* with / without, -1 when either is unknown (< 0) or without is 0. */
static inline double ratio_known(double with, double without)
{
    return with < 0 || without <= 0 ? -1.0 : with / without;
}

/* Writes the report (JSON or Markdown) of a summarised run (b->sum) into b->report and prints it;
 * --markdown appends it to that file too. */
fs_status bench_report(bench_run *b);

/* The phases bench.c runs and bench_calibrate.c shares, on configurations listed in b->cfg:
 * each one's plan and renderer; the warm-up and measured frames (nothing drawn unless st is
 * FS_OK); the summaries (b->sum); and freeing it all (the session too). */
fs_status bench_build_configs(bench_run *b);
fs_status bench_measure(bench_run *b, fs_status st);
void bench_summarise(bench_run *b);
void bench_end(bench_run *b);

#endif
