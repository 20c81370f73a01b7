/* bench_accuracy.c: `fovsim bench --accuracy`: the accuracy-vs-time matrix (alpha modes x ring
 * layouts x TAA), measured as compare measures (measure.h), written as accuracy.csv, a Markdown
 * table and plots of error against time. */
#include "commands/commands.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "core/proc_stats.h"
#include "core/strbuf.h"
#include "gl/gl_device.h"
#include "metrics/metrics.h"
#include "output/gnuplot.h"
#include "output/report_html.h"
#include "output/out_path.h"
#include "perf/cost_frame.h"
#include "commands/measure.h"
#include "session/session.h"

/* The accuracy-vs-time matrix (docs/design.md "Outputs"; docs/benchmarks.md): alpha modes x foveation
 * off / default / aggressive (and default+lod, the default rings with ring LOD, when the run asks
 * for it) / vrs x TAA off / on, every configuration drawn over the same consecutive
 * frames (TAA needs a real sequence), timings interleaved per frame so all see the same machine
 * state, accuracy measured after the warm-up against the reference in the default rings. */

#define ACC_DEFAULT_DIV 4       /* default size: the scene's display / 4 (320x180 for 1280x720) */
#define ACC_DEFAULT_FRAMES 12
#define ACC_MAX_CONFIGS (ALPHA_MODE_COUNT * ACC_LAYOUTS * 2)

/* The ring layouts of the matrix, in row order; default+lod is the default rings with the run's
 * ring LOD (docs/ring-lod.md), only with --ring-lod (or the scene's "ring_lod"); vrs is VRS
 * foveation (docs/foveation.md "Variable-rate shading"): one full-resolution pass shaded at the
 * run's rate map (--vrs, else the scene's, else auto) at the matrix's display. */
enum { ACC_OFF, ACC_DEFAULT, ACC_DEFAULT_LOD, ACC_AGGRESSIVE, ACC_VRS, ACC_LAYOUTS };
static const char *const k_layout_names[ACC_LAYOUTS] = {"off", "default", "default+lod", "aggressive", "vrs"};
/* Which band-limited reference a layout uses: default+lod has the default rings' bands; VRS, one
 * full-resolution ring, the full-resolution one (off's). */
static const int k_band_slot[ACC_LAYOUTS] = {0, 1, 1, 2, 0};

/* Per-frame counts of bench --accuracy besides the frame time, in CSV column order: process CPU
 * time (ms) and minor page faults of the draw, then its pipeline statistics (-1 = unknown); the
 * work counts of docs/benchmarks.md "Work counts" (ACC_CLIPPED on) are the CSV's last columns:
 * primitives after clipping, covered fragments (a counting frame drawn after the measured one is
 * read back) and the footprint bytes; then, after predicted_ms (added later, so the columns
 * before keep their places), shaded fragments: the fragment-shader invocations a GPU would run,
 * the covered fragments, but under VRS one per primitive and coarse pixel with a covered pixel
 * (docs/benchmarks.md "VRS: coarse-shading invocations"). The work axis is that last one. */
enum {
    ACC_CPU,
    ACC_FAULTS,
    ACC_VS,
    ACC_PRIMS,
    ACC_FS,
    ACC_CLIPPED,
    ACC_COVERED,
    ACC_READ,
    ACC_WRITTEN,
    ACC_SHADED,
    ACC_COUNTS
};
static const char *const k_acc_count_columns[ACC_COUNTS] = {
    "cpu_ms_median",         "minor_faults_median",       "vs_invocations_median",    "primitives_median",
    "fs_invocations_median", "clipped_primitives_median", "covered_fragments_median", "bytes_read_median",
    "bytes_written_median",  "shaded_fragments_median"};

typedef struct acc_config {
    mode_run run;   /* renderer, images and sums (frame_ms: measured frames only) */
    int layout;     /* ACC_OFF .. ACC_VRS */
    bool taa;
    double med, p10, p90;
    double *counts[ACC_COUNTS]; /* per measured frame */
    double count_med[ACC_COUNTS];
    double *pred;    /* per measured frame: the frame time --cost-model predicts, -1 = none */
    double pred_med; /* their median, -1 when any is unknown */
} acc_config;

/* The aggressive layout (fov_layout_aggressive) for the plan's display. */
static fov_layout aggressive_layout(const plan *pl)
{
    display_desc dd = plan_display(pl);
    return fov_layout_aggressive(&dd);
}

/* Points on the Pareto front of (time, error): no other point is at least as fast and as exact
 * and strictly better in one. */
static void pareto(const double *t, const double *e, int n, bool *front)
{
    for (int i = 0; i < n; i++) {
        front[i] = true;
        for (int j = 0; j < n && front[i]; j++)
            if (j != i && t[j] <= t[i] && e[j] <= e[i] && (t[j] < t[i] || e[j] < e[i]))
                front[i] = false;
    }
}

/* Which error bench --accuracy plots and takes its Pareto fronts on (--error). */
static const char *const k_error_names[4] = {"flip", "alpha_rmse", "rmse", "temporal_error"};
static const char *const k_error_labels[4] = {"FLIP vs reference (mean; lower is better)",
                                              "alpha RMSE vs band-limited reference (linear RGB; lower is better)",
                                              "RMSE vs reference (linear RGB; lower is better)",
                                              "temporal error, motion-compensated (linear RGB; lower is better)"};

/* Plots the error (CSV column y_col) against x_expr (a gnuplot column expression) into
 * OUT/STEM.png through OUT/STEM.gp. Colour = alpha mode, shape = ring layout (those with
 * layouts[l] set; default+lod a diamond, vrs a pentagon), filled = TAA on, hollow = off; a legend names each
 * (dummy series: one entry per mode, layout and TAA state, not one per point); the Pareto front
 * (the configurations with front[c], in the order of key[c]) is a line, drawn from their rows of
 * accuracy.csv (csv + row_at[c]) copied into the script. gnuplot runs in OUT (gnuplot.h): no path
 * is in the script, and every string in it is quoted by gnuplot_str. */
