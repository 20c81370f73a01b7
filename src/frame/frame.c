#include "frame/frame.h"

#include <math.h>

static display_desc display_scaled(const display_desc *d, int width, int height, float hfov_deg);
static mat4 frame_projection(const display_desc *d, float znear, float zfar);

frame_record frame_record_make(const scene *sc, int index, float fps, int width, int height)
{
    float t = fps > 0.0f ? (float)index / fps : 0.0f;
    float prev = index > 0 && fps > 0.0f ? (float)(index - 1) / fps : -1.0f;
    return frame_record_at(sc, index, t, prev, width, height);
}

/* What follows from the camera (fr's camera, hfov_deg and view): clip planes, projection, and
 * the centre gaze with one full-resolution ring. */
static void frame_record_project(frame_record *fr, const scene *sc, int width, int height)
{
    /* Clip planes: far just beyond the farthest scene corner, near as large as 24-bit depth
     * precision wants without clipping foliage right in front of the camera. */
    vec3 lo, hi;
    scene_bounds(sc, &lo, &hi);
    float far2 = 0.0f;
    for (int c = 0; c < 8; c++) {
        vec3 q = v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
        vec3 d = v3_sub(q, fr->camera.position);
        far2 = fmaxf(far2, v3_dot(d, d));
    }
    fr->zfar = sqrtf(far2) * 1.05f + 1.0f;
    fr->znear = fmaxf(0.02f, fminf(0.1f, fr->zfar * 1e-4f));

    fr->display = display_scaled(&sc->display, width, height, fr->hfov_deg);
    fr->proj = frame_projection(&fr->display, fr->znear, fr->zfar);
    fr->view_proj = m4_mul(fr->proj, fr->view);
    fov_layout off = fov_layout_off();
    frame_record_set_gaze(fr, &off, &fr->display, 0.5f, 0.5f);
}

frame_record frame_record_at(const scene *sc, int index, float time, float prev_time, int width, int height)
{
    frame_record fr = {0};
    fr.index = index;
    fr.time = time;
    fr.camera = camera_path_eval(&sc->camera, fr.time);
    fr.cut = prev_time >= 0.0f && camera_path_cut_between(&sc->camera, prev_time, fr.time);
    fr.hfov_deg = fr.camera.hfov_deg > 0.0f ? fr.camera.hfov_deg : sc->display.hfov_deg;
    fr.view = m4_look_at(fr.camera.position, fr.camera.target, v3(0, 1, 0));
    frame_record_project(&fr, sc, width, height);
    return fr;
}

frame_record frame_record_posed(const scene *sc, int index, float time, vec3 position, mat4 view, int width,
                                int height)
{
    frame_record fr = {0};
    fr.index = index;
    fr.time = time;
    /* the view's -z in the world: its rotation's third row, negated (m4_look_at's layout) */
    vec3 forward = v3(-view.m[2], -view.m[6], -view.m[10]);
    fr.camera = (camera_state){position, v3_add(position, forward), sc->display.hfov_deg};
    fr.hfov_deg = sc->display.hfov_deg;
    fr.view = view;
    frame_record_project(&fr, sc, width, height);
    return fr;
}

/* The scene display at the frame's size, with the frame's hfov (the camera may set its own). */
static display_desc display_scaled(const display_desc *d, int width, int height, float hfov_deg)
{
    display_desc r = display_resized(d, width, height);
    r.hfov_deg = hfov_deg;
    return r;
}

display_desc frame_display(const frame_record *fr, int width, int height)
{
    return display_scaled(&fr->display, width, height, fr->hfov_deg);
}

/* The display's projection: the symmetric one for a centred display (bit-identical to before the
 * principal point existed), glFrustum's off-axis one otherwise; NDC x = 2 px / w - 1 of the
 * principal point is 2 ppx / w, NDC y (up) is -2 ppy / h. */
static mat4 frame_projection(const display_desc *d, float znear, float zfar)
{
    float hfov = d->hfov_deg * (float)FS_PI / 180.0f, aspect = (float)d->width / (float)d->height;
    float cx = 2.0f * d->ppx / (float)d->width, cy = -2.0f * d->ppy / (float)d->height;
    return m4_perspective_offaxis(hfov, aspect, cx, cy, znear, zfar);
}

