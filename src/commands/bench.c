/* bench.c: `fovsim bench` (without --accuracy, which is bench_accuracy.c): frame time, CPU time,
 * page faults and pipeline statistics of full resolution against the ring layout (and, with ring
 * LOD, the same rings with it), per alpha mode and per stage, interleaved frame by frame so every
 * configuration sees the same machine state. */
#include "commands/commands.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <unistd.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "core/proc_stats.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "fov/fov_ring.h"
#include "fov/ring_lod.h"
#include "gaze/gaze.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "frame/frame.h"
#include "session/session.h"

/* The layouts bench measures: full resolution, the run's rings without ring LOD, and (when the run
 * asks for ring LOD and its plan compiles it) the same rings with it. */
enum { BENCH_FULL, BENCH_RINGS, BENCH_RINGS_LOD, BENCH_LAYOUTS };
static const char *const k_layout_names[BENCH_LAYOUTS] = {"full resolution", "foveated", "foveated + ring LOD"};

#define BENCH_COUNTS_MAX 7 /* work counts per stage (BENCH_COUNTS) */

/* One measured configuration of the bench (full resolution, or the run's ring layout). */
typedef struct bench_config {
    char name[64];
    alpha_mode mode;    /* the global alpha mode of this configuration */
    int layout;         /* BENCH_FULL, BENCH_RINGS or BENCH_RINGS_LOD */
    bool foveated;      /* the run's ring layout (else full resolution) */
    bool msaa_only;     /* traditional test drawn through the MSAA targets (A2C cost split) */
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
enum { COUNT_VS, COUNT_PRIMS, COUNT_FS, COUNT_CLIPPED, COUNT_COVERED, COUNT_READ, COUNT_WRITTEN, BENCH_COUNTS };
_Static_assert(BENCH_COUNTS == BENCH_COUNTS_MAX, "BENCH_COUNTS_MAX sizes the count arrays");
static const char *const k_count_keys[BENCH_COUNTS] = {"vs_invocations", "primitives", "fs_invocations",
                                                       "clipped_primitives", "covered_fragments", "bytes_read",
                                                       "bytes_written"};
static const char *const k_count_names[BENCH_COUNTS] = {"vertex shader invocations", "primitives submitted",
                                                        "fragment shader invocations", "primitives after clipping",
                                                        "covered fragments", "bytes read (footprints)",
                                                        "bytes written (footprints)"};

typedef struct summary {
    double median, p10, p90, min, max;
} summary;

/* Sorts v (n values) and summarises it. */
static summary summarise(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, stats_cmp_double);
    return (summary){stats_quantile(v, n, 0.5), stats_quantile(v, n, 0.1), stats_quantile(v, n, 0.9), v[0], v[n - 1]};
}

static bool bench_alloc(bench_config *c, int n)
{
    c->wall = calloc((size_t)n, sizeof(double));
    c->stage_wall = calloc((size_t)n * RENDERER_STATS_MAX, sizeof(double));
    c->stage_gl = calloc((size_t)n * RENDERER_STATS_MAX, sizeof(double));
    c->shaded = calloc((size_t)n, sizeof(double));
    c->cpu = calloc((size_t)n, sizeof(double));
    c->faults = calloc((size_t)n, sizeof(double));
    c->instances = calloc((size_t)n * MAX_FOV_RINGS, sizeof(double));
    bool ok = c->wall && c->stage_wall && c->stage_gl && c->shaded && c->cpu && c->faults && c->instances;
    for (int q = 0; q < BENCH_COUNTS; q++) {
        c->count[q] = calloc((size_t)n, sizeof(double));
        c->stage_count[q] = calloc((size_t)n * RENDERER_STATS_MAX, sizeof(double));
        ok = ok && c->count[q] && c->stage_count[q];
    }
    return ok;
}

static void bench_free(bench_config *c)
{
    free(c->wall);
    free(c->stage_wall);
    free(c->stage_gl);
    free(c->shaded);
    free(c->cpu);
    free(c->faults);
    free(c->instances);
    for (int q = 0; q < BENCH_COUNTS; q++) {
        free(c->count[q]);
        free(c->stage_count[q]);
    }
}

/* Draws frame k of config c twice: once as the renderer runs it (timed to glFinish; its process CPU
 * time, minor page faults and pipeline statistics are counted too), once with a finish after every
 * stage (per-stage wall times). Records when k >= 0. */
