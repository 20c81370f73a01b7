#include "core/progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

double time_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

progress progress_begin(const char *label, int total, bool quiet, double interval)
{
    progress p = {0};
    p.tty = isatty(STDERR_FILENO);
    p.enabled = !quiet && total > 1;
    p.total = total;
    p.start = time_now();
    p.last_draw = p.start;
    p.interval = interval < 0.0 ? PROGRESS_INTERVAL_DEFAULT : interval;
    p.label = label;
    return p;
}

void progress_per_frame(progress *p, int units, const char *label)
{
    p->per_frame = units > 0 ? units : 0;
    p->frame_label = label;
}

/* "2m13s", "16s", "1h05m". */
static void put_duration(char *buf, size_t n, double s)
{
    long t = (long)(s + 0.5);
    if (t >= 3600)
        snprintf(buf, n, "%ldh%02ldm", t / 3600, t / 60 % 60);
    else if (t >= 60)
        snprintf(buf, n, "%ldm%02lds", t / 60, t % 60);
    else
        snprintf(buf, n, "%lds", t);
}

/* One line for a log: `LABEL D/T (P%), R frames/s, E s elapsed, ETA X` (every label counts frames),
 * `FRAME_LABEL frame D/T ...` when the count is per_frame units a frame. */
static void plain_line(const progress *p, int done, double el)
{
    double unit = p->per_frame ? (double)p->per_frame : 1.0;
    double d = done / unit, t = p->total / unit;
    double rate = el > 0 ? d / el : 0;
    char eta[32];
    if (rate > 0)
        put_duration(eta, sizeof eta, (t - d) / rate);
    else
        snprintf(eta, sizeof eta, "unknown");
    fprintf(stderr, "%s%s %d/%d (%d%%), %.2f frames/s, %.1f s elapsed, ETA %s\n",
            p->per_frame ? p->frame_label : p->label, p->per_frame ? " frame" : "", (int)d, (int)t,
            (int)(100.0 * done / p->total), rate, el, eta);
    fflush(stderr);
}

void progress_update(progress *p, int done)
{
    if (!p->enabled)
        return;
    double now = time_now();
    if (!p->tty) {
        /* A line only when a frame was added: the first (the log shows the run started, and its
         * rate), then the first after each interval, and the last (the log ends complete). */
        int frames = p->per_frame ? done / p->per_frame : done;
        int all = p->per_frame ? p->total / p->per_frame : p->total;
        bool due = p->last_done == 0 || frames >= all || now - p->last_draw >= p->interval;
        if (frames > p->last_done && due) {
            p->last_draw = now;
            p->last_done = frames;
            plain_line(p, done, now - p->start);
        }
        return;
    }
    if (done < p->total && now - p->last_draw < 0.1)
        return;
    p->last_draw = now;
    double el = now - p->start;
    double fps = el > 0 ? done / el : 0;
    double eta = fps > 0 ? (p->total - done) / fps : 0;
    fprintf(stderr, "\r%s %d/%d  %.1f fps  ETA %.0fs   ", p->label, done, p->total, fps, eta);
    fflush(stderr);
}

void progress_end(progress *p)
{
    if (p->enabled && p->tty)
        fprintf(stderr, "\r%60s\r", "");
}
