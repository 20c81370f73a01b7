/* pose_trace.h: head and both eyes recorded by a VR headset (EyeNavGS, Meta Quest Pro), per eye a
 * time-sorted list of poses; resampling them to frame times; each eye's gaze in the head; the
 * recording's world placed into a scene; each eye's view matrix.
 *
 * Conventions (OpenXR, as the recording): right-handed, +x right, +y up, -z forward, for the world,
 * the head (view) frame and the gaze frame. Quaternions are (x, y, z, w), Hamilton product, rotating
 * column vectors: v' = q v conj(q). The reader is gaze_eyenav.c; the format, the conventions and
 * what fovsim does with them: docs/gaze-formats.md ("EyeNavGS").
 *
 * What it does NOT do: draw anything, choose the camera of a run (the owner's --head), display
 * models (src/hmd/).
 */
#ifndef FOVSIM_POSE_TRACE_H
#define FOVSIM_POSE_TRACE_H

#include <stdbool.h>
#include <stddef.h>

#include "core/fmath.h"
#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pose_v3 { double x, y, z; } pose_v3;
typedef struct pose_quat { double x, y, z, w; } pose_quat;

enum { POSE_LEFT = 0, POSE_RIGHT = 1 };

/* XrFovf order: angles of the frustum's left, right, down, up edges from the eye's forward axis,
 * radians; left and down are negative for a frustum around forward. */
enum { POSE_FOV_LEFT = 0, POSE_FOV_RIGHT, POSE_FOV_DOWN, POSE_FOV_UP };

typedef struct pose_sample {
    double t;          /* seconds since the first frame (its left row's Timestamp) */
    pose_v3 pos;       /* eye position, the recording's world units */
    pose_quat head;    /* head (view) orientation in the world: unit, sign continuous per eye */
    pose_quat gaze;    /* gaze orientation in the world: unit, in the head's hemisphere. A sample
                          without gaze holds head * (the eye-in-head rotation of the last valid
                          sample before it, else the first valid after, else identity) */
    bool gaze_valid;   /* false: GazeQ identity and GazePos 0 (the tracker gave nothing) */
    float fov[4];      /* POSE_FOV_* */
    long line;         /* the row's line in the file */
} pose_sample;

/* A recording's scene settings (scene_setting.csv): q_scene maps world directions to a
 * gravity-aligned frame (v_grav = rot(tilt, v_world)); positions are metres x scale about initial. */
typedef struct pose_scene {
    char name[64];
    pose_quat tilt;
    double scale;
    pose_v3 initial;
} pose_scene;

typedef struct pose_trace {
    char path[512];
    pose_sample *eye[2]; /* POSE_LEFT, POSE_RIGHT: one sample per frame each, same times */
    int count;           /* frames (samples per eye), >= 1 after a successful load */
    double duration;     /* t of the last frame */
    double time_offset;  /* seconds subtracted to re-base (the first row's Timestamp) */
    double r_delay_median, r_delay_max; /* s: the right row's Timestamp after its frame's left row's */
    bool has_gaze;       /* false: no row has gaze (head pose only), said by one warning at load */
    int gaze_valid_count[2];
    bool has_scene;      /* scene settings known (beside the file, or given) */
    pose_scene scene;    /* identity tilt, scale 1, initial 0 without */
} pose_trace;

typedef struct pose_load_desc {
    /* The scene settings to use (wins over scene_setting.csv beside the file); NULL: look there. */
    const pose_scene *scene;
} pose_load_desc;

/* Loads an EyeNavGS CSV (`user<ID>_<scene>.csv`). Scene settings: desc->scene, else the row named
 * <scene> of scene_setting.csv in the same folder when both exist (info line), else none (info
 * line): the recording's world is used as is. Errors: one line `file:line:column: expected ...,
 * got ...`, FS_ERR_GAZE; a missing file FS_ERR_IO. out is zeroed on failure. */
fs_status pose_load(const char *path, const pose_load_desc *desc, pose_trace *out);
/* The same on a text in memory; `name` names it in messages and gives the scene name. */
fs_status pose_parse(const char *text, long size, const char *name, const pose_load_desc *desc, pose_trace *out);
void pose_free(pose_trace *t);

