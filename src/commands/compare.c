/* compare.c: `fovsim compare` and `fovsim demo`: every alpha mode drawn with the same camera, gaze,
 * jitter and seeds, measured against the reference per frame and ring, written as two-part EXR
 * frames (a grid to look at, layers to analyse), a metrics CSV, a JSON summary and a table. */
#include "commands/commands.h"
#include "commands/compare_foveation.h"
#include "commands/compare_grid.h"
#include "commands/eyes.h"
#include "commands/compare_saccade.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
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
#include "output/grid_video.h"
#include "output/report_html.h"
#include "output/out_path.h"
#include "session/run_record.h"
#include "commands/look_hints.h"
#include "commands/measure.h"
#include "session/session.h"
#include "perf/cost_frame.h"

/* --previews unless given: enough frames to scrub through, a few MB per run at the demo's size. */
#define COMPARE_PREVIEWS 48
/* >>frame image */

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

/* The grid's inputs for this frame (compare_grid.h). */
static compare_grid_desc grid_of(const mode_run *runs, int nm, const exr_image *ref, const ring_mask *mask,
                                 const float gaze_px[2], bool annotate, alpha_mode modes[ALPHA_MODE_COUNT],
                                 const exr_image *images[ALPHA_MODE_COUNT], const float *flip[ALPHA_MODE_COUNT])
{
    for (int m = 0; m < nm; m++) {
        modes[m] = runs[m].mode;
        images[m] = &runs[m].img;
        flip[m] = runs[m].flip;
    }
    return (compare_grid_desc){.mode_count = nm, .modes = modes, .images = images, .flip = flip, .ref = ref,
                               .rings = mask ? mask->ring : NULL, .gaze_px = {gaze_px[0], gaze_px[1]},
                               .annotate = annotate};
}

/* The two-part comparison frame: part "compare" (the grid, compare_grid.h), part "layers" (every
 * image and map the metrics read, never annotated). Takes nothing over: copies planes. */
