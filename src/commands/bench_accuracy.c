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
#include "output/out_path.h"
#include "commands/measure.h"
#include "session/session.h"

/* The accuracy-vs-time matrix (docs/design.md "Outputs"; docs/benchmarks.md): alpha modes x foveation
 * off / default / aggressive (and default+lod, the default rings with ring LOD, when the run asks
 * for it) x TAA off / on, every configuration drawn over the same consecutive
 * frames (TAA needs a real sequence), timings interleaved per frame so all see the same machine
 * state, accuracy measured after the warm-up against the reference in the default rings. */

#define ACC_DEFAULT_DIV 4       /* default size: the scene's display / 4 (320x180 for 1280x720) */
#define ACC_DEFAULT_FRAMES 12
#define ACC_MAX_CONFIGS (ALPHA_MODE_COUNT * ACC_LAYOUTS * 2)

/* The ring layouts of the matrix, in row order; default+lod is the default rings with the run's
 * ring LOD (docs/ring-lod.md), only with --ring-lod (or the scene's "ring_lod"). */
enum { ACC_OFF, ACC_DEFAULT, ACC_DEFAULT_LOD, ACC_AGGRESSIVE, ACC_LAYOUTS };
static const char *const k_layout_names[ACC_LAYOUTS] = {"off", "default", "default+lod", "aggressive"};
/* Which band-limited reference a layout uses: default+lod has the default rings' bands. */
static const int k_band_slot[ACC_LAYOUTS] = {0, 1, 1, 2};

/* Per-frame counts of bench --accuracy besides the frame time, in CSV column order: process CPU
 * time (ms) and minor page faults of the draw, then its pipeline statistics (-1 = unknown). */
enum { ACC_CPU, ACC_FAULTS, ACC_VS, ACC_PRIMS, ACC_FS, ACC_COUNTS };
static const char *const k_acc_count_columns[ACC_COUNTS] = {"cpu_ms_median", "minor_faults_median",
                                                            "vs_invocations_median", "primitives_median",
                                                            "fs_invocations_median"};

typedef struct acc_config {
    mode_run run;   /* renderer, images and sums (frame_ms: measured frames only) */
    int layout;     /* ACC_OFF .. ACC_AGGRESSIVE */
    bool taa;
    double med, p10, p90;
    double *counts[ACC_COUNTS]; /* per measured frame */
    double count_med[ACC_COUNTS];
} acc_config;

/* The aggressive layout: the acuity model with twice the slope (resolution falls off twice as
 * fast with eccentricity), and half a mip level of extra bias on every reduced ring. */
