/* compare.c: `fovsim compare` and `fovsim demo`: every alpha mode drawn with the same camera, gaze,
 * jitter and seeds, measured against the reference per frame and ring, written as two-part EXR
 * frames (a grid to look at, layers to analyse), a metrics CSV, a JSON summary and a table. */
#include "commands/commands.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "core/spawn.h"
#include "core/proc_stats.h"
#include "gl/gl_device.h"
#include "metrics/metrics.h"
#include "output/fvvdp_export.h"
#include "output/out_path.h"
#include "session/run_record.h"
#include "commands/measure.h"
#include "session/session.h"

/* >>frame image */

/* Heat colour of t in [0, 1]: black, red, yellow, white (linear). */
static void heat(float t, float rgb[3])
{
    t = isfinite(t) ? fminf(fmaxf(t, 0.0f), 1.0f) : 1.0f;
    rgb[0] = fminf(3.0f * t, 1.0f);
    rgb[1] = fminf(fmaxf(3.0f * t - 1.0f, 0.0f), 1.0f);
    rgb[2] = fminf(fmaxf(3.0f * t - 2.0f, 0.0f), 1.0f);
}

/* Per-pixel RMS over linear RGB of a - b (planes R, G, B of each). */
static float pixel_error(const float *const a[3], const float *const b[3], size_t i)
{
    double s = 0;
    for (int c = 0; c < 3; c++) {
        double d = (double)a[c][i] - (double)b[c][i];
        s += isfinite(d) ? d * d : 0.0;
    }
    return (float)sqrt(s / 3.0);
}

/* Copies a w x h picture into grid cell (col, row) of the grid's R, G, B (A = 1). `rgb` NULL:
 * the cell shows value v as grey. */
static void put_cell(exr_image *grid, int col, int row, int w, int h, const float *const rgb[3], const float *grey)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++) {
        float *dst = exr_image_channel(grid, names[c]);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                size_t s = (size_t)y * (size_t)w + (size_t)x;
                size_t d = ((size_t)row * (size_t)h + (size_t)y) * (size_t)grid->width + (size_t)col * (size_t)w + (size_t)x;
                dst[d] = c == 3 ? 1.0f : rgb ? rgb[c][s] : grey[s];
            }
    }
}

/* The two-part comparison frame: part "compare" (grid: row 0 each mode then the reference, row 1
 * each mode's error heat map then the reference's coverage), part "layers". Takes nothing over:
 * copies planes. */
static fs_status build_frame(const mode_run *runs, int nm, const exr_image *ref, const ring_mask *mask,
                             exr_image *out)
{
    int w = ref->width, h = ref->height, cols = nm + 1;
    size_t n = (size_t)w * (size_t)h;
    exr_image layers;
    if (!exr_image_init(out, w * cols, h * 2) || !exr_image_init(&layers, w, h))
        return FS_ERR_NOMEM;
    exr_image_set_part_name(out, "compare");
    exr_image_set_part_name(&layers, "layers");
    static const char *const rgba[5] = {"R", "G", "B", "A", "coverage"};
    bool ok = true;
    for (int c = 0; c < 4 && ok; c++)
        ok = exr_image_add_channel(out, rgba[c]) != NULL;
    float *hr = malloc(3 * n * sizeof *hr); /* one heat map at a time, planar R, G, B */
    ok = ok && hr;
    const float *ref_rgb[3] = {exr_image_channel(ref, "R"), exr_image_channel(ref, "G"), exr_image_channel(ref, "B")};
    for (int m = 0; m <= nm && ok; m++) {
        const exr_image *src = m < nm ? &runs[m].img : ref;
        const char *name = m < nm ? alpha_mode_name(runs[m].mode) : "reference";
        for (int c = 0; c < 5 && ok; c++) {
            char ch[64];
            snprintf(ch, sizeof ch, "%s.%s", name, rgba[c]);
            float *p = exr_image_add_channel(&layers, ch);
            ok = p != NULL;
            if (ok)
                memcpy(p, exr_image_channel(src, rgba[c]), n * sizeof *p);
        }
        if (!ok)
            break;
        const float *pic[3] = {exr_image_channel(src, "R"), exr_image_channel(src, "G"), exr_image_channel(src, "B")};
        put_cell(out, m, 0, w, h, pic, NULL);
        if (m == nm) {
            put_cell(out, m, 1, w, h, NULL, exr_image_channel(ref, "coverage"));
            break;
        }
        char ch[64];
        snprintf(ch, sizeof ch, "%s.error", name);
        float *e = exr_image_add_channel(&layers, ch);
        snprintf(ch, sizeof ch, "%s.flip", name);
        float *fl = e ? exr_image_add_channel(&layers, ch) : NULL;
        ok = e && fl;
        /* Row 1 shows the FLIP map (white = 1, the largest difference); the RMS error stays a layer. */
        for (size_t i = 0; i < n && ok; i++) {
            e[i] = pixel_error(pic, ref_rgb, i);
            fl[i] = runs[m].flip[i];
            float rgb[3];
            heat(fl[i], rgb);
            for (int c = 0; c < 3; c++)
                hr[(size_t)c * n + i] = rgb[c];
        }
        const float *hp[3] = {hr, hr + n, hr + 2 * n};
        if (ok)
            put_cell(out, m, 1, w, h, hp, NULL);
    }
    float *ring = ok ? exr_image_add_channel(&layers, "ring.id") : NULL;
    ok = ok && ring;
    for (size_t i = 0; i < n && ok; i++)
        ring[i] = (float)mask->ring[i];
    free(hr);
    if (ok)
        ok = exr_image_append_part(out, &layers);
    if (!ok) {
        exr_image_free(&layers);
        exr_image_free(out);
        return FS_ERR_NOMEM;
    }
    return FS_OK;
}

