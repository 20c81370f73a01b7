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
    /* Pipeline statistics (BENCH_COUNTS order), -1 = unknown: per frame (n) and per stage (n * stages). */
    double *count[3], *stage_count[3];
    renderer_stats names; /* stage names */
} bench_config;

/* The pipeline statistics bench reports: names in the JSON and in the text. */
enum { BENCH_COUNTS = 3 };
static const char *const k_count_keys[BENCH_COUNTS] = {"vs_invocations", "primitives", "fs_invocations"};
static const char *const k_count_names[BENCH_COUNTS] = {"vertex shader invocations", "primitives submitted",
                                                        "fragment shader invocations"};

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
    c->wall[k] = (t1 - t0) * 1e3;
    c->cpu[k] = pd.cpu_ms;
    c->faults[k] = (double)pd.minor_faults;
    const long long *stage_counts[BENCH_COUNTS] = {rs.pass_vs_invocations, rs.pass_primitives, rs.pass_fs_invocations};
    const long long frame_counts[BENCH_COUNTS] = {rs.vs_invocations, rs.primitives, rs.fragments};
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

fs_status cmd_bench(const run_desc *d)
{
    session s;
    fs_status st = session_begin(d, &s, false); /* every configuration gets its own renderer */
    if (st != FS_OK)
        return st;
    int n = d->frames > 0 ? d->frames : 30;
    /* Configurations: for each alpha mode asked for (--modes, default the run's), full resolution
     * and, when the run has rings, foveated; plus traditional through the MSAA targets when an A2C
     * mode is measured, so the MSAA cost can be told from the A2C test's own. */
    alpha_mode modes[ALPHA_MODE_COUNT];
    int nmodes = 0;
    bool want_msaa = false;
    for (int m = 0; m < d->bench_mode_count; m++)
        modes[nmodes++] = d->bench_modes[m];
    if (nmodes == 0)
        modes[nmodes++] = s.pl.global_mode;
    for (int m = 0; m < nmodes; m++)
        want_msaa |= modes[m] == ALPHA_MODE_A2C || modes[m] == ALPHA_MODE_HASHED_A2C;
    enum { MAX_CFG = BENCH_LAYOUTS * (ALPHA_MODE_COUNT + 1) };
    bench_config cfg[MAX_CFG];
    memset(cfg, 0, sizeof cfg);
    int ncfg = 0;
    /* Ring LOD (docs/ring-lod.md) is measured against the same rings without it: the plain rings
     * configuration is drawn without it, whatever --ring-lod or the scene say. */
    bool lod = s.pl.rings && s.pl.ring_lod;
    if (!lod && (s.pl.ring_lod || s.pl.ring_lod_why[0]))
        log_warn("bench: ring LOD not measured (%s)", s.pl.ring_lod ? "no rings" : s.pl.ring_lod_why);
    int nlayouts = lod ? 3 : s.pl.rings ? 2 : 1;
    for (int lay = 0; lay < nlayouts; lay++)
        for (int m = 0; m < nmodes + (want_msaa ? 1 : 0); m++) {
            bench_config *c = &cfg[ncfg++];
            c->layout = lay;
            c->foveated = lay != BENCH_FULL;
            c->msaa_only = m == nmodes;
            c->mode = c->msaa_only ? ALPHA_MODE_TRADITIONAL : modes[m];
            snprintf(c->name, sizeof c->name, "%s%s, %s", alpha_mode_name(c->mode), c->msaa_only ? "+MSAA" : "",
                     k_layout_names[lay]);
        }
    for (int c = 0; c < ncfg && st == FS_OK; c++) {
        plan_options po = {.alpha_mode = cfg[c].mode, .width = d->width, .height = d->height, .frames = n,
                           .alpha = s.pl.alpha, .force_msaa = cfg[c].msaa_only, .taa = s.pl.taa,
                           .taa_controls = s.pl.taa_controls, .no_ring_cull = d->no_ring_cull,
                           .composite_per_pixel = d->composite_per_pixel};
        if (cfg[c].foveated)
            po.layout = s.pl.layout;
        if (cfg[c].layout == BENCH_RINGS_LOD)
            po.ring_lod = s.pl.ring_lod_spec;
        st = plan_build(&s.sc, &po, &cfg[c].pl);
        if (st == FS_OK)
            cfg[c].r = renderer_create(&(renderer_desc){.scene = &s.sc, .plan = &cfg[c].pl, .timers = true}, &st);
    }
    for (int c = 0; c < ncfg && st == FS_OK; c++)
        if (!bench_alloc(&cfg[c], n))
            st = FS_ERR_NOMEM;
    float span = s.sc.duration;
    progress pr = progress_begin("bench", d->bench.warmup + n, d->quiet);
    /* Frames spread evenly over the camera path (and gaze trace), configs interleaved per frame so
     * both see the same machine state. */
    for (int i = 0; i < d->bench.warmup + n && st == FS_OK; i++) {
        int k = i < d->bench.warmup ? -1 : i - d->bench.warmup;
        int kk = k < 0 ? i : k;
        float t = n > 1 ? span * (float)kk / (float)(n - 1) : 0.0f;
        for (int c = 0; c < ncfg; c++)
            bench_frame(&s, &cfg[c], k, t, n);
        progress_update(&pr, i + 1);
    }
    progress_end(&pr);

    char cpu_name[256];
    session_cpu_name(cpu_name, sizeof cpu_name);
    struct utsname un;
    uname(&un);
    double px = (double)s.pl.width * s.pl.height;
    char rings[256], lod_text[200] = "off";
    fov_layout_format(&s.pl.layout, rings, sizeof rings);
    if (lod) { /* "simplify (u = 1,1,0.25,0.0625)" */
        char u[160];
        ring_lod_format(&s.pl.ring_lod_spec, lod_text, sizeof lod_text);
        ring_lod_format_u(&s.pl.ring_lod_spec, &s.pl.layout, u, sizeof u);
        snprintf(lod_text + strlen(lod_text), sizeof lod_text - strlen(lod_text), " (u = %s)", u);
    }
    summary wall[MAX_CFG], shaded[MAX_CFG], cpu[MAX_CFG], faults[MAX_CFG], count[MAX_CFG][BENCH_COUNTS];
    summary stage_wall[MAX_CFG][RENDERER_STATS_MAX], stage_gl[MAX_CFG][RENDERER_STATS_MAX];
    summary stage_count[MAX_CFG][RENDERER_STATS_MAX][BENCH_COUNTS];
    summary instances[MAX_CFG][MAX_FOV_RINGS];
    double count_all[MAX_CFG][BENCH_COUNTS], stage_count_all[MAX_CFG][RENDERER_STATS_MAX][BENCH_COUNTS];
    for (int c = 0; c < ncfg && st == FS_OK; c++) {
        wall[c] = summarise(cfg[c].wall, n);
        shaded[c] = summarise(cfg[c].shaded, n);
        cpu[c] = summarise(cfg[c].cpu, n);
        faults[c] = summarise(cfg[c].faults, n);
        for (int i = 0; i < cfg[c].pl.layout.count; i++)
            instances[c][i] = summarise(&cfg[c].instances[(size_t)i * (size_t)n], n);
        for (int q = 0; q < BENCH_COUNTS; q++) {
            count_all[c][q] = sum_known(cfg[c].count[q], n);
            count[c][q] = summarise(cfg[c].count[q], n);
        }
        for (int p = 0; p < cfg[c].names.pass_count; p++) {
            stage_wall[c][p] = summarise(&cfg[c].stage_wall[(size_t)p * (size_t)n], n);
            stage_gl[c][p] = summarise(&cfg[c].stage_gl[(size_t)p * (size_t)n], n);
            for (int q = 0; q < BENCH_COUNTS; q++) {
                double *v = &cfg[c].stage_count[q][(size_t)p * (size_t)n];
                stage_count_all[c][p][q] = sum_known(v, n);
                stage_count[c][p][q] = summarise(v, n);
            }
        }
    }
    /* Foveation's speedup: the first mode, full resolution vs foveated. */
    int per_layout = ncfg / nlayouts;
    bool has_fov = s.pl.rings && st == FS_OK;
    double speedup = has_fov ? wall[0].median / wall[per_layout].median : 1.0;
    double ideal = has_fov ? px / shaded[per_layout].median : 1.0;

    /* Each configuration's frame time relative to traditional in the same layout (seed 000
     * Table 1's comparison); 0 when traditional was not measured. */
    double rel[MAX_CFG] = {0};
    for (int c = 0; c < ncfg && st == FS_OK; c++)
        for (int b = 0; b < ncfg; b++)
            if (cfg[b].mode == ALPHA_MODE_TRADITIONAL && !cfg[b].msaa_only && cfg[b].layout == cfg[c].layout)
                rel[c] = wall[c].median / wall[b].median;
    char *report = malloc(BENCH_REPORT_CAP);
    int o = 0;
    if (!report)
        st = FS_ERR_NOMEM;
#define OUT(...) report_printf(report, &o, __VA_ARGS__)
    if (st == FS_OK && d->bench.json) {
        OUT("{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"alpha_mode\": \"%s\",\n", s.sc.path,
            s.pl.width, s.pl.height, alpha_mode_name(s.pl.global_mode));
        OUT("  \"rings\": \"%s\",\n  \"gaze\": \"%s\",\n  \"renderer\": \"%s\",\n  \"machine\": \"%s, %ld cores\",\n",
            rings, s.gaze.count ? s.gaze.path : "centre", gl_device_renderer(), cpu_name, sysconf(_SC_NPROCESSORS_ONLN));
        OUT("  \"ring_lod\": \"%s\",\n", lod_text);
        OUT("  \"pipeline_statistics\": %s,\n", gl_device_has_pipeline_stats() ? "true" : "false");
        OUT("  \"frames\": %d,\n  \"warmup\": %d,\n  \"display_pixels\": %.0f,\n  \"configs\": [\n", n, d->bench.warmup, px);
        for (int c = 0; c < ncfg; c++) {
            char spec[256];
            fov_layout_format(&cfg[c].pl.layout, spec, sizeof spec);
            char u[160] = "off";
            if (cfg[c].pl.ring_lod)
                ring_lod_format_u(&cfg[c].pl.ring_lod_spec, &cfg[c].pl.layout, u, sizeof u);
            OUT("    {\"name\": \"%s\", \"alpha_mode\": \"%s\", \"msaa_only\": %s, \"rings\": \"%s\", "
                "\"ring_lod_u\": \"%s\", \"shaded_pixels\": %.0f, \"relative_to_traditional\": %.4f,\n",
                cfg[c].name, alpha_mode_name(cfg[c].mode), cfg[c].msaa_only ? "true" : "false", spec, u,
                shaded[c].median, rel[c]);
            OUT("     \"frame_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
                wall[c].median, wall[c].p10, wall[c].p90, wall[c].min, wall[c].max);
            OUT("     \"cpu_ms\": {\"median\": %.3f, \"p10\": %.3f, \"p90\": %.3f, \"min\": %.3f, \"max\": %.3f},\n",
                cpu[c].median, cpu[c].p10, cpu[c].p90, cpu[c].min, cpu[c].max);
            OUT("     \"minor_faults\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f},\n",
                faults[c].median, faults[c].p10, faults[c].p90, faults[c].min, faults[c].max);
            for (int q = 0; q < BENCH_COUNTS; q++)
                OUT("     \"%s\": {\"median\": %.0f, \"p10\": %.0f, \"p90\": %.0f, \"min\": %.0f, \"max\": %.0f, "
                    "\"all_frames\": %.0f},\n", k_count_keys[q], count[c][q].median, count[c][q].p10, count[c][q].p90,
                    count[c][q].min, count[c][q].max, count_all[c][q]);
            OUT("     \"ring_instances_median\": [");
            for (int i = 0; i < cfg[c].pl.layout.count; i++)
                OUT("%s%.0f", i ? ", " : "", instances[c][i].median);
            OUT("],\n");
            double frags = count[c][2].median;
            OUT("     \"fragments_per_pixel\": %.3f,\n     \"stages\": [", frags >= 0 ? frags / px : -1.0);
            for (int p = 0; p < cfg[c].names.pass_count; p++) {
                OUT("%s\n       {\"name\": \"%s\", \"wall_ms_median\": %.3f, \"gl_timer_ms_median\": %.3f", p ? "," : "",
                    cfg[c].names.pass_names[p], stage_wall[c][p].median, stage_gl[c][p].median);
                for (int q = 0; q < BENCH_COUNTS; q++)
                    OUT(",\n        \"%s_median\": %.0f, \"%s_all_frames\": %.0f", k_count_keys[q],
                        stage_count[c][p][q].median, k_count_keys[q], stage_count_all[c][p][q]);
                OUT("}");
            }
            OUT("]}%s\n", c + 1 < ncfg ? "," : "");
        }
        OUT("  ],\n");
        if (lod) {
            /* Each mode's ring LOD configuration against its plain rings: time ratios of medians,
             * count ratios of the totals over the same frames; -1 = unknown. */
            OUT("  \"ring_lod_vs_rings\": [");
            for (int c = 2 * per_layout; c < ncfg; c++) {
                int b = c - per_layout;
                OUT("%s\n    {\"name\": \"%s\", \"without\": \"%s\", \"frame_ms_ratio\": %.4f, \"cpu_ms_ratio\": %.4f",
                    c > 2 * per_layout ? "," : "", cfg[c].name, cfg[b].name, ratio_known(wall[c].median, wall[b].median),
                    ratio_known(cpu[c].median, cpu[b].median));
                for (int q = 0; q < BENCH_COUNTS; q++)
                    OUT(", \"%s_ratio\": %.4f", k_count_keys[q], ratio_known(count_all[c][q], count_all[b][q]));
                OUT(",\n     \"stages\": [");
                for (int p = 0; p < cfg[c].names.pass_count; p++) {
                    OUT("%s\n       {\"name\": \"%s\", \"wall_ms_ratio\": %.4f", p ? "," : "", cfg[c].names.pass_names[p],
                        ratio_known(stage_wall[c][p].median, stage_wall[b][p].median));
                    for (int q = 0; q < BENCH_COUNTS; q++)
                        OUT(", \"%s_ratio\": %.4f", k_count_keys[q],
                            ratio_known(stage_count_all[c][p][q], stage_count_all[b][p][q]));
                    OUT("}");
                }
                OUT("]}");
            }
            OUT("\n  ],\n");
        }
        OUT("  \"speedup\": %.4f,\n  \"ideal_speedup\": %.4f,\n  \"achieved_fraction_of_ideal\": %.4f\n}\n", speedup,
            ideal, speedup / ideal);
    } else if (st == FS_OK) {
        OUT("### %s, %dx%d, alpha %s, rings %s%s%s\n\n", s.sc.path, s.pl.width, s.pl.height,
            alpha_mode_name(s.pl.global_mode), rings, lod ? ", ring LOD " : "", lod ? lod_text : "");
        OUT("- machine: %s, %s %s (%ld cores online)\n", cpu_name, un.sysname, un.machine, sysconf(_SC_NPROCESSORS_ONLN));
        OUT("- renderer: %s (OpenGL %s, %s)%s\n", gl_device_renderer(), gl_device_version(), gl_device_description(),
            gl_device_has_pipeline_stats() ? "" : "; no GL_ARB_pipeline_statistics_query: work counts n/a");
        OUT("- %d frames spread over the %.2f s camera path after %d warm-up frames; gaze: %s\n\n", n, span, d->bench.warmup,
            s.gaze.count ? s.gaze.path : "fixation at the centre");
        OUT("| configuration | measure | median | p10 | p90 | min | max |\n|---|---|---|---|---|---|---|\n");
        for (int c = 0; c < ncfg; c++) {
            const char *cn = cfg[c].name;
            bench_row(report, &o, cn, "frame, wall clock incl. finish (ms)", wall[c], 1.0, 2);
            bench_row(report, &o, cn, "frame, process CPU time, all threads (ms)", cpu[c], 1.0, 2);
            bench_row(report, &o, cn, "frame, minor page faults", faults[c], 1.0, 0);
            for (int i = 0; i < cfg[c].pl.layout.count; i++) {
                char m[96];
                snprintf(m, sizeof m, "ring %d, instances drawn", i);
                bench_row(report, &o, cn, cfg[c].pl.layout.count > 1 ? m : "instances drawn", instances[c][i], 1.0, 0);
            }
            for (int p = 0; p < cfg[c].names.pass_count; p++) {
                char m[96];
                snprintf(m, sizeof m, "%s, wall clock with glFinish (ms)", cfg[c].names.pass_names[p]);
                bench_row(report, &o, cn, m, stage_wall[c][p], 1.0, 2);
            }
            for (int p = 0; p < cfg[c].names.pass_count; p++) {
                char m[96];
                snprintf(m, sizeof m, "%s, GL timer query (ms)", cfg[c].names.pass_names[p]);
                bench_row(report, &o, cn, m, stage_gl[c][p], 1.0, 2);
            }
            bench_row(report, &o, cn, "shaded pixels / display pixels", shaded[c], px, 3);
            for (int q = 0; q < BENCH_COUNTS; q++) {
                char m[96];
                snprintf(m, sizeof m, "frame, %s", k_count_names[q]);
                bench_row(report, &o, cn, m, count[c][q], 1.0, 0);
            }
            bench_row(report, &o, cn, "fragment shader invocations / display pixel", count[c][2], px, 2);
        }
        OUT("\nWork per stage (medians over the frames; the frame row is the median of the per-frame totals):\n\n"
            "| configuration | stage | vertex shader invocations | primitives submitted | fragment shader "
            "invocations |\n|---|---|---|---|---|\n");
        for (int c = 0; c < ncfg; c++) {
            for (int p = 0; p < cfg[c].names.pass_count; p++) {
                OUT("| %s | %s |", cfg[c].name, cfg[c].names.pass_names[p]);
                for (int q = 0; q < BENCH_COUNTS; q++)
                    out_count(report, &o, stage_count[c][p][q].median);
                OUT("\n");
            }
            OUT("| %s | **frame** |", cfg[c].name);
            for (int q = 0; q < BENCH_COUNTS; q++)
                out_count(report, &o, count[c][q].median);
            OUT("\n");
        }
        if (ncfg > 1) {
            OUT("\n| configuration | frame (ms, median) | relative to traditional |\n|---|---|---|\n");
            for (int c = 0; c < ncfg; c++)
                OUT("| %s | %.2f | %.2fx |\n", cfg[c].name, wall[c].median, rel[c]);
        }
        if (lod) {
            OUT("\nRing LOD against the same rings without it (%s): times are medians, counts are means per frame "
                "over the same frames; ratio = with / without:\n\n| configuration | stage | ms without | ms with | "
                "ratio | fragment shader invocations without | with | ratio | primitives without | with | ratio | "
                "instances without | with |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n", lod_text);
            for (int c = 2 * per_layout; c < ncfg; c++) {
                int b = c - per_layout;
                for (int p = 0; p <= cfg[c].names.pass_count; p++) {
                    bool frame = p == cfg[c].names.pass_count;
                    summary tb = frame ? wall[b] : stage_wall[b][p], tc = frame ? wall[c] : stage_wall[c][p];
                    OUT("| %s | %s | %.2f | %.2f | %.2fx |", cfg[c].name, frame ? "**frame**" : cfg[c].names.pass_names[p],
                        tb.median, tc.median, ratio_known(tc.median, tb.median));
                    for (int q = 2; q > 0; q--) { /* fragments, then primitives */
                        double vb = frame ? count_all[b][q] : stage_count_all[b][p][q];
                        double vc = frame ? count_all[c][q] : stage_count_all[c][p][q];
                        out_count(report, &o, vb < 0 ? -1.0 : vb / n);
                        out_count(report, &o, vc < 0 ? -1.0 : vc / n);
                        double r = ratio_known(vc, vb);
                        if (r < 0)
                            OUT(" n/a |");
                        else
                            OUT(" %.3fx |", r);
                    }
                    int ring = frame ? -1 : stage_ring(cfg[c].names.pass_names[p]);
                    if (ring >= 0)
                        OUT(" %.0f | %.0f |\n", instances[b][ring].median, instances[c][ring].median);
                    else
                        OUT(" | |\n");
                }
                OUT("| %s | **frame, process CPU time** | %.2f | %.2f | %.2fx | | | | | | | | |\n", cfg[c].name,
                    cpu[b].median, cpu[c].median, ratio_known(cpu[c].median, cpu[b].median));
            }
        }
        if (has_fov)
            OUT("\nfoveated vs full resolution (%s): speedup %.2fx (median frame times), ideal %.2fx (display pixels / "
                "shaded pixels), achieved %.0f %% of ideal\n", alpha_mode_name(cfg[0].mode), speedup, ideal,
                100.0 * speedup / ideal);
    }
#undef OUT
    if (st == FS_OK && o >= BENCH_REPORT_CAP) {
        log_error("bench: the report outgrew its %d-byte buffer", BENCH_REPORT_CAP);
        st = FS_ERR_INTERNAL;
    }
    if (st == FS_OK) {
        fputs(report, stdout);
        if (d->bench.markdown) {
            FILE *f = fopen(d->bench.markdown, "a");
            if (!f || fprintf(f, "\n%s", report) < 0 || fclose(f) != 0) {
                log_error("%s: cannot append the bench report: %s", d->bench.markdown, strerror(errno));
                st = FS_ERR_IO;
            } else if (!d->bench.json) {
                printf("appended to %s\n", d->bench.markdown);
            }
        }
    }
    free(report);
    for (int c = 0; c < ncfg; c++) {
        bench_free(&cfg[c]);
        renderer_destroy(cfg[c].r);
    }
    session_end(&s);
    return st;
}
