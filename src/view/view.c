/* view.c: `fovsim view`: window, keys, plans, gaze, recording, captures (view.h). */
#include "view/view.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/config.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"
#include "gl/gl_window.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "core/file_read.h"
#include "session/session.h"
#include "frame/frame.h"
#include "view/gaze_record.h"
#include "view/view_input.h"

#define VIEW_BIAS_STEP 0.5f   /* mip bias change per [ or ] press, log2 units */
#define VIEW_BIAS_MAX 8.0f    /* |mip bias| reachable from the keys */
#define VIEW_TITLE_PERIOD_S 0.25 /* the title (frame times) is updated at most this often */

static volatile sig_atomic_t g_view_interrupted;
static void on_sigint(int sig)
{
    (void)sig;
    g_view_interrupted = 1;
}

typedef enum layout_choice {
    LAYOUT_RUN = 0,   /* --rings, else the scene's, else auto (as render) */
    LAYOUT_AUTO,
    LAYOUT_AGGRESSIVE,
    LAYOUT_OFF,
    LAYOUT_COUNT
} layout_choice;

static const char *const k_layout_names[LAYOUT_COUNT] = {"run", "auto", "aggressive", "off"};

/* What the keys change; every field but `split` feeds the plan. */
typedef struct view_settings {
    alpha_mode mode[2];   /* left (the whole image without split), right */
    bool split;
    layout_choice layout;
    layout_choice last_on; /* the layout F turns foveation back on to */
    bool taa, overlay;
    bool ring_lod;        /* --ring-lod's keep fractions, or the default schedule (D) */
    float mip_bias;       /* added to every ring's own bias */
} view_settings;

typedef struct viewer {
    const run_desc *d;
    scene sc;
    gaze_trace gaze;          /* --gaze replay; count 0 = the mouse is the gaze */
    gaze_tracker_desc tracker; /* --gaze-* (or the scene's): the replayed trace as a tracker delivers it */
    view_script script;
    int script_pos;
    plan_options base;        /* the run's plan options (as render builds them) */
    fov_layout layouts[LAYOUT_COUNT];
    bool layout_dup[LAYOUT_COUNT]; /* same rings as LAYOUT_RUN: skipped by L */
    int width, height;        /* of one view (an hmd's eye: the window shows both, 2 width wide) */
    float fps;
    bool hmd;                 /* an hmd display: side 0 the left eye, side 1 the right (no split) */
    display_desc eye_disp[2]; /* each eye's display (hmd_eye_display) */
    vec3 eye_offset[2];       /* each eye's position in the head frame, metres */
    float eye_gx[2], eye_gy[2]; /* the gaze direction's point on each eye's display, normalised */
    gl_window *win;
    view_settings set;
    bool rebuild;
    plan pl[2];
    renderer *r[2];
    /* time: scene frame `tick` (time tick / fps) and the drawn-frame counter */
    long tick;
    int drawn;
    bool paused, step, frozen;
    float frozen_time, prev_cam_time;
    bool reset_history;
    /* gaze of the frame */
    float gx, gy;
    bool gaze_valid;
    bool full_res;            /* the tracker lost the replayed gaze with --gaze-loss full */
    float true_gx, true_gy;   /* the replayed trace itself (the tracker moved gx, gy) */
    /* recording and captures */
    gaze_recorder rec;
    long rec_start_tick;
    int rec_index;            /* recordings started so far */
    char capture_base[1024];  /* "<dir>/<stem>" captures are named after */
    bool capture_now;
    bool quit;                /* before drawing (Esc, Q) */
    bool quit_after;          /* after drawing this frame (the script's `quit`) */
    fs_status io_status;      /* first write failure: the run's exit status */
    /* the title line */
    double cpu_ms, gl_ms, title_time;
    bool title_dirty;
} viewer;

/* >>names */
static void strip_ext(const char *path, char *out, size_t n)
{
    snprintf(out, n, "%s", path);
    char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash) && dot != out)
        *dot = '\0';
}

static void dir_of(const char *path, char *out, size_t n)
{
    snprintf(out, n, "%s", path);
    char *slash = strrchr(out, '/');
    if (slash)
        *(slash == out ? slash + 1 : slash) = '\0';
    else
        snprintf(out, n, ".");
}