static fs_status build_frame(const mode_run *runs, int nm, const exr_image *ref, const ring_mask *mask,
                             const float gaze_px[2], bool annotate, exr_image *out)
{
    int w = ref->width, h = ref->height;
    size_t n = (size_t)w * (size_t)h;
    alpha_mode modes[ALPHA_MODE_COUNT];
    const exr_image *images[ALPHA_MODE_COUNT];
    const float *flips[ALPHA_MODE_COUNT];
    compare_grid_desc gd = grid_of(runs, nm, ref, mask, gaze_px, annotate, modes, images, flips);
    fs_status st = compare_grid_build(&gd, out);
    if (st != FS_OK)
        return st;
    exr_image layers;
    if (!exr_image_init(&layers, w, h)) {
        exr_image_free(out);
        return FS_ERR_NOMEM;
    }
    exr_image_set_part_name(&layers, "layers");
    static const char *const rgba[5] = {"R", "G", "B", "A", "coverage"};
    bool ok = true;
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
        if (!ok || m == nm)
            break;
        const float *pic[3] = {exr_image_channel(src, "R"), exr_image_channel(src, "G"), exr_image_channel(src, "B")};
        char ch[64];
        snprintf(ch, sizeof ch, "%s.error", name);
        float *e = exr_image_add_channel(&layers, ch);
        snprintf(ch, sizeof ch, "%s.flip", name);
        float *fl = e ? exr_image_add_channel(&layers, ch) : NULL;
        ok = e && fl;
        for (size_t i = 0; i < n && ok; i++) {
            e[i] = pixel_error(pic, ref_rgb, i);
            fl[i] = runs[m].flip[i];
        }
    }
    float *ring = ok ? exr_image_add_channel(&layers, "ring.id") : NULL;
    ok = ok && ring;
    for (size_t i = 0; i < n && ok; i++)
        ring[i] = (float)mask->ring[i];
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
                        const exr_image *ref, bool annotate, const reference *rf, const reference_info *ri)
{
    session_frame_attrs(img, s, fr);
    char buf[512];
    alpha_mode modes[ALPHA_MODE_COUNT];
    const exr_image *images[ALPHA_MODE_COUNT];
    const float *flips[ALPHA_MODE_COUNT];
    compare_grid_desc gd = grid_of(runs, nm, ref, NULL, fr->gaze_px, annotate, modes, images, flips);
    compare_grid_describe(&gd, buf, sizeof buf);
    exr_image_set_string(img, "fovsim:grid", buf);
    int o = 0;
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

/* What compare counts per mode and frame besides the frame time, from the renderer's statistics
 * (docs/benchmarks.md "Work counts"): primitives submitted, fragment-shader invocations and bytes
 * read + written (footprints), -1 = unknown; the frame time --cost-model predicts (-1: none); and,
 * from a counting frame (under VRS, and in a foveation study for every run), the invocations a
 * GPU would shade: covered fragments, under VRS coarse-shading invocations (-1: not counted, and
 * then absent from summary.json). */
enum { CMP_PRIMS, CMP_FS, CMP_BYTES, CMP_PREDICTED, CMP_SHADED, CMP_WORK };
static const char *const k_work_keys[CMP_WORK] = {"primitives_median", "fs_invocations_median", "bytes_median",
                                                  "predicted_frame_ms_median", "shaded_fragments_median"};

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
    double *const *work;      /* per mode: CMP_WORK values per frame (frame-major, all frames) */
    bool have_cm;             /* --cost-model given: the table shows the predicted time */
    const saccade_study *ss;  /* the gaze events and the post-saccade foveal error */
    double *med_out;          /* per mode: the median frame time, set here (NULL: not wanted) */
    double *shaded_out;       /* per mode: the median CMP_SHADED, -1 unknown, set here (NULL: not wanted) */
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

/* The run's headline and the table of each mode's metrics per ring and of its frame time. */
static void report_table(const report_desc *r, const double *med, double (*wmed)[CMP_WORK], const char *rings,
                         const char *mrings)
{
    const session *s = r->s;
    int nm = r->mode_count, nr = r->layout->count;
    char fov[256];
    plan_foveation_format(&s->pl, fov, sizeof fov); /* under VRS: its map, not the one full-resolution ring */
    printf("\ncompared %d modes over %d frames (%dx%d, %s%s, TAA %s) in %.1f s; frames in %s/\n", nm, r->frames,
           s->pl.width, s->pl.height, s->pl.vrs ? "" : "rings ", s->pl.vrs ? fov : rings, s->pl.taa ? "on" : "off",
           r->seconds, r->out);
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
    printf("\n%-12s %14s %10s%s%s\n", "mode", "frame ms (med)", "relative", r->have_cm ? "  predicted ms" : "",
           r->jod ? "  FovVideoVDP JOD" : "");
    for (int m = 0; m < nm; m++) {
        printf("%-12s %14.2f %9.2fx", alpha_mode_name(r->runs[m].mode), med[m], med[m] / med[0]);
        if (r->have_cm && wmed[m][CMP_PREDICTED] >= 0)
            printf("  %12.2f", wmed[m][CMP_PREDICTED]);
        else if (r->have_cm)
            printf("  %12s", "n/a");
        if (r->jod)
            printf("  %16.4f", r->jod[m]);
        printf("\n");
    }
    alpha_mode modes[ALPHA_MODE_COUNT];
    for (int m = 0; m < nm; m++)
        modes[m] = r->runs[m].mode;
    saccade_study_print(r->ss, modes, nm);
}

/* summary.json (written to a temporary name, then renamed into place). */
static fs_status report_json(const report_desc *r, const double *med, double (*wmed)[CMP_WORK], const char *rings,
                             const char *mrings)
{
    const session *s = r->s;
    int nm = r->mode_count, nr = r->layout->count;
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
    if (s->pl.vrs) { /* absent with rings: summaries read as before */
        char fov[256];
        plan_foveation_format(&s->pl, fov, sizeof fov);
        fprintf(f, "  \"foveation\": \"%s\",\n", fov);
    }
    if (!gaze_tracker_is_ideal(&s->tracker)) { /* absent without one: summaries read as before */
        char tr[160];
        gaze_tracker_format(&s->tracker, tr, sizeof tr);
        fprintf(f, "  \"gaze_tracker\": \"%s\",\n", tr);
    }
    saccade_study_json_events(r->ss, f);
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
        for (int q = 0; q < CMP_WORK; q++)
            if (q != CMP_SHADED || wmed[m][q] >= 0)
                fprintf(f, q == CMP_PREDICTED ? "\"%s\": %.4f, " : "\"%s\": %.0f, ", k_work_keys[q], wmed[m][q]);
        saccade_study_json_mode(r->ss, f, m);
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
    return FS_OK;
}

/* Prints the table and writes summary.json (atomically). */
static fs_status report(const report_desc *r)
{
    const session *s = r->s;
    int nm = r->mode_count;
    double med[ALPHA_MODE_COUNT], wmed[ALPHA_MODE_COUNT][CMP_WORK];
    for (int m = 0; m < nm; m++) {
        double *v = malloc(sizeof(double) * (size_t)r->frames);
        if (!v)
            return FS_ERR_NOMEM;
        memcpy(v, r->runs[m].frame_ms + r->first, sizeof(double) * (size_t)r->frames);
        qsort(v, (size_t)r->frames, sizeof *v, stats_cmp_double);
        med[m] = stats_quantile(v, r->frames, 0.5);
        for (int q = 0; q < CMP_WORK; q++) { /* -1 when any frame's is unknown */
            for (int i = 0; i < r->frames; i++)
                v[i] = r->work[m][(size_t)(r->first + i) * CMP_WORK + (size_t)q];
            qsort(v, (size_t)r->frames, sizeof *v, stats_cmp_double);
            wmed[m][q] = v[0] < 0 ? -1.0 : stats_quantile(v, r->frames, 0.5);
        }
        free(v);
    }
    for (int m = 0; m < nm && r->med_out; m++)
        r->med_out[m] = med[m];
    for (int m = 0; m < nm && r->shaded_out; m++)
        r->shaded_out[m] = wmed[m][CMP_SHADED];
    qsort(r->ref_err, (size_t)r->frames, sizeof *r->ref_err, stats_cmp_double);
    char rings[256], mrings[256];
    fov_layout_format(&s->pl.layout, rings, sizeof rings);
    fov_layout_format(r->layout, mrings, sizeof mrings);
    report_table(r, med, wmed, rings, mrings);
    fs_status st = report_json(r, med, wmed, rings, mrings);
    if (st != FS_OK)
        return st;
    printf("\nmetrics per frame, ring and mode: %s/metrics.csv; summary: %s\n", r->out, r->json_path);
    return FS_OK;
}

/* >>run */

typedef struct compare_opts {
    const char *default_out;
    bool demo;
    latency_run *study; /* a latency study's run: what it measured is set here */
    /* A foveation study's run (compare --foveation rings,vrs): every run counts what a GPU would
     * shade (CMP_SHADED), and all are measured in the same rings: the first run's, which it sets
     * here (count 0 until then). */
    bool count_shaded;
    fov_layout *measure;
    foveation_run *fstudy; /* what it measured is set here */
    int *frames_out;       /* the run's frame count is set here (NULL: not wanted) */
} compare_opts;

/* One measured (or history-end) frame as every mode sees it. */
typedef struct cmp_frame {
    int i;
    bool measured; /* i >= first: measured and written */
    frame_record fr;
    display_desc dd;
    reference_info ri;
    ring_mask mask;
    metrics_view vr, vpr, vb; /* the reference, the previous one, the band-limited one */
    bool still;               /* the camera did not move since the previous frame */
    saccade_frame sf;         /* the true gaze's event; after a saccade: the fovea's mask */
    ring_mask fovea;
} cmp_frame;

/* One compare run: what its phases share (compare_run runs them in order). */
typedef struct cmp_run {
    const run_desc *d;
    const compare_opts *co;
    session s;
    mode_run runs[ALPHA_MODE_COUNT];
    int nm;     /* modes */
    int frames; /* the scene's frames */
    /* --first-frame F (a chunk of a sweep): frames before F are drawn for the TAA history without
     * being measured or written, from `warm` on. */
    int first, warm;
    ref_progress rp;
    reference *rf;
    const char *out; /* the output folder */
    char csv_path[1200], csv_tmp[1300], json_path[1200];
    bool csv_tmp_ok;
    run_folder fo;
    FILE *csv;
    exr_writer *w;
    const char *seq_names[ALPHA_MODE_COUNT + 1]; /* the modes', then "reference" */
    fvvdp_export *fx;                            /* --export-fvvdp */
    grid_video *gv;                              /* video.mp4 or the previews (--video) */
    fov_layout ml;                               /* the measurement rings */
    double *ref_err;                             /* per frame: the reference's error estimate */
    int passes, done, ref_cached;                /* reference passes a frame; frames written; cached */
    exr_image ref, prev_ref;
    /* The band-limited reference of the frame (metrics_band_limit): R, G, B, coverage planes. */
    size_t band_n;
    float *band_buf;
    temporal te;
    float *warp_scratch; /* per mode, its previous image warped into this frame (4 planes) */
    int measure_threads; /* modes measured at once (online CPUs, at most the modes) */
    bool have_prev_ref;
    double t0; /* when the frames began */
    double *work[ALPHA_MODE_COUNT]; /* per mode: CMP_WORK values per frame */
    cost_predictor cp;              /* --cost-model */
    saccade_study ss;               /* the gaze events, the post-saccade foveal error */
    phase_clock pc;    /* --verbose: where the time went */
    double writer_cpu; /* the EXR writer threads' CPU time, -1 until they end */
    /* The frame worker: while the main thread draws frame i + 1's reference (GL, this thread only),
     * it measures frame i and writes its outputs (compare_frame). */
    exr_image ref_next;    /* frame i + 1's reference, until the worker is done with frame i's */
    cmp_frame pend;        /* the frame the worker has */
    bool pending, running; /* it has one; on its own thread (else it ran here) */
    pthread_t worker;
    fs_status worker_st;
} cmp_run;


/* The modes (--modes, default traditional and hashed), each with its plan, renderer and arrays. */
static fs_status compare_build_modes(cmp_run *c)
{
    const run_desc *d = c->d;
    fs_status st = FS_OK;
    for (int m = 0; m < d->bench_mode_count; m++)
        c->runs[c->nm++].mode = d->bench_modes[m];
    if (c->nm == 0) {
        c->runs[c->nm++].mode = ALPHA_MODE_TRADITIONAL;
        c->runs[c->nm++].mode = ALPHA_MODE_HASHED;
    }
    c->frames = session_frame_count(d, &c->s.sc);
    for (int m = 0; m < c->nm && st == FS_OK; m++) {
        mode_run *mr = &c->runs[m];
        run_desc dm = *d;
        dm.alpha = mr->mode;
        st = session_build_plan(&dm, &c->s.sc, &mr->pl);
        if (st == FS_OK)
            mr->r = renderer_create(&(renderer_desc){.scene = &c->s.sc, .plan = &mr->pl, .timers = true,
                                                     .count_fragments = mr->pl.vrs || c->co->count_shaded}, &st);
        if (st == FS_OK && !(mr->frame_ms = calloc((size_t)c->frames, sizeof(double))))
            st = FS_ERR_NOMEM;
        if (st == FS_OK && !(c->work[m] = calloc((size_t)c->frames * CMP_WORK, sizeof(double))))
            st = FS_ERR_NOMEM;
        if (st == FS_OK && !(mr->flip = malloc(sizeof(float) * (size_t)mr->pl.width * (size_t)mr->pl.height)))
            st = FS_ERR_NOMEM;
    }
    return st;
}

/* The reference and the outputs: the run folder, metrics.csv (written to a temporary name), the
 * EXR writer and, with --export-fvvdp, the sequences' export. */
static fs_status compare_open_outputs(cmp_run *c, fs_status st)
{
    const run_desc *d = c->d;
    c->rf = st == FS_OK ? session_reference(d, &c->s, &c->rp, &st) : NULL;
    c->out = d->out_dir ? d->out_dir : c->co->default_out;
    snprintf(c->csv_path, sizeof c->csv_path, "%s/metrics.csv", c->out);
    c->csv_tmp_ok = out_path_temp_name(c->csv_path, c->csv_tmp, sizeof c->csv_tmp);
    snprintf(c->json_path, sizeof c->json_path, "%s/summary.json", c->out);
    /* A killed run's litter, another configuration's output, --resume (README "Output folders"): the metrics need
     * every frame's images, so a resumed compare draws every frame again and writes only the
     * frames it lacks; the reference of the frames drawn before comes from the cache. */
    if (st == FS_OK)
        st = run_folder_open(&c->fo, c->out, d, &c->s, c->frames);
    int measured = c->frames - (d->compare.first_frame < c->frames ? d->compare.first_frame : c->frames);
    if (st == FS_OK &&
        !(c->gv = grid_video_begin(&(grid_video_desc){
              .dir = c->out, .fps = d->fps, .video = d->compare.video_set ? d->compare.video : c->co->demo,
              .frames = measured, .previews = d->compare.previews_set ? d->compare.previews : COMPARE_PREVIEWS})))
        st = FS_ERR_NOMEM;
    if (st == FS_OK && !(c->csv = c->csv_tmp_ok ? fopen(c->csv_tmp, "w") : NULL)) {
        log_error("%s: cannot create: %s", c->csv_tmp, strerror(errno));
        st = FS_ERR_IO;
    }
    c->w = st == FS_OK ? exr_writer_create(&(exr_writer_desc){.compression = d->compression, .cpu_seconds = &c->writer_cpu}) : NULL;
    if (st == FS_OK && !c->w)
        st = FS_ERR_NOMEM;
    if (c->csv)
        metrics_csv_header(c->csv);
    /* --export-fvvdp: every mode's sequence and the reference's, for the user's FovVideoVDP. */
    for (int m = 0; m < c->nm; m++)
        c->seq_names[m] = alpha_mode_name(c->runs[m].mode);
    c->seq_names[c->nm] = "reference";
    if (st == FS_OK && d->compare.export_fvvdp)
        c->fx = fvvdp_export_begin(c->out, c->seq_names, c->nm + 1, c->s.pl.width, c->s.pl.height, c->s.pl.hfov_deg,
                                   d->fps, &st);
    return st;
}

/* The measurement's buffers, the progress line (begun whatever st is), and the frames drawn: the
 * first measured one, and from where the TAA history starts. */
static fs_status compare_begin_frames(cmp_run *c, fs_status st)
{
    const run_desc *d = c->d;
    const session *s = &c->s;
    int frames = c->frames;
    c->ml = measure_layout(&s->pl);
    if (c->co->measure && c->co->measure->count > 0)
        c->ml = *c->co->measure;
    else if (c->co->measure)
        *c->co->measure = c->ml;
    c->ref_err = st == FS_OK ? calloc((size_t)frames, sizeof(double)) : NULL;
    if (st == FS_OK && !c->ref_err)
        st = FS_ERR_NOMEM;
    c->passes = c->rf ? reference_pass_count(c->rf) : 0;
    c->band_n = (size_t)s->pl.width * (size_t)s->pl.height;
    c->band_buf = st == FS_OK ? malloc(sizeof(float) * 4 * c->band_n) : NULL;
    if (st == FS_OK && !c->band_buf)
        st = FS_ERR_NOMEM;
    c->warp_scratch = st == FS_OK ? malloc(sizeof(float) * 4 * c->band_n * (size_t)c->nm) : NULL;
    if (st == FS_OK && !c->warp_scratch)
        st = FS_ERR_NOMEM;
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    c->measure_threads = cpus < 1 ? 1 : cpus < c->nm ? (int)cpus : c->nm;
    if (st == FS_OK)
        st = temporal_begin(&c->te, s);
    session_catch_sigint();
    c->rp.pr = progress_begin(c->co->demo ? "demo (reference passes)" : "compare (reference passes)",
                              (frames - (d->compare.first_frame < frames ? d->compare.first_frame : frames)) * c->passes, d->quiet,
                              d->progress_interval);
    progress_per_frame(&c->rp.pr, c->passes, c->co->demo ? "demo" : "compare");
    c->t0 = time_now();
    c->writer_cpu = -1.0;
    phase_clock_begin(&c->pc);
    /* The frame just before F also gets its reference, the previous frame of F's temporal metrics. */
    c->first = d->compare.first_frame < frames ? d->compare.first_frame : frames;
    c->warm = c->first > 0 ? c->first - 1 : 0; /* the frame before F, at least */
    if (c->first > 0 && s->pl.taa) {
        int history = run_history_start(&s->sc, c->first, d->fps, s->pl.width, s->pl.height);
        if (d->bench.warmup_set && c->first - d->bench.warmup > history)
            history = c->first - d->bench.warmup;
        c->warm = history < c->warm ? history : c->warm;
    }
    return st;
}

/* One mode's metrics of the frame (FLIP map, per-ring metrics, temporal error) into rm. Reads the
 * frame and the temporal state, writes only the mode's own FLIP map and warp scratch: the modes
 * of a frame may be measured at once. */
static fs_status measure_mode(const cmp_run *c, const cmp_frame *f, int m, ring_metrics *rm, ring_metrics *fovea)
{
    const mode_run *mr = &c->runs[m];
    metrics_view vi = measure_view(&mr->img), vp = measure_view(&mr->prev);
    bool prev = mr->have_prev && c->have_prev_ref;
    fs_status st = measure_flip(&vi, &f->vr, &f->dd, mr->flip);
    if (st == FS_OK)
        st = metrics_compute(&vi, &f->vr, &f->vb, mr->flip, prev ? &vp : NULL, &f->mask, rm);
    if (st == FS_OK)
        st = temporal_measure_in(&c->te, c->warp_scratch + (size_t)m * 4 * c->band_n, &vi, prev ? &vp : NULL,
                                 &f->vr, &f->mask,
                                 temporal_reference_noise2(c->rf, f->still, f->ri.error, f->i > 0 ? c->ref_err[f->i - 1] : 0.0),
                                 rm);
    if (st == FS_OK && f->fovea.ring) /* after a saccade: within FOVEA_DEG of the true gaze */
        st = metrics_compute(&vi, &f->vr, NULL, mr->flip, NULL, &f->fovea, fovea);
    return st;
}

/* A thread's share of the modes: first, first + step, ... */
typedef struct measure_share {
    const cmp_run *c;
    const cmp_frame *f;
    ring_metrics (*rm)[MAX_FOV_RINGS + 1];
    ring_metrics (*fovea)[3];
    fs_status *st;
    int first, step;
    double cpu; /* the thread's CPU time (--verbose) */
} measure_share;

static void *measure_share_run(void *arg)
{
    measure_share *sh = arg;
    double t0 = measure_thread_cpu_s();
    for (int m = sh->first; m < sh->c->nm; m += sh->step)
        sh->st[m] = measure_mode(sh->c, sh->f, m, sh->rm[m], sh->fovea[m]);
    sh->cpu = measure_thread_cpu_s() - t0;
    return NULL;
}

/* Every mode's metrics of the frame, on up to measure_threads threads (this one included); a
 * thread that cannot start leaves its share to this one. The results do not depend on the threads:
 * each mode is measured by the same code on its own data. */
static fs_status measure_all_modes(cmp_run *c, const cmp_frame *f, ring_metrics (*rm)[MAX_FOV_RINGS + 1],
                                   ring_metrics (*fovea)[3], double *helper_cpu)
{
    fs_status st[ALPHA_MODE_COUNT];
    measure_share sh[ALPHA_MODE_COUNT];
    pthread_t th[ALPHA_MODE_COUNT];
    bool started[ALPHA_MODE_COUNT] = {false};
    int n = c->measure_threads;
    for (int t = 0; t < n; t++)
        sh[t] = (measure_share){.c = c, .f = f, .rm = rm, .fovea = fovea, .st = st, .first = t, .step = n};
    for (int t = 1; t < n; t++)
        started[t] = pthread_create(&th[t], NULL, measure_share_run, &sh[t]) == 0;
    measure_share_run(&sh[0]);
    for (int t = 1; t < n; t++) {
        if (started[t]) {
            pthread_join(th[t], NULL);
            *helper_cpu += sh[t].cpu;
        } else {
            measure_share_run(&sh[t]);
        }
    }
    for (int m = 0; m < c->nm; m++)
        if (st[m] != FS_OK)
            return st[m];
    return FS_OK;
}

/* Every mode measured against the frame's reference; measured frames go into metrics.csv and the
 * modes' sums, in the modes' order. */
static fs_status compare_measure_modes(cmp_run *c, cmp_frame *f, double *helper_cpu)
{
    int i = f->i;
    ring_metrics rm[ALPHA_MODE_COUNT][MAX_FOV_RINGS + 1], fovea[ALPHA_MODE_COUNT][3];
    memset(rm, 0, sizeof rm);
    memset(fovea, 0, sizeof fovea);
    fs_status st = measure_all_modes(c, f, rm, fovea, helper_cpu);
    if (st == FS_OK && f->measured)
        saccade_study_count(&c->ss, &f->sf);
    const char *event = gaze_event_name(f->sf.event);
    for (int m = 0; m < c->nm && st == FS_OK && f->measured; m++) {
        mode_run *mr = &c->runs[m];
        measure_accumulate(mr, rm[m], c->ml.count, f->still);
        measure_gate_ratios(rm[m], c->ml.count, c->s.pl.rings ? &c->ml : NULL); /* metrics.csv: -1 where too little reference */
        for (int k = 0; k <= c->ml.count && st == FS_OK; k++)
            if (!metrics_csv_row(c->csv, i, f->fr.time, alpha_mode_name(mr->mode), k < c->ml.count ? k : -1, &rm[m][k],
                                 f->still, mr->frame_ms[i], event)) {
                log_error("%s: cannot write: %s", c->csv_tmp, strerror(errno));
                st = FS_ERR_IO;
            }
        if (f->fovea.ring)
            saccade_study_add(&c->ss, m, alpha_mode_name(mr->mode), i, f->fr.time, &f->sf, &fovea[m][0]);
    }
    return st;
}

/* The measured frame's outputs: the FovVideoVDP export and the two-part EXR (unless --resume kept
 * it). Frees the ring mask. */
static fs_status compare_write_frame(cmp_run *c, cmp_frame *f, fs_status st)
{
    int i = f->i;
    if (st == FS_OK && c->fx && f->measured) {
        const exr_image *seq[ALPHA_MODE_COUNT + 1];
        for (int m = 0; m < c->nm; m++)
            seq[m] = &c->runs[m].img;
        seq[c->nm] = &c->ref;
        st = fvvdp_export_frame(c->fx, i, &f->fr, seq);
    }
    exr_image frame;
    if (st == FS_OK)
        st = build_frame(c->runs, c->nm, &c->ref, &f->mask, f->fr.true_gaze_px, !c->d->compare.no_grid_annotate, &frame);
    ring_mask_free(&f->mask);
    ring_mask_free(&f->fovea);
    if (st != FS_OK)
        return st;
    if (f->measured)
        st = grid_video_frame(c->gv, i, &frame);
    if (st != FS_OK) {
        exr_image_free(&frame);
        return st;
    }
    if (c->fo.kept[i] || !f->measured) {
        exr_image_free(&frame);
    } else {
        frame_attrs(&frame, &c->s, &f->fr, c->runs, c->nm, &c->ref, !c->d->compare.no_grid_annotate, c->rf, &f->ri);
        char path[1200];
        snprintf(path, sizeof path, "%s/%s.%04d.exr", c->out, c->d->name, i);
        st = exr_writer_submit(c->w, path, &frame);
        c->done += st == FS_OK;
    }
    return st;
}

/* This frame becomes the previous one (the modes' images, the reference, the temporal state). */
static void compare_next_frame(cmp_run *c, const cmp_frame *f)
{
    for (int m = 0; m < c->nm; m++) {
        mode_run *mr = &c->runs[m];
        exr_image_move(&mr->prev, &mr->img);
        mr->have_prev = true;
    }
    exr_image_move(&c->prev_ref, &c->ref);
    c->have_prev_ref = true;
    temporal_next(&c->te, &f->fr);
}

/* Mode m's counts of frame i (rs: its statistics), and the frame time the cost model predicts
 * from them. */
static void compare_count(cmp_run *c, int m, int i, const renderer_stats *rs_in, long long shaded)
{
    renderer_stats rs = *rs_in;
    double *w = c->work[m] + (size_t)i * CMP_WORK;
    w[CMP_PRIMS] = (double)rs.primitives;
    w[CMP_FS] = (double)rs.fragments;
    w[CMP_BYTES] = rs.bytes_read < 0 || rs.bytes_written < 0 ? -1.0 : (double)(rs.bytes_read + rs.bytes_written);
    w[CMP_PREDICTED] = cost_predictor_frame_ms(&c->cp, &rs, alpha_mode_name(c->runs[m].mode));
    w[CMP_SHADED] = (double)shaded;
}

/* What the measurements need of frame f besides the images, on the worker: its ring mask, the
 * reference as the rings the modes were drawn with would show it (alpha_rmse), and the previous
 * reference warped into this frame (one warp for all modes). */
static fs_status worker_prepare(cmp_run *c, cmp_frame *f)
{
    /* Per-ring figures around where the viewer looks (the true gaze), not where the rings were drawn. */
    fs_status st = ring_mask_build(&f->dd, &c->ml, f->fr.true_gaze_px[0], f->fr.true_gaze_px[1], &f->mask);
    if (st == FS_OK && f->measured && f->sf.post >= 0)
        st = saccade_fovea_mask(&f->dd, f->fr.true_gaze_px, &f->fovea);
    float *const band[4] = {c->band_buf, c->band_buf + c->band_n, c->band_buf + 2 * c->band_n,
                            c->band_buf + 3 * c->band_n};
    if (st == FS_OK)
        st = metrics_band_limit(&f->vr, &f->dd, &c->s.pl.layout, f->fr.ring_rect, f->fr.gaze_px[0], f->fr.gaze_px[1],
                                band, &f->vb);
    if (st == FS_OK)
        temporal_warp_reference(&c->te, &f->vpr);
    return st;
}

/* The worker's share of frame c->pend: every mode's metrics, then the frame's outputs. Touches only
 * what the main thread leaves alone until compare_join: the frame, the modes' FLIP maps and warp
 * scratch, metrics.csv, the sums, the writers. */
static void *frame_worker(void *arg)
{
    cmp_run *c = arg;
    phase_clock *pc = &c->pc;
    double w0 = time_now(), c0 = measure_thread_cpu_s(), helpers = 0.0;
    fs_status st = worker_prepare(c, &c->pend);
    if (st == FS_OK)
        st = compare_measure_modes(c, &c->pend, &helpers);
    double w1 = time_now(), c1 = measure_thread_cpu_s();
    pc->job_wall[JOB_METRICS] += w1 - w0;
    pc->job_cpu[JOB_METRICS] += c1 - c0 + helpers;
    c->worker_st = compare_write_frame(c, &c->pend, st);
    pc->job_wall[JOB_OUTPUTS] += time_now() - w1;
    pc->job_cpu[JOB_OUTPUTS] += measure_thread_cpu_s() - c1;
    return NULL;
}

/* Hands frame f to the worker (on this thread when none can start: slower, not wrong). */
static void compare_start_worker(cmp_run *c, const cmp_frame *f)
{
    c->pend = *f;
    c->pending = true;
    c->running = pthread_create(&c->worker, NULL, frame_worker, c) == 0;
    if (!c->running)
        frame_worker(c);
}

/* Waits for the worker's frame; when it went well, that frame becomes the previous one. */
static fs_status compare_join(cmp_run *c)
{
    if (!c->pending)
        return FS_OK;
    if (c->running)
        pthread_join(c->worker, NULL);
    c->pending = c->running = false;
    if (c->worker_st != FS_OK)
        return c->worker_st;
    compare_next_frame(c, &c->pend);
    progress_update(&c->rp.pr, (c->pend.i + 1 - c->first) * c->passes);
    return FS_OK;
}

/* The frame again with the counting variant (once read back: it overwrites the targets, not TAA's
 * state): *shaded is what a GPU would shade, and under VRS rs's fragment-shader invocations become
 * the coarse-shading invocations a GPU would run (docs/benchmarks.md "VRS: coarse-shading
 * invocations"), not llvmpipe's emulation's. */
static fs_status count_shading(renderer *r, const frame_record *fr, renderer_stats *rs, long long *shaded)
{
    renderer_stats cs;
    fs_status st = renderer_draw_counting(r, fr, &cs);
    if (st == FS_OK) {
        renderer_stats_take_shaded(rs, &cs);
        *shaded = cs.shaded;
    }
    return st;
}

/* Every mode's draw of frame i, timed; only that for the TAA history before first - 1. */
static fs_status compare_draw_modes(cmp_run *c, const cmp_frame *f)
{
    fs_status st = FS_OK;
    for (int m = 0; m < c->nm && st == FS_OK; m++) {
        mode_run *mr = &c->runs[m];
        if (!f->measured && f->i < c->first - 1) {
            st = renderer_draw(mr->r, &f->fr);
            continue;
        }
        renderer_finish(mr->r);
        double a = time_now();
        st = renderer_draw(mr->r, &f->fr);
        renderer_finish(mr->r);
        mr->frame_ms[f->i] = (time_now() - a) * 1e3;
        renderer_stats rs = renderer_last_stats(mr->r); /* the queries are done: the frame is finished */
        if (st == FS_OK)
            st = renderer_read(mr->r, &mr->img);
        long long shaded = -1;
        if (st == FS_OK && (mr->pl.vrs || c->co->count_shaded))
            st = count_shading(mr->r, &f->fr, &rs, &shaded);
        compare_count(c, m, f->i, &rs, shaded);
    }
    return st;
}

/* What needs GL of frame f besides the images (this thread): the temporal error's depth pass
 * and warp. */
static fs_status compare_prepare(cmp_run *c, cmp_frame *f)
{
    c->ref_err[f->i] = f->ri.error;
    c->ref_cached += f->measured && f->ri.cached;
    f->dd = frame_display(&f->fr, c->s.pl.width, c->s.pl.height);
    f->vr = measure_view(&c->ref);
    f->vpr = measure_view(&c->prev_ref);
    fs_status st = temporal_depth(&c->te, &f->fr, c->have_prev_ref);
    f->still = temporal_still(&c->te, &f->fr);
    return st;
}

/* Frame i, in the order that lets the worker measure and write frame i - 1 while this thread
 * draws frame i's reference (the most of a frame's time): the reference, then (frame i - 1 done)
 * every mode, then what the worker needs, then the worker starts on frame i. The modes are timed
 * with the worker idle, as before. Every renderer draws from its own state, so drawing the
 * reference before the modes changes no pixel (the frames, cache entries, video and metrics came
 * out byte-identical to the earlier order's, docs/compare.md "Where the time goes"). */
static fs_status compare_frame(cmp_run *c, int i)
{
    const run_desc *d = c->d;
    fs_status st = FS_OK;
    c->rp.base = (i < c->first ? 0 : i - c->first) * c->passes;
    cmp_frame f = {.i = i, .measured = i >= c->first};
    f.fr = session_frame(&c->s, i, (float)i / d->fps, i > 0 ? (float)(i - 1) / d->fps : -1.0f);
    f.sf = saccade_study_frame(&c->ss, &c->s.gaze, f.fr.time);
    if (i < c->first - 1) { /* history only */
        phase_clock_switch(&c->pc, PHASE_MODES);
        return compare_draw_modes(c, &f);
    }
    phase_clock_switch(&c->pc, PHASE_REFERENCE);
    st = reference_frame(c->rf, &f.fr, &c->ref_next, &f.ri);
    phase_clock_switch(&c->pc, PHASE_WAIT);
    fs_status wst = compare_join(c);
    if (st == FS_OK)
        st = wst;
    if (st != FS_OK)
        return st;
    phase_clock_switch(&c->pc, PHASE_MODES);
    if (f.fr.cut) /* no frame-to-frame change across a cut */
        for (int m = 0; m < c->nm; m++)
            c->runs[m].have_prev = false;
    c->have_prev_ref = c->have_prev_ref && !f.fr.cut;
    st = compare_draw_modes(c, &f);
    if (st != FS_OK)
        return st;
    exr_image_move(&c->ref, &c->ref_next);
    phase_clock_switch(&c->pc, PHASE_PREPARE);
    st = compare_prepare(c, &f);
    if (st != FS_OK)
        return st;
    compare_start_worker(c, &f);
    return FS_OK;
}

/* Ends the frames' outputs: the EXR writer's queue, metrics.csv (renamed into place, or removed
 * when the run failed) and the FovVideoVDP export. */
static fs_status compare_close_outputs(cmp_run *c, fs_status st)
{
    if (c->w) {
        fs_status wst = exr_writer_finish(c->w);
        if (st == FS_OK)
            st = wst;
    }
    bool csv_bad = c->csv && ferror(c->csv);
    if (c->csv && (fclose(c->csv) != 0 || csv_bad) && st == FS_OK) {
        log_error("%s: cannot write: %s", c->csv_tmp, strerror(errno));
        st = FS_ERR_IO;
    }
    if (c->csv && st == FS_OK && rename(c->csv_tmp, c->csv_path) != 0) {
        log_error("%s: cannot rename to %s: %s", c->csv_tmp, c->csv_path, strerror(errno));
        st = FS_ERR_IO;
    }
    if (c->csv && st != FS_OK)
        unlink(c->csv_tmp);
    return st;
}

/* --fvvdp: FovVideoVDP's JOD per sequence into jod (*have set), or how to run it later when
 * pyfvvdp is not installed. A failed run is returned; the run's own results are still written. */
static fs_status compare_run_fvvdp(cmp_run *c, double *jod, bool *have)
{
    *have = false;
    if (!fvvdp_available()) {
        sbuf cmd = {0};
        sb_puts(&cmd, "python3 ");
        char script[PATH_MAX + 32];
        snprintf(script, sizeof script, "%s/fvvdp/run_fvvdp.py", c->out);
        shell_quote(&cmd, script);
        printf("FovVideoVDP: pyfvvdp is not installed for the python3 on PATH (pip install pyfvvdp); its inputs "
               "are in %s/fvvdp/, run %s once it is\n", c->out, cmd.p ? cmd.p : "");
        free(cmd.p);
        return FS_OK;
    }
    fs_status st = fvvdp_run(c->out, c->seq_names, c->nm + 1, jod);
    *have = st == FS_OK;
    return st;
}

/* A foveation study's run: each mode's figures, as the table shows them (fr->name is the study's). */
static void foveation_result(const cmp_run *c, const double *med, const double *shaded, foveation_run *fr)
{
    const fov_layout *blocks = c->s.pl.rings ? &c->ml : NULL;
    double px = (double)c->s.pl.width * c->s.pl.height;
    plan_foveation_format(&c->s.pl, fr->desc, sizeof fr->desc);
    fr->count = c->nm;
    for (int m = 0; m < c->nm; m++) {
        const mode_run *mr = &c->runs[m];
        foveation_row *r = &fr->rows[m];
        r->mode = mr->mode;
        for (int k = 0; k <= c->ml.count; k++) {
            r->coverage[k] = measure_coverage_ratio(mr, k, measure_block(blocks, k));
            r->flip[k] = measure_mean_or(mr->flip_sum[k], mr->err_n[k], -1.0);
            r->temporal[k] = measure_mean_or(mr->te_sum[k], mr->te_n[k], -1.0);
        }
        r->shaded_per_px = shaded[m] < 0 ? -1.0 : shaded[m] / px;
        r->frame_ms_median = med[m];
    }
}

/* The table and summary.json, the run folder's record, and the closing line. */
static fs_status compare_report(cmp_run *c, fs_status st, double seconds)
{
    const run_desc *d = c->d;
    double jod[ALPHA_MODE_COUNT + 1], med[ALPHA_MODE_COUNT], shaded[ALPHA_MODE_COUNT];
    bool have_jod = false;
    fs_status fvvdp_st = FS_OK; /* a failed FovVideoVDP run: the run's own results are still written */
    if (st == FS_OK && d->compare.run_fvvdp)
        fvvdp_st = compare_run_fvvdp(c, jod, &have_jod);
    if (st == FS_OK)
        st = report(&(report_desc){.s = &c->s, .runs = c->runs, .mode_count = c->nm, .frames = c->frames - c->first,
                                   .first = c->first, .layout = &c->ml, .blocks = c->s.pl.rings ? &c->ml : NULL,
                                   .ref = c->rf, .ref_err = c->ref_err + c->first, .ref_cached = c->ref_cached,
                                   .out = c->out, .json_path = c->json_path, .seconds = seconds,
                                   .jod = have_jod ? jod : NULL, .work = c->work, .have_cm = c->cp.on,
                                   .ss = &c->ss, .med_out = med, .shaded_out = shaded});
    if (st == FS_OK)
        st = saccade_study_write(&c->ss, c->out);
    latency_run *lr = c->co->study;
    for (int m = 0; m < c->nm && st == FS_OK && lr; m++)
        lr->rows[lr->count++] = (latency_row){.latency_ms = c->s.tracker.latency_ms, .mode = c->runs[m].mode,
                                              .post = saccade_study_result(&c->ss, m, -1), .frame_ms_median = med[m]};
    if (st == FS_OK && lr) {
        snprintf(lr->scene, sizeof lr->scene, "%s", c->s.sc.path);
        plan_foveation_format(&c->s.pl, lr->rings, sizeof lr->rings); /* under VRS: its map */
    }
    if (st == FS_OK && c->co->fstudy)
        foveation_result(c, med, shaded, c->co->fstudy);
    if (st == FS_OK)
        st = run_folder_complete(&c->fo);
    if (st == FS_OK)
        st = fvvdp_st;
    if (st == FS_OK && c->fo.kept_count)
        printf("resumed: kept %d complete frame%s of the earlier run; every frame was drawn again for the metrics "
               "and the TAA history, and only the missing ones written\n", c->fo.kept_count,
               c->fo.kept_count == 1 ? "" : "s");
    else if (st == FS_ERR_INTERRUPTED)
        log_error("interrupted after %d complete frames in %s (no partial frame was left; metrics.csv was not written; "
                  "--resume continues)", c->done + c->fo.kept_count, c->out);
    return st;
}

static void compare_free(cmp_run *c)
{
    run_folder_close(&c->fo);
    exr_image_free(&c->ref);
    exr_image_free(&c->ref_next);
    exr_image_free(&c->prev_ref);
    free(c->band_buf);
    free(c->warp_scratch);
    for (int m = 0; m < c->nm; m++) {
        mode_run *mr = &c->runs[m];
        exr_image_free(&mr->img);
        exr_image_free(&mr->prev);
        free(mr->frame_ms);
        free(mr->flip);
        free(c->work[m]);
        renderer_destroy(mr->r);
    }
    temporal_end(&c->te);
    saccade_study_end(&c->ss);
    free(c->ref_err);
    reference_destroy(c->rf);
    session_end(&c->s);
}

static fs_status compare_run(const run_desc *d, const compare_opts *co)
{
    cmp_run *c = calloc(1, sizeof *c);
    if (!c)
        return FS_ERR_NOMEM;
    c->d = d;
    c->co = co;
    fs_status st = session_begin(d, &c->s, false);
    if (st != FS_OK) {
        free(c);
        return st;
    }
    if (d->overlay) /* allowed (it shows what a viewer would), but it is measured */
        log_warn("--overlay draws ring borders and the gaze marker into every mode's frame, so the metrics include "
                 "them; the grid's annotation (--grid-annotate, on by default) shows them without that");
    st = cost_predictor_open(&c->cp, d->bench.cost_model, gl_device_renderer()); /* before any output */
    if (st == FS_OK)
        st = compare_build_modes(c);
    if (st == FS_OK)
        st = saccade_study_begin(&c->ss, &c->s, d->fps);
    st = compare_open_outputs(c, st);
    st = compare_begin_frames(c, st);
    if (co->frames_out)
        *co->frames_out = c->frames;
    for (int i = c->warm; i < c->frames && st == FS_OK; i++) {
        if (session_interrupted()) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        st = compare_frame(c, i);
    }
    phase_clock_switch(&c->pc, PHASE_WAIT);
    fs_status jst = compare_join(c); /* the last frame's worker, or the one a failure left running */
    if (st == FS_OK)
        st = jst;
    progress_end(&c->rp.pr);
    phase_clock_switch(&c->pc, PHASE_FINISH);
    st = compare_close_outputs(c, st);
    fs_status vst = grid_video_end(c->gv, st == FS_OK);
    c->gv = NULL;
    double el = time_now() - c->t0;
    if (c->fx) {
        fs_status fst = fvvdp_export_end(c->fx);
        if (st == FS_OK)
            st = fst;
    }
    st = compare_report(c, st, el);
    if (st == FS_OK)
        st = report_html_write(&(report_html_desc){.dir = c->out, .kind = c->co->demo ? "demo" : "compare",
                                                   .fps = d->fps});
    if (st == FS_OK)
        st = vst;
    if (st == FS_OK) /* after report.html: the hints name it first */
        look_hints_print(&(look_hints_desc){.out = c->out, .name = d->name, .first_frame = c->first,
                                            .mode = alpha_mode_name(c->runs[0].mode),
                                            .video = co->demo ? "demo.mp4" : "compare.mp4", .fps = d->fps});
    phase_clock_switch(&c->pc, -1);
    phase_clock_print(&c->pc, co->demo ? "demo" : "compare", c->writer_cpu);
    compare_free(c);
    free(c);
    return st;
}

/* compare --gaze-latency MS,MS,...: one compare run per latency into OUT/latency-MS/ (each a run
 * folder of its own, resumable, its record naming its latency; the reference frames come from the
 * cache after the first), then latency.csv and latency.png in OUT from their post-saccade foveal
 * error (docs/latency.md "A latency study"). */
static fs_status latency_study(const run_desc *d, const compare_opts *co)
{
    const char *out = d->out_dir ? d->out_dir : co->default_out;
    latency_row rows[MAX_GAZE_LATENCIES * ALPHA_MODE_COUNT];
    latency_run lr = {0};
    int n = 0;
    fs_status st = FS_OK;
    for (int k = 0; k < d->gaze_latency_count && st == FS_OK; k++) {
        char sub[1200];
        snprintf(sub, sizeof sub, "%s/latency-%g", out, (double)d->gaze_latencies[k]);
        run_desc dk = *d;
        dk.out_dir = sub;
        dk.tracker.desc.latency_ms = d->gaze_latencies[k];
        dk.tracker.latency_set = true;
        dk.gaze_latency_count = 1;
        printf("\n== latency %g ms (%d of %d): %s/\n", (double)d->gaze_latencies[k], k + 1, d->gaze_latency_count, sub);
        fflush(stdout);
        compare_opts ck = *co;
        lr.count = 0;
        ck.study = &lr;
        st = compare_run(&dk, &ck);
        for (int m = 0; m < lr.count && st == FS_OK; m++)
            rows[n++] = lr.rows[m];
    }
    return st == FS_OK ? latency_study_write(out, lr.scene, lr.rings, rows, n) : st;
}

/* compare --foveation rings,vrs,...: one compare run per foveation into OUT/foveation-NAME/ (rings,
 * vrs, off in that order, whatever the list's: the rings' run measures first, and every later run in
 * its measurement rings), each counting what a GPU would shade; then foveation.csv and the modes
 * side by side (docs/foveation.md "Rings or VRS for alpha-tested foliage"). The reference frames
 * come from the cache after the first run. */
static fs_status foveation_study(const run_desc *d, const compare_opts *co)
{
    const char *out = d->out_dir ? d->out_dir : co->default_out;
    static const foveation_kind order[] = {FOVEATION_RINGS, FOVEATION_VRS, FOVEATION_OFF};
    foveation_run runs[3];
    memset(runs, 0, sizeof runs);
    fov_layout ml = {0};
    int n = 0;
    fs_status st = FS_OK;
    for (int o = 0; o < 3 && st == FS_OK; o++) {
        bool listed = false;
        for (int i = 0; i < d->foveation_count; i++)
            listed |= d->foveations[i] == order[o];
        if (!listed)
            continue;
        char sub[1200];
        const char *name = foveation_kind_name(order[o]);
        snprintf(sub, sizeof sub, "%s/foveation-%s", out, name);
        run_desc dk = *d;
        dk.out_dir = sub;
        dk.foveation = order[o];
        dk.foveation_count = 1;
        if (order[o] != FOVEATION_VRS) { /* the rate map's options are VRS's run's */
            dk.vrs = NULL;
            dk.vrs_tile = 0;
        }
        printf("\n== foveation %s (%d of %d): %s/\n", name, n + 1, d->foveation_count, sub);
        fflush(stdout);
        compare_opts ck = *co;
        ck.count_shaded = true;
        ck.measure = &ml;
        ck.fstudy = &runs[n];
        snprintf(runs[n].name, sizeof runs[n].name, "%s", name);
        st = compare_run(&dk, &ck);
        n++;
    }
    return st == FS_OK ? foveation_study_write(out, &ml, runs, n) : st;
}

/* An hmd display: one compare run per eye into OUT/eye-left/ and OUT/eye-right/ (each complete and
 * resumable, with its own reference, TAA history and metrics), then metrics.csv with an eye column,
 * summary.json per eye and both, and the frames joined: part 0 both eyes' grids side by side, the
 * layers part the eyes as a multi-view image (docs/hmd.md "Two eyes"). */
static fs_status compare_eyes(const run_desc *d, const compare_opts *co)
{
    const char *out = d->out_dir ? d->out_dir : co->default_out;
    int frames = 0;
    fs_status st = FS_OK;
    for (int e = 1; e <= 2 && st == FS_OK; e++) {
        char sub[1200];
        run_desc de = eyes_run_desc(d, out, e, sub, sizeof sub);
        compare_opts ce = *co;
        ce.frames_out = &frames;
        st = compare_run(&de, &ce);
    }
    if (st == FS_OK)
        st = eyes_join_metrics(out);
    if (st == FS_OK)
        st = eyes_join_summary(out);
    int first = d->compare.first_frame < frames ? d->compare.first_frame : frames;
    if (st == FS_OK)
        st = eyes_join_frames(out, d->name, first, frames, d->compression, 1);
    if (st == FS_OK)
        printf("both eyes: %s/metrics.csv (an eye column), summary.json (per eye and both), %s.####.exr (the grids "
               "side by side; the layers part multi-view: left, right)\n", out, d->name);
    return st;
}

fs_status cmd_compare(const run_desc *d)
{
    compare_opts co = {.default_out = "out/compare"};
    bool hmd = false;
    fs_status st = d->eye_run ? FS_OK : session_display_is_hmd(d, &hmd);
    if (st != FS_OK)
        return st;
    if (hmd && (d->foveation_count > 1 || d->gaze_latency_count > 1)) {
        log_error("compare: an hmd display runs one compare per eye; a foveation or latency study of it is not "
                  "built (give one foveation and one latency)");
        return FS_ERR_USAGE;
    }
    if (hmd)
        return compare_eyes(d, &co);
    if (d->foveation_count > 1)
        return foveation_study(d, &co);
    return d->gaze_latency_count > 1 ? latency_study(d, &co) : compare_run(d, &co);
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
    /* PIZ: the same pixels (lossless, every OpenEXR reader has it) in about 60 % of ZIP's CPU time,
     * for files about 10 % larger (docs/compare.md "Where the time goes"). */
    if (!dd.compression_set)
        dd.compression = EXR_COMPRESS_PIZ;
    compare_opts co = {.default_out = "out/demo", .demo = true};
    return dd.gaze_latency_count > 1 ? latency_study(&dd, &co) : compare_run(&dd, &co);
}
