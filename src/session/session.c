/* session.c: what every command shares: loading and checking the inputs (scene, plan, gaze trace,
 * GL context) before anything is written, per-frame gaze and footprints, EXR header attributes,
 * the reference cache, and small statistics. */
#include "session/session.h"

#include "scene/gltf_shim.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "common/shared_defs.h"
#include "core/file_read.h"
#include "core/log.h"
#include "core/progress.h"
#include "gl/gl_device.h"

static volatile sig_atomic_t g_interrupted;
static void on_sigint(int sig)
{
    (void)sig;
    g_interrupted = 1;
}

void session_catch_sigint(void)
{
    signal(SIGINT, on_sigint);
}

bool session_interrupted(void)
{
    return g_interrupted != 0;
}

/* >>setup */
const hmd_desc *session_hmd(const run_desc *d, const scene *sc)
{
    display_kind k = d->display ? d->display_kind : sc->display_kind;
    return k != DISPLAY_HMD ? NULL : d->display ? &d->display_hmd : &sc->hmd;
}

/* render and compare draw an hmd display one eye at a time (d->eye_run); plan prints it; every other
 * command says so here, where they all load their scene. */
static fs_status refuse_hmd(const run_desc *d, const scene *sc)
{
    if (d->cmd == CMD_PLAN || d->cmd == CMD_VIEW || d->eye_run > 0 || !session_hmd(d, sc))
        return FS_OK;
    log_error("%s: an hmd display is drawn by render and compare (one run per eye) and view; fovsim %s draws one view "
              "(docs/hmd.md)", cli_command_name(d->cmd), cli_command_name(d->cmd));
    return FS_ERR_USAGE;
}

/* An eye's run: the scene's display becomes the eye's (hmd_eye_display). */
static fs_status eye_display(const run_desc *d, scene *sc)
{
    const hmd_desc *h = session_hmd(d, sc);
    if (d->eye_run == 0 || !h)
        return FS_OK;
    display_desc dd;
    if (!hmd_eye_display(&h->eye[d->eye_run - 1], &dd)) {
        log_error("%s eye: the field of view spans 180 degrees or more", d->eye_run == 1 ? "left" : "right");
        return FS_ERR_USAGE;
    }
    sc->display = dd;
    return FS_OK;
}

/* Only a scene file's "display" object can say hmd: read that much of it (not the scene, whose
 * loading would warn twice); anything wrong with the file is the real load's to report. */
fs_status session_display_is_hmd(const run_desc *d, bool *hmd)
{
    *hmd = d->display ? d->display_kind == DISPLAY_HMD : false;
    size_t n = d->scene_path ? strlen(d->scene_path) : 0;
    if (d->display || n < 5 || strcmp(d->scene_path + n - 5, ".json") != 0)
        return FS_OK;
    char *text = NULL;
    size_t size;
    log_set_quiet_errors(true);
    fs_status st = file_read_all(d->scene_path, (size_t)1 << 26, "a scene file", FS_ERR_IO, &text, &size);
    log_set_quiet_errors(false);
    cJSON *root = st == FS_OK ? cJSON_Parse(text) : NULL;
    const cJSON *kind = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(root, "display"), "kind");
    *hmd = cJSON_IsString(kind) && !strcmp(kind->valuestring, "hmd");
    cJSON_Delete(root);
    free(text);
    return FS_OK;
}

fs_status session_load_scene(const run_desc *d, scene *sc)
{
    fs_status st = gltf_set_asset_root(d->asset_root);
    if (st != FS_OK)
        return st;
    gltf_set_pixel_budget((uint64_t)d->max_image_mpixels << 20, (uint64_t)d->max_scene_mpixels << 20);
    st = d->scene_path ? scene_load_file(d->scene_path, sc) : scene_load_builtin(d->builtin, sc);
    if (st == FS_OK)
        st = scene_validate(sc);
    if (st == FS_OK)
        st = refuse_hmd(d, sc);
    if (st == FS_OK)
        st = eye_display(d, sc);
    if (st != FS_OK)
        scene_free(sc);
    return st;
}

int session_frame_count(const run_desc *d, const scene *sc)
{
    if (d->frames > 0)
        return d->frames;
    int n = (int)floorf(sc->duration * d->fps + 1e-3f) + 1;
    return n < 1 ? 1 : n > MAX_FRAMES ? MAX_FRAMES : n;
}