/* Path of the next recording: --record for the first, then <stem>-2.csv, -3, ...; by default
 * out/view/gaze-<n>.csv with the first n not taken. */
static void next_record_path(const viewer *v, char *out, size_t n)
{
    if (v->d->view.record) {
        if (v->rec_index == 0) {
            snprintf(out, n, "%s", v->d->view.record);
            return;
        }
        char stem[1024];
        strip_ext(v->d->view.record, stem, sizeof stem);
        const char *ext = v->d->view.record + strlen(stem);
        snprintf(out, n, "%.900s-%d%.32s", stem, v->rec_index + 1, ext);
        return;
    }
    for (int k = 0;; k++) {
        snprintf(out, n, "out/view/gaze-%d.csv", k);
        if (access(out, F_OK) != 0 || k >= 99999)
            return;
    }
}

/* >>plans */
static const char *layout_label(const viewer *v, layout_choice c, char *buf, size_t n)
{
    const fov_layout *l = &v->layouts[c];
    if (c == LAYOUT_RUN)
        snprintf(buf, n, "%s", l->kind == FOV_LAYOUT_EXPLICIT ? "custom" : fov_layout_kind_name(l->kind));
    else
        snprintf(buf, n, "%s", k_layout_names[c]);
    size_t len = strlen(buf);
    if (l->count > 1 || l->rings[0].scale_log2 > 0)
        snprintf(buf + len, n - len, " (%d rings)", l->count);
    return buf;
}

/* The ring layouts L cycles through, resolved once for the display. */
static fs_status resolve_layouts(viewer *v)
{
    v->layouts[LAYOUT_RUN] = v->base.layout;
    run_desc da = *v->d;
    da.rings = "auto";
    da.frames = MAX_FRAMES;
    plan_options po;
    fs_status st = session_plan_options(&da, &v->sc, &po); /* auto, off where it would not save pixels */
    if (st != FS_OK)
        return st;
    v->layouts[LAYOUT_AUTO] = po.layout;
    display_desc dd = display_resized(&v->sc.display, v->width, v->height);
    v->layouts[LAYOUT_AGGRESSIVE] = fov_layout_aggressive(&dd);
    v->layouts[LAYOUT_OFF] = fov_layout_off();
    char run[256], other[256];
    fov_layout_format(&v->layouts[LAYOUT_RUN], run, sizeof run);
    for (int c = 1; c < LAYOUT_COUNT; c++) {
        fov_layout_format(&v->layouts[c], other, sizeof other);
        v->layout_dup[c] = !strcmp(run, other);
    }
    return FS_OK;
}

static fs_status build_side(viewer *v, int side)
{
    plan_options po = v->base;
    po.alpha_mode = v->set.mode[v->hmd ? 0 : side]; /* an hmd's eyes: one mode */
    po.taa = v->set.taa;
    po.overlay = v->set.overlay;
    po.layout = v->layouts[v->set.layout];
    /* Ring LOD: the run's keep fractions where they fit this layout, else the default schedule. */
    bool fits = v->base.ring_lod.kind != RING_LOD_EXPLICIT || v->base.ring_lod.count == po.layout.count;
    po.ring_lod = !v->set.ring_lod ? (ring_lod_spec){0}
                  : fits && v->base.ring_lod.kind != RING_LOD_OFF ? v->base.ring_lod
                                                                  : (ring_lod_spec){.kind = RING_LOD_SCHEDULE};
    for (int i = 0; i < po.layout.count; i++)
        po.layout.rings[i].mip_bias += v->set.mip_bias;
    if (v->hmd) /* each eye's plan on its own display */
        v->sc.display = v->eye_disp[side];
    fs_status st = plan_build(&v->sc, &po, &v->pl[side]);
    renderer_destroy(v->r[side]);
    v->r[side] = NULL;
    if (st == FS_OK)
        v->r[side] = renderer_create(&(renderer_desc){.scene = &v->sc, .plan = &v->pl[side], .timers = true}, &st);
    return st;
}