static void bench_frame(session *s, bench_config *c, int k, float t, int n)
{
    frame_record fr = frame_record_at(&s->sc, k < 0 ? 0 : k, t, -1.0f, c->pl.width, c->pl.height);
    float gx = 0.5f, gy = 0.5f;
    if (s->gaze.count > 0) {
        gaze_point g = gaze_at(&s->gaze, t, NULL);
        gx = g.x;
        gy = g.y;
    }
    display_desc dd = {c->pl.width, c->pl.height, fr.hfov_deg};
    frame_record_set_gaze(&fr, &c->pl.layout, &dd, gx, gy);
    renderer_set_pass_sync(c->r, false);
    proc_stats p0 = proc_stats_now();
    double t0 = time_now();
    renderer_draw(c->r, &fr);
    renderer_finish(c->r);
    double t1 = time_now();
    proc_stats pd = proc_stats_since(p0);
    renderer_stats rs = renderer_last_stats(c->r);
    renderer_set_pass_sync(c->r, true);
    renderer_draw(c->r, &fr);
    renderer_stats sync = renderer_last_stats(c->r);
    c->names = rs;
    if (k < 0)
        return;
    /* The counting variant, in a frame of its own: the timed frame above has no counter. */
    renderer_set_counting(c->r, true);
    renderer_draw(c->r, &fr);
    renderer_stats cs = renderer_last_stats(c->r);
    renderer_set_counting(c->r, false);
    memcpy(c->names.pass_geometry, cs.pass_geometry, sizeof cs.pass_geometry);
    for (int i = 0; i < MAX_FOV_RINGS; i++)
        for (int p = 0; p < PLAN_MAX_PASSES; p++)
            c->ring_pass_covered[i][p] += (double)cs.ring_pass_covered[i][p];
    c->wall[k] = (t1 - t0) * 1e3;
    c->cpu[k] = pd.cpu_ms;
    c->faults[k] = (double)pd.minor_faults;
    const long long *stage_counts[BENCH_COUNTS] = {rs.pass_vs_invocations, rs.pass_primitives, rs.pass_fs_invocations,
                                                   rs.pass_clipped, cs.pass_covered, rs.pass_bytes_read,
                                                   rs.pass_bytes_written};
    const long long frame_counts[BENCH_COUNTS] = {rs.vs_invocations, rs.primitives, rs.fragments, rs.clipped,
                                                  cs.covered, rs.bytes_read, rs.bytes_written};
    for (int p = 0; p < rs.pass_count; p++) {
        size_t at = (size_t)p * (size_t)n + (size_t)k;
        c->stage_wall[at] = sync.pass_wall_ms[p];
        c->stage_gl[at] = rs.pass_ms[p];
        for (int q = 0; q < BENCH_COUNTS; q++)
            c->stage_count[q][at] = (double)stage_counts[q][p];
    }
    for (int q = 0; q < BENCH_COUNTS; q++)
        c->count[q][k] = (double)frame_counts[q];
    c->shaded[k] = (double)rs.shaded_pixels;
    for (int i = 0; i < rs.ring_count; i++)
        c->instances[(size_t)i * (size_t)n + (size_t)k] = rs.ring_instances[i];
}

/* Sum of n values, -1 when any is unknown (< 0). */
static double sum_known(const double *v, int n)
{
    double sum = 0;
    for (int i = 0; i < n; i++) {
        if (v[i] < 0)
            return -1.0;
        sum += v[i];
    }
    return sum;
}

enum { BENCH_REPORT_CAP = 1 << 20 };

/* Appends to the report (BENCH_REPORT_CAP bytes); *o counts what was asked for, so an overflow
 * shows as *o >= BENCH_REPORT_CAP. */