static alpha_params run_alpha_params(const run_desc *d)
{
    alpha_params a = {.hash_scale = d->hash_scale, .anisotropic = d->hash_aniso, .no_fade = d->no_fade,
                      .no_frame_offset = d->no_hash_offset, .fade_n = d->fade_n, .a2c_sharpen = d->a2c_sharpen,
                      .lod_clamp = d->alpha_lod, .lod_max = d->alpha_lod_max};
    a.hash_kind = d->hash_kind != HASH_CHOICE_DEFAULT ? (int)d->hash_kind : ALPHA_HASH_DEFAULT;
    return alpha_params_defaults(&a);
}

foveation_kind session_foveation(const run_desc *d, const scene *sc)
{
    if (d->foveation != FOVEATION_UNSET)
        return d->foveation;
    /* A --rings layout asks for rings, whatever the scene's "foveation" says (the CLI wins). */
    return !d->rings && sc->foveation != FOVEATION_UNSET ? sc->foveation : FOVEATION_RINGS;
}

void session_vrs(const run_desc *d, const scene *sc, vrs_spec *spec, int *tile)
{
    *spec = d->vrs ? d->vrs_spec : sc->vrs[0] ? sc->vrs_spec : (vrs_spec){.is_auto = true};
    *tile = d->vrs_tile ? d->vrs_tile : sc->vrs_tile ? sc->vrs_tile : VRS_TILE_DEFAULT;
}

/* The ring layout of a run: off with foveation off, else --rings (parsed by the CLI), else the scene
 * file's, else auto; "auto" resolved against the display. Under VRS foveation the rings are what
 * fovsim plan compares the rate map with. */
static fs_status resolve_layout(const run_desc *d, const scene *sc, int width, int height, fov_layout *out)
{
    if (session_foveation(d, sc) == FOVEATION_OFF) {
        *out = fov_layout_off();
        return FS_OK;
    }
    display_desc dd = display_resized(&sc->display, width > 0 ? width : sc->display.width,
                                      height > 0 ? height : sc->display.height);
    /* Both were parsed once, where they were read; only "auto" and "aggressive" depend on the
     * display. */
    const fov_layout *given = d->rings ? &d->rings_layout : sc->rings[0] ? &sc->rings_layout : NULL;
    *out = !given || given->kind == FOV_LAYOUT_AUTO ? fov_layout_auto(&dd, 0.0f, 0.0f)
           : given->kind == FOV_LAYOUT_AGGRESSIVE   ? fov_layout_aggressive(&dd)
                                                    : *given;
    /* An auto layout that would shade as many pixels as the display (small or coarse displays,
     * where the fovea already spans most of the view) only adds work: foveation off. */
    if (out->kind == FOV_LAYOUT_AUTO && out->count > 1 &&
        fov_shaded_pixels(&dd, out, 0.5f * (float)dd.width, 0.5f * (float)dd.height, FOV_MARGIN_BLOCKS, NULL) >=
            (long long)dd.width * dd.height) {
        log_info("FOV: auto rings would not save pixels on a %dx%d display; foveation off", dd.width, dd.height);
        *out = fov_layout_off();
    }
    return FS_OK;
}

/* The ring LOD of a run: --ring-lod, else the scene file's, else off; one keep fraction per ring. */
static fs_status resolve_ring_lod(const run_desc *d, const scene *sc, const fov_layout *l, ring_lod_spec *out)
{
    const char *spec = d->ring_lod ? d->ring_lod : sc->ring_lod[0] ? sc->ring_lod : "off";
    char err[256];
    if (ring_lod_parse(spec, out, err, sizeof err) != FS_OK || ring_lod_check(out, l, err, sizeof err) != FS_OK) {
        log_error("%s: %s%s", d->ring_lod ? "--ring-lod" : sc->path, d->ring_lod ? "" : "ring_lod: ", err);
        return FS_ERR_USAGE;
    }
    return FS_OK;
}