/* (Re)builds the plan and renderer of each side shown; a new renderer starts without history. */
static fs_status rebuild(viewer *v)
{
    fs_status st = build_side(v, 0);
    if (st == FS_OK && v->set.mode[0] == ALPHA_MODE_DEFAULT)
        v->set.mode[0] = v->pl[0].global_mode; /* so A cycles on from what is shown */
    if (st == FS_OK && (v->set.split || v->hmd))
        st = build_side(v, 1);
    else if (!v->set.split) {
        renderer_destroy(v->r[1]);
        v->r[1] = NULL;
    }
    v->rebuild = false;
    v->title_dirty = true;
    return st;
}

static alpha_mode next_mode(alpha_mode m, alpha_mode skip)
{
    do
        m = m + 1 >= ALPHA_MODE_COUNT ? ALPHA_MODE_TRADITIONAL : (alpha_mode)(m + 1);
    while (m == skip);
    return m;
}

/* >>actions */
static void start_or_stop_recording(viewer *v);

static void apply_action(viewer *v, view_action a)
{
    view_settings *s = &v->set;
    switch (a) {
    case VIEW_ACT_NONE: return;
    case VIEW_ACT_ALPHA_NEXT: s->mode[0] = next_mode(s->mode[0], s->split ? s->mode[1] : ALPHA_MODE_DEFAULT); break;
    case VIEW_ACT_SPLIT_NEXT:
        if (!s->split)
            return;
        s->mode[1] = next_mode(s->mode[1], s->mode[0]);
        break;
    case VIEW_ACT_SPLIT:
        if (v->hmd) /* the two halves are the eyes */
            return;
        s->split = !s->split;
        if (s->split && (s->mode[1] == ALPHA_MODE_DEFAULT || s->mode[1] == s->mode[0]))
            s->mode[1] = s->mode[0] == ALPHA_MODE_HASHED ? ALPHA_MODE_TRADITIONAL : ALPHA_MODE_HASHED;
        break;
    case VIEW_ACT_TAA: s->taa = !s->taa; break;
    case VIEW_ACT_FOVEATION:
        if (s->layout != LAYOUT_OFF) {
            s->last_on = s->layout;
            s->layout = LAYOUT_OFF;
        } else {
            s->layout = s->last_on;
        }
        break;
    case VIEW_ACT_LAYOUT_NEXT:
        do
            s->layout = (layout_choice)((s->layout + 1) % LAYOUT_COUNT);
        while (s->layout != LAYOUT_RUN && v->layout_dup[s->layout]);
        if (s->layout != LAYOUT_OFF)
            s->last_on = s->layout;
        break;
    case VIEW_ACT_BIAS_DOWN: s->mip_bias = fmaxf(s->mip_bias - VIEW_BIAS_STEP, -VIEW_BIAS_MAX); break;
    case VIEW_ACT_BIAS_UP: s->mip_bias = fminf(s->mip_bias + VIEW_BIAS_STEP, VIEW_BIAS_MAX); break;
    case VIEW_ACT_OVERLAY: s->overlay = !s->overlay; break;
    case VIEW_ACT_RING_LOD: s->ring_lod = !s->ring_lod; break;
    /* The rest do not change the plan. */
    case VIEW_ACT_FREEZE:
        v->frozen = !v->frozen;
        v->frozen_time = v->prev_cam_time >= 0.0f ? v->prev_cam_time : 0.0f;
        v->title_dirty = true;
        return;
    case VIEW_ACT_RESET_HISTORY: v->reset_history = true; return;
    case VIEW_ACT_RECORD: start_or_stop_recording(v); return;
    case VIEW_ACT_CAPTURE: v->capture_now = true; return;
    case VIEW_ACT_PAUSE:
        v->paused = !v->paused;
        v->title_dirty = true;
        return;
    case VIEW_ACT_STEP: v->step = v->paused; return;
    case VIEW_ACT_QUIT: v->quit = true; return;
    }
    v->rebuild = true;
}

