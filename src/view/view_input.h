/* view_input.h: what the viewer's keys do, and scripted input (`fovsim view --script FILE`).
 *
 * Keys are named as gl_window names them ("A", "SPACE", "LEFT_BRACKET", ...); view_key_action maps
 * a name to an action, and the same names are what a script's `key NAME` lines use, so a script
 * presses exactly the keys a user would.
 *
 * A script is a text file, one event per line (docs/viewer.md):
 *   # comment                 blank lines and '#' comments are ignored
 *   frame N                   the events below apply to the N-th frame the viewer draws (0-based,
 *                             non-decreasing); events before any `frame` line apply to frame 0
 *   move X Y                  the cursor at normalised display coordinates X, Y in [0, 1] (origin
 *                             top-left), as the gaze
 *   move Xpx Ypx              the cursor at window coordinates in pixels (goes through the same
 *                             window-to-display mapping as the real mouse)
 *   leave                     the cursor leaves the window (the gaze holds; recorded as invalid)
 *   resize W H                the window resized to W x H screen coordinates (16..MAX_DISPLAY_SIZE),
 *                             as a user dragging its border would
 *   key NAME                  a key press
 *   capture                   write the frame once drawn (as the P key does)
 *   quit                      close the window after the frame (and its captures)
 * All events of frame N apply, in file order, before frame N is drawn; capture and quit act after it.
 * A bad line is one error `<file>:<line>: expected <what>, got '<text>'` and FS_ERR_USAGE.
 *
 * Pure C, no GL: the unit tests parse scripts directly.
 * What it does NOT do: timing by wall clock (frames only, so runs are deterministic).
 */
#ifndef FOVSIM_VIEW_INPUT_H
#define FOVSIM_VIEW_INPUT_H

#include <stdbool.h>

#include "core/status.h"

typedef enum view_action {
    VIEW_ACT_NONE = 0,
    VIEW_ACT_ALPHA_NEXT,     /* A: next alpha mode (left-hand side in a split) */
    VIEW_ACT_TAA,            /* T: TAA on/off */
    VIEW_ACT_FOVEATION,      /* F: foveation on/off (back to the last ring layout) */
    VIEW_ACT_LAYOUT_NEXT,    /* L: ring layout: the run's, auto, aggressive, off */
    VIEW_ACT_BIAS_DOWN,      /* [: mip bias -0.5 on every ring */
    VIEW_ACT_BIAS_UP,        /* ]: mip bias +0.5 */
    VIEW_ACT_OVERLAY,        /* O: ring borders and gaze marker */
    VIEW_ACT_RING_LOD,       /* D: ring LOD on/off (docs/ring-lod.md) */
    VIEW_ACT_FREEZE,         /* C: freeze the camera (gaze and time go on) */
    VIEW_ACT_RESET_HISTORY,  /* H: drop the TAA history */
    VIEW_ACT_SPLIT,          /* S: split screen on/off */
    VIEW_ACT_SPLIT_NEXT,     /* M: next alpha mode on the right-hand side */
    VIEW_ACT_RECORD,         /* R: start/stop recording the gaze */
    VIEW_ACT_CAPTURE,        /* P: capture the frame as EXR */
    VIEW_ACT_PAUSE,          /* SPACE: pause/resume time (camera and replayed trace) */
    VIEW_ACT_STEP,           /* N or RIGHT: one frame forward while paused */
    VIEW_ACT_QUIT,           /* ESCAPE or Q */
} view_action;

/* The action of a key name (case-insensitive), VIEW_ACT_NONE for a key without one. */
view_action view_key_action(const char *name);
/* Help text: one line per key ("  A            next alpha mode\n" ...). Static. */
const char *view_key_help(void);

typedef enum view_event_kind {
    VIEW_EV_MOVE = 0,  /* x, y normalised display coordinates */
    VIEW_EV_MOVE_PX,   /* x, y window coordinates */
    VIEW_EV_LEAVE,
    VIEW_EV_RESIZE,    /* x, y window size */
    VIEW_EV_KEY,       /* key */
    VIEW_EV_CAPTURE,
    VIEW_EV_QUIT,
} view_event_kind;

typedef struct view_event {
    int frame;           /* drawn-frame number it applies to */
    view_event_kind kind;
    float x, y;
    char key[16];        /* upper-case key name (VIEW_EV_KEY) */
    int line;            /* 1-based line in the script */
} view_event;

typedef struct view_script {
    char path[512];
    view_event *events;  /* sorted by frame (file order within a frame) */
    int count;
} view_script;

/* Parses a script held in memory; `name` is used in messages. */
fs_status view_script_parse(const char *text, long size, const char *name, view_script *out);
/* Reads and parses a script file (FS_ERR_IO with one line when it cannot be read). */
fs_status view_script_load(const char *path, view_script *out);
/* No-op on a zeroed script. */
void view_script_free(view_script *s);

#endif
