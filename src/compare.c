/* compare.c: `fovsim compare` and `fovsim demo`: every alpha mode drawn with the same camera, gaze,
 * jitter and seeds, measured against the reference per frame and ring, written as two-part EXR
 * frames (a grid to look at, layers to analyse), a metrics CSV, a JSON summary and a table. */
#include "compare.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "core/proc_stats.h"
#include "gl/gl_device.h"
#include "metrics/flip.h"
#include "metrics/metrics.h"
#include "metrics/warp.h"
#include "output/fvvdp_export.h"
#include "output/out_path.h"
#include "run_record.h"

/* One alpha mode's renderer and what it measured. */
typedef struct mode_run {
    alpha_mode mode;
    plan pl;
    renderer *r;
    exr_image img, prev;   /* this frame's and the previous frame's image */
    bool have_prev;
    double *frame_ms;      /* per frame: draw to glFinish */
    /* Sums over frames, per measurement ring (+1: the whole display). */
    double ratio_sum[MAX_FOV_RINGS + 1], rmse_sum[MAX_FOV_RINGS + 1], psnr_sum[MAX_FOV_RINGS + 1];
    double alpha_rmse_sum[MAX_FOV_RINGS + 1]; /* against the band-limited reference */
    double flip_sum[MAX_FOV_RINGS + 1];       /* mean LDR-FLIP */
    double te_sum[MAX_FOV_RINGS + 1];         /* motion-compensated temporal error */
    int te_n[MAX_FOV_RINGS + 1];
    float *flip;                              /* this frame's FLIP map against the reference */
    double still_sum[MAX_FOV_RINGS + 1]; /* static-view flicker: change on frames with a still camera */
    int ratio_n[MAX_FOV_RINGS + 1], err_n[MAX_FOV_RINGS + 1], still_n[MAX_FOV_RINGS + 1];
} mode_run;

/* The rings metrics are reported in: the run's own layout when it is foveated, else the acuity
 * model's (so a full-resolution run is still measured where its periphery would be). */
static fov_layout measure_layout(const plan *pl)
{
    if (pl->rings)
        return pl->layout;
    display_desc dd = {pl->width, pl->height, pl->hfov_deg};
    return fov_layout_auto(&dd, FOV_ACUITY_SLOPE_DEFAULT, FOV_ACUITY_OMEGA0_DEFAULT);
}

static metrics_view view_of(const exr_image *img)
{
    return (metrics_view){img->width, img->height, exr_image_channel(img, "R"), exr_image_channel(img, "G"),
                          exr_image_channel(img, "B"), exr_image_channel(img, "coverage")};
}

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

/* >>metrics */

/* The LDR-FLIP map of img against ref (metrics/flip.h) at the display's pixels per degree at its
 * centre (FLIP assumes one ppd for the whole image; a planar display has more towards its edges). */
static fs_status flip_of(const metrics_view *img, const metrics_view *ref, const display_desc *d, float *out)
{
    const float *t[3] = {img->r, img->g, img->b}, *r[3] = {ref->r, ref->g, ref->b};
    return flip_ldr(r, t, img->width, img->height, (double)fov_pixels_per_degree(d), out);
}

/* still: the camera did not move since the previous frame (the static-view flicker counts). */
static void accumulate(mode_run *mr, const ring_metrics *rm, int count, bool still)
{
    for (int k = 0; k <= count; k++) {
        const ring_metrics *m = &rm[k];
        if (m->pixels == 0)
            continue;
        mr->rmse_sum[k] += m->rmse;
        mr->alpha_rmse_sum[k] += m->alpha_rmse;
        mr->flip_sum[k] += m->flip;
        mr->psnr_sum[k] += m->psnr;
        mr->err_n[k]++;
        if (m->ref_coverage > METRICS_EPS) {
            mr->ratio_sum[k] += m->coverage_ratio;
            mr->ratio_n[k]++;
        }
        if (m->has_prev && still) {
            mr->still_sum[k] += m->change;
            mr->still_n[k]++;
        }
        if (m->temporal_error >= 0.0 && m->disoccluded < 1.0) {
            mr->te_sum[k] += m->temporal_error;
            mr->te_n[k]++;
        }
    }
}