/* >>recording */
static void start_or_stop_recording(viewer *v)
{
    v->title_dirty = true;
    if (gaze_recorder_is_open(&v->rec)) {
        int n = v->rec.samples;
        char path[1024];
        snprintf(path, sizeof path, "%s", v->rec.path);
        fs_status st = gaze_recorder_end(&v->rec);
        if (st != FS_OK && v->io_status == FS_OK)
            v->io_status = st;
        if (!v->d->quiet && st == FS_OK)
            printf("VIEW: recorded %d frames of gaze to %s\n", n, path);
        return;
    }
    char path[1024], dir[1024];
    next_record_path(v, path, sizeof path);
    dir_of(path, dir, sizeof dir);
    fs_status st = file_make_dirs(dir);
    if (st != FS_OK) {
        if (v->io_status == FS_OK)
            v->io_status = st;
        return;
    }
    char comment[512];
    snprintf(comment, sizeof comment,
             "fovsim view recording: scene %.300s, display %dx%d, %g fps\n"
             "t = 0 is scene frame %ld (t %.4f s); replay: fovsim render --gaze THIS_FILE (from frame 0)",
             v->sc.path, v->width, v->height, (double)v->fps, v->tick, (double)((float)v->tick / v->fps));
    gaze_recorder_begin(&v->rec, path, comment);
    v->rec_start_tick = v->tick;
    v->rec_index++;
    strip_ext(path, v->capture_base, sizeof v->capture_base);
    if (!v->d->quiet)
        printf("VIEW: recording the gaze to %s (R stops)\n", path);
}

/* >>capture: the frame as render writes it (+ the right-hand side's channels as <mode>.* layers
 * in a split), and the window as shown. */
static fs_status capture(viewer *v, const frame_record *fr)
{
    char dir[1024], path[1200];
    dir_of(v->capture_base, dir, sizeof dir);
    fs_status st = file_make_dirs(dir);
    exr_image img = {0}, right = {0}, win = {0};
    if (st == FS_OK)
        st = renderer_read(v->r[0], &img);
    if (st == FS_OK) {
        session_attrs(&img, &v->sc, &v->pl[0], &v->gaze, fr);
        exr_image_set_int(&img, "fovsim:frame", (int)v->tick); /* the scene frame: render's numbering */
        if (v->gaze.count == 0)
            exr_image_set_string(&img, "fovsim:gaze_trace", gaze_recorder_is_open(&v->rec) ? v->rec.path : "mouse");
        char what[256];
        snprintf(what, sizeof what, "fovsim view capture: drawn frame %d, scene frame %ld%s%s", v->drawn, v->tick,
                 v->frozen ? ", camera frozen" : "", v->paused ? ", paused" : "");
        exr_image_set_string(&img, "fovsim:view", what);
    }
    if (st == FS_OK && v->hmd) { /* both eyes: one multi-view image (left the default view) */
        exr_image joined = {0};
        st = renderer_read(v->r[1], &right);
        if (st == FS_OK)
            st = exr_image_join_eyes_move(&joined, &img, &right);
        if (st == FS_OK)
            exr_image_move(&img, &joined);
    }
    if (st == FS_OK && v->set.split) {
        st = renderer_read(v->r[1], &right);
        const char *mode = alpha_mode_name(v->pl[1].global_mode);
        for (int c = 0; c < right.channel_count && st == FS_OK; c++) {
            char name[64];
            snprintf(name, sizeof name, "%.20s.%.40s", mode, right.channel_names[c]);
            float *p = exr_image_add_channel(&img, name);
            if (!p)
                st = FS_ERR_NOMEM;
            else
                memcpy(p, right.planes[c], sizeof(float) * (size_t)img.width * (size_t)img.height);
        }
        char what[256];
        snprintf(what, sizeof what, "left half shown: R, G, B, A, coverage (%s); right half shown: %s.*",
                 alpha_mode_name(v->pl[0].global_mode), mode);
        exr_image_set_string(&img, "fovsim:split", what);
    }
    if (st == FS_OK) {
        snprintf(path, sizeof path, "%s.capture.%04ld.exr", v->capture_base, v->tick);
        st = exr_write_file(path, &img, v->d->compression);
    }
    if (st == FS_OK)
        st = gl_window_read(v->win, &win);
    if (st == FS_OK) {
        exr_image_set_string(&win, "fovsim:view", gl_window_is_srgb(v->win)
                                                      ? "the window as shown: 8-bit sRGB-encoded values"
                                                      : "the window as shown: 8-bit linear values");
        exr_image_set_int(&win, "fovsim:frame", (int)v->tick);
        char wpath[1200];
        snprintf(wpath, sizeof wpath, "%s.window.%04ld.exr", v->capture_base, v->tick);
        st = exr_write_file(wpath, &win, v->d->compression);
        if (st == FS_OK && !v->d->quiet)
            printf("VIEW: captured %s and %s\n", path, wpath);
    }
    exr_image_free(&img);
    exr_image_free(&right);
    exr_image_free(&win);
    return st;
}

