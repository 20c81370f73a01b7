/* proc_stats.h: what a stretch of code cost the process, beside wall time: minor page faults
 * (fresh memory touched: allocator churn, mmap'd buffers) and CPU time. Pure C, no GL.
 *
 * Usage:
 *   proc_stats a = proc_stats_now();  ...work...  proc_stats d = proc_stats_since(a);
 *   d.minor_faults, d.cpu_ms
 *
 * Both counters are the whole process's: every thread (llvmpipe's rasteriser threads included),
 * not just the caller's, so a frame's CPU time on a software renderer is the rasterising too, and
 * may exceed its wall time on several cores. A counter that cannot be read is -1.
 */
#ifndef FOVSIM_PROC_STATS_H
#define FOVSIM_PROC_STATS_H

typedef struct proc_stats {
    long long minor_faults; /* getrusage(RUSAGE_SELF).ru_minflt: page faults served without I/O */
    long long major_faults; /* ru_majflt: page faults that read from disk */
    double cpu_ms;          /* clock_gettime(CLOCK_PROCESS_CPUTIME_ID): user + system, all threads */
} proc_stats;

/* The counters since the process started. */
proc_stats proc_stats_now(void);
/* later - earlier, counter by counter; -1 where either is -1. */
proc_stats proc_stats_diff(proc_stats later, proc_stats earlier);
/* proc_stats_diff(proc_stats_now(), start). */
proc_stats proc_stats_since(proc_stats start);

#endif
