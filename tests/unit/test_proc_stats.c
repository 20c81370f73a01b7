/* test_proc_stats.c: the frame-loop counters of bench (src/core/proc_stats.c) see what they claim
 * to: a loop that maps and touches fresh pages every "frame" faults at least once per page per
 * frame, one that reuses a buffer does (nearly) not; CPU time grows with a busy loop and not with
 * a sleep. Each check fails for a counter that reads the wrong field, the wrong clock (wall time)
 * or nothing. */
#define _DEFAULT_SOURCE /* MAP_ANONYMOUS, madvise */
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include "core/proc_stats.h"
#include "test.h"

enum { PAGES = 64, FRAMES = 20 };

static double wall_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* getrusage's user + system time (ms): an oracle independent of proc_stats' clock_gettime. */
static double rusage_cpu_ms(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 +
           (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) * 1e-3;
}

static void touch(volatile unsigned char *p, size_t bytes, size_t page, unsigned char v)
{
    for (size_t i = 0; i < bytes; i += page)
        p[i] = v;
}

static unsigned char *map_pages(size_t bytes)
{
    void *p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
        return NULL;
#ifdef MADV_NOHUGEPAGE
    madvise(p, bytes, MADV_NOHUGEPAGE); /* one fault per 4 KiB page, not one per 2 MiB */
#endif
    return p;
}

TEST(fresh_pages_fault_every_frame)
{
    size_t page = (size_t)sysconf(_SC_PAGESIZE), bytes = PAGES * page;
    long long total = 0;
    for (int f = 0; f < FRAMES; f++) {
        proc_stats s = proc_stats_now();
        unsigned char *p = map_pages(bytes);
        CHECK(p != NULL);
        if (!p)
            return;
        touch(p, bytes, page, (unsigned char)f);
        munmap(p, bytes);
        proc_stats d = proc_stats_since(s);
        CHECK(d.minor_faults >= PAGES);
        total += d.minor_faults;
    }
    CHECK(total >= (long long)PAGES * FRAMES);
}

TEST(reused_buffer_does_not_fault)
{
    size_t page = (size_t)sysconf(_SC_PAGESIZE), bytes = PAGES * page;
    unsigned char *p = map_pages(bytes);
    CHECK(p != NULL);
    if (!p)
        return;
    touch(p, bytes, page, 1); /* faulted in once, outside the frames */
    long long total = 0;
    for (int f = 0; f < FRAMES; f++) {
        proc_stats s = proc_stats_now();
        memset(p, f, bytes);
        proc_stats d = proc_stats_since(s);
        CHECK(d.minor_faults >= 0);
        total += d.minor_faults;
    }
    munmap(p, bytes);
    /* Fresh pages would be PAGES (64) per frame, 1280 in all; allow a few stray faults (NUMA
     * balancing's hinting faults count as minor faults too). */
    CHECK(total <= 8);
}

TEST(cpu_time_grows_with_work)
{
    proc_stats s = proc_stats_now();
    double t0 = wall_ms(), r0 = rusage_cpu_ms();
    volatile double x = 0;
    while (rusage_cpu_ms() - r0 < 60.0) /* 60 ms of CPU, however long the loaded machine takes */
        for (int i = 0; i < 10000; i++)
            x += 1e-9 * i;
    proc_stats d = proc_stats_since(s);
    double wall = wall_ms() - t0;
    CHECK(d.cpu_ms >= 55.0);
    CHECK(d.cpu_ms <= wall + 1.0); /* one thread: never more CPU than wall time */
    (void)x;
}

TEST(cpu_time_does_not_grow_with_sleep)
{
    proc_stats s = proc_stats_now();
    double t0 = wall_ms();
    struct timespec ts = {0, 150 * 1000 * 1000};
    while (nanosleep(&ts, &ts) != 0) {
    }
    proc_stats d = proc_stats_since(s);
    CHECK(wall_ms() - t0 >= 149.0);
    CHECK(d.cpu_ms >= 0.0);
    CHECK(d.cpu_ms < 20.0);
    CHECK(d.minor_faults >= 0 && d.minor_faults < 4);
}

TEST(unknown_stays_unknown)
{
    proc_stats a = {10, 0, 5.0}, b = {-1, -1, -1.0};
    proc_stats d = proc_stats_diff(a, b);
    CHECK(d.minor_faults == -1 && d.major_faults == -1 && d.cpu_ms < 0);
    d = proc_stats_diff(b, a);
    CHECK(d.minor_faults == -1 && d.cpu_ms < 0);
    d = proc_stats_diff((proc_stats){15, 1, 7.5}, a);
    CHECK(d.minor_faults == 5 && d.major_faults == 1);
    CHECK_NEAR(d.cpu_ms, 2.5, 1e-12);
}

int main(void)
{
    RUN(fresh_pages_fault_every_frame);
    RUN(reused_buffer_does_not_fault);
    RUN(cpu_time_grows_with_work);
    RUN(cpu_time_does_not_grow_with_sleep);
    RUN(unknown_stays_unknown);
    return test_summary();
}
