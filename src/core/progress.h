/* progress.h: progress of multi-frame work on stderr, unless --quiet. On a terminal, the
 * `frame 12/96  5.1 fps  ETA 16s` line redrawn in place with '\r'; otherwise (a log file, a batch
 * job) a plain line at the first frame, at the first update after every `interval` seconds and at
 * the last frame, e.g.
 * `compare frame 12/97 (12%), 0.64 frames/s, 18.8 s elapsed, ETA 2m13s` (docs/compare.md "Progress in a log"). */
#ifndef FOVSIM_PROGRESS_H
#define FOVSIM_PROGRESS_H

#include <stdbool.h>

/* Seconds between the plain lines when stderr is not a terminal (--progress-interval). */
#define PROGRESS_INTERVAL_DEFAULT 10.0

typedef struct progress {
    bool enabled;
    bool tty;         /* redrawn in place; else a plain line per interval */
    int total;
    int per_frame;    /* units of `total` per frame (compare counts reference passes); 0 = frames */
    int last_done;    /* the frames of the last plain line: a line only when they advanced */
    double start;     /* seconds, monotonic */
    double last_draw; /* throttles redraws to 10 per second, plain lines to one per interval */
    double interval;  /* seconds between plain lines */
    const char *label;
    const char *frame_label; /* the plain line's label when per_frame is set */
} progress;

/* Monotonic clock in seconds. */
double time_now(void);
/* `interval`: seconds between plain lines off a terminal (0: one per update that advanced the
 * count; negative: PROGRESS_INTERVAL_DEFAULT). */
progress progress_begin(const char *label, int total, bool quiet, double interval);
/* The count is `units` per frame (compare's reference passes): the plain line counts frames,
 * under `label`. */
void progress_per_frame(progress *p, int units, const char *label);
void progress_update(progress *p, int done);
/* Clears the line (when redrawn in place). */
void progress_end(progress *p);

#endif