/* Normalised gaze -> its clamped normalised, pixel and angle forms. */
static void gaze_forms(const display_desc *d, float gx, float gy, float n[2], float px[2], float deg[2])
{
    gx = isfinite(gx) ? fminf(fmaxf(gx, 0.0f), 1.0f) : 0.5f;
    gy = isfinite(gy) ? fminf(fmaxf(gy, 0.0f), 1.0f) : 0.5f;
    n[0] = gx;
    n[1] = gy;
    px[0] = gx * (float)d->width;
    px[1] = gy * (float)d->height;
    fov_gaze_clamp(d, &px[0], &px[1]); /* the exact gaze the footprints use */
    /* Angles from the view axis, i.e. from the principal point (cx = 0.5 w on a centred display). */
    display_geom g = display_geom_of(d);
    float f = (float)g.f;
    deg[0] = atanf((px[0] - (float)g.cx) / f) * (float)(180.0 / FS_PI);
    deg[1] = atanf(((float)g.cy - px[1]) / f) * (float)(180.0 / FS_PI);
}

void frame_record_set_true_gaze(frame_record *fr, const display_desc *d, float gx, float gy)
{
    gaze_forms(d, gx, gy, fr->true_gaze, fr->true_gaze_px, fr->true_gaze_deg);
}

void frame_record_set_full_res(frame_record *fr, const display_desc *d)
{
    fr->full_res = true;
    for (int i = 0; i < fr->ring_count; i++) {
        fr->ring_rect[i] = (fov_ring_rect){0, 0, d->width, d->height, d->width, d->height, 1};
        fr->ring_view_proj[i] = m4_mul(fov_ring_crop(d, &fr->ring_rect[i]), fr->view_proj);
    }
}

void frame_record_set_layout(frame_record *fr, const fov_layout *l, const display_desc *d)
{
    float truth[2] = {fr->true_gaze[0], fr->true_gaze[1]};
    bool full = fr->full_res;
    frame_record_set_gaze(fr, l, d, fr->gaze[0], fr->gaze[1]);
    frame_record_set_true_gaze(fr, d, truth[0], truth[1]);
    if (full)
        frame_record_set_full_res(fr, d);
}

void frame_record_set_gaze(frame_record *fr, const fov_layout *l, const display_desc *d, float gx, float gy)
{
    gaze_forms(d, gx, gy, fr->gaze, fr->gaze_px, fr->gaze_deg);
    frame_record_set_true_gaze(fr, d, gx, gy);
    fr->full_res = false;
    fr->ring_count = l->count;
    for (int i = 0; i < l->count; i++) {
        fr->ring_rect[i] = fov_ring_footprint(d, l, i, fr->gaze_px[0], fr->gaze_px[1], FOV_MARGIN_BLOCKS);
        fr->ring_view_proj[i] = m4_mul(fov_ring_crop(d, &fr->ring_rect[i]), fr->view_proj);
    }
}

void frame_record_shift(frame_record *fr, const display_desc *d, float dx, float dy)
{
    /* NDC y points up, display y down. */
    mat4 t = m4_translate(v3(2.0f * dx / (float)d->width, -2.0f * dy / (float)d->height, 0.0f));
    fr->proj = m4_mul(t, fr->proj);
    fr->view_proj = m4_mul(t, fr->view_proj);
    for (int i = 0; i < fr->ring_count; i++)
        fr->ring_view_proj[i] = m4_mul(fov_ring_crop(d, &fr->ring_rect[i]), fr->view_proj);
}

frame_record frame_record_eye(const scene *sc, const frame_record *head, vec3 offset, int width, int height)
{
    mat4 view = m4_mul(m4_translate(v3_scale(offset, -1.0f)), head->view), inv;
    vec3 pos = m4_invert(view, &inv) ? m4_point(inv, v3(0, 0, 0)) : head->camera.position;
    frame_record fr = frame_record_posed(sc, head->index, head->time, pos, view, width, height);
    fr.cut = head->cut;
    return fr;
}