fs_status session_plan_options(const run_desc *d, const scene *sc, plan_options *out)
{
    *out = (plan_options){.alpha_mode = d->alpha, .width = d->width, .height = d->height,
                          .frames = session_frame_count(d, sc), .overlay = d->overlay,
                          .debug_channels = d->debug_channels, .alpha = run_alpha_params(d),
                          .taa = d->taa.mode != TAA_SWITCH_SCENE ? d->taa.mode == TAA_SWITCH_ON : !sc->taa.off,
                          .taa_controls = {.blend = d->taa.blend > 0 ? d->taa.blend : sc->taa.blend,
                                           .gamma = d->taa.gamma > 0 ? d->taa.gamma : sc->taa.gamma,
                                           .sparse = d->taa.sparse != 0 ? d->taa.sparse : sc->taa.sparse,
                                           .jitter_length = d->taa.jitter_length > 0 ? d->taa.jitter_length
                                                                                 : sc->taa.jitter_length,
                                           .no_object_motion = d->taa.no_object_motion,
                                           .no_disocclusion = d->taa.no_disocclusion,
                                           .neighbourhood = d->taa.neighbourhood,
                                           .history = d->taa.history,
                                           .nan_check = d->taa.nan},
                          .composite_per_pixel = d->composite_per_pixel, .no_ring_cull = d->no_ring_cull};
    if (session_foveation(d, sc) == FOVEATION_VRS) {
        if (!RUN_TAKES_VRS(d)) { /* the CLI's refused in cli_finish */
            log_error("%s: \"foveation\": \"vrs\": %s", sc->path, VRS_NOT_BUILT);
            return FS_ERR_USAGE;
        }
        out->vrs = true;
        session_vrs(d, sc, &out->vrs_spec, &out->vrs_tile);
    }
    fs_status st = resolve_layout(d, sc, d->width, d->height, &out->layout);
    return st == FS_OK ? resolve_ring_lod(d, sc, &out->layout, &out->ring_lod) : st;
}

fs_status session_build_plan(const run_desc *d, const scene *sc, plan *pl)
{
    plan_options po;
    fs_status st = session_plan_options(d, sc, &po);
    return st == FS_OK ? plan_build(sc, &po, pl) : st;
}


void session_end(session *s)
{
    renderer_destroy(s->r);
    gl_device_destroy();
    gaze_free(&s->gaze);
    pose_free(&s->head);
    scene_free(&s->sc);
}

/* The runs whose frames come from session_frame (CMDS_HEAD in the CLI). */
static bool replays_head(const run_desc *d)
{
    return d->cmd == CMD_RENDER || d->cmd == CMD_COMPARE || d->cmd == CMD_DEMO ||
           (d->cmd == CMD_BENCH && d->bench.accuracy);
}

/* The head recording's mean eye position and head orientation at time t, placed by pl (NULL: the
 * zero placement). */
static void head_pose(const session *s, const pose_place *pl, double t, pose_v3 *pos, pose_quat *q)
{
    pose_state l = pose_at(&s->head, POSE_LEFT, t, NULL), r = pose_at(&s->head, POSE_RIGHT, t, NULL);
    pose_v3 mid = {(l.pos.x + r.pos.x) * 0.5, (l.pos.y + r.pos.y) * 0.5, (l.pos.z + r.pos.z) * 0.5};
    pose_to_scene(&s->head, pl, mid, l.head, pos, q);
}

/* Without --head-place: the recording's first pose on the scene camera's start, its heading (the
 * horizontal part of where the head looks) along the camera's, 1 scene unit per metre. A turn by
 * a about +y takes heading h = atan2(x, -z) to h - a. */
static pose_place default_head_place(const session *s)
{
    pose_v3 p;
    pose_quat q;
    head_pose(s, NULL, 0.0, &p, &q);
    pose_v3 f = pose_qrot(q, (pose_v3){0, 0, -1});
    camera_state cam = camera_path_eval(&s->sc.camera, 0.0f);
    vec3 cf = v3_sub(cam.target, cam.position);
    pose_place pl = {{0, 0, 0}, (atan2(f.x, -f.z) - atan2(cf.x, -cf.z)) * (180.0 / FS_PI), 1.0};
    head_pose(s, &pl, 0.0, &p, NULL);
    pl.pos = (pose_v3){cam.position.x - p.x, cam.position.y - p.y, cam.position.z - p.z};
    return pl;
}

/* --head FILE, else the --gaze recording's head poses (an EyeNavGS file), unless --head off: one
 * line says which recording moves the camera (docs/hmd.md "Head replay"). */