static void frame_attrs(exr_image *img, const session *s, const frame_record *fr, const mode_run *runs, int nm,
                        const reference *rf, const reference_info *ri)
{
    session_frame_attrs(img, s, fr);
    char buf[512];
    int o = snprintf(buf, sizeof buf, "%d columns x 2 rows of %dx%d tiles; row 0:", nm + 1, s->pl.width, s->pl.height);
    for (int m = 0; m < nm; m++)
        o += snprintf(buf + o, sizeof buf - (size_t)o, " %s |", alpha_mode_name(runs[m].mode));
    o += snprintf(buf + o, sizeof buf - (size_t)o, " reference; row 1: the LDR-FLIP map of each mode against the "
                  "reference (white = 1) | reference coverage");
    exr_image_set_string(img, "fovsim:grid", buf);
    o = 0;
    for (int m = 0; m < nm; m++)
        o += snprintf(buf + o, sizeof buf - (size_t)o, "%s%s", m ? "," : "", alpha_mode_name(runs[m].mode));
    exr_image_set_string(img, "fovsim:modes", buf);
    exr_image_set_string(img, "fovsim:alpha_mode", buf);
    snprintf(buf, sizeof buf, "%s; estimated error %.5f; key %016llx", reference_describe(rf), ri->error,
             (unsigned long long)ri->key);
    exr_image_set_string(img, "fovsim:reference", buf);
    exr_image_set_string(img, "fovsim:layers",
                         "part 'layers': <mode>.R/G/B/A (linear premultiplied), <mode>.coverage, <mode>.error (RMS "
                         "over RGB vs the reference), <mode>.flip (LDR-FLIP vs the reference), "
                         "reference.R/G/B/A/coverage, ring.id (measurement ring)");
}

/* >>report */

typedef struct report_desc {
    const session *s;
    const mode_run *runs;
    int mode_count, frames;
    const fov_layout *layout; /* measurement rings */
    const fov_layout *blocks; /* the rings' texel sizes for the coverage rule: layout when the run is
                               * foveated, NULL (full resolution) when not */
    const reference *ref;
    double *ref_err;          /* per measured frame (sorted here) */
    int first;                /* the first measured frame (--first-frame): frame_ms[first..] */
    int ref_cached;
    const char *out, *json_path;
    double seconds;
    const double *jod;        /* per mode, FovVideoVDP's JOD (--fvvdp); NULL when it did not run */
} report_desc;