static fs_status plot_accuracy(const char *out, const char *stem, const char *title, const char *xlabel,
                               const char *x_expr, int y_col, const char *ylabel, const double *key, const bool *front,
                               const char *csv, const int *row_at, int nc, const alpha_mode *modes, int mode_count,
                               const bool *layouts)
{
    /* circle, square, diamond, triangle, pentagon */
    static const int shape_filled[ACC_LAYOUTS] = {7, 5, 13, 9, 15}, shape_hollow[ACC_LAYOUTS] = {6, 4, 12, 8, 14};
    sbuf b = {0};
    sb_puts(&b, "set datafile separator ','\nset title ");
    gnuplot_str(&b, title);
    sb_puts(&b, "\nset xlabel ");
    gnuplot_str(&b, xlabel);
    sb_puts(&b, "\nset ylabel ");
    gnuplot_str(&b, ylabel);
    /* The front's rows, sorted by key. */
    sb_puts(&b, "\n$front << EOD\n");
    for (double last = -INFINITY;;) {
        int next = -1;
        for (int c = 0; c < nc; c++)
            if (front[c] && key[c] > last && (next < 0 || key[c] < key[next]))
                next = c;
        if (next < 0)
            break;
        for (int c = 0; c < nc; c++) /* equal keys: each row once */
            if (front[c] && key[c] == key[next])
                sb_append(&b, csv + row_at[c], (size_t)(row_at[c + 1] - row_at[c]));
        last = key[next];
    }
    sb_puts(&b, "EOD\nset grid\nset key outside right top\nplot ");
    for (int m = 0; m < mode_count; m++) {
        char col[8]; /* each mode its own colour in every plot (FS_ALPHA_MODES) */
        const char *name = alpha_mode_name(modes[m]);
        alpha_mode_colour(modes[m], col);
        for (int l = 0; l < ACC_LAYOUTS; l++)
            for (int t = 0; t < 2 && layouts[l]; t++) {
                sb_puts(&b, "'accuracy.csv' u ");
                sb_puts(&b, x_expr);
                sb_puts(&b, ":(strcol(1) eq ");
                gnuplot_str(&b, name);
                sb_puts(&b, " && strcol(2) eq ");
                gnuplot_str(&b, k_layout_names[l]);
                sb_puts(&b, " && strcol(3) eq ");
                gnuplot_str(&b, t ? "on" : "off");
                sb_printf(&b, " ? column(%d) : NaN) w p pt %d ps 1.4 lc rgb ", y_col,
                          t ? shape_filled[l] : shape_hollow[l]);
                gnuplot_str(&b, col);
                sb_puts(&b, " notitle, \\\n     ");
            }
        sb_puts(&b, "NaN w p pt 7 ps 1.4 lc rgb ");
        gnuplot_str(&b, col);
        sb_puts(&b, " t ");
        gnuplot_str(&b, name);
        sb_puts(&b, ", \\\n     ");
    }
    for (int l = 0; l < ACC_LAYOUTS; l++)
        if (layouts[l]) {
            char t[64];
            snprintf(t, sizeof t, l == ACC_VRS ? "VRS (coarse shading)" : "rings %s", k_layout_names[l]);
            sb_printf(&b, "NaN w p pt %d ps 1.4 lc rgb 'black' t ", shape_hollow[l]);
            gnuplot_str(&b, t);
            sb_puts(&b, ", \\\n     ");
        }
    sb_printf(&b, "NaN w p pt 7 ps 1.4 lc rgb 'gray40' t 'TAA on (filled)', NaN w p pt 6 ps 1.4 lc rgb 'gray40' "
                  "t 'TAA off (hollow)', \\\n     $front u %s:%d w l lw 2 lc rgb 'black' t 'Pareto front'\n",
              x_expr, y_col);
    fs_status st = gnuplot_png(out, stem, 1100, 750, &b);
    free(b.p);
    return st;
}

/* The ring LOD of the matrix's default+lod rows: the run's (--ring-lod, else the scene's), checked
 * against the default rings `l`. *use is false when there is none, or when it would change nothing
 * there (every ring keeps all cards, or no MASK primitive is an aggregate: said on stderr). */
static fs_status acc_ring_lod(const run_desc *d, const session *s, const fov_layout *l, ring_lod_spec *out, bool *use)
{
    plan_options po;
    fs_status st = session_plan_options(d, &s->sc, &po);
    *use = false;
    if (st != FS_OK || po.ring_lod.kind == RING_LOD_OFF)
        return st;
    char err[256];
    if (ring_lod_check(&po.ring_lod, l, err, sizeof err) != FS_OK) {
        log_error("--ring-lod: the default rings of bench --accuracy: %s", err);
        return FS_ERR_USAGE;
    }
    po.layout = *l;
    plan *probe = malloc(sizeof *probe);
    if (!probe)
        return FS_ERR_NOMEM;
    st = plan_build(&s->sc, &po, probe);
    if (st == FS_OK && !probe->ring_lod)
        log_warn("bench --accuracy: no default+lod rows: ring LOD changes nothing here (%s)", probe->ring_lod_why);
    *use = st == FS_OK && probe->ring_lod;
    *out = po.ring_lod;
    free(probe);
    return st;
}

/* >>phases: cmd_bench_accuracy runs them in order, sharing one acc_run. */

enum { ACC_REPORT_CAP = 1 << 16 }; /* bytes of accuracy.csv and of accuracy.md */