static fs_status session_load_head(const run_desc *d, session *s)
{
    const char *path = d->head_path;
    if (path && !strcmp(path, "off"))
        return FS_OK;
    if (!path && (s->gaze.count == 0 || s->gaze.format != GAZE_FORMAT_EYENAV))
        return FS_OK;
    if (!replays_head(d)) { /* only a --gaze recording gets here: --head is refused elsewhere */
        log_info("%s: its head motion is replayed by render, compare, demo and bench --accuracy; fovsim %s keeps "
                 "the scene's camera", d->gaze_path, cli_command_name(d->cmd));
        return FS_OK;
    }
    fs_status st = pose_load(path ? path : d->gaze_path, NULL, &s->head);
    if (st != FS_OK)
        return st;
    s->head_place = d->head_place_set ? d->head_place : default_head_place(s);
    const pose_place *hp = &s->head_place;
    if (!d->quiet)
        printf("head: %s's head motion replaces the scene's camera path (%d frames, %.2f s%s; placed at %.3g,%.3g,%.3g, "
               "turned %.1f deg, %g units/m%s; --head off keeps the camera)\n", s->head.path, s->head.count,
               s->head.duration, s->head.has_scene ? ", its scene settings undone" : "", hp->pos.x, hp->pos.y,
               hp->pos.z, hp->yaw_deg, hp->scale, d->head_place_set ? "" : ": the scene camera's start");
    return FS_OK;
}

/* --gaze; in an eye's run of an hmd display, that eye's samples where the recording has both eyes
 * (EyeNavGS, binocular EyeLink) and --eye does not choose: each eye its own gaze. A recording of
 * one eye gives both eyes that eye's gaze. */
static fs_status load_gaze(const run_desc *d, session *s)
{
    gaze_load_desc gd = {.format = d->gaze_format, .eye = d->eye};
    fs_status st = gaze_load(d->gaze_path, &gd, &s->gaze);
    if (st != FS_OK || s->eye == 0 || d->eye != GAZE_EYE_AUTO ||
        (s->gaze.format != GAZE_FORMAT_EYENAV && s->gaze.format != GAZE_FORMAT_EYELINK))
        return st;
    gaze_trace one;
    gd.eye = s->eye == 1 ? GAZE_EYE_LEFT : GAZE_EYE_RIGHT;
    log_set_quiet_errors(true); /* a monocular EyeLink file lacks the other eye: it serves both */
    if (gaze_load(d->gaze_path, &gd, &one) == FS_OK) {
        gaze_free(&s->gaze);
        s->gaze = one;
    }
    log_set_quiet_errors(false);
    return FS_OK;
}

/* Scene, plan, gaze trace, GL context and (with `with_renderer`) the renderer: everything that can
 * reject bad input, before anything is written. */
fs_status session_begin(const run_desc *d, session *s, bool with_renderer)
{
    memset(s, 0, sizeof *s);
    fs_status st = session_load_scene(d, &s->sc);
    if (st != FS_OK)
        return st;
    st = session_build_plan(d, &s->sc, &s->pl);
    s->tracker = gaze_tracker_merge(&d->tracker, &s->sc.tracker);
    const hmd_desc *hmd = st == FS_OK && d->eye_run > 0 ? session_hmd(d, &s->sc) : NULL;
    if (hmd) {
        s->eye = d->eye_run;
        s->eye_offset = hmd->eye[s->eye - 1].position;
    }
    if (st == FS_OK && d->gaze_path)
        st = load_gaze(d, s);
    if (st == FS_OK && d->gaze_path) { /* by angle on the display frames are drawn for (gaze.h) */
        gaze_place_desc pd = gaze_place_merge(&d->place, &s->sc.gaze_place);
        display_desc at = display_resized(&s->sc.display, s->pl.width, s->pl.height);
        gaze_place(&s->gaze, &pd, &at);
    }
    if (st == FS_OK)
        st = session_load_head(d, s);
    if (st == FS_OK)
        st = gl_device_create(&(gl_device_desc){.gpu_index = d->gpu, .gl_debug = d->gl_debug});
    if (st == FS_OK) {
        log_info("SCENE: [%s] %d assets, %d instances, %.2f s camera path", s->sc.path, s->sc.asset_count,
                 s->sc.instance_count, s->sc.duration);
        if (s->gaze.count > 0)
            log_info("GAZE: [%s] %s, %d samples (%d valid) over %.2f s", s->gaze.path,
                     gaze_format_name(s->gaze.format), s->gaze.count, s->gaze.valid_count, s->gaze.duration);
        if (!gaze_tracker_is_ideal(&s->tracker)) {
            char tr[160];
            gaze_tracker_format(&s->tracker, tr, sizeof tr);
            log_info("GAZE: eye tracker %s; rings follow it, metrics the true gaze", tr);
        }
        if (with_renderer)
            s->r = renderer_create(&(renderer_desc){.scene = &s->sc, .plan = &s->pl}, &st);
    }
    if (st != FS_OK)
        session_end(s);
    return st;
}

