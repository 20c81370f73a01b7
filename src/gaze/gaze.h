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

#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum gaze_format {
    GAZE_FORMAT_AUTO = 0,
    GAZE_FORMAT_CSV,     /* fovsim t,x,y[,confidence] */
    GAZE_FORMAT_PUPIL,   /* Pupil Labs gaze_positions.csv */
    GAZE_FORMAT_EYELINK, /* EyeLink ASC */
    GAZE_FORMAT_TOBII,   /* Tobii Pro Glasses 2 livedata.json */
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
} gaze_trace;

typedef struct gaze_load_desc {
    gaze_format format;     /* default AUTO */
    gaze_eye eye;           /* default AUTO */
    float min_confidence;   /* samples below are invalid; default 0.6 (Pupil Labs' recommendation);
                               negative = keep all */
} gaze_load_desc;

const char *gaze_format_name(gaze_format f); /* "csv", "pupil", "eyelink", "tobii", "auto" */
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
