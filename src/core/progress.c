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

progress progress_begin(const char *label, int total, bool quiet)
{
    progress p = {0};
    p.enabled = !quiet && total > 1 && isatty(STDERR_FILENO);
    p.total = total;
    p.start = time_now();
    p.label = label;
    return p;
}

void progress_update(progress *p, int done)
{
    if (!p->enabled)
        return;
    double now = time_now();
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
    if (p->enabled)
        fprintf(stderr, "\r%60s\r", "");
}