static void report_printf(char *report, int *o, const char *fmt, ...)
{
    if (*o >= BENCH_REPORT_CAP - 1) {
        *o = BENCH_REPORT_CAP;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(report + *o, (size_t)(BENCH_REPORT_CAP - *o), fmt, ap);
    va_end(ap);
    *o = k < 0 || k >= BENCH_REPORT_CAP - *o ? BENCH_REPORT_CAP : *o + k;
}

/* One cell of a count: the integer, or n/a when unknown (< 0). */
static void out_count(char *report, int *o, double v)
{
    if (v < 0)
        report_printf(report, o, " n/a |");
    else
        report_printf(report, o, " %.0f |", v);
}

/* One row of the bench table: the summary / scale with `decimals` digits; n/a where unknown (< 0). */
static void bench_row(char *report, int *o, const char *cfg, const char *measure, summary v, double scale,
                      int decimals)
{
    const double x[5] = {v.median, v.p10, v.p90, v.min, v.max};
    report_printf(report, o, "| %s | %s |", cfg, measure);
    for (int i = 0; i < 5; i++) {
        if (x[i] < 0)
            report_printf(report, o, " n/a |");
        else
            report_printf(report, o, " %.*f |", decimals, x[i] / scale);
    }
    report_printf(report, o, "\n");
}

/* with / without, -1 when either is unknown (< 0) or without is 0. */
static double ratio_known(double with, double without)
{
    return with < 0 || without <= 0 ? -1.0 : with / without;
}

/* The ring a stage draws ("ring 2 (1/4, all passes)"), -1 for any other stage. */
static int stage_ring(const char *name)
{
    int ring = -1, at = 0;
    return sscanf(name, "ring %d (%n", &ring, &at) == 1 && at > 0 ? ring : -1;
}

/* What one fragment-shader invocation of the pipeline statistics is: GPUs shade 2x2 quads,
 * llvmpipe whole 4x4 blocks (docs/benchmarks.md "Work counts"). */
static const char *bench_invocation_unit(void)
{
    return strstr(gl_device_renderer(), "llvmpipe") ? "4x4 blocks (llvmpipe)" : "2x2 quads (GPU)";
}

/* >>phases: cmd_bench runs them in order, sharing one bench_run. */

enum { BENCH_MAX_CFG = BENCH_LAYOUTS * (ALPHA_MODE_COUNT + 1) };

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

/* The configurations: for each alpha mode asked for (--modes, default the run's), full resolution
 * and, when the run has rings, foveated (and foveated with ring LOD); plus traditional through the
 * MSAA targets when an A2C mode is measured, so the MSAA cost can be told from the A2C test's own. */
static void bench_list_configs(bench_run *b)
{
    const run_desc *d = b->d;
    alpha_mode modes[ALPHA_MODE_COUNT];
    int nmodes = 0;
    bool want_msaa = false;
    for (int m = 0; m < d->bench_mode_count; m++)
        modes[nmodes++] = d->bench_modes[m];
    if (nmodes == 0)
        modes[nmodes++] = b->s.pl.global_mode;
    for (int m = 0; m < nmodes; m++)
        want_msaa |= alpha_mode_has(modes[m], ALPHA_TRAIT_MSAA);
    /* Ring LOD (docs/ring-lod.md) is measured against the same rings without it: the plain rings
     * configuration is drawn without it, whatever --ring-lod or the scene say. */
    const plan *pl = &b->s.pl;
    b->lod = pl->rings && pl->ring_lod;
    if (!b->lod && (pl->ring_lod || pl->ring_lod_why[0]))
        log_warn("bench: ring LOD not measured (%s)", pl->ring_lod ? "no rings" : pl->ring_lod_why);
    b->nlayouts = b->lod ? 3 : pl->rings ? 2 : 1;
    for (int lay = 0; lay < b->nlayouts; lay++)
        for (int m = 0; m < nmodes + (want_msaa ? 1 : 0); m++) {
            bench_config *c = &b->cfg[b->ncfg++];
            c->layout = lay;
            c->foveated = lay != BENCH_FULL;
            c->msaa_only = m == nmodes;
            c->mode = c->msaa_only ? ALPHA_MODE_TRADITIONAL : modes[m];
            snprintf(c->name, sizeof c->name, "%s%s, %s", alpha_mode_name(c->mode), c->msaa_only ? "+MSAA" : "",
                     k_layout_names[lay]);
        }
    b->per_layout = b->ncfg / b->nlayouts;
}

/* Each configuration's plan, renderer (with timers) and sample arrays. */
static fs_status bench_build_configs(bench_run *b)
{
    const run_desc *d = b->d;
    fs_status st = FS_OK;
    for (int c = 0; c < b->ncfg && st == FS_OK; c++) {
        bench_config *cf = &b->cfg[c];
        plan_options po = {.alpha_mode = cf->mode, .width = d->width, .height = d->height, .frames = b->n,
                           .alpha = b->s.pl.alpha, .force_msaa = cf->msaa_only, .taa = b->s.pl.taa,
                           .taa_controls = b->s.pl.taa_controls, .no_ring_cull = d->no_ring_cull,
                           .composite_per_pixel = d->composite_per_pixel};
        if (cf->foveated)
            po.layout = b->s.pl.layout;
        if (cf->layout == BENCH_RINGS_LOD)
            po.ring_lod = b->s.pl.ring_lod_spec;
        st = plan_build(&b->s.sc, &po, &cf->pl);
        if (st == FS_OK)
            cf->r = renderer_create(
                &(renderer_desc){.scene = &b->s.sc, .plan = &cf->pl, .timers = true, .count_fragments = true}, &st);
    }
    for (int c = 0; c < b->ncfg && st == FS_OK; c++)
        if (!bench_alloc(&b->cfg[c], b->n))
            st = FS_ERR_NOMEM;
    return st;
}

/* The warm-up and measured frames, spread evenly over the camera path (and gaze trace), the
 * configurations interleaved per frame so all see the same machine state. Draws nothing when st
 * (the setup's status) is not FS_OK; the progress line is begun and ended either way. */
static fs_status bench_measure(bench_run *b, fs_status st)
{
    const run_desc *d = b->d;
    int n = b->n;
    b->span = b->s.sc.duration;
    progress pr = progress_begin("bench", d->bench.warmup + n, d->quiet, d->progress_interval);
    for (int i = 0; i < d->bench.warmup + n && st == FS_OK; i++) {
        int k = i < d->bench.warmup ? -1 : i - d->bench.warmup;
        int kk = k < 0 ? i : k;
        float t = n > 1 ? b->span * (float)kk / (float)(n - 1) : 0.0f;
        for (int c = 0; c < b->ncfg; c++)
            bench_frame(&b->s, &b->cfg[c], k, t, n);
        progress_update(&pr, i + 1);
    }
    progress_end(&pr);
    return st;
}

/* Summarises every configuration's samples (sorting them), and the speedups. */
static void bench_summarise(bench_run *b)
{
    bench_summaries *u = &b->sum;
    int n = b->n;
    for (int c = 0; c < b->ncfg; c++) {
        bench_config *cf = &b->cfg[c];
        u->wall[c] = summarise(cf->wall, n);
        u->shaded[c] = summarise(cf->shaded, n);
        u->cpu[c] = summarise(cf->cpu, n);
        u->faults[c] = summarise(cf->faults, n);
        for (int i = 0; i < cf->pl.layout.count; i++)
            u->instances[c][i] = summarise(&cf->instances[(size_t)i * (size_t)n], n);
        for (int q = 0; q < BENCH_COUNTS; q++) {
            u->count_all[c][q] = sum_known(cf->count[q], n);
            u->count[c][q] = summarise(cf->count[q], n);
        }
        for (int p = 0; p < cf->names.pass_count; p++) {
            u->stage_wall[c][p] = summarise(&cf->stage_wall[(size_t)p * (size_t)n], n);
            u->stage_gl[c][p] = summarise(&cf->stage_gl[(size_t)p * (size_t)n], n);
            for (int q = 0; q < BENCH_COUNTS; q++) {
                double *v = &cf->stage_count[q][(size_t)p * (size_t)n];
                u->stage_count_all[c][p][q] = sum_known(v, n);
                u->stage_count[c][p][q] = summarise(v, n);
            }
        }
        u->geom_covered[c] = u->geom_fs[c] = 0;
        for (int p = 0; p < cf->names.pass_count; p++)
            if (cf->names.pass_geometry[p]) {
                double cv = u->stage_count_all[c][p][COUNT_COVERED], fs = u->stage_count_all[c][p][COUNT_FS];
                u->geom_covered[c] = cv < 0 || u->geom_covered[c] < 0 ? -1.0 : u->geom_covered[c] + cv;
                u->geom_fs[c] = fs < 0 || u->geom_fs[c] < 0 ? -1.0 : u->geom_fs[c] + fs;
            }
    }
    /* Foveation's speedup: the first mode, full resolution vs foveated. */
    u->has_fov = b->s.pl.rings;
    u->speedup = u->has_fov ? u->wall[0].median / u->wall[b->per_layout].median : 1.0;
    u->ideal = u->has_fov ? b->px / u->shaded[b->per_layout].median : 1.0;
    u->covered_ideal = u->has_fov ? ratio_known(u->geom_covered[0], u->geom_covered[b->per_layout]) : 1.0;
    /* Each configuration's frame time relative to traditional in the same layout (seed 000
     * Table 1's comparison); 0 when traditional was not measured. */
    for (int c = 0; c < b->ncfg; c++)
        for (int t = 0; t < b->ncfg; t++)
            if (b->cfg[t].mode == ALPHA_MODE_TRADITIONAL && !b->cfg[t].msaa_only && b->cfg[t].layout == b->cfg[c].layout)
                u->rel[c] = u->wall[c].median / u->wall[t].median;
}

#define OUT(...) report_printf(b->report, &b->o, __VA_ARGS__)

/* --json: one configuration's object. */
static void bench_json_config(bench_run *b, int c)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    char spec[256];
    fov_layout_format(&cf->pl.layout, spec, sizeof spec);
    char lu[160] = "off";
    if (cf->pl.ring_lod)
        ring_lod_format_u(&cf->pl.ring_lod_spec, &cf->pl.layout, lu, sizeof lu);
    OUT("    {\"name\": \"%s\", \"alpha_mode\": \"%s\", \"msaa_only\": %s, \"rings\": \"%s\", "
        "\"ring_lod_u\": \"%s\", \"shaded_pixels\": %.0f, \"relative_to_traditional\": %.4f,\n",
        cf->name, alpha_mode_name(cf->mode), cf->msaa_only ? "true" : "false", spec, lu, u->shaded[c].median,
        u->rel[c]);
    OUT("     \"frame_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
        u->wall[c].median, u->wall[c].p10, u->wall[c].p90, u->wall[c].min, u->wall[c].max);
    OUT("     \"cpu_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
        u->cpu[c].median, u->cpu[c].p10, u->cpu[c].p90, u->cpu[c].min, u->cpu[c].max);
    OUT("     \"minor_faults\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f},\n",
        u->faults[c].median, u->faults[c].p10, u->faults[c].p90, u->faults[c].min, u->faults[c].max);
    for (int q = 0; q < BENCH_COUNTS; q++)
        OUT("     \"%s\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f, "
            "\"all_frames\": %.0f},\n", k_count_keys[q], u->count[c][q].median, u->count[c][q].p10,
            u->count[c][q].p90, u->count[c][q].min, u->count[c][q].max, u->count_all[c][q]);
    OUT("     \"ring_instances_median\": [");
    for (int i = 0; i < cf->pl.layout.count; i++)
        OUT("%s%.0f", i ? ", " : "", u->instances[c][i].median);
    OUT("],\n");
    double frags = u->count[c][2].median;
    OUT("     \"fragments_per_pixel\": %.3f,\n", frags >= 0 ? frags / b->px : -1.0);
    OUT("     \"geometry_covered_fragments_all_frames\": %.0f, \"geometry_fs_invocations_per_covered\": %.4f,\n",
        u->geom_covered[c], ratio_known(u->geom_fs[c], u->geom_covered[c]));
    OUT("     \"stages\": [");
    int ring = 0;
    for (int p = 0; p < cf->names.pass_count; p++) {
        bool geom = cf->names.pass_geometry[p];
        OUT("%s\n       {\"name\": \"%s\", \"geometry\": %s, \"wall_ms_median\": %.3f, \"gl_timer_ms_median\": %.3f",
            p ? "," : "", cf->names.pass_names[p], geom ? "true" : "false", u->stage_wall[c][p].median,
            u->stage_gl[c][p].median);
        for (int q = 0; q < BENCH_COUNTS; q++)
            OUT(",\n        \"%s_median\": %.0f, \"%s_all_frames\": %.0f", k_count_keys[q],
                u->stage_count[c][p][q].median, k_count_keys[q], u->stage_count_all[c][p][q]);
        OUT(",\n        \"fs_invocations_per_covered\": %.4f",
            ratio_known(u->stage_count_all[c][p][COUNT_FS], u->stage_count_all[c][p][COUNT_COVERED]));
        if (geom && cf->pl.composite) { /* a ring: its forward passes' covered fragments */
            OUT(",\n        \"covered_fragments_by_pass\": [");
            for (int i = 0; i < cf->pl.pass_count; i++)
                OUT("%s{\"pass\": \"%s\", \"all_frames\": %.0f}", i ? ", " : "", cf->pl.passes[i].name,
                    cf->ring_pass_covered[ring][i]);
            OUT("]");
            ring++;
        }
        OUT("}");
    }
    OUT("]}%s\n", c + 1 < b->ncfg ? "," : "");
}

