/* gaze.h: gaze traces — loading recorded and scripted traces, and resampling them to frame times.
 *
 * Formats (detected from the content; gaze_load_desc.format overrides):
 *   - fovsim CSV: header `t,x,y[,confidence]` (any column order, extra columns ignored), t in
 *     seconds, x, y normalised display coordinates with origin top-left.
 *   - Pupil Labs Player export `gaze_positions.csv`: gaze_timestamp (s), norm_pos_x, norm_pos_y
 *     (origin BOTTOM-left, flipped on load), confidence.
 *   - SR Research EyeLink ASC (edf2asc): sample lines `time x y pupil [xR yR pupilR] flags...`,
 *     time in ms, x, y in screen pixels (origin top-left), `.` for missing; screen size from
 *     DISPLAY_COORDS / GAZE_COORDS; several recording blocks; mono, binocular (eye chosen or
 *     averaged), remote-mode files with extra trailing fields. Parsed by the fields present on each
 *     line, not by the SAMPLES header.
 *   - Tobii Pro Glasses 2 livedata.json: one JSON object per line, streams interleaved and not in
 *     time order; gaze records {"ts" (us), "s" (0 = valid), "gp": [x, y]} normalised to the scene
 *     camera image, origin top-left.
 *   - EyeNavGS CSV (Meta Quest Pro head and both eyes, pose_trace.h): ViewIndex, FOV1..4, eye
 *     Position, head Quaternion, GazePos, GazeQ, Timestamp (ms); one L and one R row per frame.
 *     As a gaze trace: the eye-in-head gaze as per-sample directions (dir), x, y normalised in the
 *     eye's field of view; a recording without gaze (head pose only) fails.
 * Every trace becomes a list of samples sorted by time, re-based so the first sample is at t = 0,
 * with repeated timestamps averaged into one sample. Invalid samples (blinks, `.`, status != 0,
 * confidence below the threshold) are kept as invalid so resampling can hold the last good gaze.
 *
 * Errors: a bad trace fails before anything is drawn, with one line
 * `<file>:<line>:<column>: expected <what>, got <what>` (column = 1-based field number for CSV/ASC,
 * byte column for JSON) and FS_ERR_GAZE; a missing file is FS_ERR_IO. Time going backwards is an
 * error (except in Tobii files, whose streams interleave: they are sorted); NaN/Inf is an error.
 *
 * What it does NOT do: map gaze to rings (src/fov), fixation/saccade detection.
 */
#ifndef FOVSIM_GAZE_H
#define FOVSIM_GAZE_H

#include <stdbool.h>

#include "core/display.h"
#include "core/status.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gaze_format {
    GAZE_FORMAT_AUTO = 0,
    GAZE_FORMAT_CSV,     /* fovsim t,x,y[,confidence] */
    GAZE_FORMAT_PUPIL,   /* Pupil Labs gaze_positions.csv */
    GAZE_FORMAT_EYELINK, /* EyeLink ASC */
    GAZE_FORMAT_TOBII,   /* Tobii Pro Glasses 2 livedata.json */
    GAZE_FORMAT_EYENAV,  /* EyeNavGS head and both eyes (VR headset; pose_trace.h) */
} gaze_format;

typedef enum gaze_eye {
    GAZE_EYE_AUTO = 0, /* binocular: average the eyes that are valid; monocular: the recorded eye */
    GAZE_EYE_LEFT,
    GAZE_EYE_RIGHT,
    GAZE_EYE_AVERAGE,  /* binocular: both eyes must be valid, else the sample is invalid */
} gaze_eye;

typedef struct gaze_sample {
    double t;          /* seconds since the first sample */
    float x, y;        /* normalised display coordinates, origin top-left; NOT clamped. An invalid
                          sample holds the gaze to show in its place (the last valid one before it,
                          else the first valid one after, else 0.5): gaze_at relies on it to stay
                          one binary search */
    float confidence;  /* 0..1; 1 when the format has none */
    bool valid;        /* false for blinks, missing values, bad status, low confidence */
} gaze_sample;

typedef struct gaze_trace {
    char path[512];
    gaze_format format;
    gaze_sample *samples; /* sorted by t, strictly increasing after averaging repeats */
    int count;            /* >= 1 after a successful load */
    int valid_count;
    double duration;      /* t of the last sample */
    double time_offset;   /* seconds subtracted to re-base (the first raw timestamp, in seconds) */
    int screen_w, screen_h; /* recording screen in pixels when the file says (EyeLink), else 0 */
    /* The recording's geometry where the file says it (docs/gaze-formats.md, "degrees"), read by
     * gaze_place. A pinhole frame: normalised (x, y) looks along tan(theta_x) = (x - 0.5) * tan_per_x,
     * tan(theta_y) = (0.5 - y) * tan_per_y (theta_y up, straight ahead at the frame centre);
     * 0 = unknown. */
    double tan_per_x, tan_per_y;
    /* Per-sample directions where the format gives them (Pupil gaze_point_3d, Tobii gp3): tan(theta_x),
     * tan(theta_y) for sample i at dir[2i], dir[2i+1]; NaN for a sample without one; NULL if none has. */
    float *dir;
    char geometry[160]; /* how the geometry was derived, for the log; "" without */
} gaze_trace;