static fov_layout aggressive_layout(const plan *pl)
{
    display_desc dd = {pl->width, pl->height, pl->hfov_deg};
    fov_layout l = fov_layout_auto(&dd, 2.0f * FOV_ACUITY_SLOPE_DEFAULT, FOV_ACUITY_OMEGA0_DEFAULT);
    l.kind = FOV_LAYOUT_EXPLICIT;
    for (int i = 0; i < l.count; i++)
        if (l.rings[i].scale_log2 > 0)
            l.rings[i].mip_bias += 0.5f;
    return l;
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
static const char *const k_error_labels[4] = {"FLIP vs reference (mean)",
                                              "alpha RMSE vs band-limited reference (linear RGB)",
                                              "RMSE vs reference (linear RGB)",
                                              "temporal error, motion-compensated (linear RGB)"};

/* Plots the error (CSV column y_col) against x_expr (a gnuplot column expression) into
 * OUT/STEM.png through OUT/STEM.gp. Colour = alpha mode, shape = ring layout (those with
 * layouts[l] set; default+lod a diamond), filled = TAA on, hollow = off; a legend names each
 * (dummy series: one entry per mode, layout and TAA state, not one per point); the Pareto front
 * (the configurations with front[c], in the order of key[c]) is a line, drawn from their rows of
 * accuracy.csv (csv + row_at[c]) copied into the script. gnuplot runs in OUT (gnuplot.h): no path
 * is in the script, and every string in it is quoted by gnuplot_str. */
static fs_status plot_accuracy(const char *out, const char *stem, const char *title, const char *xlabel,
                               const char *x_expr, int y_col, const char *ylabel, const double *key, const bool *front,
                               const char *csv, const int *row_at, int nc, const alpha_mode *modes, int mode_count,
                               const bool *layouts)
{
    /* circle, square, diamond, triangle */
    static const int shape_filled[ACC_LAYOUTS] = {7, 5, 13, 9}, shape_hollow[ACC_LAYOUTS] = {6, 4, 12, 8};
    static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
    char gp[1200], png[1200], pngtmp[1300];
    snprintf(gp, sizeof gp, "%s.gp", stem);
    snprintf(png, sizeof png, "%s/%s.png", out, stem);
    if (!out_path_temp_name(png, pngtmp, sizeof pngtmp)) {
        log_error("%s: cannot write: the path is too long", png);
        return FS_ERR_IO;
    }
    const char *tmp_name = strrchr(pngtmp, '/') ? strrchr(pngtmp, '/') + 1 : pngtmp;
    sbuf b = {0};
    sb_puts(&b, "set terminal pngcairo size 1100,750 noenhanced\nset output ");
    gnuplot_str(&b, tmp_name);
    sb_puts(&b, "\nset datafile separator ','\nset title ");
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
        const char *name = alpha_mode_name(modes[m]), *col = colours[m % 7];
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
            snprintf(t, sizeof t, "rings %s", k_layout_names[l]);
            sb_printf(&b, "NaN w p pt %d ps 1.4 lc rgb 'black' t ", shape_hollow[l]);
            gnuplot_str(&b, t);
            sb_puts(&b, ", \\\n     ");
        }
    sb_printf(&b, "NaN w p pt 7 ps 1.4 lc rgb 'gray40' t 'TAA on (filled)', NaN w p pt 6 ps 1.4 lc rgb 'gray40' "
                  "t 'TAA off (hollow)', \\\n     $front u %s:%d w l lw 2 lc rgb 'black' t 'Pareto front'\n",
              x_expr, y_col);
    fs_status st = gnuplot_run(out, gp, &b);
    free(b.p);
    if (st == FS_OK && rename(pngtmp, png) != 0) {
        log_error("%s: cannot rename to %s: %s", pngtmp, png, strerror(errno));
        st = FS_ERR_IO;
    }
    if (st != FS_OK)
        unlink(pngtmp);
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

fs_status cmd_bench_accuracy(const run_desc *d)
{
    if (!gnuplot_available()) {
        log_error("gnuplot: not found; bench --accuracy plots with it (Debian package gnuplot-nox)");
        return FS_ERR_IO;
    }
    run_desc dd = *d;
    if (!dd.width) { /* resolved against the scene below */
        scene probe;
        fs_status st = session_load_scene(d, &probe);
        if (st != FS_OK)
            return st;
        dd.width = probe.display.width / ACC_DEFAULT_DIV;
        dd.height = probe.display.height / ACC_DEFAULT_DIV;
        scene_free(&probe);
    }
    if (!dd.ref.supersample)
        dd.ref.supersample = DEMO_SUPERSAMPLE;
    if (!dd.ref.samples)
        dd.ref.samples = DEMO_SAMPLES;
    if (dd.taa.mode == TAA_SWITCH_SCENE)
        dd.taa.mode = TAA_SWITCH_ON; /* the session's plan carries TAA controls; each config sets its own */
    int n = d->frames > 0 ? d->frames : ACC_DEFAULT_FRAMES;
    int warm = d->bench.warmup; /* TAA history and the JIT settle before measuring */
    dd.frames = n + warm;
    session s;
    fs_status st = session_begin(&dd, &s, false);
    if (st != FS_OK)
        return st;
    alpha_mode modes[ALPHA_MODE_COUNT];
    int nmodes = 0;
    for (int m = 0; m < d->bench_mode_count; m++)
        modes[nmodes++] = d->bench_modes[m];
    if (nmodes == 0)
        for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++)
            modes[nmodes++] = (alpha_mode)m;
    /* The default rings are the run's own (auto unless --rings/the scene say otherwise); when the
     * display is too small for them to save pixels, the acuity model's anyway: a matrix whose
     * "default" column equals "off" would measure nothing. */
    fov_layout layouts[ACC_LAYOUTS] = {fov_layout_off(), s.pl.layout, s.pl.layout, aggressive_layout(&s.pl)};
    if (!s.pl.rings)
        layouts[ACC_DEFAULT] = layouts[ACC_DEFAULT_LOD] = measure_layout(&s.pl);
    fov_layout ml = layouts[ACC_DEFAULT];
    /* Ring LOD (--ring-lod or the scene's): measured as its own layout, default+lod; every other
     * configuration is drawn without it. */
    bool use_layout[ACC_LAYOUTS] = {true, true, false, true};
    ring_lod_spec lod = {0};
    char lod_u[160] = "";
    if (st == FS_OK)
        st = acc_ring_lod(&dd, &s, &layouts[ACC_DEFAULT_LOD], &lod, &use_layout[ACC_DEFAULT_LOD]);
    if (use_layout[ACC_DEFAULT_LOD])
        ring_lod_format_u(&lod, &layouts[ACC_DEFAULT_LOD], lod_u, sizeof lod_u);
    acc_config *cfg = calloc(ACC_MAX_CONFIGS, sizeof *cfg);
    int nc = 0;
    if (!cfg)
        st = FS_ERR_NOMEM;
    for (int m = 0; m < nmodes && st == FS_OK; m++)
        for (int l = 0; l < ACC_LAYOUTS && st == FS_OK; l++)
            for (int t = 0; t < 2 && st == FS_OK && use_layout[l]; t++) {
                acc_config *c = &cfg[nc++];
                c->run.mode = modes[m];
                c->layout = l;
                c->taa = t == 1;
                plan_options po = {.alpha_mode = modes[m], .width = s.pl.width, .height = s.pl.height,
                                   .frames = n + warm, .layout = layouts[l], .alpha = s.pl.alpha, .taa = c->taa,
                                   .taa_controls = s.pl.taa_controls, .no_ring_cull = d->no_ring_cull,
                                   .composite_per_pixel = d->composite_per_pixel,
                                   .ring_lod = l == ACC_DEFAULT_LOD ? lod : (ring_lod_spec){0}};
                st = plan_build(&s.sc, &po, &c->run.pl);
                /* timers: the pipeline statistics queries come with them */
                if (st == FS_OK)
                    c->run.r = renderer_create(&(renderer_desc){.scene = &s.sc, .plan = &c->run.pl, .timers = true},
                                               &st);
                if (st == FS_OK && !(c->run.frame_ms = calloc((size_t)n, sizeof(double))))
                    st = FS_ERR_NOMEM;
                for (int q = 0; q < ACC_COUNTS && st == FS_OK; q++)
                    if (!(c->counts[q] = calloc((size_t)n, sizeof(double))))
                        st = FS_ERR_NOMEM;
            }
    ref_progress rp = {0};
    reference *rf = st == FS_OK ? session_reference(&dd, &s, &rp, &st) : NULL;
    const char *out = d->out_dir ? d->out_dir : "out/bench";
    if (st == FS_OK)
        st = file_make_dirs(out);
    if (st == FS_OK)
        out_dir_remove_stale_temps(out);
    session_catch_sigint();
    progress pr = progress_begin("accuracy frame", n + warm, d->quiet);
    rp.pr.enabled = false; /* one progress line: frames */
    exr_image ref = {0}, prev_ref = {0};
    /* The band-limited reference of the frame for each ring layout (metrics_band_limit): R, G, B,
     * coverage planes; made once per frame and layout, shared by that layout's configurations. */
    size_t band_n = (size_t)s.pl.width * (size_t)s.pl.height;
    float *band_buf = st == FS_OK ? malloc(sizeof(float) * 12 * band_n) : NULL;
    if (st == FS_OK && !band_buf)
        st = FS_ERR_NOMEM;
    metrics_view bands[3] = {{0}};
    float *flip_map = st == FS_OK ? malloc(sizeof(float) * band_n) : NULL; /* each configuration's FLIP map */
    if (st == FS_OK && !flip_map)
        st = FS_ERR_NOMEM;
    temporal te = {0};
    double prev_err = 0.0; /* the previous measured frame's reference error estimate */
    if (st == FS_OK)
        st = temporal_begin(&te, &s);
    bool have_prev_ref = false;
    for (int i = 0; i < n + warm && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        bool measured = i >= warm;
        frame_record base = session_frame(&s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
        display_desc disp = {s.pl.width, s.pl.height, base.hfov_deg};
        reference_info ri;
        ring_mask mask = {0};
        bool band_done[3] = {false, false, false}; /* per k_band_slot */
        if (measured) {
            st = reference_frame(rf, &base, &ref, &ri);
            if (st == FS_OK)
                st = ring_mask_build(&disp, &ml, base.gaze_px[0], base.gaze_px[1], &mask);
        }
        metrics_view vr = measure_view(&ref), vpr = measure_view(&prev_ref);
        if (measured && st == FS_OK) /* this frame's depth and the previous reference warped into it */
            st = temporal_frame(&te, &base, have_prev_ref && !base.cut ? &vpr : NULL);
        for (int c = 0; c < nc && st == FS_OK; c++) {
            mode_run *mr = &cfg[c].run;
            frame_record fr = base;
            frame_record_set_gaze(&fr, &mr->pl.layout, &disp, base.gaze[0], base.gaze[1]);
            renderer_finish(mr->r);
            proc_stats p0 = proc_stats_now();
            double a = time_now();
            st = renderer_draw(mr->r, &fr);
            renderer_finish(mr->r);
            double ms = (time_now() - a) * 1e3;
            proc_stats pd = proc_stats_since(p0);
            renderer_stats rs = renderer_last_stats(mr->r); /* also when not measured: the queries are done */
            if (!measured || st != FS_OK)
                continue;
            mr->frame_ms[i - warm] = ms;
            const double counts[ACC_COUNTS] = {pd.cpu_ms, (double)pd.minor_faults, (double)rs.vs_invocations,
                                               (double)rs.primitives, (double)rs.fragments};
            for (int q = 0; q < ACC_COUNTS; q++)
                cfg[c].counts[q][i - warm] = counts[q];
            st = renderer_read(mr->r, &mr->img);
            ring_metrics rm[MAX_FOV_RINGS + 1] = {0};
            metrics_view vi = measure_view(&mr->img), vp = measure_view(&mr->prev);
            bool prev = mr->have_prev && have_prev_ref && !fr.cut;
            int l = k_band_slot[cfg[c].layout];
            if (st == FS_OK && !band_done[l]) {
                float *b = band_buf + (size_t)(4 * l) * band_n;
                float *const planes[4] = {b, b + band_n, b + 2 * band_n, b + 3 * band_n};
                st = metrics_band_limit(&vr, &disp, &mr->pl.layout, fr.ring_rect, fr.gaze_px[0], fr.gaze_px[1], planes,
                                        &bands[l]);
                band_done[l] = true;
            }
            metrics_view vb = bands[l];
            if (st == FS_OK)
                st = measure_flip(&vi, &vr, &disp, flip_map);
            if (st == FS_OK)
                st = metrics_compute(&vi, &vr, &vb, flip_map, prev ? &vp : NULL, &mask, rm);
            if (st == FS_OK)
                st = temporal_measure(&te, &vi, prev ? &vp : NULL, &vr, &mask,
                                      temporal_reference_noise2(rf, temporal_still(&te, &base), ri.error, prev_err), rm);
            measure_accumulate(mr, rm, ml.count, measured && temporal_still(&te, &base));
            exr_image_free(&mr->prev);
            mr->prev = mr->img;
            memset(&mr->img, 0, sizeof mr->img);
            mr->have_prev = true;
        }
        ring_mask_free(&mask);
        if (measured) {
            temporal_next(&te, &base);
            prev_err = ri.error;
            exr_image_free(&prev_ref);
            prev_ref = ref;
            memset(&ref, 0, sizeof ref);
            have_prev_ref = true;
        }
        progress_update(&pr, i + 1);
    }
    progress_end(&pr);

    /* Report: CSV, Markdown, gnuplot. Base of the speedups: full-resolution traditional, TAA off
     * (else the first configuration). */
    char *csv = NULL, *md = NULL;
    double *tx = NULL, *ey = NULL, *fx = NULL;
    bool *front = NULL, *front_fs = NULL;
    int *row_at = NULL; /* where configuration c's row starts in csv (nc + 1 entries) */
    if (st == FS_OK) {
        row_at = calloc((size_t)nc + 1, sizeof *row_at);
        csv = malloc(1 << 16);
        md = malloc(1 << 16);
        tx = calloc((size_t)nc, sizeof *tx);
        ey = calloc((size_t)nc, sizeof *ey);
        fx = calloc((size_t)nc, sizeof *fx);
        front = calloc((size_t)nc, sizeof *front);
        front_fs = calloc((size_t)nc, sizeof *front_fs);
        if (!csv || !md || !tx || !ey || !fx || !front || !front_fs || !row_at)
            st = FS_ERR_NOMEM;
    }
    if (st == FS_OK) {
        int base = 0;
        for (int c = 0; c < nc; c++) {
            double *v = cfg[c].run.frame_ms;
            qsort(v, (size_t)n, sizeof *v, stats_cmp_double);
            cfg[c].med = stats_quantile(v, n, 0.5);
            cfg[c].p10 = stats_quantile(v, n, 0.1);
            cfg[c].p90 = stats_quantile(v, n, 0.9);
            if (cfg[c].run.mode == ALPHA_MODE_TRADITIONAL && cfg[c].layout == ACC_OFF && !cfg[c].taa)
                base = c;
            for (int q = 0; q < ACC_COUNTS; q++) {
                double *u = cfg[c].counts[q];
                qsort(u, (size_t)n, sizeof *u, stats_cmp_double);
                cfg[c].count_med[q] = u[0] < 0 ? -1.0 : stats_quantile(u, n, 0.5); /* -1: unknown */
            }
            tx[c] = cfg[c].med;
            fx[c] = cfg[c].count_med[ACC_FS];
            const mode_run *er = &cfg[c].run; /* the error of --error, over the whole display */
            if (d->bench.error == ACC_ERROR_TEMPORAL) {
                ey[c] = measure_mean_or(er->te_sum[ml.count], er->te_n[ml.count], 0.0);
            } else {
                const double *esum = d->bench.error == ACC_ERROR_FLIP         ? er->flip_sum
                                     : d->bench.error == ACC_ERROR_ALPHA_RMSE ? er->alpha_rmse_sum
                                     : er->rmse_sum;
                ey[c] = measure_mean_or(esum[ml.count], er->err_n[ml.count], 0.0);
            }
        }
        pareto(tx, ey, nc, front);
        bool have_fs = nc > 0;
        for (int c = 0; c < nc; c++)
            have_fs = have_fs && fx[c] >= 0;
        if (have_fs)
            pareto(fx, ey, nc, front_fs);
        char cpu[256], rings[256], aggr[256];
        session_cpu_name(cpu, sizeof cpu);
        fov_layout_format(&layouts[ACC_DEFAULT], rings, sizeof rings);
        fov_layout_format(&layouts[ACC_AGGRESSIVE], aggr, sizeof aggr);
        int oc = 0, om = 0;
#define CSV(...) oc += snprintf(csv + oc, (1 << 16) - (size_t)oc, __VA_ARGS__)
#define MD(...) om += snprintf(md + om, (1 << 16) - (size_t)om, __VA_ARGS__)
        CSV("mode,rings,taa,frame_ms_median,frame_ms_p10,frame_ms_p90,speedup,rmse,psnr,temporal_error,pareto");
        for (int q = 0; q < ACC_COUNTS; q++)
            CSV(",%s", k_acc_count_columns[q]);
        CSV(",pareto_fragments");
        for (int k = 0; k < ml.count; k++)
            CSV(",coverage_ratio_ring%d", k);
        CSV(",alpha_rmse");
        for (int k = 0; k < ml.count; k++)
            CSV(",alpha_rmse_ring%d", k);
        CSV(",flip");
        for (int k = 0; k < ml.count; k++)
            CSV(",flip_ring%d", k);
        CSV("\n");
        MD("### Accuracy vs time: %s, %dx%d\n\n", s.sc.path, s.pl.width, s.pl.height);
        MD("- machine: %s (%ld cores online); renderer: %s\n", cpu, sysconf(_SC_NPROCESSORS_ONLN), gl_device_renderer());
        MD("- %d frames measured after %d warm-up frames (consecutive, %g fps); gaze: %s\n", n, warm, d->fps,
           s.gaze.count ? s.gaze.path : "fixation at the centre");
        MD("- rings: default %s; aggressive %s; measured in the default rings\n", rings, aggr);
        if (use_layout[ACC_DEFAULT_LOD]) {
            char spec[160];
            ring_lod_format(&lod, spec, sizeof spec);
            MD("- default+lod: the default rings with ring LOD %s, keep fraction u = %s per ring (the other rows "
               "without ring LOD; the reference never simplified)\n", spec, lod_u);
        }
        MD("- reference: %s\n", reference_describe(rf));
        MD("- speedup: median frame time of traditional, full resolution, TAA off / this one's; * = on the "
           "Pareto front of (time, %s) (--error)\n", k_error_names[d->bench.error]);
        MD("- CPU ms: process CPU time of the draw, all threads; frag./px: fragment-shader invocations per display "
           "pixel (GL_ARB_pipeline_statistics_query; medians per frame)\n");
        MD("- cov. ring K: the mode's coverage summed over the frames / the reference's (n/a where the reference "
           "holds under %g ring texels of coverage)\n\n", METRICS_MIN_REF_TEXELS);
        MD("| mode | rings | TAA | frame ms (p10-p90) | speedup | RMSE | %s | temporal err. | CPU ms | frag./px |",
           d->bench.error == ACC_ERROR_RMSE ? "PSNR" : k_error_names[d->bench.error]);
        for (int k = 0; k < ml.count; k++)
            MD(" cov. ring %d |", k);
        MD("\n|---|---|---|---|---|---|---|---|---|---|");
        for (int k = 0; k < ml.count; k++)
            MD("---|");
        MD("\n");
        for (int c = 0; c < nc; c++) {
            const mode_run *mr = &cfg[c].run;
            int all = ml.count;
            double rmse = measure_mean_or(mr->rmse_sum[all], mr->err_n[all], 0.0), psnr = measure_mean_or(mr->psnr_sum[all], mr->err_n[all], 0.0),
                   fl = measure_mean_or(mr->te_sum[all], mr->te_n[all], -1.0), sp = cfg[base].med / cfg[c].med;
            const double *cm = cfg[c].count_med;
            row_at[c] = oc;
            CSV("%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.6f,%.3f,%.6f,%d", alpha_mode_name(mr->mode),
                k_layout_names[cfg[c].layout], cfg[c].taa ? "on" : "off", cfg[c].med, cfg[c].p10, cfg[c].p90, sp,
                rmse, psnr, fl, front[c]);
            CSV(",%.4f,%.0f,%.0f,%.0f,%.0f,%d", cm[ACC_CPU], cm[ACC_FAULTS], cm[ACC_VS], cm[ACC_PRIMS], cm[ACC_FS],
                front_fs[c]);
            MD("| %s%s | %s | %s | %.2f (%.2f-%.2f) | %.2fx | %.4f | %.4f | %.4f | %.2f |", alpha_mode_name(mr->mode),
               front[c] ? " *" : "", k_layout_names[cfg[c].layout], cfg[c].taa ? "on" : "off", cfg[c].med,
               cfg[c].p10, cfg[c].p90, sp, rmse, d->bench.error == ACC_ERROR_RMSE ? psnr : ey[c], fl, cm[ACC_CPU]);
            if (cm[ACC_FS] >= 0)
                MD(" %.2f |", cm[ACC_FS] / ((double)s.pl.width * s.pl.height));
            else
                MD(" n/a |");
            for (int k = 0; k < ml.count; k++) {
                /* The ratio of the coverage summed over frames, -1 (n/a) where the reference holds
                 * too little in the ring (measure_coverage_ratio). The texels are the measurement
                 * rings' (the default layout's) for every row: the reference is the same for all. */
                double r = measure_coverage_ratio(mr, k, measure_block(&ml, k));
                CSV(",%.4f", r);
                if (r < 0.0)
                    MD(" n/a |");
                else
                    MD(" %.2f |", r);
            }
            for (int k = 0; k <= ml.count; k++) /* the whole display, then each ring */
                CSV(",%.6f", measure_mean_or(mr->alpha_rmse_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
            for (int k = 0; k <= ml.count; k++)
                CSV(",%.6f", measure_mean_or(mr->flip_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
            CSV("\n");
            MD("\n");
        }
        row_at[nc] = oc;
        if (oc >= 1 << 16) {
            log_error("%s/accuracy.csv: longer than the %d bytes it may take (too many modes?)", out, 1 << 16);
            st = FS_ERR_INTERNAL;
        }
#undef CSV
#undef MD
        char path[1200];
        snprintf(path, sizeof path, "%s/accuracy.csv", out);
        if (st == FS_OK)
            st = out_write_atomic(path, csv);
        snprintf(path, sizeof path, "%s/accuracy.md", out);
        if (st == FS_OK)
            st = out_write_atomic(path, md);
        if (st == FS_OK && d->bench.markdown) {
            FILE *f = fopen(d->bench.markdown, "a");
            if (!f || fprintf(f, "\n%s", md) < 0 || fclose(f) != 0) {
                log_error("%s: cannot append the accuracy table: %s", d->bench.markdown, strerror(errno));
                st = FS_ERR_IO;
            }
        }
        char title[600], x_expr[64];
        /* The whole-display column of the chosen error in accuracy.csv: rmse is column 8,
         * temporal_error 10; after the 17 fixed columns come N coverage ratios, alpha_rmse and its
         * N rings, flip and its N. */
        int y_col = d->bench.error == ACC_ERROR_TEMPORAL     ? 10
                    : d->bench.error == ACC_ERROR_RMSE       ? 8
                    : d->bench.error == ACC_ERROR_ALPHA_RMSE ? 18 + ml.count
                                        : 19 + 2 * ml.count;
        if (st == FS_OK) {
            snprintf(title, sizeof title, "accuracy vs time: %s %dx%d (%s)", s.sc.path, s.pl.width, s.pl.height,
                     gl_device_renderer());
            st = plot_accuracy(out, "accuracy", title, "frame time, median (ms)", "4", y_col, k_error_labels[d->bench.error],
                               tx, front, csv, row_at, nc, modes, nmodes, use_layout);
        }
        /* Accuracy vs fragment work: what transfers to a GPU, where wall time on llvmpipe does not. */
        snprintf(path, sizeof path, "%s/accuracy-fragments.png", out);
        if (st == FS_OK && have_fs) {
            snprintf(title, sizeof title, "accuracy vs fragment work: %s %dx%d", s.sc.path, s.pl.width, s.pl.height);
            snprintf(x_expr, sizeof x_expr, "($16/%d.0)", s.pl.width * s.pl.height);
            st = plot_accuracy(out, "accuracy-fragments", title,
                               "fragment-shader invocations per display pixel, median per frame", x_expr, y_col,
                               k_error_labels[d->bench.error], fx, front_fs, csv, row_at, nc, modes, nmodes,
                               use_layout);
        } else if (st == FS_OK) {
            unlink(path); /* not one from an earlier run beside this run's CSV */
            log_warn("no GL_ARB_pipeline_statistics_query: fragment counts unknown, %s not drawn", path);
        }
        if (st == FS_OK) {
            fputs(md, stdout);
            printf("\nwrote %s/accuracy.csv, accuracy.md, accuracy.png%s\n", out,
                   have_fs ? " and accuracy-fragments.png" : "");
        }
    }
    free(csv);
    free(md);
    free(tx);
    free(ey);
    free(fx);
    free(front);
    free(front_fs);
    free(row_at);
    exr_image_free(&ref);
    exr_image_free(&prev_ref);
    free(band_buf);
    free(flip_map);
    temporal_end(&te);
    for (int c = 0; c < nc; c++) {
        exr_image_free(&cfg[c].run.img);
        exr_image_free(&cfg[c].run.prev);
        free(cfg[c].run.frame_ms);
        for (int q = 0; q < ACC_COUNTS; q++)
            free(cfg[c].counts[q]);
        renderer_destroy(cfg[c].run.r);
    }
    free(cfg);
    reference_destroy(rf);
    session_end(&s);
    return st;
}