/* --json: each mode's ring LOD configuration against its plain rings: time ratios of medians,
 * count ratios of the totals over the same frames; -1 = unknown. */
static void bench_json_ring_lod(bench_run *b)
{
    const bench_summaries *u = &b->sum;
    int per_layout = b->per_layout;
    OUT("  \"ring_lod_vs_rings\": [");
    for (int c = 2 * per_layout; c < b->ncfg; c++) {
        int w = c - per_layout;
        const bench_config *cf = &b->cfg[c];
        OUT("%s\n    {\"name\": \"%s\", \"without\": \"%s\", \"frame_ms_ratio\": %.4f, \"cpu_ms_ratio\": %.4f",
            c > 2 * per_layout ? "," : "", cf->name, b->cfg[w].name, ratio_known(u->wall[c].median, u->wall[w].median),
            ratio_known(u->cpu[c].median, u->cpu[w].median));
        for (int q = 0; q < BENCH_COUNTS; q++)
            OUT(", \"%s_ratio\": %.4f", k_count_keys[q], ratio_known(u->count_all[c][q], u->count_all[w][q]));
        OUT(",\n     \"stages\": [");
        for (int p = 0; p < cf->names.pass_count; p++) {
            OUT("%s\n       {\"name\": \"%s\", \"wall_ms_ratio\": %.4f", p ? "," : "", cf->names.pass_names[p],
                ratio_known(u->stage_wall[c][p].median, u->stage_wall[w][p].median));
            for (int q = 0; q < BENCH_COUNTS; q++)
                OUT(", \"%s_ratio\": %.4f", k_count_keys[q],
                    ratio_known(u->stage_count_all[c][p][q], u->stage_count_all[w][p][q]));
            OUT("}");
        }
        OUT("]}");
    }
    OUT("\n  ],\n");
}