typedef struct gaze_load_desc {
    gaze_format format;     /* default AUTO */
    gaze_eye eye;           /* default AUTO */
    float min_confidence;   /* samples below are invalid; default 0.6 (Pupil Labs' recommendation);
                               negative = keep all */
} gaze_load_desc;

/* Placement of a trace on the simulated display (gaze_place). */
typedef enum gaze_map {
    GAZE_MAP_ANGLE = 0,  /* by visual angle: the recording's straight-ahead point at the display's centre */
    GAZE_MAP_NORMALIZED, /* by normalised position, as loaded */
} gaze_map;

/* --gaze-screen: the recording's geometry where the file lacks it; it wins over the file's. */
typedef enum gaze_screen_kind {
    GAZE_SCREEN_NONE = 0,
    GAZE_SCREEN_MM,  /* W_MMxH_MM@DIST_MM: a flat screen seen from DIST_MM in front of its centre */
    GAZE_SCREEN_FOV, /* HxVdeg: a pinhole camera frame of that field of view (scene cameras) */
} gaze_screen_kind;

typedef struct gaze_screen {
    gaze_screen_kind kind;
    double w, h;  /* MM: screen width, height (mm); FOV: horizontal, vertical field of view (deg) */
    double dist;  /* MM: viewing distance (mm) */
} gaze_screen;

typedef struct gaze_place_desc {
    gaze_map map;
    gaze_screen screen;
} gaze_place_desc;

/* As a command line or scene file gives them: each with whether it was given, so the command line
 * wins field by field over the scene file. */
typedef struct gaze_place_opts {
    gaze_place_desc desc;
    bool map_set, screen_set;
} gaze_place_opts;

#define GAZE_SCREEN_MAX_MM 1e6
#define GAZE_SCREEN_MAX_FOV_DEG 179.0

/* Parses --gaze-screen: "520x290@600" (mm) or "82x52deg". False with a message in err
 * ("expected ..., got ...") on anything else. */
bool gaze_screen_parse(const char *text, gaze_screen *out, char *err, size_t cap);
/* The text gaze_screen_parse reads back ("" for NONE). */
void gaze_screen_format(const gaze_screen *s, char *buf, size_t cap);
const char *gaze_map_name(gaze_map m); /* "angle", "normalized" */
gaze_place_desc gaze_place_merge(const gaze_place_opts *first, const gaze_place_opts *second);

/* Rewrites the samples' x, y from the recording's frame to the display's (GAZE_MAP_ANGLE): each
 * valid sample where its direction falls on a pinhole display of `disp` (width, height, hfov),
 * straight ahead at the centre; directions past the display's edge clamped to it with one warning.
 * The geometry: desc->screen if given, else the file's (per-sample directions, else tan_per_x/y);
 * without any the trace stays as loaded, said once with log_info. GAZE_MAP_NORMALIZED leaves it
 * untouched. Invalid samples hold the placed gaze again. */
void gaze_place(gaze_trace *t, const gaze_place_desc *desc, const display_desc *disp);

const char *gaze_format_name(gaze_format f); /* "csv", "pupil", "eyelink", "tobii", "eyenav", "auto" */
gaze_format gaze_format_parse(const char *name); /* AUTO for unknown names */

/* Loads a trace file, or a scripted trace compiled into the binary: "builtin:NAME" for
 * gaze_paths/NAME.csv (gaze_builtin_list() names them). */
fs_status gaze_load(const char *path, const gaze_load_desc *desc, gaze_trace *out);
/* Comma-separated names of the built-in traces. Borrowed, static. */
const char *gaze_builtin_list(void);
/* Parses a trace held in memory (same rules; `name` is used in messages). */
fs_status gaze_parse(const char *text, long size, const char *name, const gaze_load_desc *desc, gaze_trace *out);
void gaze_free(gaze_trace *t);

/* Gaze at time t (seconds since the trace start): linear interpolation between the valid samples
 * around t; inside a run of invalid samples, the last valid gaze before it is held (the first valid
 * one if the trace starts invalid); after the end, the last valid gaze is held. The result is
 * clamped to [0, 1]. `beyond_end` (may be NULL) tells whether t was past the last sample. A trace
 * with no valid sample gives the display centre. */
typedef struct gaze_point {
    float x, y;
    bool held;        /* the value was held (invalid run or past the end), not interpolated */
} gaze_point;
gaze_point gaze_at(const gaze_trace *t, double time, bool *beyond_end);
/* Index of the last sample at or before `time` (0 before the first; -1 for an empty trace). */
int gaze_sample_index(const gaze_trace *t, double time);

#ifdef __cplusplus
}
#endif

#endif