typedef struct acc_run {
    const run_desc *d;
    run_desc dd; /* the run's, with the matrix's defaults (size, supersampling, TAA) */
    session s;
    int n, warm; /* measured frames, warm-up frames before them */
    alpha_mode modes[ALPHA_MODE_COUNT];
    int nmodes;
    fov_layout layouts[ACC_LAYOUTS];
    fov_layout ml; /* the measurement rings (the default layout) */
    vrs_spec vrs_spec; /* the vrs layout's rate map and tile (session_vrs) */
    int vrs_tile;
    bool use_layout[ACC_LAYOUTS];
    ring_lod_spec lod; /* default+lod's */
    char lod_u[160];
    acc_config *cfg;
    int nc;
    ref_progress rp;
    reference *rf;
    const char *out; /* the output folder */
    progress pr;
    /* >>measurement: what the frames share */
    exr_image ref, prev_ref;
    /* The band-limited reference of the frame for each ring layout (metrics_band_limit): R, G, B,
     * coverage planes; made once per frame and layout, shared by that layout's configurations. */
    size_t band_n;
    float *band_buf;
    metrics_view bands[3];
    float *flip_map; /* each configuration's FLIP map */
    temporal te;
    double prev_err; /* the previous measured frame's reference error estimate */
    bool have_prev_ref;
    /* >>report */
    char *csv, *md;
    int oc, om; /* their lengths (as asked for: >= ACC_REPORT_CAP means too long) */
    double *tx, *ey, *fx; /* per configuration: median time, the --error error, fragment work */
    bool *front, *front_fs; /* on the Pareto front of (time, error), of (fragments, error) */
    int *row_at;            /* where configuration c's row starts in csv (nc + 1 entries) */
    int base;               /* the configuration the speedups are relative to */
    bool have_fs;           /* fragment counts known for every configuration */
    /* >>the cost model (--cost-model) and the x axis of accuracy.png (--cost) */
    cost_predictor cp;
    double *cx;           /* per configuration: the --cost x value, INFINITY when unknown */
    bool *front_cost;     /* on the Pareto front of (cx, error) */
} acc_run;

/* One frame of the matrix, as every configuration sees it. */
typedef struct acc_frame {
    int i;
    bool measured; /* past the warm-up */
    frame_record base;
    display_desc disp;
    reference_info ri;
    ring_mask mask;
    bool band_done[3]; /* per k_band_slot */
    metrics_view vr, vpr; /* the reference, the previous frame's */
} acc_frame;

/* The run's options with the matrix's defaults, and its session. */
static fs_status acc_begin(acc_run *a)
{
    const run_desc *d = a->d;
    a->dd = *d;
    if (!a->dd.width) { /* resolved against the scene below */
        scene probe;
        fs_status st = session_load_scene(d, &probe);
        if (st != FS_OK)
            return st;
        a->dd.width = probe.display.width / ACC_DEFAULT_DIV;
        a->dd.height = probe.display.height / ACC_DEFAULT_DIV;
        scene_free(&probe);
    }
    if (!a->dd.ref.supersample)
        a->dd.ref.supersample = DEMO_SUPERSAMPLE;
    if (!a->dd.ref.samples)
        a->dd.ref.samples = DEMO_SAMPLES;
    if (a->dd.taa.mode == TAA_SWITCH_SCENE)
        a->dd.taa.mode = TAA_SWITCH_ON; /* the session's plan carries TAA controls; each config sets its own */
    a->n = d->frames > 0 ? d->frames : ACC_DEFAULT_FRAMES;
    a->warm = d->bench.warmup; /* TAA history and the JIT settle before measuring */
    a->dd.frames = a->n + a->warm;
    return session_begin(&a->dd, &a->s, false);
}

/* The matrix's rows: alpha modes (--modes, else all), ring layouts (default+lod only with ring LOD
 * that changes something). */
static fs_status acc_choose_layouts(acc_run *a)
{
    const run_desc *d = a->d;
    for (int m = 0; m < d->bench_mode_count; m++)
        a->modes[a->nmodes++] = d->bench_modes[m];
    if (a->nmodes == 0)
        for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++)
            a->modes[a->nmodes++] = (alpha_mode)m;
    /* The default rings are the run's own (auto unless --rings/the scene say otherwise); when the
     * display is too small for them to save pixels, the acuity model's anyway: a matrix whose
     * "default" column equals "off" would measure nothing. */
    const plan *pl = &a->s.pl;
    fov_layout *layouts = a->layouts;
    layouts[ACC_OFF] = fov_layout_off();
    layouts[ACC_DEFAULT] = layouts[ACC_DEFAULT_LOD] = pl->layout;
    layouts[ACC_AGGRESSIVE] = aggressive_layout(pl);
    if (!pl->rings)
        layouts[ACC_DEFAULT] = layouts[ACC_DEFAULT_LOD] = measure_layout(pl);
    a->ml = layouts[ACC_DEFAULT];
    /* VRS is measured in these rings too, like off: one full-resolution ring (measure_layout). Its
     * plan keeps the default rings only as what it is compared with (plan.vrs_rings). */
    layouts[ACC_VRS] = layouts[ACC_DEFAULT];
    session_vrs(a->d, &a->s.sc, &a->vrs_spec, &a->vrs_tile);
    a->use_layout[ACC_VRS] = true;
    /* Ring LOD (--ring-lod or the scene's): measured as its own layout, default+lod; every other
     * configuration is drawn without it. */
    a->use_layout[ACC_OFF] = a->use_layout[ACC_DEFAULT] = a->use_layout[ACC_AGGRESSIVE] = true;
    fs_status st = acc_ring_lod(&a->dd, &a->s, &layouts[ACC_DEFAULT_LOD], &a->lod, &a->use_layout[ACC_DEFAULT_LOD]);
    if (a->use_layout[ACC_DEFAULT_LOD])
        ring_lod_format_u(&a->lod, &layouts[ACC_DEFAULT_LOD], a->lod_u, sizeof a->lod_u);
    return st;
}

/* Each configuration's plan, renderer (with timers: the pipeline statistics queries come with
 * them) and per-frame arrays. */