/* The --json report. */
static void bench_report_json(bench_run *b, const char *cpu_name)
{
    const session *s = &b->s;
    const bench_summaries *u = &b->sum;
    OUT("{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"alpha_mode\": \"%s\",\n", s->sc.path,
        s->pl.width, s->pl.height, alpha_mode_name(s->pl.global_mode));
    OUT("  \"rings\": \"%s\",\n  \"gaze\": \"%s\",\n  \"renderer\": \"%s\",\n  \"machine\": \"%s, %ld cores\",\n",
        b->rings, s->gaze.count ? s->gaze.path : "centre", gl_device_renderer(), cpu_name,
        sysconf(_SC_NPROCESSORS_ONLN));
    OUT("  \"ring_lod\": \"%s\",\n", b->lod_text);
    OUT("  \"pipeline_statistics\": %s,\n", gl_device_has_pipeline_stats() ? "true" : "false");
    OUT("  \"fs_invocation_unit\": \"%s\",\n", bench_invocation_unit());
    OUT("  \"frames\": %d,\n  \"warmup\": %d,\n  \"display_pixels\": %.0f,\n  \"configs\": [\n", b->n,
        b->d->bench.warmup, b->px);
    for (int c = 0; c < b->ncfg; c++)
        bench_json_config(b, c);
    OUT("  ],\n");
    if (b->lod)
        bench_json_ring_lod(b);
    OUT("  \"speedup\": %.4f,\n  \"ideal_speedup\": %.4f,\n  \"achieved_fraction_of_ideal\": %.4f,\n", u->speedup,
        u->ideal, u->speedup / u->ideal);
    OUT("  \"covered_fragment_ideal_speedup\": %.4f,\n  \"achieved_fraction_of_covered_fragment_ideal\": %.4f\n}\n",
        u->covered_ideal, u->covered_ideal > 0 ? u->speedup / u->covered_ideal : -1.0);
}