static double mean_or(double sum, int n, double none)
{
    return n > 0 ? sum / n : none;
}


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
} temporal;

static fs_status temporal_begin(temporal *t, const session *s)
{
    memset(t, 0, sizeof *t);
    t->width = s->pl.width;
    t->height = s->pl.height;
    size_t n = (size_t)t->width * (size_t)t->height;
    plan_options po = {.width = t->width, .height = t->height, .frames = 1, .alpha_mode = ALPHA_MODE_TRADITIONAL};
    fs_status st = plan_build(&s->sc, &po, &t->pl);
    if (st == FS_OK)
        t->probe = renderer_create(&(renderer_desc){.scene = &s->sc, .plan = &t->pl}, &st);
    if (st == FS_OK && (!(t->buf = malloc(sizeof(float) * 12 * n)) || !(t->valid = malloc(n))))
        st = FS_ERR_NOMEM;
    if (st == FS_OK) {
        t->depth[0] = t->buf;
        t->depth[1] = t->buf + n;
        t->coords = t->buf + 10 * n;
    }
    return st;
}

static metrics_view temporal_view(const temporal *t, int k)
{
    size_t n = (size_t)t->width * (size_t)t->height;
    float *p = t->buf + (size_t)(2 + 4 * k) * n; /* k = 0: the warped reference, 1: the warped method */
    return (metrics_view){t->width, t->height, p, p + n, p + 2 * n, p + 3 * n};
}

/* This frame's depth, and the previous reference (NULL: none, e.g. after a cut) warped into it. */
static fs_status temporal_frame(temporal *t, const frame_record *fr, const metrics_view *prev_ref)
{
    display_desc dd = {t->width, t->height, fr->hfov_deg};
    frame_record fp = *fr;
    fov_layout off = fov_layout_off();
    frame_record_set_gaze(&fp, &off, &dd, fr->gaze[0], fr->gaze[1]);
    fs_status st = renderer_draw(t->probe, &fp);
    if (st == FS_OK)
        st = renderer_read_depth(t->probe, t->depth[0]);
    warp_desc wd = {.width = t->width, .height = t->height, .depth = t->depth[0], .view_proj = fr->view_proj,
                    .prev_view_proj = t->prev.view_proj, .prev_depth = t->depth[1], .prev_znear = t->prev.znear,
                    .prev_zfar = t->prev.zfar};
    t->warped = st == FS_OK && t->have_prev && prev_ref && warp_build(&wd, t->coords, t->valid) >= 0;
    if (t->warped) {
        metrics_view wr = temporal_view(t, 0);
        float *const out[4] = {(float *)wr.r, (float *)wr.g, (float *)wr.b, (float *)wr.coverage};
        warp_apply(t->coords, t->valid, prev_ref, out);
    }
    return st;
}

/* One method's temporal error into rm (left unmeasured without a warped previous frame). noise2:
 * the reference's own frame-to-frame noise to subtract from tE (a stochastic reference's e_t^2 +
 * e_{t-1}^2 from its error estimate; 0 for the exact one, and when both frames reuse one reference). */
static fs_status temporal_measure(temporal *t, const metrics_view *img, const metrics_view *prev_img,
                                  const metrics_view *ref, const ring_mask *mask, double noise2, ring_metrics *rm)
{
    if (!t->warped || !prev_img)
        return FS_OK;
    metrics_view wi = temporal_view(t, 1), wr = temporal_view(t, 0);
    float *const out[4] = {(float *)wi.r, (float *)wi.g, (float *)wi.b, (float *)wi.coverage};
    warp_apply(t->coords, t->valid, prev_img, out); /* the frame's warp, built once in temporal_frame */
    fs_status st = metrics_temporal(img, &wi, ref, &wr, t->valid, mask, rm);
    for (int k = 0; k <= mask->ring_count && st == FS_OK && noise2 > 0.0; k++) {
        double te2 = rm[k].temporal_error * rm[k].temporal_error - noise2;
        rm[k].temporal_error = te2 > 0.0 ? sqrt(te2) : 0.0;
    }
    return st;
}