/* The true gaze at `time`: the trace's, else the display centre. `warn`: say once when the trace
 * has ended. */
static gaze_point true_gaze(session *s, float time, bool warn)
{
    if (s->gaze.count == 0) { /* straight ahead: the principal point (the centre of a planar display) */
        const display_desc *d = &s->sc.display;
        return (gaze_point){0.5f + d->ppx / (float)d->width, 0.5f + d->ppy / (float)d->height, false};
    }
    bool beyond = false;
    gaze_point g = gaze_at(&s->gaze, time, &beyond);
    if (warn && beyond && !s->gaze_ended) {
        log_warn("%s: the gaze trace ends at %.2f s; frames after it hold its last gaze", s->gaze.path,
                 s->gaze.duration);
        s->gaze_ended = true;
    }
    return g;
}

static void set_frame_gaze(session *s, frame_record *fr, const fov_layout *l, const display_desc *d, float time,
                           bool warn)
{
    gaze_point g = true_gaze(s, time, warn);
    if (gaze_tracker_is_ideal(&s->tracker)) { /* the rings around the true gaze, as without a tracker */
        frame_record_set_gaze(fr, l, d, g.x, g.y);
        return;
    }
    gaze_delivery sys = gaze_tracker_at(&s->gaze, &s->tracker, d, time, NULL);
    frame_record_set_gaze(fr, l, d, sys.x, sys.y);
    frame_record_set_true_gaze(fr, d, g.x, g.y);
    if (sys.full)
        frame_record_set_full_res(fr, d);
}

void session_set_frame_gaze(session *s, frame_record *fr, const fov_layout *l, const display_desc *d, float time)
{
    set_frame_gaze(s, fr, l, d, time, false);
}

/* The frame's camera from the head recording: between the two eyes (their mean position), looking
 * along the head's orientation, placed into the scene (pose_trace.h). */
static frame_record head_frame(const session *s, int index, float time)
{
    pose_v3 pos;
    pose_quat q;
    if (s->eye > 0) { /* an hmd eye: the recorded eye's own position, the head's orientation */
        pose_state e = pose_at(&s->head, s->eye == 1 ? POSE_LEFT : POSE_RIGHT, time, NULL);
        pose_to_scene(&s->head, &s->head_place, e.pos, e.head, &pos, &q);
    } else {
        head_pose(s, &s->head_place, time, &pos, &q);
    }
    return frame_record_posed(&s->sc, index, time, v3((float)pos.x, (float)pos.y, (float)pos.z),
                              pose_view_matrix(pos, q), s->pl.width, s->pl.height);
}

/* An hmd eye on the scene's camera path: the camera is the head, the eye sits at its offset in the
 * head frame (view_eye = T(-offset) view). */
static frame_record eye_frame(const session *s, int index, float time, float prev_time)
{
    frame_record head = frame_record_at(&s->sc, index, time, prev_time, s->pl.width, s->pl.height);
    return frame_record_eye(&s->sc, &head, s->eye_offset, s->pl.width, s->pl.height);
}

/* Frame `index` with its gaze (from the trace, or straight ahead) and ring footprints. */
frame_record session_frame(session *s, int index, float time, float prev_time)
{
    frame_record fr = s->head.count > 0 ? head_frame(s, index, time)
                      : s->eye > 0      ? eye_frame(s, index, time, prev_time)
                                        : frame_record_at(&s->sc, index, time, prev_time, s->pl.width, s->pl.height);
    display_desc dd = frame_display(&fr, s->pl.width, s->pl.height);
    set_frame_gaze(s, &fr, &s->pl.layout, &dd, time, true);
    return fr;
}

