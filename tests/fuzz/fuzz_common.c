/* fuzz_common.c: see fuzz_common.h. */
#include "fuzz_common.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "core/log.h"

#define TMP_PREFIX "fovsim-fuzz."

static char g_dir[512];

void fuzz_check_fail(const char *expr, const char *file, int line)
{
    fprintf(stderr, "%s:%d: fuzz invariant broken: %s\n", file, line, expr);
    fflush(stderr);
    abort();
}

void fuzz_init(void)
{
    static bool done;
    if (done)
        return;
    done = true;
    const char *q = getenv("FOVSIM_FUZZ_QUIET");
    if (q && strcmp(q, "1") == 0)
        log_set_quiet_errors(true);
}

static bool usable_dir(const char *d)
{
    struct stat sb;
    return d && d[0] == '/' && strlen(d) < 256 && stat(d, &sb) == 0 && S_ISDIR(sb.st_mode) &&
           access(d, W_OK | X_OK) == 0;
}

/* Removes a flat folder (the scratch folders hold only files). */
static void remove_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *e;
        char p[1024];
        while ((e = readdir(d)) != NULL) {
            if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
                continue;
            snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
            unlink(p);
        }
        closedir(d);
    }
    rmdir(dir);
}

/* The folders a crashed fuzzer left: libFuzzer leaves through _Exit on a crash, so atexit never
 * ran there. A folder whose process is gone is removed. */
static void remove_stale(const char *base)
{
    DIR *d = opendir(base);
    if (!d)
        return;
    struct dirent *e;
    char p[1024];
    while ((e = readdir(d)) != NULL) {
        if (strncmp(e->d_name, TMP_PREFIX, strlen(TMP_PREFIX)) != 0)
            continue;
        char *end;
        long pid = strtol(e->d_name + strlen(TMP_PREFIX), &end, 10);
        if (*end || pid <= 0 || pid == (long)getpid())
            continue;
        if (kill((pid_t)pid, 0) == 0 || errno != ESRCH)
            continue;
        snprintf(p, sizeof p, "%s/%s", base, e->d_name);
        remove_dir(p);
    }
    closedir(d);
}

static void remove_own_dir(void)
{
    if (g_dir[0])
        remove_dir(g_dir);
}

const char *fuzz_tmp_dir(void)
{
    if (g_dir[0])
        return g_dir;
    const char *base = getenv("FOVSIM_FUZZ_TMP");
    if (!usable_dir(base))
        base = usable_dir("/dev/shm") ? "/dev/shm" : usable_dir(getenv("TMPDIR")) ? getenv("TMPDIR") : "/tmp";
    remove_stale(base);
    snprintf(g_dir, sizeof g_dir, "%s/" TMP_PREFIX "%ld", base, (long)getpid());
    if (mkdir(g_dir, 0700) != 0 && errno != EEXIST) { /* EEXIST: left by a dead process with our pid */
        fprintf(stderr, "fuzz: cannot make %s: %s\n", g_dir, strerror(errno));
        abort();
    }
    atexit(remove_own_dir);
    return g_dir;
}

const char *fuzz_write_tmp(const char *name, const void *data, size_t size)
{
    static char path[1024];
    snprintf(path, sizeof path, "%s/%s", fuzz_tmp_dir(), name);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    const char *p = data;
    size_t left = size;
    while (fd >= 0 && left > 0) {
        ssize_t n = write(fd, p, left);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        p += n;
        left -= (size_t)n;
    }
    if (fd < 0 || left > 0 || close(fd) != 0) {
        fprintf(stderr, "fuzz: cannot write %s: %s\n", path, strerror(errno));
        abort();
    }
    return path;
}