static fs_status acc_build_configs(acc_run *a)
{
    const run_desc *d = a->d;
    int n = a->n;
    fs_status st = FS_OK;
    a->cfg = calloc(ACC_MAX_CONFIGS, sizeof *a->cfg);
    if (!a->cfg)
        st = FS_ERR_NOMEM;
    for (int m = 0; m < a->nmodes && st == FS_OK; m++)
        for (int l = 0; l < ACC_LAYOUTS && st == FS_OK; l++)
            for (int t = 0; t < 2 && st == FS_OK && a->use_layout[l]; t++) {
                acc_config *c = &a->cfg[a->nc++];
                c->run.mode = a->modes[m];
                c->layout = l;
                c->taa = t == 1;
                plan_options po = {.alpha_mode = a->modes[m], .width = a->s.pl.width, .height = a->s.pl.height,
                                   .frames = n + a->warm, .layout = a->layouts[l], .alpha = a->s.pl.alpha,
                                   .taa = c->taa, .taa_controls = a->s.pl.taa_controls,
                                   .no_ring_cull = d->no_ring_cull, .composite_per_pixel = d->composite_per_pixel,
                                   .ring_lod = l == ACC_DEFAULT_LOD ? a->lod : (ring_lod_spec){0},
                                   .vrs = l == ACC_VRS, .vrs_spec = a->vrs_spec, .vrs_tile = a->vrs_tile};
                st = plan_build(&a->s.sc, &po, &c->run.pl);
                if (st == FS_OK)
                    c->run.r = renderer_create(
                        &(renderer_desc){.scene = &a->s.sc, .plan = &c->run.pl, .timers = true,
                                         .count_fragments = true}, &st);
                if (st == FS_OK && !(c->run.frame_ms = calloc((size_t)n, sizeof(double))))
                    st = FS_ERR_NOMEM;
                if (st == FS_OK && !(c->pred = calloc((size_t)n, sizeof(double))))
                    st = FS_ERR_NOMEM;
                for (int q = 0; q < ACC_COUNTS && st == FS_OK; q++)
                    if (!(c->counts[q] = calloc((size_t)n, sizeof(double))))
                        st = FS_ERR_NOMEM;
            }
    return st;
}

/* The reference, the output folder, the progress line and the measurement's buffers. Given the
 * setup's status st: with st not FS_OK, only the progress line is begun (and SIGINT caught). */
static fs_status acc_begin_measuring(acc_run *a, fs_status st)
{
    const run_desc *d = a->d;
    a->rf = st == FS_OK ? session_reference(&a->dd, &a->s, &a->rp, &st) : NULL;
    a->out = d->out_dir ? d->out_dir : "out/bench";
    if (st == FS_OK)
        st = file_make_dirs(a->out);
    if (st == FS_OK)
        out_dir_remove_stale_temps(a->out);
    session_catch_sigint();
    a->pr = progress_begin("accuracy frame", a->n + a->warm, d->quiet, d->progress_interval);
    a->rp.pr.enabled = false; /* one progress line: frames */
    a->band_n = (size_t)a->s.pl.width * (size_t)a->s.pl.height;
    a->band_buf = st == FS_OK ? malloc(sizeof(float) * 12 * a->band_n) : NULL;
    if (st == FS_OK && !a->band_buf)
        st = FS_ERR_NOMEM;
    a->flip_map = st == FS_OK ? malloc(sizeof(float) * a->band_n) : NULL;
    if (st == FS_OK && !a->flip_map)
        st = FS_ERR_NOMEM;
    if (st == FS_OK)
        st = temporal_begin(&a->te, &a->s);
    return st;
}

/* Configuration c's draw of frame f: timed (wall clock, process CPU time, page faults, pipeline
 * statistics) and, once measured, read back and measured against the reference. */
static fs_status acc_run_config(acc_run *a, acc_frame *f, int c)
{
    acc_config *cf = &a->cfg[c];
    mode_run *mr = &cf->run;
    int i = f->i, warm = a->warm;
    frame_record fr = f->base;
    frame_record_set_layout(&fr, &mr->pl.layout, &f->disp);
    renderer_finish(mr->r);
    proc_stats p0 = proc_stats_now();
    double t0 = time_now();
    fs_status st = renderer_draw(mr->r, &fr);
    renderer_finish(mr->r);
    double ms = (time_now() - t0) * 1e3;
    proc_stats pd = proc_stats_since(p0);
    renderer_stats rs = renderer_last_stats(mr->r); /* also when not measured: the queries are done */
    if (!f->measured || st != FS_OK)
        return st;
    mr->frame_ms[i - warm] = ms;
    st = renderer_read(mr->r, &mr->img);
    renderer_stats cs = {0}; /* covered fragments: the counting variant, once the frame is read back */
    if (st == FS_OK) {
        st = renderer_draw_counting(mr->r, &fr, &cs);
        renderer_stats_take_shaded(&rs, &cs); /* VRS: what a GPU would shade, not llvmpipe's count */
    }
    const double counts[ACC_COUNTS] = {pd.cpu_ms, (double)pd.minor_faults, (double)rs.vs_invocations,
                                       (double)rs.primitives, (double)rs.fragments, (double)rs.clipped,
                                       (double)cs.covered, (double)rs.bytes_read, (double)rs.bytes_written,
                                       (double)cs.shaded};
    for (int q = 0; q < ACC_COUNTS; q++)
        cf->counts[q][i - warm] = counts[q];
    cf->pred[i - warm] = cost_predictor_frame_ms(&a->cp, &rs, alpha_mode_name(mr->mode));
    ring_metrics rm[MAX_FOV_RINGS + 1] = {0};
    metrics_view vi = measure_view(&mr->img), vp = measure_view(&mr->prev);
    bool prev = mr->have_prev && a->have_prev_ref && !fr.cut;
    int l = k_band_slot[cf->layout];
    if (st == FS_OK && !f->band_done[l]) {
        float *b = a->band_buf + (size_t)(4 * l) * a->band_n;
        float *const planes[4] = {b, b + a->band_n, b + 2 * a->band_n, b + 3 * a->band_n};
        st = metrics_band_limit(&f->vr, &f->disp, &mr->pl.layout, fr.ring_rect, fr.gaze_px[0], fr.gaze_px[1], planes,
                                &a->bands[l]);
        f->band_done[l] = true;
    }
    metrics_view vb = a->bands[l];
    if (st == FS_OK)
        st = measure_flip(&vi, &f->vr, &f->disp, a->flip_map);
    if (st == FS_OK)
        st = metrics_compute(&vi, &f->vr, &vb, a->flip_map, prev ? &f->vpr : NULL, &f->mask, rm);
    bool still = temporal_still(&a->te, &f->base);
    if (st == FS_OK)
        st = temporal_measure(&a->te, &vi, prev ? &vp : NULL, &f->vr, &f->mask,
                              temporal_reference_noise2(a->rf, still, f->ri.error, a->prev_err), rm);
    measure_accumulate(mr, rm, a->ml.count, f->measured && still);
    exr_image_move(&mr->prev, &mr->img);
    mr->have_prev = true;
    return st;
}