static void ring_label(const fov_layout *l, int k, char *buf, size_t n)
{
    if (k == l->count)
        snprintf(buf, n, "all");
    else if (isinf(l->rings[k].outer_deg))
        snprintf(buf, n, "%d: >%.1f deg", k, k ? (double)l->rings[k - 1].outer_deg : 0.0);
    else
        snprintf(buf, n, "%d: %.1f-%.1f deg", k, k ? (double)l->rings[k - 1].outer_deg : 0.0,
                 (double)l->rings[k].outer_deg);
}

/* Prints the table and writes summary.json (atomically). */
static fs_status report(const report_desc *r)
{
    const session *s = r->s;
    int nm = r->mode_count, nr = r->layout->count;
    double med[ALPHA_MODE_COUNT];
    for (int m = 0; m < nm; m++) {
        double *v = malloc(sizeof(double) * (size_t)r->frames);
        if (!v)
            return FS_ERR_NOMEM;
        memcpy(v, r->runs[m].frame_ms + r->first, sizeof(double) * (size_t)r->frames);
        qsort(v, (size_t)r->frames, sizeof *v, stats_cmp_double);
        med[m] = stats_quantile(v, r->frames, 0.5);
        free(v);
    }
    qsort(r->ref_err, (size_t)r->frames, sizeof *r->ref_err, stats_cmp_double);
    char rings[256], mrings[256];
    fov_layout_format(&s->pl.layout, rings, sizeof rings);
    fov_layout_format(r->layout, mrings, sizeof mrings);
    printf("\ncompared %d modes over %d frames (%dx%d, rings %s, TAA %s) in %.1f s; frames in %s/\n", nm, r->frames,
           s->pl.width, s->pl.height, rings, s->pl.taa ? "on" : "off", r->seconds, r->out);
    printf("reference: %s, %d of %d frames from the cache, estimated error median %.5f\n", reference_describe(r->ref),
           r->ref_cached, r->frames, stats_quantile(r->ref_err, r->frames, 0.5));
    printf("measured in rings %s (eccentricity from each frame's gaze); coverage: the ratio of the coverage summed "
           "over frames, resting on the reference's coverage in display pixels (ref px; n/a below %g ring texels); "
           "the rest means over frames\n\n", mrings, METRICS_MIN_REF_TEXELS);
    printf("%-12s %-18s %10s %11s %10s %10s %8s %8s %10s %9s\n", "mode", "ring", "coverage", "ref px", "RMSE",
           "alpha RMSE", "FLIP", "PSNR", "temporal", "static");
    printf("%-12s %-18s %10s %11s %10s %10s %8s %8s %10s %9s\n", "", "", "/ reference", "(summed)", "(linear)",
           "(band-lim.)", "(mean)", "(dB)", "error", "flicker");
    for (int m = 0; m < nm; m++)
        for (int k = 0; k <= nr; k++) {
            const mode_run *mr = &r->runs[m];
            char label[48];
            ring_label(r->layout, k, label, sizeof label);
            /* -1: not measured (no frame with a warped previous one; no frame with a still camera;
             * too little reference coverage for a ratio) */
            double te = measure_mean_or(mr->te_sum[k], mr->te_n[k], -1.0), sf = measure_mean_or(mr->still_sum[k], mr->still_n[k], -1.0);
            double cr = measure_coverage_ratio(mr, k, measure_block(r->blocks, k));
            char tes[32], sfs[32], crs[32];
            snprintf(tes, sizeof tes, te < 0.0 ? "n/a" : "%.4f", te);
            snprintf(sfs, sizeof sfs, sf < 0.0 ? "n/a" : "%.4f", sf);
            snprintf(crs, sizeof crs, cr < 0.0 ? "n/a" : "%.3f", cr);
            printf("%-12s %-18s %10s %11.0f %10.4f %10.4f %8.4f %8.2f %10s %9s\n", k == 0 ? alpha_mode_name(mr->mode) : "",
                   label, crs, mr->ref_px[k], measure_mean_or(mr->rmse_sum[k], mr->err_n[k], 0.0),
                   measure_mean_or(mr->alpha_rmse_sum[k], mr->err_n[k], 0.0), measure_mean_or(mr->flip_sum[k], mr->err_n[k], 0.0),
                   measure_mean_or(mr->psnr_sum[k], mr->err_n[k], 0.0), tes, sfs);
        }
    printf("\n%-12s %14s %10s%s\n", "mode", "frame ms (med)", "relative", r->jod ? "  FovVideoVDP JOD" : "");
    for (int m = 0; m < nm; m++) {
        printf("%-12s %14.2f %9.2fx", alpha_mode_name(r->runs[m].mode), med[m], med[m] / med[0]);
        if (r->jod)
            printf("  %16.4f", r->jod[m]);
        printf("\n");
    }

    char tmp[1300];
    FILE *f = out_path_temp_name(r->json_path, tmp, sizeof tmp) ? fopen(tmp, "w") : NULL;
    if (!f) {
        log_error("%s: cannot create: %s", tmp, strerror(errno));
        return FS_ERR_IO;
    }
    fprintf(f, "{\n  \"scene\": \"%s\",\n  \"width\": %d,\n  \"height\": %d,\n  \"frames\": %d,\n", s->sc.path,
            s->pl.width, s->pl.height, r->frames);
    fprintf(f, "  \"rings\": \"%s\",\n  \"measurement_rings\": \"%s\",\n  \"taa\": %s,\n  \"gaze\": \"%s\",\n", rings,
            mrings, s->pl.taa ? "true" : "false", s->gaze.count ? s->gaze.path : "centre");
    fprintf(f, "  \"renderer\": \"%s\",\n  \"reference\": {\"kind\": \"%s\", \"supersample\": %d, \"samples\": %d, "
            "\"error_median\": %.6f, \"error_max\": %.6f, \"frames_from_cache\": %d},\n  \"modes\": [\n",
            gl_device_renderer(), reference_kind_name(reference_get_kind(r->ref)), reference_supersample(r->ref),
            reference_samples(r->ref),
            stats_quantile(r->ref_err, r->frames, 0.5), r->ref_err[r->frames - 1], r->ref_cached);
    for (int m = 0; m < nm; m++) {
        const mode_run *mr = &r->runs[m];
        fprintf(f, "    {\"mode\": \"%s\", \"frame_ms_median\": %.4f, \"relative_time\": %.4f, ",
                alpha_mode_name(mr->mode), med[m], med[m] / med[0]);
        if (r->jod && isfinite(r->jod[m]))
            fprintf(f, "\"fvvdp_jod\": %.6f, ", r->jod[m]);
        fprintf(f, "\"rings\": [");
        for (int k = 0; k <= nr; k++) {
            double outer = k < nr && !isinf(r->layout->rings[k].outer_deg) ? r->layout->rings[k].outer_deg : -1.0;
            int block = measure_block(r->blocks, k);
            fprintf(f, "%s\n      {\"ring\": %d, \"outer_deg\": %.3f, \"coverage_ratio\": %.5f, \"coverage_px\": %.3f, "
                    "\"ref_coverage_px\": %.3f, \"ratio_min_ref_px\": %.0f, \"rmse\": %.6f, "
                    "\"alpha_rmse\": %.6f, \"flip\": %.6f, \"psnr\": %.3f, \"temporal_error\": %.6f, "
                    "\"static_flicker\": %.6f, \"frames_measured\": %d, \"temporal_error_frames\": %d, "
                    "\"static_flicker_frames\": %d}",
                    k ? "," : "", k < nr ? k : -1, outer, measure_coverage_ratio(mr, k, block), mr->cov_px[k],
                    mr->ref_px[k], METRICS_MIN_REF_TEXELS * block * block,
                    measure_mean_or(mr->rmse_sum[k], mr->err_n[k], 0.0), measure_mean_or(mr->alpha_rmse_sum[k], mr->err_n[k], 0.0),
                    measure_mean_or(mr->flip_sum[k], mr->err_n[k], 0.0),
                    measure_mean_or(mr->psnr_sum[k], mr->err_n[k], 0.0), measure_mean_or(mr->te_sum[k], mr->te_n[k], -1.0),
                    measure_mean_or(mr->still_sum[k], mr->still_n[k], -1.0), mr->err_n[k], mr->te_n[k], mr->still_n[k]);
        }
        fprintf(f, "]}%s\n", m + 1 < nm ? "," : "");
    }
    fprintf(f, "  ]\n}\n");
    if (fclose(f) != 0 || rename(tmp, r->json_path) != 0) {
        log_error("%s: cannot write: %s", r->json_path, strerror(errno));
        unlink(tmp);
        return FS_ERR_IO;
    }
    printf("\nmetrics per frame, ring and mode: %s/metrics.csv; summary: %s\n", r->out, r->json_path);
    return FS_OK;
}