/* One row of scene_setting.csv, `Name,"qx, qy, qz, qw",scale,"ix,iy,iz"` (blanks allowed, quotes
 * optional around single numbers). False with "expected ..., got ..." in err. */
bool pose_scene_parse_row(const char *row, size_t n, pose_scene *out, char *err, size_t cap);
/* The row named `scene` of a scene_setting.csv text (BOM and header skipped). FS_OK, or
 * FS_ERR_GAZE with one line naming file:line (or that no row has the name). */
fs_status pose_scene_find(const char *text, size_t size, const char *file, const char *scene, pose_scene *out);

/* >>resampling */

typedef struct pose_state {
    pose_v3 pos;
    pose_quat head, gaze; /* unit */
    float fov[4];
    bool gaze_valid;      /* false: the gaze is held (an invalid run, or none at all) */
    bool held;            /* before the first or after the last frame, or the gaze held */
} pose_state;

/* Eye `eye` (POSE_LEFT / POSE_RIGHT) at time t (s since the first frame), gaze_at's rules: before
 * the first frame the first, after the last the last (*beyond_end, may be NULL, set); between two
 * frames positions linear, orientations slerp on the shorter arc, exact at the frames; no gap is
 * too long to interpolate across (gaze_at has no such rule either). The gaze between a valid and an
 * invalid frame, or in an invalid run: the earlier frame's eye-in-head rotation held on the
 * interpolated head. FOV: the earlier frame's. */
pose_state pose_at(const pose_trace *t, int eye, double time, bool *beyond_end);

/* >>quaternions */

pose_quat pose_qmul(pose_quat a, pose_quat b);       /* Hamilton product a * b (b applies first) */
pose_quat pose_qconj(pose_quat q);
pose_quat pose_qnorm(pose_quat q);                   /* unit; identity for a zero quaternion */
pose_v3 pose_qrot(pose_quat q, pose_v3 v);           /* q v conj(q) */
pose_quat pose_slerp(pose_quat a, pose_quat b, double f); /* shorter arc, unit, exact at f = 0, 1 */
pose_quat pose_qaxis(pose_v3 axis, double radians);  /* rotation about a unit axis */

/* >>eye in head */

/* conj(head) * gaze: the eye's rotation in the head frame. */
pose_quat pose_eye_in_head(pose_quat head, pose_quat gaze);
/* The gaze direction in the head frame: rotate(eye_in_head, (0, 0, -1)), unit. */
pose_v3 pose_gaze_dir(pose_quat head, pose_quat gaze);
/* Angles of a head-frame direction, radians: yaw = atan2(d.x, -d.z) (+ right), pitch =
 * atan2(d.y, hypot(d.x, d.z)) (+ up), eccentricity = the angle from -z. Any may be NULL. */
void pose_dir_angles(pose_v3 d, double *yaw, double *pitch, double *eccentricity);

/* >>placement */

/* Where the recording goes in a scene: after undoing the recording's tilt and scale (metres,
 * gravity-aligned, about Initial_Position), rotate by yaw_deg about +y, multiply by scale (scene
 * units per metre; 0 counts as 1), move by pos. The zero value places the initial position at the
 * scene's origin, 1 unit per metre. */
typedef struct pose_place {
    pose_v3 pos;
    double yaw_deg;
    double scale;
} pose_place;

/* A pose of the recording's world (position, orientation) in the scene. */
void pose_to_scene(const pose_trace *t, const pose_place *pl, pose_v3 pos, pose_quat q, pose_v3 *pos_out,
                   pose_quat *q_out);
/* World -> eye matrix of a camera at pos with orientation q (the eye looks along q's -z, q's +y
 * up): fovsim's view convention (m4_look_at's). */
mat4 pose_view_matrix(pose_v3 pos, pose_quat q);
/* Eye `eye`'s view matrix at time t, placed by pl (NULL: the zero placement). */
mat4 pose_eye_view(const pose_trace *t, const pose_place *pl, int eye, double time);

#ifdef __cplusplus
}
#endif

#endif
