/* compare_saccade.c: compare's eye-movement events and post-saccade foveal error, and the latency
 * study's outputs (compare_saccade.h, docs/latency.md). */
#include "commands/compare_saccade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "output/gnuplot.h"
#include "output/out_path.h"

/* >>events */

fs_status saccade_study_begin(saccade_study *ss, const session *s, float fps)
{
    memset(ss, 0, sizeof *ss);
    ss->fps = fps;
    ss->last_saccade = -1;
    double n = ceil(POST_SACCADE_MS * 1e-3 * fps - 1e-9);
    ss->frames_after = n < 1 ? 1 : n > MAX_POST_FRAMES ? MAX_POST_FRAMES : (int)n;
    if (s->gaze.count == 0)
        return FS_OK;
    /* Angles on the display the trace was placed on (the scene's field of view at the run's size). */
    display_desc d = display_resized(&s->sc.display, s->pl.width, s->pl.height);
    fs_status st = gaze_events_classify(&s->gaze, &d, NULL, &ss->ev);
    ss->on = st == FS_OK;
    if (ss->on)
        sb_puts(&ss->csv, "frame,time,mode,saccade,landing_time,amplitude_deg,frames_after,ms_after,fovea_pixels,"
                          "fovea_coverage,fovea_ref_coverage,fovea_coverage_ratio,fovea_rmse,fovea_flip\n");
    return st;
}

void saccade_study_end(saccade_study *ss)
{
    gaze_events_free(&ss->ev);
    free(ss->csv.p);
    memset(ss, 0, sizeof *ss);
}

saccade_frame saccade_study_frame(const saccade_study *ss, const gaze_trace *t, double time)
{
    saccade_frame sf = {GAZE_EVENT_FIXATION, -1, -1, 0.0};
    if (!ss->on)
        return sf;
    sf.event = gaze_events_at(&ss->ev, t, time);
    const gaze_saccade *g = gaze_events_landed(&ss->ev, time);
    if (!g || sf.event == GAZE_EVENT_SACCADE)
        return sf;
    double after = time - g->end;
    if (after >= POST_SACCADE_MS * 1e-3)
        return sf;
    /* Frames are at i / fps: the first at or after the landing is the 0th after it. */
    double fps = ss->fps;
    double first = ceil(g->end * fps - 1e-6), now = floor(time * fps + 0.5);
    int k = (int)(now - first);
    sf.post = k < 0 ? 0 : k >= ss->frames_after ? ss->frames_after - 1 : k;
    sf.saccade = (int)(g - ss->ev.saccades);
    sf.ms_after = after * 1e3;
    return sf;
}

fs_status saccade_fovea_mask(const display_desc *d, const float true_gaze_px[2], ring_mask *out)
{
    fov_layout l = {.kind = FOV_LAYOUT_EXPLICIT, .count = 2, .blend_deg = 0.0f};
    l.rings[0] = (fov_ring){FOVEA_DEG, 0, 0.0f};
    l.rings[1] = (fov_ring){INFINITY, 0, 0.0f};
    return ring_mask_build(d, &l, true_gaze_px[0], true_gaze_px[1], out);
}

void saccade_study_count(saccade_study *ss, const saccade_frame *sf)
{
    if ((unsigned)sf->event < GAZE_EVENT_COUNT)
        ss->event_frames[sf->event]++;
    if (sf->post >= 0 && sf->saccade != ss->last_saccade) {
        ss->landings++;
        ss->last_saccade = sf->saccade;
    }
}

void saccade_study_add(saccade_study *ss, int m, const char *mode, int frame, float time, const saccade_frame *sf,
                       const ring_metrics *fovea)
{
    if (sf->post < 0 || fovea->pixels == 0)
        return;
    post_sums *p = &ss->mode[m];
    double cov = fovea->coverage * (double)fovea->pixels, ref = fovea->ref_coverage * (double)fovea->pixels;
    const int at[2] = {sf->post, MAX_POST_FRAMES};
    for (int i = 0; i < 2; i++) {
        p->rmse[at[i]] += fovea->rmse;
        p->flip[at[i]] += fovea->flip;
        p->cov_px[at[i]] += cov;
        p->ref_px[at[i]] += ref;
        p->n[at[i]]++;
    }
    const gaze_saccade *g = &ss->ev.saccades[sf->saccade];
    sb_printf(&ss->csv, "%d,%.9g,%s,%d,%.9g,%.6g,%d,%.6g,%lld,%.9g,%.9g,%.9g,%.9g,%.9g\n", frame, (double)time, mode,
              sf->saccade, g->end, (double)g->amplitude_deg, sf->post, sf->ms_after, fovea->pixels, fovea->coverage,
              fovea->ref_coverage, metrics_coverage_ratio_of_sums(cov, ref, 1), fovea->rmse, fovea->flip);
}

