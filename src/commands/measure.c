/* measure.c: what compare and bench --accuracy share to measure a mode against the reference:
 * the measurement rings, per-ring sums over frames, FLIP, and the motion-compensated temporal
 * error's state (docs/metrics.md). */
#include "commands/measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/log.h"
#include "core/proc_stats.h"
#include "core/progress.h"

#include "metrics/flip.h"
#include "metrics/warp.h"

/* The rings metrics are reported in: the run's own layout when it is foveated, else the acuity
 * model's (so a full-resolution run is still measured where its periphery would be). */
fov_layout measure_layout(const plan *pl)
{
    if (pl->rings)
        return pl->layout;
    display_desc dd = plan_display(pl);
    return fov_layout_auto(&dd, FOV_ACUITY_SLOPE_DEFAULT, FOV_ACUITY_OMEGA0_DEFAULT);
}

metrics_view measure_view(const exr_image *img)
{
    return (metrics_view){img->width, img->height, exr_image_channel(img, "R"), exr_image_channel(img, "G"),
                          exr_image_channel(img, "B"), exr_image_channel(img, "coverage")};
}


/* The LDR-FLIP map of img against ref (metrics/flip.h) at the display's pixels per degree at its
 * centre (FLIP assumes one ppd for the whole image; a planar display has more towards its edges). */
fs_status measure_flip(const metrics_view *img, const metrics_view *ref, const display_desc *d, float *out)
{
    const float *t[3] = {img->r, img->g, img->b}, *r[3] = {ref->r, ref->g, ref->b};
    return flip_ldr(r, t, img->width, img->height, (double)fov_pixels_per_degree(d), out);
}

/* still: the camera did not move since the previous frame (the static-view flicker counts). */
void measure_accumulate(mode_run *mr, const ring_metrics *rm, int count, bool still)
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
        /* Coverage in display pixels: every frame counts, one whose reference is empty too (what
         * the method drew there is bloat), each by the coverage it holds, not as a ratio. */
        mr->cov_px[k] += m->coverage * (double)m->pixels;
        mr->ref_px[k] += m->ref_coverage * (double)m->pixels;
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

double measure_mean_or(double sum, int n, double none)
{
    return n > 0 ? sum / n : none;
}

int measure_block(const fov_layout *l, int k)
{
    return l && k >= 0 && k < l->count ? 1 << l->rings[k].scale_log2 : 1;
}

double measure_coverage_ratio(const mode_run *mr, int k, int block)
{
    return metrics_coverage_ratio_of_sums(mr->cov_px[k], mr->ref_px[k], block);
}

void measure_gate_ratios(ring_metrics *rm, int count, const fov_layout *l)
{
    for (int k = 0; k <= count; k++)
        if (!metrics_coverage_ratio_rests(rm[k].ref_coverage * (double)rm[k].pixels, measure_block(l, k)))
            rm[k].coverage_ratio = -1.0;
}



fs_status temporal_begin(temporal *t, const session *s)
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

fs_status temporal_depth(temporal *t, const frame_record *fr, bool have_prev_ref)
{
    display_desc dd = frame_display(fr, t->width, t->height);
    frame_record fp = *fr;
    fov_layout off = fov_layout_off();
    frame_record_set_gaze(&fp, &off, &dd, fr->gaze[0], fr->gaze[1]);
    fs_status st = renderer_draw(t->probe, &fp);
    if (st == FS_OK)
        st = renderer_read_depth(t->probe, t->depth[0]);
    t->near_depth = st == FS_OK ? warp_min_depth(t->depth[0], t->width, t->height) : 0.0f;
    warp_desc wd = {.width = t->width, .height = t->height, .depth = t->depth[0], .view_proj = fr->view_proj,
                    .prev_view_proj = t->prev.view_proj, .prev_depth = t->depth[1], .prev_znear = t->prev.znear,
                    .prev_zfar = t->prev.zfar};
    t->warped = st == FS_OK && t->have_prev && have_prev_ref && warp_build(&wd, t->coords, t->valid) >= 0;
    return st;
}

void temporal_warp_reference(temporal *t, const metrics_view *prev_ref)
{
    if (!t->warped)
        return;
    metrics_view wr = temporal_view(t, 0);
    float *const out[4] = {(float *)wr.r, (float *)wr.g, (float *)wr.b, (float *)wr.coverage};
    warp_apply(t->coords, t->valid, prev_ref, out);
}

/* This frame's depth, and the previous reference (NULL: none, e.g. after a cut) warped into it. */
fs_status temporal_frame(temporal *t, const frame_record *fr, const metrics_view *prev_ref)
{
    fs_status st = temporal_depth(t, fr, prev_ref != NULL);
    if (st == FS_OK)
        temporal_warp_reference(t, prev_ref);
    return st;
}