/* The text report's first table: every measure of configuration c, one row each. */
static void bench_text_measures(bench_run *b, int c)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    const char *cn = cf->name;
    bench_row(b->report, &b->o, cn, "frame, wall clock incl. finish (ms)", u->wall[c], 1.0, 2);
    bench_row(b->report, &b->o, cn, "frame, process CPU time, all threads (ms)", u->cpu[c], 1.0, 2);
    bench_row(b->report, &b->o, cn, "frame, minor page faults", u->faults[c], 1.0, 0);
    for (int i = 0; i < cf->pl.layout.count; i++) {
        char m[96];
        snprintf(m, sizeof m, "ring %d, instances drawn", i);
        bench_row(b->report, &b->o, cn, cf->pl.layout.count > 1 ? m : "instances drawn", u->instances[c][i], 1.0, 0);
    }
    for (int p = 0; p < cf->names.pass_count; p++) {
        char m[96];
        snprintf(m, sizeof m, "%s, wall clock with glFinish (ms)", cf->names.pass_names[p]);
        bench_row(b->report, &b->o, cn, m, u->stage_wall[c][p], 1.0, 2);
    }
    for (int p = 0; p < cf->names.pass_count; p++) {
        char m[96];
        snprintf(m, sizeof m, "%s, GL timer query (ms)", cf->names.pass_names[p]);
        bench_row(b->report, &b->o, cn, m, u->stage_gl[c][p], 1.0, 2);
    }
    bench_row(b->report, &b->o, cn, "shaded pixels / display pixels", u->shaded[c], b->px, 3);
    for (int q = 0; q < BENCH_COUNTS; q++) {
        char m[96];
        snprintf(m, sizeof m, "frame, %s", k_count_names[q]);
        bench_row(b->report, &b->o, cn, m, u->count[c][q], 1.0, 0);
    }
    bench_row(b->report, &b->o, cn, "fragment shader invocations / display pixel", u->count[c][2], b->px, 2);
}