/* The noise a reference adds to the temporal error between two frames (temporal_measure). */
static double reference_noise2(const reference *rf, bool still, double e_now, double e_prev)
{
    return reference_get_kind(rf) == REFERENCE_STOCHASTIC && !still ? e_now * e_now + e_prev * e_prev : 0.0;
}

/* Whether the camera has not moved since the previous frame (the static-view flicker counts). */
static bool temporal_still(const temporal *t, const frame_record *fr)
{
    return t->have_prev && !fr->cut && memcmp(&t->prev.view_proj, &fr->view_proj, sizeof fr->view_proj) == 0;
}

/* This frame becomes the previous one. */
static void temporal_next(temporal *t, const frame_record *fr)
{
    t->prev = *fr;
    t->have_prev = true;
    float *d = t->depth[0];
    t->depth[0] = t->depth[1];
    t->depth[1] = d;
}

static void temporal_end(temporal *t)
{
    renderer_destroy(t->probe);
    free(t->buf);
    free(t->valid);
}

/* >>report */

typedef struct report_desc {
    const session *s;
    const mode_run *runs;
    int mode_count, frames;
    const fov_layout *layout; /* measurement rings */
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
    printf("measured in rings %s (eccentricity from each frame's gaze); means over frames\n\n", mrings);
    printf("%-12s %-18s %10s %10s %10s %8s %8s %10s %9s\n", "mode", "ring", "coverage", "RMSE", "alpha RMSE", "FLIP",
           "PSNR", "temporal", "static");
    printf("%-12s %-18s %10s %10s %10s %8s %8s %10s %9s\n", "", "", "/ reference", "(linear)", "(band-lim.)", "(mean)",
           "(dB)", "error", "flicker");
    for (int m = 0; m < nm; m++)
        for (int k = 0; k <= nr; k++) {
            const mode_run *mr = &r->runs[m];
            char label[48];
            ring_label(r->layout, k, label, sizeof label);
            /* -1: not measured (no frame with a warped previous one; no frame with a still camera) */
            double te = mean_or(mr->te_sum[k], mr->te_n[k], -1.0), sf = mean_or(mr->still_sum[k], mr->still_n[k], -1.0);
            char tes[32], sfs[32];
            snprintf(tes, sizeof tes, te < 0.0 ? "n/a" : "%.4f", te);
            snprintf(sfs, sizeof sfs, sf < 0.0 ? "n/a" : "%.4f", sf);
            printf("%-12s %-18s %10.3f %10.4f %10.4f %8.4f %8.2f %10s %9s\n", k == 0 ? alpha_mode_name(mr->mode) : "",
                   label, mean_or(mr->ratio_sum[k], mr->ratio_n[k], 1.0), mean_or(mr->rmse_sum[k], mr->err_n[k], 0.0),
                   mean_or(mr->alpha_rmse_sum[k], mr->err_n[k], 0.0), mean_or(mr->flip_sum[k], mr->err_n[k], 0.0),
                   mean_or(mr->psnr_sum[k], mr->err_n[k], 0.0), tes, sfs);
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
            fprintf(f, "%s\n      {\"ring\": %d, \"outer_deg\": %.3f, \"coverage_ratio\": %.5f, \"rmse\": %.6f, "
                    "\"alpha_rmse\": %.6f, \"flip\": %.6f, \"psnr\": %.3f, \"temporal_error\": %.6f, "
                    "\"static_flicker\": %.6f, \"frames_measured\": %d}",
                    k ? "," : "", k < nr ? k : -1, outer, mean_or(mr->ratio_sum[k], mr->ratio_n[k], 1.0),
                    mean_or(mr->rmse_sum[k], mr->err_n[k], 0.0), mean_or(mr->alpha_rmse_sum[k], mr->err_n[k], 0.0),
                    mean_or(mr->flip_sum[k], mr->err_n[k], 0.0),
                    mean_or(mr->psnr_sum[k], mr->err_n[k], 0.0), mean_or(mr->te_sum[k], mr->te_n[k], -1.0),
                    mean_or(mr->still_sum[k], mr->still_n[k], -1.0), mr->err_n[k]);
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
    /* A killed run's litter, another configuration's output, --resume (issue 17): the metrics need
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
    if (st == FS_OK && d->export_fvvdp)
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
                           (frames - (d->first_frame < frames ? d->first_frame : frames)) * passes, d->quiet);
    double t0 = time_now();
    /* --first-frame F (a chunk of a sweep): frames before F are drawn for the TAA history without
     * being measured or written, from `warm` on; the one just before F also gets its reference, the
     * previous frame of F's temporal metrics. */
    const int first = d->first_frame < frames ? d->first_frame : frames;
    int warm = first > 0 ? first - 1 : 0; /* the frame before F, at least */
    if (first > 0 && s.pl.taa) {
        int history = run_history_start(&s.sc, first, d->fps, s.pl.width, s.pl.height);
        if (d->warmup_set && first - d->warmup > history)
            history = first - d->warmup;
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
        metrics_view vr = view_of(&ref), vpr = view_of(&prev_ref), vb;
        /* The reference as the rings the modes were drawn with would show it (alpha_rmse). */
        if (st == FS_OK)
            st = metrics_band_limit(&vr, &dd, &s.pl.layout, fr.ring_rect, fr.gaze_px[0], fr.gaze_px[1], band, &vb);
        /* This frame's depth, and the previous reference warped into this frame (one warp for all). */
        if (st == FS_OK)
            st = temporal_frame(&te, &fr, have_prev_ref ? &vpr : NULL);
        bool still = temporal_still(&te, &fr);
        for (int m = 0; m < nm && st == FS_OK; m++) {
            ring_metrics rm[MAX_FOV_RINGS + 1] = {0};
            metrics_view vi = view_of(&runs[m].img), vp = view_of(&runs[m].prev);
            bool prev = runs[m].have_prev && have_prev_ref;
            st = flip_of(&vi, &vr, &dd, runs[m].flip);
            if (st == FS_OK)
                st = metrics_compute(&vi, &vr, &vb, runs[m].flip, prev ? &vp : NULL, &mask, rm);
            if (st == FS_OK)
                st = temporal_measure(&te, &vi, prev ? &vp : NULL, &vr, &mask,
                                      reference_noise2(rf, still, ri.error, i > 0 ? ref_err[i - 1] : 0.0), rm);
            if (!measured)
                continue;
            accumulate(&runs[m], rm, ml.count, still);
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
    if (st == FS_OK && d->run_fvvdp) {
        if (!fvvdp_available())
            printf("FovVideoVDP: the fvvdp command is not installed (pip install pyfvvdp); its inputs are in %s/fvvdp/, "
                   "run python3 %s/fvvdp/run_fvvdp.py once it is\n", out, out);
        else
            have_jod = fvvdp_run(out, seq_names, nm + 1, jod) == FS_OK;
    }
    if (st == FS_OK)
        st = report(&(report_desc){.s = &s, .runs = runs, .mode_count = nm, .frames = frames - first,
                                   .first = first, .layout = &ml, .ref = rf, .ref_err = ref_err + first,
                                   .ref_cached = ref_cached, .out = out,
                                   .json_path = json_path, .seconds = el, .jod = have_jod ? jod : NULL});
    if (st == FS_OK)
        st = run_folder_complete(&fo);
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

fs_status run_compare(const run_desc *d)
{
    return compare_run(d, &(compare_opts){.default_out = "out/compare"});
}

/* The demo's defaults: small enough to finish in a few minutes on 2 cores with llvmpipe. */
#define DEMO_WIDTH 640
#define DEMO_HEIGHT 360
#define DEMO_SUPERSAMPLE 2
#define DEMO_SAMPLES 16

fs_status run_demo(const run_desc *d)
{
    run_desc dd = *d;
    if (!dd.gaze_path)
        dd.gaze_path = "builtin:demo_tour";
    if (!dd.width) {
        dd.width = DEMO_WIDTH;
        dd.height = DEMO_HEIGHT;
    }
    if (!dd.supersample)
        dd.supersample = DEMO_SUPERSAMPLE;
    if (!dd.samples)
        dd.samples = DEMO_SAMPLES;
    fs_status st = compare_run(&dd, &(compare_opts){.default_out = "out/demo", .demo = true});
    if (st != FS_OK)
        return st;
    const char *out = d->out_dir ? d->out_dir : "out/demo";
    printf("\nlook at it (part 0 of each frame is the side-by-side grid; part 'layers' has every image):\n"
           "  oiiotool --info -v %s/%s.0000.exr                 # parts, layers, header attributes\n"
           "  ffmpeg -framerate %g -apply_trc iec61966_2_1 -i %s/%s.%%04d.exr -pix_fmt yuv420p %s/demo.mp4\n"
           "  oiiotool %s/%s.0000.exr --subimage layers --ch hashed.coverage -o coverage.png\n",
           out, d->name, d->fps, out, d->name, out, out, d->name);
    return FS_OK;
}

/* >>bench --accuracy */

/* The accuracy-vs-time matrix (DESIGN.md "Outputs"; docs/benchmarks.md): alpha modes x foveation
 * off / default / aggressive x TAA off / on, every configuration drawn over the same consecutive
 * frames (TAA needs a real sequence), timings interleaved per frame so all see the same machine
 * state, accuracy measured after the warm-up against the reference in the default rings. */

#define ACC_DEFAULT_DIV 4       /* default size: the scene's display / 4 (320x180 for 1280x720) */
#define ACC_DEFAULT_FRAMES 12
#define ACC_MAX_CONFIGS (ALPHA_MODE_COUNT * 3 * 2)

static const char *const k_layout_names[3] = {"off", "default", "aggressive"};

/* Per-frame counts of bench --accuracy besides the frame time, in CSV column order: process CPU
 * time (ms) and minor page faults of the draw, then its pipeline statistics (-1 = unknown). */
enum { ACC_CPU, ACC_FAULTS, ACC_VS, ACC_PRIMS, ACC_FS, ACC_COUNTS };
static const char *const k_acc_count_columns[ACC_COUNTS] = {"cpu_ms_median", "minor_faults_median",
                                                            "vs_invocations_median", "primitives_median",
                                                            "fs_invocations_median"};

typedef struct acc_config {
    mode_run run;   /* renderer, images and sums (frame_ms: measured frames only) */
    int layout;     /* 0 off, 1 default, 2 aggressive */
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
 * DIR/STEM.png through DIR/STEM.gp. Colour = alpha mode, shape = ring layout, filled = TAA on,
 * hollow = off; a legend names each (dummy series: one entry per mode, layout and TAA state, not
 * one per point); the Pareto front (rows with front_col == 1, sorted by sort_col) is a line.
 * buf: scratch of 1 << 16 bytes. */
static fs_status plot_accuracy(const char *out, const char *stem, const char *title, const char *xlabel,
                               const char *x_expr, int y_col, const char *ylabel, int sort_col, int front_col,
                               const alpha_mode *modes, int mode_count, char *buf)
{
    static const int shape_filled[3] = {7, 5, 9}, shape_hollow[3] = {6, 4, 8}; /* circle, square, triangle */
    static const char *const colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2"};
    char gp[1200], png[1200], pngtmp[1300];
    snprintf(gp, sizeof gp, "%s/%s.gp", out, stem);
    snprintf(png, sizeof png, "%s/%s.png", out, stem);
    if (!out_path_temp_name(png, pngtmp, sizeof pngtmp)) {
        log_error("%s: cannot write: the path is too long", png);
        return FS_ERR_IO;
    }
    size_t cap = 1 << 16;
    int o = 0;
    o += snprintf(buf + o, cap - (size_t)o,
                  "set terminal pngcairo size 1100,750 noenhanced\nset output '%s'\nset datafile separator ','\n"
                  "set title '%s'\nset xlabel '%s'\nset ylabel '%s'\nset grid\nset key outside right top\nplot ",
                  pngtmp, title, xlabel, ylabel);
    for (int m = 0; m < mode_count; m++) {
        const char *name = alpha_mode_name(modes[m]), *col = colours[m % 7];
        for (int l = 0; l < 3; l++)
            for (int t = 0; t < 2; t++)
                o += snprintf(buf + o, cap - (size_t)o,
                              "'< awk -F, \"\\$1==\\\"%s\\\" && \\$2==\\\"%s\\\" && \\$3==\\\"%s\\\"\" %s/accuracy.csv' "
                              "u %s:%d w p pt %d ps 1.4 lc rgb '%s' notitle, \\\n     ",
                              name, k_layout_names[l], t ? "on" : "off", out, x_expr, y_col,
                              t ? shape_filled[l] : shape_hollow[l], col);
        o += snprintf(buf + o, cap - (size_t)o, "NaN w p pt 7 ps 1.4 lc rgb '%s' t '%s', \\\n     ", col, name);
    }
    for (int l = 0; l < 3; l++)
        o += snprintf(buf + o, cap - (size_t)o, "NaN w p pt %d ps 1.4 lc rgb 'black' t 'rings %s', \\\n     ",
                      shape_hollow[l], k_layout_names[l]);
    o += snprintf(buf + o, cap - (size_t)o,
                  "NaN w p pt 7 ps 1.4 lc rgb 'gray40' t 'TAA on (filled)', NaN w p pt 6 ps 1.4 lc rgb 'gray40' "
                  "t 'TAA off (hollow)', \\\n     '< sort -t, -g -k%d,%d %s/accuracy.csv | awk -F, \"\\$%d==1\"' "
                  "u %s:%d w l lw 2 lc rgb 'black' t 'Pareto front'\n",
                  sort_col, sort_col, out, front_col, x_expr, y_col);
    fs_status st = o < (int)cap - 1 ? out_write_atomic(gp, buf) : FS_ERR_INTERNAL;
    char cmd[2600];
    snprintf(cmd, sizeof cmd, "gnuplot '%s' 2>'%s/gnuplot.log'", gp, out);
    if (st == FS_OK && (system(cmd) != 0 || rename(pngtmp, png) != 0)) {
        log_error("%s: gnuplot failed (see %s/gnuplot.log)", gp, out);
        unlink(pngtmp);
        st = FS_ERR_IO;
    }
    if (st == FS_OK) {
        snprintf(cmd, sizeof cmd, "%s/gnuplot.log", out);
        unlink(cmd); /* kept only when gnuplot failed */
    }
    return st;
}

fs_status run_bench_accuracy(const run_desc *d)
{
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) {
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
    if (!dd.supersample)
        dd.supersample = DEMO_SUPERSAMPLE;
    if (!dd.samples)
        dd.samples = DEMO_SAMPLES;
    if (dd.taa < 0)
        dd.taa = 1; /* the session's plan carries TAA controls; each config sets its own */
    int n = d->frames > 0 ? d->frames : ACC_DEFAULT_FRAMES;
    int warm = d->warmup; /* TAA history and the JIT settle before measuring */
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
    fov_layout layouts[3] = {fov_layout_off(), s.pl.layout, aggressive_layout(&s.pl)};
    if (!s.pl.rings)
        layouts[1] = measure_layout(&s.pl);
    fov_layout ml = layouts[1];
    acc_config *cfg = calloc(ACC_MAX_CONFIGS, sizeof *cfg);
    int nc = 0;
    if (!cfg)
        st = FS_ERR_NOMEM;
    for (int m = 0; m < nmodes && st == FS_OK; m++)
        for (int l = 0; l < 3 && st == FS_OK; l++)
            for (int t = 0; t < 2 && st == FS_OK; t++) {
                acc_config *c = &cfg[nc++];
                c->run.mode = modes[m];
                c->layout = l;
                c->taa = t == 1;
                plan_options po = {.alpha_mode = modes[m], .width = s.pl.width, .height = s.pl.height,
                                   .frames = n + warm, .layout = layouts[l], .alpha = s.pl.alpha, .taa = c->taa,
                                   .taa_controls = s.pl.taa_controls, .no_ring_cull = d->no_ring_cull,
                                   .composite_per_pixel = d->composite_per_pixel};
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
        bool band_done[3] = {false, false, false};
        if (measured) {
            st = reference_frame(rf, &base, &ref, &ri);
            if (st == FS_OK)
                st = ring_mask_build(&disp, &ml, base.gaze_px[0], base.gaze_px[1], &mask);
        }
        metrics_view vr = view_of(&ref), vpr = view_of(&prev_ref);
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
            metrics_view vi = view_of(&mr->img), vp = view_of(&mr->prev);
            bool prev = mr->have_prev && have_prev_ref && !fr.cut;
            int l = cfg[c].layout;
            if (st == FS_OK && !band_done[l]) {
                float *b = band_buf + (size_t)(4 * l) * band_n;
                float *const planes[4] = {b, b + band_n, b + 2 * band_n, b + 3 * band_n};
                st = metrics_band_limit(&vr, &disp, &mr->pl.layout, fr.ring_rect, fr.gaze_px[0], fr.gaze_px[1], planes,
                                        &bands[l]);
                band_done[l] = true;
            }
            metrics_view vb = bands[l];
            if (st == FS_OK)
                st = flip_of(&vi, &vr, &disp, flip_map);
            if (st == FS_OK)
                st = metrics_compute(&vi, &vr, &vb, flip_map, prev ? &vp : NULL, &mask, rm);
            if (st == FS_OK)
                st = temporal_measure(&te, &vi, prev ? &vp : NULL, &vr, &mask,
                                      reference_noise2(rf, temporal_still(&te, &base), ri.error, prev_err), rm);
            accumulate(mr, rm, ml.count, measured && temporal_still(&te, &base));
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
    if (st == FS_OK) {
        csv = malloc(1 << 16);
        md = malloc(1 << 16);
        tx = calloc((size_t)nc, sizeof *tx);
        ey = calloc((size_t)nc, sizeof *ey);
        fx = calloc((size_t)nc, sizeof *fx);
        front = calloc((size_t)nc, sizeof *front);
        front_fs = calloc((size_t)nc, sizeof *front_fs);
        if (!csv || !md || !tx || !ey || !fx || !front || !front_fs)
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
            if (cfg[c].run.mode == ALPHA_MODE_TRADITIONAL && cfg[c].layout == 0 && !cfg[c].taa)
                base = c;
            for (int q = 0; q < ACC_COUNTS; q++) {
                double *u = cfg[c].counts[q];
                qsort(u, (size_t)n, sizeof *u, stats_cmp_double);
                cfg[c].count_med[q] = u[0] < 0 ? -1.0 : stats_quantile(u, n, 0.5); /* -1: unknown */
            }
            tx[c] = cfg[c].med;
            fx[c] = cfg[c].count_med[ACC_FS];
            const mode_run *er = &cfg[c].run; /* the error of --error, over the whole display */
            if (d->acc_error == 3) {
                ey[c] = mean_or(er->te_sum[ml.count], er->te_n[ml.count], 0.0);
            } else {
                const double *esum = d->acc_error == 0   ? er->flip_sum
                                     : d->acc_error == 1 ? er->alpha_rmse_sum
                                                         : er->rmse_sum;
                ey[c] = mean_or(esum[ml.count], er->err_n[ml.count], 0.0);
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
        fov_layout_format(&layouts[1], rings, sizeof rings);
        fov_layout_format(&layouts[2], aggr, sizeof aggr);
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
        MD("- reference: %s\n", reference_describe(rf));
        MD("- speedup: median frame time of traditional, full resolution, TAA off / this one's; * = on the "
           "Pareto front of (time, %s) (--error)\n", k_error_names[d->acc_error]);
        MD("- CPU ms: process CPU time of the draw, all threads; frag./px: fragment-shader invocations per display "
           "pixel (GL_ARB_pipeline_statistics_query; medians per frame)\n\n");
        MD("| mode | rings | TAA | frame ms (p10-p90) | speedup | RMSE | %s | temporal err. | CPU ms | frag./px |",
           d->acc_error == 2 ? "PSNR" : k_error_names[d->acc_error]);
        for (int k = 0; k < ml.count; k++)
            MD(" cov. ring %d |", k);
        MD("\n|---|---|---|---|---|---|---|---|---|---|");
        for (int k = 0; k < ml.count; k++)
            MD("---|");
        MD("\n");
        for (int c = 0; c < nc; c++) {
            const mode_run *mr = &cfg[c].run;
            int all = ml.count;
            double rmse = mean_or(mr->rmse_sum[all], mr->err_n[all], 0.0), psnr = mean_or(mr->psnr_sum[all], mr->err_n[all], 0.0),
                   fl = mean_or(mr->te_sum[all], mr->te_n[all], -1.0), sp = cfg[base].med / cfg[c].med;
            const double *cm = cfg[c].count_med;
            CSV("%s,%s,%s,%.4f,%.4f,%.4f,%.4f,%.6f,%.3f,%.6f,%d", alpha_mode_name(mr->mode),
                k_layout_names[cfg[c].layout], cfg[c].taa ? "on" : "off", cfg[c].med, cfg[c].p10, cfg[c].p90, sp,
                rmse, psnr, fl, front[c]);
            CSV(",%.4f,%.0f,%.0f,%.0f,%.0f,%d", cm[ACC_CPU], cm[ACC_FAULTS], cm[ACC_VS], cm[ACC_PRIMS], cm[ACC_FS],
                front_fs[c]);
            MD("| %s%s | %s | %s | %.2f (%.2f-%.2f) | %.2fx | %.4f | %.4f | %.4f | %.2f |", alpha_mode_name(mr->mode),
               front[c] ? " *" : "", k_layout_names[cfg[c].layout], cfg[c].taa ? "on" : "off", cfg[c].med,
               cfg[c].p10, cfg[c].p90, sp, rmse, d->acc_error == 2 ? psnr : ey[c], fl, cm[ACC_CPU]);
            if (cm[ACC_FS] >= 0)
                MD(" %.2f |", cm[ACC_FS] / ((double)s.pl.width * s.pl.height));
            else
                MD(" n/a |");
            for (int k = 0; k < ml.count; k++) {
                double r = mean_or(mr->ratio_sum[k], mr->ratio_n[k], 1.0);
                CSV(",%.4f", r);
                MD(" %.2f |", r);
            }
            for (int k = 0; k <= ml.count; k++) /* the whole display, then each ring */
                CSV(",%.6f", mean_or(mr->alpha_rmse_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
            for (int k = 0; k <= ml.count; k++)
                CSV(",%.6f", mean_or(mr->flip_sum[k == 0 ? all : k - 1], mr->err_n[k == 0 ? all : k - 1], 0.0));
            CSV("\n");
            MD("\n");
        }
#undef CSV
#undef MD
        char path[1200];
        snprintf(path, sizeof path, "%s/accuracy.csv", out);
        st = out_write_atomic(path, csv);
        snprintf(path, sizeof path, "%s/accuracy.md", out);
        if (st == FS_OK)
            st = out_write_atomic(path, md);
        if (st == FS_OK && d->markdown) {
            FILE *f = fopen(d->markdown, "a");
            if (!f || fprintf(f, "\n%s", md) < 0 || fclose(f) != 0) {
                log_error("%s: cannot append the accuracy table: %s", d->markdown, strerror(errno));
                st = FS_ERR_IO;
            }
        }
        char title[600], x_expr[64];
        /* The whole-display column of the chosen error in accuracy.csv: rmse is column 8,
         * temporal_error 10; after the 17 fixed columns come N coverage ratios, alpha_rmse and its
         * N rings, flip and its N. */
        int y_col = d->acc_error == 3   ? 10
                    : d->acc_error == 2 ? 8
                    : d->acc_error == 1 ? 18 + ml.count
                                        : 19 + 2 * ml.count;
        if (st == FS_OK) {
            snprintf(title, sizeof title, "accuracy vs time: %s %dx%d (%s)", s.sc.path, s.pl.width, s.pl.height,
                     gl_device_renderer());
            st = plot_accuracy(out, "accuracy", title, "frame time, median (ms)", "4", y_col, k_error_labels[d->acc_error],
                               4, 11, modes, nmodes, csv);
        }
        /* Accuracy vs fragment work: what transfers to a GPU, where wall time on llvmpipe does not. */
        snprintf(path, sizeof path, "%s/accuracy-fragments.png", out);
        if (st == FS_OK && have_fs) {
            snprintf(title, sizeof title, "accuracy vs fragment work: %s %dx%d", s.sc.path, s.pl.width, s.pl.height);
            snprintf(x_expr, sizeof x_expr, "($16/%d.0)", s.pl.width * s.pl.height);
            st = plot_accuracy(out, "accuracy-fragments", title,
                               "fragment-shader invocations per display pixel, median per frame", x_expr, y_col,
                               k_error_labels[d->acc_error], 16, 17, modes, nmodes, csv);
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
