/* session.h: what the commands (src/commands/) share. A session holds the inputs of one run, all
 * loaded and checked before any output is touched, so bad input leaves nothing behind. */
#ifndef FOVSIM_SESSION_H
#define FOVSIM_SESSION_H

#include <stdbool.h>
#include <stddef.h>

#include "cli/cli.h"
#include "core/progress.h"
#include "core/stats.h" /* stats_cmp_double, stats_quantile: the commands' summaries */
#include "gaze/gaze.h"
#include "gaze/pose_trace.h"
#include "output/exr_write.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "reference/reference.h"
#include "frame/frame.h"
#include "scene/scene.h"

typedef struct session {
    scene sc;
    plan pl;
    renderer *r;
    gaze_trace gaze;    /* count == 0: no trace, fixation at the centre */
    bool gaze_ended;    /* the "trace ends before the sequence" note was printed */
    gaze_tracker_desc tracker; /* the eye tracker between the true gaze and the renderer: the CLI's
                                  --gaze-* over the scene file's "gaze" (all 0: the true gaze) */
    pose_trace head;    /* count > 0: a recording's head motion replaces the scene's camera path */
    pose_place head_place; /* --head-place: the recording's world in the scene */
    int eye;            /* an hmd display's eye this run draws: 1 left, 2 right (run_desc.eye_run); 0: planar */
    vec3 eye_offset;    /* that eye's position in the head frame (metres; the scene camera path's runs) */
} session;

/* Ctrl-C sets a flag the frame loops check, so they stop between complete frames. */
void session_catch_sigint(void);
bool session_interrupted(void);

/* The scene of a run, loaded and checked; a command other than plan given an hmd display
 * (--display or the scene's "display") refuses it here: one line, FS_ERR_USAGE (docs/hmd.md). */
fs_status session_load_scene(const run_desc *d, scene *sc);
/* The run's hmd: --display, else the scene's "display"; NULL for a planar display. */
/* Whether the run's display (--display, else the scene's) is an hmd: render and compare then run
 * once per eye (d->eye_run). Loads the scene to see; FS_OK or the scene's error. */
fs_status session_display_is_hmd(const run_desc *d, bool *hmd);
const hmd_desc *session_hmd(const run_desc *d, const scene *sc);
/* --frames, else the camera path at --fps (at least 1, at most MAX_FRAMES). */
int session_frame_count(const run_desc *d, const scene *sc);
/* How a run foveates: --foveation, else rings where --rings is given, else the scene's
 * "foveation", else rings. */
foveation_kind session_foveation(const run_desc *d, const scene *sc);
/* The VRS rate map of a run: --vrs, else the scene's "vrs", else auto; the tile: --vrs-tile, else
 * the scene's "vrs_tile", else VRS_TILE_DEFAULT. */
void session_vrs(const run_desc *d, const scene *sc, vrs_spec *spec, int *tile);
/* The plan options of a run: --alpha, the size, TAA and alpha controls (the CLI's, else the
 * scene's), and the ring layout (--rings, else the scene's, else auto; auto falls back to off where
 * it would not save pixels; off with foveation off). One line and FS_ERR_USAGE for a bad layout,
 * and for VRS foveation in a command that does not draw it (VRS_NOT_BUILT); under VRS the options
 * carry the rate map's rule and tile. */
fs_status session_plan_options(const run_desc *d, const scene *sc, plan_options *out);
/* plan_build of those options. */
fs_status session_build_plan(const run_desc *d, const scene *sc, plan *pl);
/* Scene, plan, gaze trace, GL context and (with `with_renderer`) the renderer: everything that can
 * reject bad input, before anything is written. */
fs_status session_begin(const run_desc *d, session *s, bool with_renderer);
void session_end(session *s);
/* Frame `index` with its gaze (from the trace, or the centre) and ring footprints: the rings
 * around the gaze the eye tracker delivers (s->tracker), the true gaze beside it (frame.h). */
frame_record session_frame(session *s, int index, float time, float prev_time);
/* The same gaze for a frame record of another layout or size (bench's configurations): sets the
 * rendered and the true gaze of `fr` for layout `l` on display `d` at `time`. */
void session_set_frame_gaze(session *s, frame_record *fr, const fov_layout *l, const display_desc *d, float time);
/* The header attributes of a rendered frame (version, renderer, scene, gaze, mode, rings, TAA). */
void session_attrs(exr_image *img, const scene *sc, const plan *pl, const gaze_trace *gz, const frame_record *fr);
void session_frame_attrs(exr_image *img, const session *s, const frame_record *fr);
/* The machine's CPU model ("unknown CPU" when /proc/cpuinfo does not say). */
void session_cpu_name(char *buf, size_t n);

/* >>reference */

/* The reference cache of a run: --cache, else the default; NULL with --no-cache. */
const char *session_cache_dir(const run_desc *d, char *buf, int size);
/* Progress of reference passes across a whole sequence. */
typedef struct ref_progress {
    progress pr;
    int base; /* passes of the frames before this one */
} ref_progress;
/* The run's reference (--supersample, --samples, cache) at the plan's size; passes report to rp. */
reference *session_reference(const run_desc *d, const session *s, ref_progress *rp, fs_status *st);

#endif