/* The text report's ring LOD table: configuration c (with ring LOD) against w, the same rings
 * without it, per stage and for the frame. */
static void bench_text_ring_lod(bench_run *b, int c, int w)
{
    const bench_config *cf = &b->cfg[c];
    const bench_summaries *u = &b->sum;
    for (int p = 0; p <= cf->names.pass_count; p++) {
        bool frame = p == cf->names.pass_count;
        summary tb = frame ? u->wall[w] : u->stage_wall[w][p], tc = frame ? u->wall[c] : u->stage_wall[c][p];
        OUT("| %s | %s | %.2f | %.2f | %.2fx |", cf->name, frame ? "**frame**" : cf->names.pass_names[p], tb.median,
            tc.median, ratio_known(tc.median, tb.median));
        for (int q = 2; q > 0; q--) { /* fragments, then primitives */
            double vb = frame ? u->count_all[w][q] : u->stage_count_all[w][p][q];
            double vc = frame ? u->count_all[c][q] : u->stage_count_all[c][p][q];
            out_count(b->report, &b->o, vb < 0 ? -1.0 : vb / b->n);
            out_count(b->report, &b->o, vc < 0 ? -1.0 : vc / b->n);
            double r = ratio_known(vc, vb);
            if (r < 0)
                OUT(" n/a |");
            else
                OUT(" %.3fx |", r);
        }
        int ring = frame ? -1 : stage_ring(cf->names.pass_names[p]);
        if (ring >= 0)
            OUT(" %.0f | %.0f |\n", u->instances[w][ring].median, u->instances[c][ring].median);
        else
            OUT(" | |\n");
    }
    OUT("| %s | **frame, process CPU time** | %.2f | %.2f | %.2fx | | | | | | | | |\n", cf->name, u->cpu[w].median,
        u->cpu[c].median, ratio_known(u->cpu[c].median, u->cpu[w].median));
}