/* Frame i: its reference (once measured), then every configuration's draw. */
static fs_status acc_run_frame(acc_run *a, int i)
{
    const run_desc *d = a->d;
    acc_frame f = {.i = i, .measured = i >= a->warm};
    f.base = session_frame(&a->s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
    f.disp = frame_display(&f.base, a->s.pl.width, a->s.pl.height);
    fs_status st = FS_OK;
    if (f.measured) {
        st = reference_frame(a->rf, &f.base, &a->ref, &f.ri);
        if (st == FS_OK)
            st = ring_mask_build(&f.disp, &a->ml, f.base.true_gaze_px[0], f.base.true_gaze_px[1], &f.mask);
    }
    f.vr = measure_view(&a->ref);
    f.vpr = measure_view(&a->prev_ref);
    if (f.measured && st == FS_OK) /* this frame's depth and the previous reference warped into it */
        st = temporal_frame(&a->te, &f.base, a->have_prev_ref && !f.base.cut ? &f.vpr : NULL);
    for (int c = 0; c < a->nc && st == FS_OK; c++)
        st = acc_run_config(a, &f, c);
    ring_mask_free(&f.mask);
    if (f.measured) {
        temporal_next(&a->te, &f.base);
        a->prev_err = f.ri.error;
        exr_image_move(&a->prev_ref, &a->ref);
        a->have_prev_ref = true;
    }
    return st;
}

/* The frames: every configuration drawn over the same consecutive frames, interleaved per frame. */
static fs_status acc_run_frames(acc_run *a, fs_status st)
{
    for (int i = 0; i < a->n + a->warm && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        st = acc_run_frame(a, i);
        progress_update(&a->pr, i + 1);
    }
    progress_end(&a->pr);
    return st;
}

/* Medians and quantiles per configuration, the error --error plots, and the Pareto fronts. Base of
 * the speedups: full-resolution traditional, TAA off (else the first configuration). */
static fs_status acc_summarise(acc_run *a)
{
    int nc = a->nc, n = a->n;
    const run_desc *d = a->d;
    a->row_at = calloc((size_t)nc + 1, sizeof *a->row_at);
    a->csv = malloc(ACC_REPORT_CAP);
    a->md = malloc(ACC_REPORT_CAP);
    a->tx = calloc((size_t)nc, sizeof *a->tx);
    a->ey = calloc((size_t)nc, sizeof *a->ey);
    a->fx = calloc((size_t)nc, sizeof *a->fx);
    a->front = calloc((size_t)nc, sizeof *a->front);
    a->front_fs = calloc((size_t)nc, sizeof *a->front_fs);
    if (!a->csv || !a->md || !a->tx || !a->ey || !a->fx || !a->front || !a->front_fs || !a->row_at)
        return FS_ERR_NOMEM;
    a->base = 0;
    for (int c = 0; c < nc; c++) {
        acc_config *cf = &a->cfg[c];
        double *v = cf->run.frame_ms;
        qsort(v, (size_t)n, sizeof *v, stats_cmp_double);
        cf->med = stats_quantile(v, n, 0.5);
        cf->p10 = stats_quantile(v, n, 0.1);
        cf->p90 = stats_quantile(v, n, 0.9);
        if (cf->run.mode == ALPHA_MODE_TRADITIONAL && cf->layout == ACC_OFF && !cf->taa)
            a->base = c;
        for (int q = 0; q < ACC_COUNTS; q++) {
            double *u = cf->counts[q];
            qsort(u, (size_t)n, sizeof *u, stats_cmp_double);
            cf->count_med[q] = u[0] < 0 ? -1.0 : stats_quantile(u, n, 0.5); /* -1: unknown */
        }
        a->tx[c] = cf->med;
        a->fx[c] = cf->count_med[ACC_FS];
        const mode_run *er = &cf->run; /* the error of --error, over the whole display */
        int all = a->ml.count;
        if (d->bench.error == ACC_ERROR_TEMPORAL) {
            a->ey[c] = measure_mean_or(er->te_sum[all], er->te_n[all], 0.0);
        } else {
            const double *esum = d->bench.error == ACC_ERROR_FLIP   ? er->flip_sum
                                 : d->bench.error == ACC_ERROR_ALPHA_RMSE ? er->alpha_rmse_sum
                                                     : er->rmse_sum;
            a->ey[c] = measure_mean_or(esum[all], er->err_n[all], 0.0);
        }
    }
    pareto(a->tx, a->ey, nc, a->front);
    a->have_fs = nc > 0;
    for (int c = 0; c < nc; c++)
        a->have_fs = a->have_fs && a->fx[c] >= 0;
    if (a->have_fs)
        pareto(a->fx, a->ey, nc, a->front_fs);
    return FS_OK;
}

/* The median predicted frame time per configuration (-1 when a frame's is unknown), the x value
 * of accuracy.png per --cost (time; model: predicted ms; work: shaded fragments per display
 * pixel; INFINITY when unknown) and the Pareto front on it, of the known ones. */
static fs_status acc_cost_axis(acc_run *a)
{
    int nc = a->nc, n = a->n;
    a->cx = calloc((size_t)nc, sizeof *a->cx);
    a->front_cost = calloc((size_t)nc, sizeof *a->front_cost);
    if (!a->cx || !a->front_cost)
        return FS_ERR_NOMEM;
    double px = (double)a->s.pl.width * a->s.pl.height;
    for (int c = 0; c < nc; c++) {
        acc_config *cf = &a->cfg[c];
        qsort(cf->pred, (size_t)n, sizeof *cf->pred, stats_cmp_double);
        cf->pred_med = cf->pred[0] < 0 ? -1.0 : stats_quantile(cf->pred, n, 0.5);
        double x = a->d->bench.cost == ACC_COST_MODEL  ? cf->pred_med
                   : a->d->bench.cost == ACC_COST_WORK ? cf->count_med[ACC_SHADED] / px
                                                       : cf->med;
        a->cx[c] = x >= 0 ? x : INFINITY;
    }
    pareto(a->cx, a->ey, nc, a->front_cost);
    for (int c = 0; c < nc; c++)
        a->front_cost[c] = a->front_cost[c] && isfinite(a->cx[c]);
    return FS_OK;
}

#define CSV(...) a->oc += snprintf(a->csv + a->oc, ACC_REPORT_CAP - (size_t)a->oc, __VA_ARGS__)
#define MD(...) a->om += snprintf(a->md + a->om, ACC_REPORT_CAP - (size_t)a->om, __VA_ARGS__)

/* accuracy.csv's header line. */
static void acc_csv_header(acc_run *a)
{
    int rings = a->ml.count;
    CSV("mode,rings,taa,frame_ms_median,frame_ms_p10,frame_ms_p90,speedup,rmse,psnr,temporal_error,pareto");
    for (int q = 0; q < ACC_CLIPPED; q++)
        CSV(",%s", k_acc_count_columns[q]);
    CSV(",pareto_fragments");
    for (int k = 0; k < rings; k++)
        CSV(",coverage_ratio_ring%d", k);
    CSV(",alpha_rmse");
    for (int k = 0; k < rings; k++)
        CSV(",alpha_rmse_ring%d", k);
    CSV(",flip");
    for (int k = 0; k < rings; k++)
        CSV(",flip_ring%d", k);
    for (int q = ACC_CLIPPED; q < ACC_SHADED; q++)
        CSV(",%s", k_acc_count_columns[q]);
    CSV(",predicted_ms,%s\n", k_acc_count_columns[ACC_SHADED]);
}

/* accuracy.md's heading, what was measured how, and the table's header. */
static void acc_md_header(acc_run *a)
{
    const run_desc *d = a->d;
    const session *s = &a->s;
    char cpu[256], rings[256], aggr[256];
    session_cpu_name(cpu, sizeof cpu);
    fov_layout_format(&a->layouts[ACC_DEFAULT], rings, sizeof rings);
    fov_layout_format(&a->layouts[ACC_AGGRESSIVE], aggr, sizeof aggr);
    MD("### Accuracy vs time: %s, %dx%d\n\n", s->sc.path, s->pl.width, s->pl.height);
    MD("- machine: %s (%ld cores online); renderer: %s\n", cpu, sysconf(_SC_NPROCESSORS_ONLN), gl_device_renderer());
    MD("- %d frames measured after %d warm-up frames (consecutive, %g fps); gaze: %s\n", a->n, a->warm, d->fps,
       s->gaze.count ? s->gaze.path : "fixation at the centre");
    MD("- rings: default %s; aggressive %s; measured in the default rings\n", rings, aggr);
    if (a->use_layout[ACC_DEFAULT_LOD]) {
        char spec[160];
        ring_lod_format(&a->lod, spec, sizeof spec);
        MD("- default+lod: the default rings with ring LOD %s, keep fraction u = %s per ring (the other rows "
           "without ring LOD; the reference never simplified)\n", spec, a->lod_u);
    }
    char vrs[160];
    vrs_spec_format(&a->vrs_spec, vrs, sizeof vrs);
    MD("- vrs: one full-resolution pass, coarse shading at the rate map %s, %d px tiles, for each frame's gaze; "
       "measured in the default rings like off; its frag./px and shaded/px are a GPU's coarse-shading "
       "invocations (one per primitive and coarse pixel with a covered pixel), not what llvmpipe's emulation "
       "runs (docs/foveation.md)\n", vrs, a->vrs_tile);
    MD("- reference: %s\n", reference_describe(a->rf));
    MD("- speedup: median frame time of traditional, full resolution, TAA off / this one's; * = on the "
       "Pareto front of (time, %s) (--error)\n", k_error_names[d->bench.error]);
    MD("- CPU ms: process CPU time of the draw, all threads; frag./px: fragment-shader invocations per display "
       "pixel (GL_ARB_pipeline_statistics_query; medians per frame); shaded/px: the invocations a GPU would run "
       "per display pixel, from a counting frame: covered fragments, under VRS coarse-shading invocations "
       "(docs/benchmarks.md \"Work counts\"; the work axis)\n");
    MD("- cov. ring K: the mode's coverage summed over the frames / the reference's (n/a where the reference "
       "holds under %g ring texels of coverage)\n", METRICS_MIN_REF_TEXELS);
    if (a->cp.on)
        MD("- predicted ms: the frame time the cost model %s predicts from each frame's per-stage counts "
           "(median per frame; docs/benchmarks.md \"Cost model\")\n", d->bench.cost_model);
    MD("\n");
    MD("| mode | rings | TAA | frame ms (p10-p90) | speedup | RMSE | %s | temporal err. | CPU ms | frag./px | shaded/px |",
       d->bench.error == ACC_ERROR_RMSE ? "PSNR" : k_error_names[d->bench.error]);
    for (int k = 0; k < a->ml.count; k++)
        MD(" cov. ring %d |", k);
    if (a->cp.on)
        MD(" predicted ms |");
    MD("\n|---|---|---|---|---|---|---|---|---|---|---|");
    for (int k = 0; k < a->ml.count + (a->cp.on ? 1 : 0); k++)
        MD("---|");
    MD("\n");
}

/* Configuration c's row of accuracy.csv and of the Markdown table. */
static void acc_row(acc_run *a, int c)
{
    const acc_config *cf = &a->cfg[c];
    const mode_run *mr = &cf->run;
    int all = a->ml.count;
    double rmse = measure_mean_or(mr->rmse_sum[all], mr->err_n[all], 0.0),
           psnr = measure_mean_or(mr->psnr_sum[all], mr->err_n[all], 0.0),
           fl = measure_mean_or(mr->te_sum[all], mr->te_n[all], -1.0), sp = a->cfg[a->base].med / cf->med;
    const double *cm = cf->count_med;
    a->row_at[c] = a->oc;
    CSV("%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.6f,%.3f,%.6f,%d", alpha_mode_name(mr->mode), k_layout_names[cf->layout],
        cf->taa ? "on" : "off", cf->med, cf->p10, cf->p90, sp, rmse, psnr, fl, a->front[c]);
    CSV(",%.4f,%.0f,%.0f,%.0f,%.0f,%d", cm[ACC_CPU], cm[ACC_FAULTS], cm[ACC_VS], cm[ACC_PRIMS], cm[ACC_FS],
        a->front_fs[c]);
    MD("| %s%s | %s | %s | %.2f (%.2f-%.2f) | %.2fx | %.4f | %.4f | %.4f | %.2f |", alpha_mode_name(mr->mode),
       a->front[c] ? " *" : "", k_layout_names[cf->layout], cf->taa ? "on" : "off", cf->med, cf->p10, cf->p90, sp,
       rmse, a->d->bench.error == ACC_ERROR_RMSE ? psnr : a->ey[c], fl, cm[ACC_CPU]);
    const int per_px[2] = {ACC_FS, ACC_SHADED}; /* frag./px, shaded/px */
    for (int j = 0; j < 2; j++)
        if (cm[per_px[j]] >= 0)
            MD(" %.2f |", cm[per_px[j]] / ((double)a->s.pl.width * a->s.pl.height));
        else
            MD(" n/a |");
    for (int k = 0; k < a->ml.count; k++) {
        /* The ratio of the coverage summed over frames, -1 (n/a) where the reference holds
         * too little in the ring (measure_coverage_ratio). The texels are the measurement
         * rings' (the default layout's) for every row: the reference is the same for all. */
        double r = measure_coverage_ratio(mr, k, measure_block(&a->ml, k));
        CSV(",%.4f", r);
        if (r < 0.0)
            MD(" n/a |");
        else
            MD(" %.2f |", r);
    }
    for (int k = 0; k <= a->ml.count; k++) /* the whole display, then each ring */
        CSV(",%.6f", measure_mean_or(mr->alpha_rmse_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
    for (int k = 0; k <= a->ml.count; k++)
        CSV(",%.6f", measure_mean_or(mr->flip_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
    for (int q = ACC_CLIPPED; q < ACC_SHADED; q++)
        CSV(",%.0f", cm[q]);
    CSV(",%.4f,%.0f\n", cf->pred_med, cm[ACC_SHADED]);
    if (a->cp.on && cf->pred_med >= 0)
        MD(" %.2f |", cf->pred_med);
    else if (a->cp.on)
        MD(" n/a |");
    MD("\n");
}

#undef CSV
#undef MD

/* accuracy.csv and accuracy.md's text, in a->csv and a->md. */
static fs_status acc_tabulate(acc_run *a)
{
    a->oc = a->om = 0;
    acc_csv_header(a);
    acc_md_header(a);
    for (int c = 0; c < a->nc; c++)
        acc_row(a, c);
    a->row_at[a->nc] = a->oc;
    if (a->oc >= ACC_REPORT_CAP) {
        log_error("%s/accuracy.csv: longer than the %d bytes it may take (too many modes?)", a->out, ACC_REPORT_CAP);
        return FS_ERR_INTERNAL;
    }
    return FS_OK;
}

/* accuracy.png: the --error error (CSV column y_col) against the --cost x axis. */
static fs_status acc_plot_cost(acc_run *a, int y_col)
{
    const session *s = &a->s;
    const run_desc *d = a->d;
    char title[1000], x_expr[64], xlabel[300];
    int rings = a->ml.count;
    if (d->bench.cost == ACC_COST_MODEL) { /* predicted_ms; -1 (unknown) not drawn */
        snprintf(title, sizeof title, "accuracy vs predicted time: %s %dx%d (cost model of %s)", s->sc.path,
                 s->pl.width, s->pl.height, a->cp.model.renderer);
        snprintf(x_expr, sizeof x_expr, "($%d >= 0 ? $%d : NaN)", 24 + 3 * rings, 24 + 3 * rings);
        snprintf(xlabel, sizeof xlabel, "frame time predicted by the cost model, median (ms; lower is better)");
    } else if (d->bench.cost == ACC_COST_WORK) { /* shaded_fragments_median (after predicted_ms) per pixel */
        snprintf(title, sizeof title, "accuracy vs work: %s %dx%d", s->sc.path, s->pl.width, s->pl.height);
        snprintf(x_expr, sizeof x_expr, "($%d >= 0 ? $%d/%d.0 : NaN)", 25 + 3 * rings, 25 + 3 * rings,
                 s->pl.width * s->pl.height);
        snprintf(xlabel, sizeof xlabel, "shaded fragments per display pixel (covered; VRS: coarse invocations), "
                                        "median per frame (device-independent work; lower is better)");
    } else {
        snprintf(title, sizeof title, "accuracy vs time: %s %dx%d (%s)", s->sc.path, s->pl.width, s->pl.height,
                 gl_device_renderer());
        snprintf(x_expr, sizeof x_expr, "4");
        snprintf(xlabel, sizeof xlabel, "frame time, median (ms; lower is better)");
    }
    return plot_accuracy(a->out, "accuracy", title, xlabel, x_expr, y_col, k_error_labels[d->bench.error], a->cx,
                         a->front_cost, a->csv, a->row_at, a->nc, a->modes, a->nmodes, a->use_layout);
}

/* Writes accuracy.csv and accuracy.md (and appends the table to --markdown), draws the plots and
 * prints the table. */
static fs_status acc_write(acc_run *a)
{
    const run_desc *d = a->d;
    const session *s = &a->s;
    const char *out = a->out;
    fs_status st = acc_tabulate(a);
    char path[1200];
    snprintf(path, sizeof path, "%s/accuracy.csv", out);
    if (st == FS_OK)
        st = out_write_atomic(path, a->csv);
    snprintf(path, sizeof path, "%s/accuracy.md", out);
    if (st == FS_OK)
        st = out_write_atomic(path, a->md);
    if (st == FS_OK && d->bench.markdown) {
        FILE *f = fopen(d->bench.markdown, "a");
        if (!f || fprintf(f, "\n%s", a->md) < 0 || fclose(f) != 0) {
            log_error("%s: cannot append the accuracy table: %s", d->bench.markdown, strerror(errno));
            st = FS_ERR_IO;
        }
    }
    char title[600], x_expr[64];
    /* The whole-display column of the chosen error in accuracy.csv: rmse is column 8,
     * temporal_error 10; after the 17 fixed columns come N coverage ratios, alpha_rmse and its
     * N rings, flip and its N. */
    int y_col = d->bench.error == ACC_ERROR_TEMPORAL   ? 10
                : d->bench.error == ACC_ERROR_RMSE ? 8
                : d->bench.error == ACC_ERROR_ALPHA_RMSE ? 18 + a->ml.count
                                    : 19 + 2 * a->ml.count;
    if (st == FS_OK)
        st = acc_plot_cost(a, y_col);
    /* Accuracy vs fragment work: what transfers to a GPU, where wall time on llvmpipe does not. */
    snprintf(path, sizeof path, "%s/accuracy-fragments.png", out);
    if (st == FS_OK && a->have_fs) {
        snprintf(title, sizeof title, "accuracy vs fragment work: %s %dx%d", s->sc.path, s->pl.width, s->pl.height);
        snprintf(x_expr, sizeof x_expr, "($16/%d.0)", s->pl.width * s->pl.height);
        st = plot_accuracy(out, "accuracy-fragments", title,
                           "fragment-shader invocations per display pixel, median per frame (lower is better)", x_expr, y_col,
                           k_error_labels[d->bench.error], a->fx, a->front_fs, a->csv, a->row_at, a->nc, a->modes,
                           a->nmodes, a->use_layout);
    } else if (st == FS_OK) {
        unlink(path); /* not one from an earlier run beside this run's CSV */
        log_warn("no GL_ARB_pipeline_statistics_query: fragment counts unknown, %s not drawn", path);
    }
    if (st == FS_OK) {
        fputs(a->md, stdout);
        printf("\nwrote %s/accuracy.csv, accuracy.md, accuracy.png%s\n", out,
               a->have_fs ? " and accuracy-fragments.png" : "");
    }
    return st;
}

static void acc_free(acc_run *a)
{
    free(a->csv);
    free(a->md);
    free(a->tx);
    free(a->ey);
    free(a->fx);
    free(a->front);
    free(a->front_fs);
    free(a->row_at);
    free(a->cx);
    free(a->front_cost);
    exr_image_free(&a->ref);
    exr_image_free(&a->prev_ref);
    free(a->band_buf);
    free(a->flip_map);
    temporal_end(&a->te);
    for (int c = 0; c < a->nc; c++) {
        acc_config *cf = &a->cfg[c];
        exr_image_free(&cf->run.img);
        exr_image_free(&cf->run.prev);
        free(cf->run.frame_ms);
        free(cf->pred);
        for (int q = 0; q < ACC_COUNTS; q++)
            free(cf->counts[q]);
        renderer_destroy(cf->run.r);
    }
    free(a->cfg);
    reference_destroy(a->rf);
    session_end(&a->s);
}

fs_status cmd_bench_accuracy(const run_desc *d)
{
    if (!gnuplot_available()) {
        log_error("gnuplot: not found; bench --accuracy plots with it (Debian package gnuplot-nox)");
        return FS_ERR_IO;
    }
    acc_run *a = calloc(1, sizeof *a);
    if (!a)
        return FS_ERR_NOMEM;
    a->d = d;
    fs_status st = acc_begin(a);
    if (st != FS_OK) {
        free(a);
        return st;
    }
    st = cost_predictor_open(&a->cp, d->bench.cost_model, gl_device_renderer());
    if (st == FS_OK)
        st = acc_choose_layouts(a);
    if (st == FS_OK)
        st = acc_build_configs(a);
    st = acc_begin_measuring(a, st);
    st = acc_run_frames(a, st);
    if (st == FS_OK)
        st = acc_summarise(a);
    if (st == FS_OK)
        st = acc_cost_axis(a);
    if (st == FS_OK)
        st = acc_write(a);
    if (st == FS_OK)
        st = report_html_write(&(report_html_desc){.dir = a->out, .kind = "bench --accuracy",
                                                   .acc_error = k_error_names[d->bench.error],
                                                   .acc_error_label = k_error_labels[d->bench.error]});
    acc_free(a);
    free(a);
    return st;
}
