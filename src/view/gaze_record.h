/* gaze_record.h: writing a gaze trace as fovsim CSV while the viewer runs (the R key).
 *
 * The file is `t,x,y,confidence` (docs/gaze-formats.md), t in seconds from the first sample, x, y
 * normalised display coordinates (origin top-left), confidence 1 while the cursor is over the
 * image and 0 when it is not (the loader treats those samples as a blink: the gaze holds). It is
 * valid at every moment it exists under its name: it is written under a temporary name and renamed
 * once it holds its header, comments and first sample, and every later sample is one complete
 * line flushed at once, so a window closed (or a process killed) mid-recording leaves a trace that
 * gaze_load reads, ending at the last frame drawn.
 * t is written with 17 significant digits (round-trips the double the loader reads) and x, y with
 * 9 (round-trips a float): replaying the trace in `fovsim render` gives each frame exactly the gaze
 * it had in the viewer, not an interpolation a rounding error away from it.
 *
 * What it does NOT do: choose file names (the viewer does), resample (one sample per frame).
 */
#ifndef FOVSIM_GAZE_RECORD_H
#define FOVSIM_GAZE_RECORD_H

#include <stdbool.h>
#include <stdio.h>

#include "core/status.h"

typedef struct gaze_recorder {
    char path[1024];
    char comment[512];  /* '#' lines written after the header (may be empty) */
    FILE *f;            /* NULL until the first sample */
    int samples;
    double last_t;
} gaze_recorder;

/* Prepares a recording to `path`; nothing is written before the first sample. `comment` (may be
 * NULL) is written as '#' comment lines, one per '\n'-separated line. */
void gaze_recorder_begin(gaze_recorder *r, const char *path, const char *comment);
/* Appends one sample (t must increase; a sample not after the last is dropped); creates the file
 * with the first. One line and FS_ERR_IO when the file cannot be written (the recording is then
 * closed, what was written before stays valid). */
fs_status gaze_recorder_add(gaze_recorder *r, double t, float x, float y, bool valid);
/* Closes the file (if any); FS_ERR_IO when the final close fails. */
fs_status gaze_recorder_end(gaze_recorder *r);
bool gaze_recorder_is_open(const gaze_recorder *r);

#endif