/* The Markdown report (without --json). */
static void bench_report_text(bench_run *b, const char *cpu_name)
{
    const session *s = &b->s;
    const bench_summaries *u = &b->sum;
    struct utsname un;
    uname(&un);
    OUT("### %s, %dx%d, alpha %s, rings %s%s%s\n\n", s->sc.path, s->pl.width, s->pl.height,
        alpha_mode_name(s->pl.global_mode), b->rings, b->lod ? ", ring LOD " : "", b->lod ? b->lod_text : "");
    OUT("- machine: %s, %s %s (%ld cores online)\n", cpu_name, un.sysname, un.machine, sysconf(_SC_NPROCESSORS_ONLN));
    OUT("- renderer: %s (OpenGL %s, %s)%s\n", gl_device_renderer(), gl_device_version(), gl_device_description(),
        gl_device_has_pipeline_stats() ? "" : "; no GL_ARB_pipeline_statistics_query: work counts n/a");
    OUT("- %d frames spread over the %.2f s camera path after %d warm-up frames; gaze: %s\n\n", b->n, b->span,
        b->d->bench.warmup, s->gaze.count ? s->gaze.path : "fixation at the centre");
    OUT("| configuration | measure | median | p10 | p90 | min | max |\n|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < b->ncfg; c++)
        bench_text_measures(b, c);
    OUT("\nWork per stage (medians over the frames; the frame row is the median of the per-frame totals). "
        "Covered fragments come from a frame drawn with the counting variant (not the timed one); "
        "full-screen stages cover the pixels they draw. A fragment shader invocation here is one pixel "
        "of the %s the rasteriser shades; invocations / covered is over all frames:\n\n"
        "| configuration | stage |", bench_invocation_unit());
    for (int q = 0; q < BENCH_COUNTS; q++)
        OUT(" %s |", k_count_names[q]);
    OUT(" invocations / covered |\n|---|---|---|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < b->ncfg; c++) {
        for (int p = 0; p <= b->cfg[c].names.pass_count; p++) {
            bool frame = p == b->cfg[c].names.pass_count;
            OUT("| %s | %s |", b->cfg[c].name, frame ? "**frame**" : b->cfg[c].names.pass_names[p]);
            for (int q = 0; q < BENCH_COUNTS; q++)
                out_count(b->report, &b->o, frame ? u->count[c][q].median : u->stage_count[c][p][q].median);
            double r = frame ? ratio_known(u->count_all[c][COUNT_FS], u->count_all[c][COUNT_COVERED])
                             : ratio_known(u->stage_count_all[c][p][COUNT_FS], u->stage_count_all[c][p][COUNT_COVERED]);
            if (r < 0)
                OUT(" n/a |\n");
            else
                OUT(" %.2f |\n", r);
        }
    }
    if (b->ncfg > 1) {
        OUT("\n| configuration | frame (ms, median) | relative to traditional |\n|---|---|---|\n");
        for (int c = 0; c < b->ncfg; c++)
            OUT("| %s | %.2f | %.2fx |\n", b->cfg[c].name, u->wall[c].median, u->rel[c]);
    }
    if (b->lod) {
        OUT("\nRing LOD against the same rings without it (%s): times are medians, counts are means per frame "
            "over the same frames; ratio = with / without:\n\n| configuration | stage | ms without | ms with | "
            "ratio | fragment shader invocations without | with | ratio | primitives without | with | ratio | "
            "instances without | with |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n", b->lod_text);
        for (int c = 2 * b->per_layout; c < b->ncfg; c++)
            bench_text_ring_lod(b, c, c - b->per_layout);
    }
    if (u->has_fov)
        OUT("\nfoveated vs full resolution (%s): speedup %.2fx (median frame times), ideal %.2fx (display pixels / "
            "shaded pixels), achieved %.0f %% of ideal\n", alpha_mode_name(b->cfg[0].mode), u->speedup, u->ideal,
            100.0 * u->speedup / u->ideal);
    if (u->has_fov && u->covered_ideal > 0)
        OUT("covered-fragment ideal %.2fx (full resolution's covered fragments / the foveated frame's, over the "
            "stages that draw the scene): achieved %.0f %% of it\n", u->covered_ideal,
            100.0 * u->speedup / u->covered_ideal);
}

#undef OUT

/* Writes the report (JSON or Markdown) into b->report and prints it; --markdown appends it to
 * that file too. */
static fs_status bench_report(bench_run *b)
{
    const run_desc *d = b->d;
    char cpu_name[256];
    session_cpu_name(cpu_name, sizeof cpu_name);
    b->px = (double)b->s.pl.width * b->s.pl.height;
    fov_layout_format(&b->s.pl.layout, b->rings, sizeof b->rings);
    snprintf(b->lod_text, sizeof b->lod_text, "off");
    if (b->lod) { /* "simplify (u = 1,1,0.25,0.0625)" */
        char u[160];
        ring_lod_format(&b->s.pl.ring_lod_spec, b->lod_text, sizeof b->lod_text);
        ring_lod_format_u(&b->s.pl.ring_lod_spec, &b->s.pl.layout, u, sizeof u);
        snprintf(b->lod_text + strlen(b->lod_text), sizeof b->lod_text - strlen(b->lod_text), " (u = %s)", u);
    }
    bench_summarise(b);
    b->report = malloc(BENCH_REPORT_CAP);
    b->o = 0;
    if (!b->report)
        return FS_ERR_NOMEM;
    if (d->bench.json)
        bench_report_json(b, cpu_name);
    else
        bench_report_text(b, cpu_name);
    if (b->o >= BENCH_REPORT_CAP) {
        log_error("bench: the report outgrew its %d-byte buffer", BENCH_REPORT_CAP);
        return FS_ERR_INTERNAL;
    }
    fputs(b->report, stdout);
    if (d->bench.markdown) {
        FILE *f = fopen(d->bench.markdown, "a");
        if (!f || fprintf(f, "\n%s", b->report) < 0 || fclose(f) != 0) {
            log_error("%s: cannot append the bench report: %s", d->bench.markdown, strerror(errno));
            return FS_ERR_IO;
        } else if (!d->bench.json) {
            printf("appended to %s\n", d->bench.markdown);
        }
    }
    return FS_OK;
}

fs_status cmd_bench(const run_desc *d)
{
    bench_run *b = calloc(1, sizeof *b);
    if (!b)
        return FS_ERR_NOMEM;
    b->d = d;
    fs_status st = session_begin(d, &b->s, false); /* every configuration gets its own renderer */
    if (st != FS_OK) {
        free(b);
        return st;
    }
    b->n = d->frames > 0 ? d->frames : 30;
    bench_list_configs(b);
    st = bench_build_configs(b);
    st = bench_measure(b, st);
    if (st == FS_OK)
        st = bench_report(b);
    free(b->report);
    for (int c = 0; c < b->ncfg; c++) {
        bench_free(&b->cfg[c]);
        renderer_destroy(b->cfg[c].r);
    }
    session_end(&b->s);
    free(b);
    return st;
}
