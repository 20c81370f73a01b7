/* bench.c: `fovsim bench` (without --accuracy, which is bench_accuracy.c): frame time, CPU time,
 * page faults and work counts (pipeline statistics, covered fragments from a counting frame of
 * their own, footprint bytes) of full resolution against the ring layout (and, with ring LOD, the
 * same rings with it), per alpha mode and per stage, interleaved frame by frame so every
 * configuration sees the same machine state. bench_report.c writes the report. */
#include "commands/bench_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "core/proc_stats.h"
#include "core/progress.h"
#include "fov/ring_lod.h"
#include "gaze/gaze.h"
#include "frame/frame.h"

/* Each layout's name in the configurations' names (BENCH_FULL .. BENCH_RINGS_LOD). */
static const char *const k_layout_names[BENCH_LAYOUTS] = {"full resolution", "foveated", "foveated + ring LOD"};

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

/* The timed draw: to glFinish, with its process CPU time and minor page faults. */
static void draw_timed(renderer *r, const frame_record *fr, proc_stats *pd, double *t0, double *t1)
{
    proc_stats p0 = proc_stats_now();
    *t0 = time_now();
    renderer_draw(r, fr);
    renderer_finish(r);
    *t1 = time_now();
    *pd = proc_stats_since(p0);
}

/* Frame k's per-stage times (sync: the synced draw's wall clock; rs: the GL timers) and work
 * counts (rs's statistics, cs's covered and shaded fragments), and the frame's totals. */
static void bench_record(bench_config *c, const renderer_stats *rs, const renderer_stats *sync,
                         const renderer_stats *cs, int k, int n)
{
    const long long *stage_counts[BENCH_COUNTS] = {rs->pass_vs_invocations, rs->pass_primitives, rs->pass_fs_invocations,
                                                   rs->pass_clipped, cs->pass_covered, rs->pass_bytes_read,
                                                   rs->pass_bytes_written, cs->pass_shaded};
    const long long frame_counts[BENCH_COUNTS] = {rs->vs_invocations, rs->primitives, rs->fragments, rs->clipped,
                                                  cs->covered, rs->bytes_read, rs->bytes_written, cs->shaded};
    for (int p = 0; p < rs->pass_count; p++) {
        size_t at = (size_t)p * (size_t)n + (size_t)k;
        c->stage_wall[at] = sync->pass_wall_ms[p];
        c->stage_gl[at] = rs->pass_ms[p];
        for (int q = 0; q < BENCH_COUNTS; q++)
            c->stage_count[q][at] = (double)stage_counts[q][p];
    }
    for (int q = 0; q < BENCH_COUNTS; q++)
        c->count[q][k] = (double)frame_counts[q];
    c->shaded[k] = (double)rs->shaded_pixels;
    for (int i = 0; i < rs->ring_count; i++)
        c->instances[(size_t)i * (size_t)n + (size_t)k] = rs->ring_instances[i];
}

/* Draws frame k of config c twice: once as the renderer runs it (timed to glFinish; its process CPU
 * time, minor page faults and pipeline statistics are counted too), once with a finish after every
 * stage (per-stage wall times); then a third time with the counting variant (covered fragments).
 * With c->stages_only, only the second draw (its statistics are the counts). Records when k >= 0. */
static void bench_frame(session *s, bench_config *c, int k, float t, int n)
{
    frame_record fr = frame_record_at(&s->sc, k < 0 ? 0 : k, t, -1.0f, c->pl.width, c->pl.height);
    display_desc dd = frame_display(&fr, c->pl.width, c->pl.height);
    session_set_frame_gaze(s, &fr, &c->pl.layout, &dd, t); /* the eye tracker's gaze, as every command */
    renderer_stats rs = {0};
    proc_stats pd = {0};
    double t0 = 0.0, t1 = 0.0;
    if (!c->stages_only) {
        renderer_set_pass_sync(c->r, false);
        draw_timed(c->r, &fr, &pd, &t0, &t1);
        rs = renderer_last_stats(c->r);
    }
    renderer_set_pass_sync(c->r, true);
    renderer_draw(c->r, &fr);
    renderer_stats sync = renderer_last_stats(c->r);
    if (c->stages_only)
        rs = sync;
    c->names = rs;
    if (k < 0)
        return;
    renderer_stats cs = rs; /* covered fragments unknown (-1) unless counted */
    if (!c->stages_only) { /* the counting variant, in a frame of its own: the timed frame has no counter */
        (void)renderer_draw_counting(c->r, &fr, &cs);
        memcpy(c->names.pass_geometry, cs.pass_geometry, sizeof cs.pass_geometry);
        for (int i = 0; i < MAX_FOV_RINGS; i++)
            for (int p = 0; p < PLAN_MAX_PASSES; p++)
                c->ring_pass_covered[i][p] += (double)cs.ring_pass_covered[i][p];
        renderer_stats_take_shaded(&rs, &cs); /* VRS: what a GPU would shade, not llvmpipe's count */
    }
    c->wall[k] = (t1 - t0) * 1e3;
    c->cpu[k] = pd.cpu_ms;
    c->faults[k] = (double)pd.minor_faults;
    bench_record(c, &rs, &sync, &cs, k, n);
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

/* >>phases: cmd_bench runs them in order, sharing one bench_run. */

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
    b->nlayouts = b->lod ? 3 : pl->rings || pl->vrs ? 2 : 1; /* foveated: by rings or by VRS */
    for (int lay = 0; lay < b->nlayouts; lay++)
        for (int m = 0; m < nmodes + (want_msaa ? 1 : 0); m++) {
            bench_config *c = &b->cfg[b->ncfg++];
            c->layout = lay;
            c->foveated = lay != BENCH_FULL;
            c->msaa_only = m == nmodes;
            c->mode = c->msaa_only ? ALPHA_MODE_TRADITIONAL : modes[m];
            c->width = d->width;
            c->height = d->height;
            c->taa = b->s.pl.taa;
            c->rings = b->s.pl.layout;
            snprintf(c->name, sizeof c->name, "%s%s, %s%s", alpha_mode_name(c->mode), c->msaa_only ? "+MSAA" : "",
                     k_layout_names[lay], c->foveated && pl->vrs ? " (VRS)" : "");
        }
    b->per_layout = b->ncfg / b->nlayouts;
}

