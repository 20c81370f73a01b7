/* proc_stats.c: minor page faults and CPU time of the process (proc_stats.h). */
#include "core/proc_stats.h"

#include <sys/resource.h>
#include <time.h>

proc_stats proc_stats_now(void)
{
    proc_stats s = {-1, -1, -1.0};
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) == 0) {
        s.minor_faults = (long long)ru.ru_minflt;
        s.major_faults = (long long)ru.ru_majflt;
    }
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) == 0)
        s.cpu_ms = (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
    return s;
}

proc_stats proc_stats_diff(proc_stats later, proc_stats earlier)
{
    proc_stats d;
    d.minor_faults = later.minor_faults < 0 || earlier.minor_faults < 0 ? -1 : later.minor_faults - earlier.minor_faults;
    d.major_faults = later.major_faults < 0 || earlier.major_faults < 0 ? -1 : later.major_faults - earlier.major_faults;
    d.cpu_ms = later.cpu_ms < 0 || earlier.cpu_ms < 0 ? -1.0 : later.cpu_ms - earlier.cpu_ms;
    return d;
}

proc_stats proc_stats_since(proc_stats start)
{
    return proc_stats_diff(proc_stats_now(), start);
}