void session_attrs(exr_image *img, const scene *sc, const plan *pl, const gaze_trace *gz, const frame_record *fr)
{
    exr_image_set_string(img, "fovsim:version", FOVSIM_VERSION);
    exr_image_set_string(img, "fovsim:renderer", gl_device_renderer());
    exr_image_set_string(img, "fovsim:scene", sc->path);
    exr_image_set_int(img, "fovsim:frame", fr->index);
    exr_image_set_float(img, "fovsim:time", fr->time);
    exr_image_set_v2f(img, "fovsim:gaze", fr->gaze[0], fr->gaze[1]);
    exr_image_set_v2f(img, "fovsim:gaze_deg", fr->gaze_deg[0], fr->gaze_deg[1]);
    if (fr->true_gaze[0] != fr->gaze[0] || fr->true_gaze[1] != fr->gaze[1] || fr->full_res) {
        /* only when the tracker moved the rings: frames without it stay as they were */
        exr_image_set_v2f(img, "fovsim:true_gaze", fr->true_gaze[0], fr->true_gaze[1]);
        exr_image_set_v2f(img, "fovsim:true_gaze_deg", fr->true_gaze_deg[0], fr->true_gaze_deg[1]);
        exr_image_set_int(img, "fovsim:full_res", fr->full_res);
    }
    exr_image_set_string(img, "fovsim:alpha_mode", alpha_mode_name(pl->global_mode));
    if (pl->ring_lod) { /* only when it changes pixels: frames without it stay as they were */
        char lod[160];
        ring_lod_format_u(&pl->ring_lod_spec, &pl->layout, lod, sizeof lod);
        exr_image_set_string(img, "fovsim:ring_lod_u", lod);
    }
    if (pl->alpha_lod_prims > 0) { /* only when it changes pixels, as ring LOD */
        char lods[256];
        plan_alpha_lod_format(pl, sc, lods, sizeof lods);
        exr_image_set_string(img, "fovsim:alpha_lod_max", lods);
    }
    char rings[256];
    fov_layout_format(&pl->layout, rings, sizeof rings);
    exr_image_set_string(img, "fovsim:rings", rings);
    if (pl->vrs) { /* only under VRS: other frames' headers stay as they were */
        char fov[192];
        plan_foveation_format(pl, fov, sizeof fov);
        exr_image_set_string(img, "fovsim:foveation", fov);
    }
    exr_image_set_string(img, "fovsim:gaze_trace", gz->count > 0 ? gz->path : "centre fixation");
    char taa[128];
    if (pl->taa)
        snprintf(taa, sizeof taa, "on: blend %.3f, gamma %.2f, jitter Halton(2,3) x %d", pl->taa_controls.blend,
                 pl->taa_controls.gamma, pl->taa_controls.jitter_length);
    else
        snprintf(taa, sizeof taa, "off");
    exr_image_set_string(img, "fovsim:taa", taa);
    exr_image_set_float(img, "fovsim:hfov_deg", fr->hfov_deg);
    exr_image_set_string(img, "fovsim:channels",
                         "RGBA: linear premultiplied radiance; coverage: opacity of alpha-mapped surfaces");
}

void session_frame_attrs(exr_image *img, const session *s, const frame_record *fr)
{
    session_attrs(img, &s->sc, &s->pl, &s->gaze, fr);
}


/* >>reference */

/* The reference cache of a run: --cache, else the default; NULL with --no-cache. */
const char *session_cache_dir(const run_desc *d, char *buf, int size)
{
    if (d->ref.no_cache)
        return NULL;
    if (d->ref.cache_dir)
        return d->ref.cache_dir;
    reference_default_cache_dir(buf, size);
    return buf;
}


static void on_ref_pass(void *user, int done, int total)
{
    (void)total;
    ref_progress *rp = user;
    progress_update(&rp->pr, rp->base + done);
}

reference *session_reference(const run_desc *d, const session *s, ref_progress *rp, fs_status *st)
{
    char buf[1024];
    reference_desc rd = {.width = s->pl.width, .height = s->pl.height, .supersample = d->ref.supersample,
                         .kind = d->ref.kind,
                         .samples = d->ref.samples, .list_mb = d->ref.memory_mb,
                         .cache_dir = session_cache_dir(d, buf, sizeof buf),
                         .on_pass = on_ref_pass, .user = rp};
    return reference_create(&s->sc, &rd, st);
}


void session_cpu_name(char *buf, size_t n)
{
    snprintf(buf, n, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            char *c = strchr(line, ':');
            if (c) {
                c += 2;
                c[strcspn(c, "\n")] = '\0';
                snprintf(buf, n, "%s", c);
            }
            break;
        }
    fclose(f);
}