/* Each configuration's plan, renderer (with timers) and sample arrays. */
fs_status bench_build_configs(bench_run *b)
{
    const run_desc *d = b->d;
    fs_status st = FS_OK;
    for (int c = 0; c < b->ncfg && st == FS_OK; c++) {
        bench_config *cf = &b->cfg[c];
        plan_options po = {.alpha_mode = cf->mode, .width = cf->width, .height = cf->height, .frames = b->n,
                           .alpha = b->s.pl.alpha, .force_msaa = cf->msaa_only, .taa = cf->taa,
                           .taa_controls = b->s.pl.taa_controls, .no_ring_cull = d->no_ring_cull,
                           .composite_per_pixel = d->composite_per_pixel};
        if (cf->foveated)
            po.layout = b->s.pl.vrs ? b->s.pl.vrs_rings : cf->rings;
        if (cf->foveated && b->s.pl.vrs) { /* VRS foveation: one full-resolution pass, coarse tiles */
            po.vrs = true;
            po.vrs_spec = b->s.pl.vrs_spec;
            po.vrs_tile = b->s.pl.vrs_tile;
        }
        if (cf->layout == BENCH_RINGS_LOD)
            po.ring_lod = b->s.pl.ring_lod_spec;
        st = plan_build(&b->s.sc, &po, &cf->pl);
        if (st == FS_OK)
            cf->r = renderer_create(&(renderer_desc){.scene = &b->s.sc, .plan = &cf->pl, .timers = true,
                                                     .count_fragments = !cf->stages_only}, &st);
    }
    for (int c = 0; c < b->ncfg && st == FS_OK; c++)
        if (!bench_alloc(&b->cfg[c], b->n))
            st = FS_ERR_NOMEM;
    return st;
}

/* The warm-up and measured frames, spread evenly over the camera path (and gaze trace), the
 * configurations interleaved per frame so all see the same machine state. Draws nothing when st
 * (the setup's status) is not FS_OK; the progress line is begun and ended either way. */
fs_status bench_measure(bench_run *b, fs_status st)
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

/* Median over the frames of configuration cf's frame time less its composite stage's synced time
 * (frame by frame, so before summarise sorts them); -1 when it has no composite or a time is
 * unknown. */
static double median_without_composite(const bench_config *cf, int n)
{
    int p = cf->names.pass_count - 1; /* the composite is the last stage */
    if (p < 0 || strcmp(cf->names.pass_names[p], "composite") != 0)
        return -1.0;
    double *v = malloc(sizeof(double) * (size_t)n);
    if (!v)
        return -1.0;
    bool known = true;
    for (int k = 0; k < n; k++) {
        double c = cf->stage_wall[(size_t)p * (size_t)n + (size_t)k];
        known = known && c >= 0;
        v[k] = cf->wall[k] - c;
    }
    double m = known ? summarise(v, n).median : -1.0;
    free(v);
    return m;
}

/* Summarises every configuration's samples (sorting them), and the speedups. */
void bench_summarise(bench_run *b)
{
    bench_summaries *u = &b->sum;
    int n = b->n;
    u->has_fov = b->s.pl.rings;
    double fov_rest = u->has_fov ? median_without_composite(&b->cfg[b->per_layout], n) : -1.0;
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
    u->speedup = u->has_fov ? u->wall[0].median / u->wall[b->per_layout].median : 1.0;
    u->speedup_no_composite = ratio_known(u->wall[0].median, fov_rest);
    u->ideal = u->has_fov ? b->px / u->shaded[b->per_layout].median : 1.0;
    u->covered_ideal = u->has_fov ? ratio_known(u->geom_covered[0], u->geom_covered[b->per_layout]) : 1.0;
    /* Each configuration's frame time relative to traditional in the same layout (seed 000
     * Table 1's comparison); 0 when traditional was not measured. */
    for (int c = 0; c < b->ncfg; c++)
        for (int t = 0; t < b->ncfg; t++)
            if (b->cfg[t].mode == ALPHA_MODE_TRADITIONAL && !b->cfg[t].msaa_only && b->cfg[t].layout == b->cfg[c].layout)
                u->rel[c] = u->wall[c].median / u->wall[t].median;
}

void bench_end(bench_run *b)
{
    free(b->report);
    for (int c = 0; c < b->ncfg; c++) {
        bench_free(&b->cfg[c]);
        renderer_destroy(b->cfg[c].r);
    }
    session_end(&b->s);
    free(b);
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
    if (st == FS_OK) {
        b->px = (double)b->s.pl.width * b->s.pl.height;
        bench_summarise(b);
        st = bench_report(b);
    }
    bench_end(b);
    return st;
}