/* >>run */

typedef struct compare_opts {
    const char *default_out;
    bool demo;
} compare_opts;

static fs_status compare_run(const run_desc *d, const compare_opts *co)
{
    session s;
    fs_status st = session_begin(d, &s, false);
    if (st != FS_OK)
        return st;
    mode_run runs[ALPHA_MODE_COUNT];
    memset(runs, 0, sizeof runs);
    int nm = 0;
    for (int m = 0; m < d->bench_mode_count; m++)
        runs[nm++].mode = d->bench_modes[m];
    if (nm == 0) {
        runs[nm++].mode = ALPHA_MODE_TRADITIONAL;
        runs[nm++].mode = ALPHA_MODE_HASHED;
    }
    int frames = session_frame_count(d, &s.sc);
    for (int m = 0; m < nm && st == FS_OK; m++) {
        run_desc dm = *d;
        dm.alpha = runs[m].mode;
        st = session_build_plan(&dm, &s.sc, &runs[m].pl);
        if (st == FS_OK)
            runs[m].r = renderer_create(&(renderer_desc){.scene = &s.sc, .plan = &runs[m].pl}, &st);
        if (st == FS_OK && !(runs[m].frame_ms = calloc((size_t)frames, sizeof(double))))
            st = FS_ERR_NOMEM;
        if (st == FS_OK && !(runs[m].flip = malloc(sizeof(float) * (size_t)runs[m].pl.width * (size_t)runs[m].pl.height)))
            st = FS_ERR_NOMEM;
    }
    ref_progress rp = {0};
    reference *rf = st == FS_OK ? session_reference(d, &s, &rp, &st) : NULL;
    const char *out = d->out_dir ? d->out_dir : co->default_out;
    char csv_path[1200], csv_tmp[1300], json_path[1200];
    snprintf(csv_path, sizeof csv_path, "%s/metrics.csv", out);
    bool csv_tmp_ok = out_path_temp_name(csv_path, csv_tmp, sizeof csv_tmp);
    snprintf(json_path, sizeof json_path, "%s/summary.json", out);
    run_folder fo = {0};
    /* A killed run's litter, another configuration's output, --resume (README "Output folders"): the metrics need
     * every frame's images, so a resumed compare draws every frame again and writes only the
     * frames it lacks; the reference of the frames drawn before comes from the cache. */
    if (st == FS_OK)
        st = run_folder_open(&fo, out, d, &s, frames);
    FILE *csv = NULL;
    if (st == FS_OK && !(csv = csv_tmp_ok ? fopen(csv_tmp, "w") : NULL)) {
        log_error("%s: cannot create: %s", csv_tmp, strerror(errno));
        st = FS_ERR_IO;
    }
    exr_writer *w = st == FS_OK ? exr_writer_create(&(exr_writer_desc){.compression = d->compression}) : NULL;
    if (st == FS_OK && !w)
        st = FS_ERR_NOMEM;
    if (csv)
        metrics_csv_header(csv);
    /* --export-fvvdp: every mode's sequence and the reference's, for the user's FovVideoVDP. */
    const char *seq_names[ALPHA_MODE_COUNT + 1];
    for (int m = 0; m < nm; m++)
        seq_names[m] = alpha_mode_name(runs[m].mode);
    seq_names[nm] = "reference";
    fvvdp_export *fx = NULL;
    if (st == FS_OK && d->compare.export_fvvdp)
        fx = fvvdp_export_begin(out, seq_names, nm + 1, s.pl.width, s.pl.height, s.pl.hfov_deg, d->fps, &st);
    fov_layout ml = measure_layout(&s.pl);
    double *ref_err = st == FS_OK ? calloc((size_t)frames, sizeof(double)) : NULL;
    if (st == FS_OK && !ref_err)
        st = FS_ERR_NOMEM;
    int passes = rf ? reference_pass_count(rf) : 0, done = 0, ref_cached = 0;
    exr_image ref = {0}, prev_ref = {0};
    /* The band-limited reference of the frame (metrics_band_limit): R, G, B, coverage planes. */
    size_t band_n = (size_t)s.pl.width * (size_t)s.pl.height;
    float *band_buf = st == FS_OK ? malloc(sizeof(float) * 4 * band_n) : NULL;
    if (st == FS_OK && !band_buf)
        st = FS_ERR_NOMEM;
    float *const band[4] = {band_buf, band_buf + band_n, band_buf + 2 * band_n, band_buf + 3 * band_n};
    temporal te = {0};
    if (st == FS_OK)
        st = temporal_begin(&te, &s);
    bool have_prev_ref = false;
    session_catch_sigint();
    rp.pr = progress_begin(co->demo ? "demo (reference passes)" : "compare (reference passes)",
                           (frames - (d->compare.first_frame < frames ? d->compare.first_frame : frames)) * passes, d->quiet);
    double t0 = time_now();
    /* --first-frame F (a chunk of a sweep): frames before F are drawn for the TAA history without
     * being measured or written, from `warm` on; the one just before F also gets its reference, the
     * previous frame of F's temporal metrics. */
    const int first = d->compare.first_frame < frames ? d->compare.first_frame : frames;
    int warm = first > 0 ? first - 1 : 0; /* the frame before F, at least */
    if (first > 0 && s.pl.taa) {
        int history = run_history_start(&s.sc, first, d->fps, s.pl.width, s.pl.height);
        if (d->bench.warmup_set && first - d->bench.warmup > history)
            history = first - d->bench.warmup;
        warm = history < warm ? history : warm;
    }
    for (int i = warm; i < frames && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        rp.base = (i < first ? 0 : i - first) * passes;
        frame_record fr = session_frame(&s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
        if (i < first - 1) { /* history only */
            for (int m = 0; m < nm && st == FS_OK; m++)
                st = renderer_draw(runs[m].r, &fr);
            continue;
        }
        const bool measured = i >= first;
        if (fr.cut) /* no frame-to-frame change across a cut */
            for (int m = 0; m < nm; m++)
                runs[m].have_prev = false;
        have_prev_ref = have_prev_ref && !fr.cut;
        for (int m = 0; m < nm && st == FS_OK; m++) {
            renderer_finish(runs[m].r);
            double a = time_now();
            st = renderer_draw(runs[m].r, &fr);
            renderer_finish(runs[m].r);
            runs[m].frame_ms[i] = (time_now() - a) * 1e3;
            if (st == FS_OK)
                st = renderer_read(runs[m].r, &runs[m].img);
        }
        reference_info ri;
        if (st == FS_OK)
            st = reference_frame(rf, &fr, &ref, &ri);
        if (st != FS_OK)
            break;
        ref_err[i] = ri.error;
        ref_cached += measured && ri.cached;
        display_desc dd = {s.pl.width, s.pl.height, fr.hfov_deg};
        ring_mask mask;
        st = ring_mask_build(&dd, &ml, fr.gaze_px[0], fr.gaze_px[1], &mask);
        metrics_view vr = measure_view(&ref), vpr = measure_view(&prev_ref), vb;
        /* The reference as the rings the modes were drawn with would show it (alpha_rmse). */
        if (st == FS_OK)
            st = metrics_band_limit(&vr, &dd, &s.pl.layout, fr.ring_rect, fr.gaze_px[0], fr.gaze_px[1], band, &vb);
        /* This frame's depth, and the previous reference warped into this frame (one warp for all). */
        if (st == FS_OK)
            st = temporal_frame(&te, &fr, have_prev_ref ? &vpr : NULL);
        bool still = temporal_still(&te, &fr);
        for (int m = 0; m < nm && st == FS_OK; m++) {
            ring_metrics rm[MAX_FOV_RINGS + 1] = {0};
            metrics_view vi = measure_view(&runs[m].img), vp = measure_view(&runs[m].prev);
            bool prev = runs[m].have_prev && have_prev_ref;
            st = measure_flip(&vi, &vr, &dd, runs[m].flip);
            if (st == FS_OK)
                st = metrics_compute(&vi, &vr, &vb, runs[m].flip, prev ? &vp : NULL, &mask, rm);
            if (st == FS_OK)
                st = temporal_measure(&te, &vi, prev ? &vp : NULL, &vr, &mask,
                                      temporal_reference_noise2(rf, still, ri.error, i > 0 ? ref_err[i - 1] : 0.0), rm);
            if (!measured)
                continue;
            measure_accumulate(&runs[m], rm, ml.count, still);
            measure_gate_ratios(rm, ml.count, s.pl.rings ? &ml : NULL); /* metrics.csv: -1 where too little reference */
            for (int k = 0; k <= ml.count && st == FS_OK; k++)
                if (!metrics_csv_row(csv, i, fr.time, alpha_mode_name(runs[m].mode), k < ml.count ? k : -1, &rm[k],
                                     still, runs[m].frame_ms[i])) {
                    log_error("%s: cannot write: %s", csv_tmp, strerror(errno));
                    st = FS_ERR_IO;
                }
        }
        if (st == FS_OK && fx && measured) {
            const exr_image *seq[ALPHA_MODE_COUNT + 1];
            for (int m = 0; m < nm; m++)
                seq[m] = &runs[m].img;
            seq[nm] = &ref;
            st = fvvdp_export_frame(fx, i, &fr, seq);
        }
        exr_image frame;
        if (st == FS_OK)
            st = build_frame(runs, nm, &ref, &mask, &frame);
        ring_mask_free(&mask);
        if (st != FS_OK)
            break;
        if (fo.kept[i] || !measured) {
            exr_image_free(&frame);
        } else {
            frame_attrs(&frame, &s, &fr, runs, nm, rf, &ri);
            char path[1200];
            snprintf(path, sizeof path, "%s/%s.%04d.exr", out, d->name, i);
            st = exr_writer_submit(w, path, &frame);
            done += st == FS_OK;
        }
        /* This frame becomes the previous one. */
        for (int m = 0; m < nm; m++) {
            exr_image_free(&runs[m].prev);
            runs[m].prev = runs[m].img;
            memset(&runs[m].img, 0, sizeof runs[m].img);
            runs[m].have_prev = true;
        }
        exr_image_free(&prev_ref);
        prev_ref = ref;
        memset(&ref, 0, sizeof ref);
        have_prev_ref = true;
        temporal_next(&te, &fr);
        progress_update(&rp.pr, (i + 1 - first) * passes);
    }
    progress_end(&rp.pr);
    if (w) {
        fs_status wst = exr_writer_finish(w);
        if (st == FS_OK)
            st = wst;
    }
    bool csv_bad = csv && ferror(csv);
    if (csv && (fclose(csv) != 0 || csv_bad) && st == FS_OK) {
        log_error("%s: cannot write: %s", csv_tmp, strerror(errno));
        st = FS_ERR_IO;
    }
    if (csv && st == FS_OK && rename(csv_tmp, csv_path) != 0) {
        log_error("%s: cannot rename to %s: %s", csv_tmp, csv_path, strerror(errno));
        st = FS_ERR_IO;
    }
    if (csv && st != FS_OK)
        unlink(csv_tmp);
    double el = time_now() - t0;
    if (fx) {
        fs_status fst = fvvdp_export_end(fx);
        if (st == FS_OK)
            st = fst;
    }
    double jod[ALPHA_MODE_COUNT + 1];
    bool have_jod = false;
    fs_status fvvdp_st = FS_OK; /* a failed FovVideoVDP run: the run's own results are still written */
    if (st == FS_OK && d->compare.run_fvvdp) {
        if (!fvvdp_available()) {
            sbuf cmd = {0};
            sb_puts(&cmd, "python3 ");
            char script[PATH_MAX + 32];
            snprintf(script, sizeof script, "%s/fvvdp/run_fvvdp.py", out);
            shell_quote(&cmd, script);
            printf("FovVideoVDP: pyfvvdp is not installed for the python3 on PATH (pip install pyfvvdp); its inputs "
                   "are in %s/fvvdp/, run %s once it is\n", out, cmd.p ? cmd.p : "");
            free(cmd.p);
        } else {
            fvvdp_st = fvvdp_run(out, seq_names, nm + 1, jod);
            have_jod = fvvdp_st == FS_OK;
        }
    }
    if (st == FS_OK)
        st = report(&(report_desc){.s = &s, .runs = runs, .mode_count = nm, .frames = frames - first,
                                   .first = first, .layout = &ml, .blocks = s.pl.rings ? &ml : NULL, .ref = rf, .ref_err = ref_err + first,
                                   .ref_cached = ref_cached, .out = out,
                                   .json_path = json_path, .seconds = el, .jod = have_jod ? jod : NULL});
    if (st == FS_OK)
        st = run_folder_complete(&fo);
    if (st == FS_OK)
        st = fvvdp_st;
    if (st == FS_OK && fo.kept_count)
        printf("resumed: kept %d complete frame%s of the earlier run; every frame was drawn again for the metrics "
               "and the TAA history, and only the missing ones written\n", fo.kept_count,
               fo.kept_count == 1 ? "" : "s");
    else if (st == FS_ERR_INTERRUPTED)
        log_error("interrupted after %d complete frames in %s (no partial frame was left; metrics.csv was not written; "
                  "--resume continues)", done + fo.kept_count, out);
    run_folder_close(&fo);
    exr_image_free(&ref);
    exr_image_free(&prev_ref);
    free(band_buf);
    for (int m = 0; m < nm; m++) {
        exr_image_free(&runs[m].img);
        exr_image_free(&runs[m].prev);
        free(runs[m].frame_ms);
        free(runs[m].flip);
        renderer_destroy(runs[m].r);
    }
    temporal_end(&te);
    free(ref_err);
    reference_destroy(rf);
    session_end(&s);
    return st;
}

fs_status cmd_compare(const run_desc *d)
{
    return compare_run(d, &(compare_opts){.default_out = "out/compare"});
}

/* The demo's size: small enough to finish in a few minutes on 2 cores with llvmpipe. */
#define DEMO_WIDTH 640
#define DEMO_HEIGHT 360

fs_status cmd_demo(const run_desc *d)
{
    run_desc dd = *d;
    if (!dd.gaze_path)
        dd.gaze_path = "builtin:demo_tour";
    if (!dd.width) {
        dd.width = DEMO_WIDTH;
        dd.height = DEMO_HEIGHT;
    }
    if (!dd.ref.supersample)
        dd.ref.supersample = DEMO_SUPERSAMPLE;
    if (!dd.ref.samples)
        dd.ref.samples = DEMO_SAMPLES;
    fs_status st = compare_run(&dd, &(compare_opts){.default_out = "out/demo", .demo = true});
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : "out/demo";
    /* The paths in these commands are shell-quoted: they are for copying into a shell. */
    char p0[PATH_MAX + 64], seq[PATH_MAX + 64], mp4[PATH_MAX + 16];
    snprintf(p0, sizeof p0, "%s/%s.0000.exr", out, d->name);
    snprintf(seq, sizeof seq, "%s/%s.%%04d.exr", out, d->name);
    snprintf(mp4, sizeof mp4, "%s/demo.mp4", out);
    sbuf a = {0}, b = {0}, c = {0};
    shell_quote(&a, p0);
    shell_quote(&b, seq);
    shell_quote(&c, mp4);
    printf("\nlook at it (part 0 of each frame is the side-by-side grid; part 'layers' has every image):\n"
           "  oiiotool --info -v %s                 # parts, layers, header attributes\n"
           "  ffmpeg -framerate %g -apply_trc iec61966_2_1 -i %s -pix_fmt yuv420p %s\n"
           "  oiiotool %s --subimage layers --ch hashed.coverage -o coverage.png\n",
           a.p ? a.p : "", d->fps, b.p ? b.p : "", c.p ? c.p : "", a.p ? a.p : "");
    free(a.p);
    free(b.p);
    free(c.p);
    return FS_OK;
}