post_result saccade_study_result(const saccade_study *ss, int m, int after)
{
    int k = after < 0 ? MAX_POST_FRAMES : after;
    const post_sums *p = &ss->mode[m];
    post_result r = {p->n[k], -1.0, -1.0, -1.0};
    if (r.frames == 0)
        return r;
    r.rmse = p->rmse[k] / r.frames;
    r.flip = p->flip[k] / r.frames;
    r.coverage_ratio = metrics_coverage_ratio_of_sums(p->cov_px[k], p->ref_px[k], 1);
    return r;
}

/* >>outputs */

fs_status saccade_study_write(const saccade_study *ss, const char *out)
{
    if (!ss->on)
        return FS_OK;
    char path[1200];
    snprintf(path, sizeof path, "%s/post_saccade.csv", out);
    return out_write_atomic(path, ss->csv.p ? ss->csv.p : "");
}

void saccade_study_json_events(const saccade_study *ss, FILE *f)
{
    if (!ss->on)
        return;
    const gaze_events_desc *e = &ss->ev.desc;
    fprintf(f, "  \"gaze_events\": {\"method\": \"I-VVT\", \"saccade_deg_s\": %.6g, \"pursuit_deg_s\": %.6g, "
            "\"window_ms\": %.6g, \"saccades_in_trace\": %d, \"landings_measured\": %d, \"frames\": {",
            (double)e->saccade_deg_s, (double)e->pursuit_deg_s, (double)e->window_ms, ss->ev.saccade_count,
            ss->landings);
    for (int k = 0; k < GAZE_EVENT_COUNT; k++)
        fprintf(f, "%s\"%s\": %d", k ? ", " : "", gaze_event_name((gaze_event)k), ss->event_frames[k]);
    fprintf(f, "}, \"fovea_deg\": %.6g, \"post_saccade_ms\": %.6g},\n", (double)FOVEA_DEG, POST_SACCADE_MS);
}

static void json_result(FILE *f, post_result r)
{
    fprintf(f, "\"frames\": %d, \"rmse\": %.6f, \"flip\": %.6f, \"coverage_ratio\": %.5f", r.frames, r.rmse, r.flip,
            r.coverage_ratio);
}

void saccade_study_json_mode(const saccade_study *ss, FILE *f, int m)
{
    if (!ss->on)
        return;
    fprintf(f, "\"post_saccade\": {");
    json_result(f, saccade_study_result(ss, m, -1));
    fprintf(f, ", \"by_frame_after_landing\": [");
    for (int k = 0; k < ss->frames_after; k++) {
        fprintf(f, "%s{\"frame\": %d, ", k ? ", " : "", k);
        json_result(f, saccade_study_result(ss, m, k));
        fprintf(f, "}");
    }
    fprintf(f, "]}, ");
}

static void print_result(post_result r)
{
    char cr[32];
    snprintf(cr, sizeof cr, r.coverage_ratio < 0 ? "n/a" : "%.3f", r.coverage_ratio);
    if (r.frames == 0)
        printf(" %8s %8s %8s", "-", "-", "-");
    else
        printf(" %8.4f %8.4f %8s", r.rmse, r.flip, cr);
}

void saccade_study_print(const saccade_study *ss, const alpha_mode *modes, int nm)
{
    if (!ss->on)
        return;
    int *n = (int *)ss->event_frames;
    printf("\ngaze events (true gaze, I-VVT %.0f/%.0f deg/s): %d fixation, %d saccade, %d pursuit, %d lost frames; "
           "%d of the trace's %d saccades landed in the measured frames\n",
           (double)ss->ev.desc.saccade_deg_s, (double)ss->ev.desc.pursuit_deg_s, n[GAZE_EVENT_FIXATION],
           n[GAZE_EVENT_SACCADE], n[GAZE_EVENT_PURSUIT], n[GAZE_EVENT_LOST], ss->landings, ss->ev.saccade_count);
    if (ss->landings == 0)
        return;
    printf("foveal error after a saccade lands (within %.0f deg of the true gaze, the first %.0f ms; RMSE, FLIP, "
           "coverage ratio):\n%-12s %8s", (double)FOVEA_DEG, POST_SACCADE_MS, "mode", "frames");
    for (int k = -1; k < ss->frames_after && k < 6; k++) {
        char h[32];
        snprintf(h, sizeof h, k < 0 ? "all" : "frame %d after", k);
        printf(" | %-26s", h);
    }
    printf("\n");
    for (int m = 0; m < nm; m++) {
        printf("%-12s %8d", alpha_mode_name(modes[m]), saccade_study_result(ss, m, -1).frames);
        for (int k = -1; k < ss->frames_after && k < 6; k++) {
            printf(" |");
            print_result(saccade_study_result(ss, m, k));
        }
        printf("\n");
    }
}

/* >>latency study */

