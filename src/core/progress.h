/* progress.h: the `frame 12/96  5.1 fps  ETA 16s` line on stderr for multi-frame work.
 * Shown only when stderr is a terminal and not --quiet; redrawn in place with '\r'. */
#ifndef FOVSIM_PROGRESS_H
#define FOVSIM_PROGRESS_H

#include <stdbool.h>

typedef struct progress {
    bool enabled;
    int total;
    double start;     /* seconds, monotonic */
    double last_draw; /* throttles redraws to 10 per second */
    const char *label;
} progress;

/* Monotonic clock in seconds. */
double time_now(void);
progress progress_begin(const char *label, int total, bool quiet);
void progress_update(progress *p, int done);
/* Clears the line (when shown). */
void progress_end(progress *p);

#endif