/* >>frame */
static void update_title(viewer *v)
{
    double now = time_now();
    if (!v->title_dirty && now - v->title_time < VIEW_TITLE_PERIOD_S)
        return;
    v->title_time = now;
    v->title_dirty = false;
    char title[512], lay[64];
    const char *name = strrchr(v->sc.path, '/');
    int o = snprintf(title, sizeof title, "fovsim view: %s | %s", name ? name + 1 : v->sc.path,
                     alpha_mode_name(v->pl[0].global_mode));
    if (v->set.split)
        o += snprintf(title + o, sizeof title - (size_t)o, " vs %s", alpha_mode_name(v->pl[1].global_mode));
    o += snprintf(title + o, sizeof title - (size_t)o, " | rings %s%s | TAA %s | bias %+.1f%s | %.1f ms cpu, %.1f ms gl",
                  layout_label(v, v->set.layout, lay, sizeof lay), v->pl[0].ring_lod ? " + ring LOD" : "",
                  v->pl[0].taa ? "on" : "off", (double)v->set.mip_bias, v->set.overlay ? " | overlay" : "", v->cpu_ms,
                  v->gl_ms);
    if (v->paused)
        o += snprintf(title + o, sizeof title - (size_t)o, " | paused");
    if (v->frozen)
        o += snprintf(title + o, sizeof title - (size_t)o, " | camera frozen");
    if (gaze_recorder_is_open(&v->rec))
        snprintf(title + o, sizeof title - (size_t)o, " | REC %d", v->rec.samples);
    gl_window_set_title(v->win, title);
}

/* The gaze of this frame: the replayed trace at the scene time, else the cursor (held where it
 * leaves the image). */
/* The width of the image the window shows: both eyes side by side for an hmd. */
static int shown_width(const viewer *v)
{
    return v->hmd ? 2 * v->width : v->width;
}

/* An hmd's gaze: the direction through (px, py) of eye k's display, then where that direction
 * meets each eye's display (eye_gx, eye_gy, normalised): both eyes look the same way. */
static void hmd_gaze(viewer *v, int k, double px, double py)
{
    double dir[3];
    display_geom g = display_geom_of(&v->eye_disp[k]);
    display_ray(&g, px, py, dir);
    for (int e = 0; e < 2; e++) {
        display_geom ge = display_geom_of(&v->eye_disp[e]);
        double x, y;
        if (display_pixel(&ge, dir, &x, &y)) {
            v->eye_gx[e] = (float)(x / ge.w);
            v->eye_gy[e] = (float)(y / ge.h);
        }
    }
}

static void update_gaze(viewer *v, bool use_mouse)
{
    if (v->gaze.count > 0) {
        display_desc dd = display_resized(&v->sc.display, v->width, v->height);
        gaze_delivery g = gaze_tracker_at(&v->gaze, &v->tracker, &dd, (float)v->tick / v->fps, NULL);
        gaze_point truth = gaze_at(&v->gaze, (float)v->tick / v->fps, NULL);
        v->true_gx = truth.x;
        v->true_gy = truth.y;
        v->gx = g.x;
        v->gy = g.y;
        v->full_res = g.full;
        v->gaze_valid = true;
        return;
    }
    if (!use_mouse)
        return;
    double x, y;
    float nx, ny;
    v->gaze_valid = gl_window_cursor(v->win, &x, &y) &&
                    gl_window_to_display(v->win, x, y, shown_width(v), v->height, &nx, &ny);
    if (v->gaze_valid) {
        v->gx = nx;
        v->gy = ny;
    }
}