/* latency.png: the post-saccade foveal FLIP against the latency, a line per mode. */
static fs_status latency_plot(const char *out, const char *scene, const char *rings, const latency_row *rows, int n)
{
    char title[600];
    snprintf(title, sizeof title, "foveal error after saccades vs eye-tracker latency: %s, rings %s", scene, rings);
    sbuf b = {0};
    sb_puts(&b, "set datafile separator ','\nset title ");
    gnuplot_str(&b, title);
    sb_puts(&b, "\nset xlabel 'eye-tracker latency (ms)'\nset ylabel ");
    char yl[200];
    snprintf(yl, sizeof yl, "FLIP within %.0f deg of the true gaze, first %.0f ms after landing (lower is better)",
             (double)FOVEA_DEG, POST_SACCADE_MS);
    gnuplot_str(&b, yl);
    sb_puts(&b, "\nset grid\nset offsets graph 0.03, graph 0.03, graph 0.05, graph 0.05\nset key outside right top\nplot ");
    bool first = true;
    for (int i = 0; i < n; i++) {
        bool seen = false; /* one line per mode, in the order they first appear */
        for (int j = 0; j < i; j++)
            seen |= rows[j].mode == rows[i].mode;
        if (seen)
            continue;
        char col[8];
        alpha_mode_colour(rows[i].mode, col);
        sb_puts(&b, first ? "" : ", \\\n     ");
        sb_puts(&b, "'latency.csv' u 1:(strcol(2) eq ");
        gnuplot_str(&b, alpha_mode_name(rows[i].mode));
        sb_puts(&b, " && $5 >= 0 ? $5 : NaN) w lp pt 7 ps 1.3 lw 2 lc rgb ");
        gnuplot_str(&b, col);
        sb_puts(&b, " t ");
        gnuplot_str(&b, alpha_mode_name(rows[i].mode));
        first = false;
    }
    sb_puts(&b, "\n");
    fs_status st = gnuplot_png(out, "latency", 1000, 650, &b);
    free(b.p);
    return st;
}

fs_status latency_study_write(const char *out, const char *scene, const char *rings, const latency_row *rows, int n)
{
    sbuf b = {0};
    /* rings last: a layout holds commas, and gnuplot reads the columns before it */
    sb_puts(&b, "latency_ms,mode,post_saccade_frames,fovea_rmse,fovea_flip,fovea_coverage_ratio,frame_ms_median,rings\n");
    printf("\nlatency study: foveal error after saccades (within %.0f deg of the true gaze, the first %.0f ms after "
           "landing), rings %s\n%-12s %-12s %8s %10s %10s %10s\n", (double)FOVEA_DEG, POST_SACCADE_MS, rings,
           "latency ms", "mode", "frames", "RMSE", "FLIP", "coverage");
    for (int i = 0; i < n; i++) { /* the table by latency */
        const latency_row *r = &rows[i];
        printf("%-12.6g %-12s %8d", (double)r->latency_ms, alpha_mode_name(r->mode), r->post.frames);
        print_result(r->post);
        printf("\n");
    }
    /* the CSV by mode, each mode's rows together: the plot's line through them is unbroken */
    for (int i = 0; i < n; i++) {
        bool seen = false;
        for (int j = 0; j < i; j++)
            seen |= rows[j].mode == rows[i].mode;
        for (int k = i; k < n && !seen; k++) {
            const latency_row *r = &rows[k];
            if (r->mode == rows[i].mode)
                sb_printf(&b, "%.6g,%s,%d,%.9g,%.9g,%.9g,%.4f,\"%s\"\n", (double)r->latency_ms,
                          alpha_mode_name(r->mode), r->post.frames, r->post.rmse, r->post.flip, r->post.coverage_ratio,
                          r->frame_ms_median, rings);
        }
    }
    char path[1200];
    snprintf(path, sizeof path, "%s/latency.csv", out);
    fs_status st = out_write_atomic(path, b.p);
    free(b.p);
    if (st != FS_OK)
        return st;
    int measured = 0;
    for (int i = 0; i < n; i++)
        measured += rows[i].post.frames > 0;
    if (measured == 0) { /* nothing to plot: gnuplot refuses a plot without a point */
        snprintf(path, sizeof path, "%s/latency.png", out);
        unlink(path); /* an earlier study's plot would not be this one's */
        printf("no saccade landed in the measured frames, so there is no post-saccade error to compare (a trace "
               "with saccades, or more frames); latency.csv in %s/, no latency.png\n", out);
        return FS_OK;
    }
    if (!gnuplot_available()) {
        printf("latency.csv in %s/; latency.png needs gnuplot (not on PATH)\n", out);
        return FS_OK;
    }
    st = latency_plot(out, scene, rings, rows, n);
    if (st == FS_OK)
        printf("latency.csv and latency.png in %s/\n", out);
    return st;
}