/* One method's temporal error into rm (left unmeasured without a warped previous frame). noise2:
 * the reference's own frame-to-frame noise to subtract from tE (a stochastic reference's e_t^2 +
 * e_{t-1}^2 from its error estimate; 0 for the exact one, and when both frames reuse one reference). */
fs_status temporal_measure(temporal *t, const metrics_view *img, const metrics_view *prev_img,
                                  const metrics_view *ref, const ring_mask *mask, double noise2, ring_metrics *rm)
{
    float *scratch = t->buf + 6 * (size_t)t->width * (size_t)t->height; /* temporal_view(t, 1) */
    return temporal_measure_in(t, scratch, img, prev_img, ref, mask, noise2, rm);
}

fs_status temporal_measure_in(const temporal *t, float *scratch, const metrics_view *img, const metrics_view *prev_img,
                              const metrics_view *ref, const ring_mask *mask, double noise2, ring_metrics *rm)
{
    if (!t->warped || !prev_img)
        return FS_OK;
    size_t n = (size_t)t->width * (size_t)t->height;
    metrics_view wi = {t->width, t->height, scratch, scratch + n, scratch + 2 * n, scratch + 3 * n};
    metrics_view wr = temporal_view(t, 0);
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
double temporal_reference_noise2(const reference *rf, bool still, double e_now, double e_prev)
{
    return reference_get_kind(rf) == REFERENCE_STOCHASTIC && !still ? e_now * e_now + e_prev * e_prev : 0.0;
}

/* Whether the camera has not moved since the previous frame (the static-view flicker counts): within
 * WARP_STILL_TOLERANCE_PX, the test that makes the temporal error's warp the identity. */
bool temporal_still(const temporal *t, const frame_record *fr)
{
    return t->have_prev && !fr->cut && warp_camera_still(&t->prev.view_proj, &fr->view_proj, t->width, t->height,
                                                          t->near_depth);
}

/* This frame becomes the previous one. */
void temporal_next(temporal *t, const frame_record *fr)
{
    t->prev = *fr;
    t->have_prev = true;
    float *d = t->depth[0];
    t->depth[0] = t->depth[1];
    t->depth[1] = d;
}

void temporal_end(temporal *t)
{
    renderer_destroy(t->probe);
    free(t->buf);
    free(t->valid);
}

/* >>phase clock */

double measure_thread_cpu_s(void)
{
    struct timespec ts;
    return clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) == 0 ? (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9 : 0.0;
}

void phase_clock_begin(phase_clock *pc)
{
    memset(pc, 0, sizeof *pc);
    pc->cur = -1;
}

void phase_clock_switch(phase_clock *pc, int phase)
{
    double wall = time_now(), cpu = proc_stats_now().cpu_ms * 1e-3, own = measure_thread_cpu_s();
    if (pc->cur >= 0) {
        pc->wall[pc->cur] += wall - pc->at_wall;
        pc->cpu[pc->cur] += cpu - pc->at_cpu;
        pc->own_cpu[pc->cur] += own - pc->at_own;
    }
    pc->cur = phase;
    pc->at_wall = wall;
    pc->at_cpu = cpu;
    pc->at_own = own;
}

void phase_clock_print(const phase_clock *pc, const char *name, double writer_cpu_s)
{
    static const char *const names[PHASE_COUNT] = {"modes", "reference", "prepare", "wait", "finish"};
    static const char *const jobs[JOB_COUNT] = {"metrics", "outputs"};
    double w = 0, c = 0, o = 0;
    for (int p = 0; p < PHASE_COUNT; p++) {
        log_info("TIME: %s %-9s %7.2f s wall %7.2f s CPU (process) %7.2f s CPU (main thread)", name, names[p],
                 pc->wall[p], pc->cpu[p], pc->own_cpu[p]);
        w += pc->wall[p];
        c += pc->cpu[p];
        o += pc->own_cpu[p];
    }
    log_info("TIME: %s %-9s %7.2f s wall %7.2f s CPU (process) %7.2f s CPU (main thread)", name, "total", w, c, o);
    for (int j = 0; j < JOB_COUNT; j++)
        log_info("TIME: %s worker %-9s %7.2f s wall %7.2f s CPU (its threads; beside the main thread's phases)", name,
                 jobs[j], pc->job_wall[j], pc->job_cpu[j]);
    if (writer_cpu_s >= 0)
        log_info("TIME: %s EXR writer threads %.2f s CPU (inside the process CPU above)", name, writer_cpu_s);
}