/* Both eyes' gaze of the frame: a replayed trace is placed on the left eye's display; the mouse lies on
 * either eye's half of the window; each eye then looks the same way (hmd_gaze). */
static void eye_gaze(viewer *v)
{
    if (v->gaze.count > 0)
        hmd_gaze(v, 0, v->gx * v->width, v->gy * v->height);
    else {
        double px = v->gx * 2.0 * v->width, py = v->gy * v->height;
        int k = px >= v->width;
        hmd_gaze(v, k, px - k * v->width, py);
    }
}

/* The script's events for the frame about to be drawn. */
static void apply_script(viewer *v)
{
    while (v->script_pos < v->script.count && v->script.events[v->script_pos].frame <= v->drawn) {
        const view_event *e = &v->script.events[v->script_pos++];
        float nx, ny;
        switch (e->kind) {
        case VIEW_EV_MOVE:
            v->gx = e->x;
            v->gy = e->y;
            v->gaze_valid = true;
            break;
        case VIEW_EV_MOVE_PX:
            v->gaze_valid = gl_window_to_display(v->win, e->x, e->y, shown_width(v), v->height, &nx, &ny);
            if (v->gaze_valid) {
                v->gx = nx;
                v->gy = ny;
            }
            break;
        case VIEW_EV_LEAVE: v->gaze_valid = false; break;
        case VIEW_EV_RESIZE: gl_window_set_size(v->win, (int)e->x, (int)e->y); break;
        case VIEW_EV_KEY: apply_action(v, view_key_action(e->key)); break;
        case VIEW_EV_CAPTURE: v->capture_now = true; break;
        case VIEW_EV_QUIT: v->quit_after = true; break;
        }
    }
}

static void sleep_s(double s)
{
    if (s <= 0)
        return;
    struct timespec ts = {(time_t)s, (long)((s - floor(s)) * 1e9)};
    nanosleep(&ts, NULL);
}

/* One frame: input, gaze, draw, present, capture, record. *running becomes false when the viewer
 * ends (Esc, the script's quit). */
/* The frame record of view side `side` (an hmd: eye `side`, at its offset on its own display, with
 * its point of the gaze direction; else the one view). */
static frame_record view_frame(viewer *v, int side, float cam_t)
{
    if (v->hmd)
        v->sc.display = v->eye_disp[side];
    frame_record fr = frame_record_at(&v->sc, v->drawn, cam_t, v->prev_cam_time, v->width, v->height);
    if (v->hmd)
        fr = frame_record_eye(&v->sc, &fr, v->eye_offset[side], v->width, v->height);
    if (v->reset_history)
        fr.cut = true; /* the renderer drops TAA history across a cut */
    display_desc dd = frame_display(&fr, v->width, v->height);
    frame_record_set_gaze(&fr, &v->pl[side].layout, &dd, v->hmd ? v->eye_gx[side] : v->gx,
                          v->hmd ? v->eye_gy[side] : v->gy);
    if (v->gaze.count > 0 && !v->hmd) /* captures name both */
        frame_record_set_true_gaze(&fr, &dd, v->true_gx, v->true_gy);
    if (v->full_res)
        frame_record_set_full_res(&fr, &dd);
    return fr;
}

static fs_status frame(viewer *v, bool *running)
{
    double t0 = time_now();
    bool scripted = v->script_pos < v->script.count;
    gl_window_poll(v->win, 0);
    char key[GL_WINDOW_KEY_NAME];
    /* While a script runs, real input is ignored: the run must not depend on the desk it runs on. */
    while (gl_window_next_key(v->win, key))
        if (!scripted)
            apply_action(v, view_key_action(key));
    if (scripted) {
        apply_script(v);
        update_gaze(v, false);
    } else {
        update_gaze(v, true);
    }
    if (v->quit) {
        *running = false;
        return FS_OK;
    }
    if (gl_window_is_hidden(v->win) && !scripted) {
        /* Minimised: nothing to draw into; time (and a recording) stands still. */
        gl_window_poll(v->win, 0.1);
        return FS_OK;
    }
    fs_status st = v->rebuild ? rebuild(v) : FS_OK;
    if (st != FS_OK)
        return st;

    float cam_t = v->frozen ? v->frozen_time : (float)v->tick / v->fps;
    if (v->hmd)
        eye_gaze(v);
    frame_record fr[2];
    for (int s = 0; s < (v->hmd ? 2 : 1); s++)
        fr[s] = view_frame(v, s, cam_t);
    if (!v->hmd)
        fr[1] = fr[0]; /* a split shows the same frame in another mode */
    v->reset_history = false;
    v->prev_cam_time = cam_t;

    int sides = v->set.split || v->hmd ? 2 : 1;
    for (int s = 0; s < sides && st == FS_OK; s++)
        st = renderer_draw(v->r[s], &fr[s]);
    if (st != FS_OK)
        return st;
    gl_window_source src[2] = {{renderer_output_framebuffer(v->r[0]), 0, v->width, 0}};
    if (v->hmd) /* the eyes side by side, each whole */
        src[1] = (gl_window_source){renderer_output_framebuffer(v->r[1]), v->width, 2 * v->width, v->width};
    else if (sides == 2) {
        src[0].x1 = v->width / 2;
        src[1] = (gl_window_source){renderer_output_framebuffer(v->r[1]), v->width / 2, v->width, 0};
    }
    gl_window_present(v->win, src, sides, shown_width(v), v->height);
    if (v->capture_now) {
        v->capture_now = false;
        fs_status cst = capture(v, &fr[0]);
        if (cst != FS_OK && v->io_status == FS_OK)
            v->io_status = cst;
    }
    gl_window_swap(v->win);

    if (gaze_recorder_is_open(&v->rec)) {
        fs_status rst = gaze_recorder_add(&v->rec, (double)((float)(v->tick - v->rec_start_tick) / v->fps), v->gx,
                                          v->gy, v->gaze_valid);
        if (rst != FS_OK && v->io_status == FS_OK)
            v->io_status = rst;
    }
    double gl = 0;
    for (int s = 0; s < sides; s++) {
        renderer_stats rs = renderer_last_stats(v->r[s]); /* waits for this frame's timer queries */
        for (int p = 0; p < rs.pass_count; p++)
            gl += rs.pass_ms[p] > 0 ? rs.pass_ms[p] : 0;
    }
    v->gl_ms = gl;
    v->cpu_ms = (time_now() - t0) * 1e3;
    update_title(v);
    if (!v->paused || v->step)
        v->tick++;
    v->step = false;
    v->drawn++;
    if (v->quit_after) {
        *running = false;
        return FS_OK;
    }
    /* Interactive: at most fps frames per second (scene time advances 1/fps per frame). */
    if (!scripted)
        sleep_s(1.0 / v->fps - (time_now() - t0));
    return FS_OK;
}

/* >>run */
/* An hmd display: each eye's display (its angles at its panel width) and position; the plan is the
 * left eye's (the right mirrors it). */
static fs_status setup_hmd(viewer *v, const run_desc *d)
{
    const hmd_desc *h = session_hmd(d, &v->sc);
    if (!h)
        return FS_OK;
    if (d->view.split[0] != ALPHA_MODE_DEFAULT) {
        log_error("view: --split and an hmd display: the window's halves are the eyes");
        return FS_ERR_USAGE;
    }
    v->hmd = true;
    for (int e = 0; e < 2; e++) {
        if (!hmd_eye_display(&h->eye[e], &v->eye_disp[e])) {
            log_error("view: the %s eye's field of view spans 180 degrees or more", e ? "right" : "left");
            return FS_ERR_USAGE;
        }
        v->eye_offset[e] = h->eye[e].position;
    }
    v->sc.display = v->eye_disp[0];
    return FS_OK;
}

static fs_status setup(viewer *v, const run_desc *d)
{
    fs_status st = session_load_scene(d, &v->sc);
    if (st == FS_OK)
        st = setup_hmd(v, d);
    if (st != FS_OK)
        return st;
    /* The viewer runs for an unknown number of frames: TAA is on unless asked off (as render for
     * more than one frame). */
    run_desc dv = *d;
    dv.frames = MAX_FRAMES;
    st = session_plan_options(&dv, &v->sc, &v->base);
    plan probe;
    if (st == FS_OK)
        st = plan_build(&v->sc, &v->base, &probe);
    if (st != FS_OK)
        return st;
    v->width = probe.width;
    v->height = probe.height;
    for (int e = 0; e < 2 && v->hmd; e++) /* --width/--height: each eye at that size */
        v->eye_disp[e] = display_resized(&v->eye_disp[e], probe.width, probe.height);
    v->fps = d->fps;
    v->set.mode[0] = d->view.split[0] ? d->view.split[0] : d->alpha;
    v->set.mode[1] = d->view.split[1];
    v->set.split = d->view.split[0] != ALPHA_MODE_DEFAULT;
    v->set.taa = probe.taa;
    v->set.overlay = d->overlay;
    v->set.ring_lod = v->base.ring_lod.kind != RING_LOD_OFF;
    v->set.layout = LAYOUT_RUN;
    st = resolve_layouts(v);
    v->set.last_on = v->layouts[LAYOUT_RUN].kind == FOV_LAYOUT_OFF ? LAYOUT_AUTO : LAYOUT_RUN;
    if (st == FS_OK && d->gaze_path)
        st = gaze_load(d->gaze_path, &(gaze_load_desc){.format = d->gaze_format, .eye = d->eye}, &v->gaze);
    if (st == FS_OK && d->gaze_path) { /* by angle, as session_begin places it */
        gaze_place_desc pd = gaze_place_merge(&d->place, &v->sc.gaze_place);
        display_desc at = display_resized(&v->sc.display, probe.width, probe.height);
        gaze_place(&v->gaze, &pd, &at);
    }
    v->tracker = gaze_tracker_merge(&d->tracker, &v->sc.tracker);
    if (st == FS_OK && d->view.script)
        st = view_script_load(d->view.script, &v->script);
    if (d->view.record)
        strip_ext(d->view.record, v->capture_base, sizeof v->capture_base);
    else
        snprintf(v->capture_base, sizeof v->capture_base, "out/view/view");
    v->gx = v->gy = 0.5f;
    v->prev_cam_time = -1.0f;
    return st;
}

fs_status view_run(const run_desc *d)
{
    viewer *v = calloc(1, sizeof *v);
    if (!v)
        return FS_ERR_NOMEM;
    v->d = d;
    fs_status st = setup(v, d);
    if (st == FS_OK) {
        v->win = gl_window_create(&(gl_window_desc){.width = shown_width(v), .height = v->height, .title = "fovsim view",
                                                    .gl_debug = d->gl_debug},
                                  &st);
    }
    if (st == FS_OK)
        st = rebuild(v);
    if (st == FS_OK && !d->quiet) {
        printf("fovsim view: %s, %dx%d, on %s (%s)%s\nkeys:\n%s", v->sc.path, v->width, v->height,
               gl_device_renderer(), gl_device_description(), v->gaze.count ? ", gaze replayed" : ", the mouse is the gaze",
               view_key_help());
        fflush(stdout);
    }
    g_view_interrupted = 0;
    void (*old_handler)(int) = signal(SIGINT, on_sigint);
    bool running = st == FS_OK;
    while (running) {
        if (g_view_interrupted) {
            st = FS_ERR_INTERRUPTED;
            break;
        }
        if (gl_window_should_close(v->win))
            break;
        st = frame(v, &running);
        if (st != FS_OK)
            break;
    }
    signal(SIGINT, old_handler);
    /* Whatever ended the run (the window closed, Esc, the script, Ctrl-C, an error), a recording in
     * progress is closed: every frame's line is already on disk. */
    if (gaze_recorder_is_open(&v->rec))
        start_or_stop_recording(v);
    if (st == FS_ERR_INTERRUPTED)
        log_error("interrupted; the gaze recording (if any) is complete up to the last frame drawn");
    renderer_destroy(v->r[0]);
    renderer_destroy(v->r[1]);
    gl_window_destroy(v->win);
    view_script_free(&v->script);
    gaze_free(&v->gaze);
    scene_free(&v->sc);
    if (st == FS_OK)
        st = v->io_status;
    free(v);
    return st;
}
