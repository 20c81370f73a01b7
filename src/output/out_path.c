/* out_path.c: output path lengths, checked before a run starts (see out_path.h). */
#include "output/out_path.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/config.h"
#include "core/log.h"

#ifndef NAME_MAX
#define NAME_MAX 255
#endif

int out_path_temp_overhead(void)
{
    char digits[32];
    int frame = snprintf(digits, sizeof digits, "%04d", MAX_FRAMES - 1);
    /* "." name "." frame ".exr" ".tmp." pid "." n */
    return 1 + 1 + frame + 4 + 5 + 7 + 1 + 10;
}

int out_path_name_max(void)
{
    return NAME_MAX - out_path_temp_overhead();
}

/* The first component of `dir` longer than NAME_MAX, as its length (0 when none). */
static size_t long_component(const char *dir)
{
    size_t run = 0;
    for (const char *p = dir;; p++) {
        if (*p == '/' || *p == '\0') {
            if (run > NAME_MAX)
                return run;
            run = 0;
            if (*p == '\0')
                return 0;
        } else {
            run++;
        }
    }
}

/* `s` for a message: whole when short, else its first 40 characters, "...", and its length. */
static const char *shown(const char *s, char *buf, size_t cap)
{
    size_t n = strlen(s);
    if (n <= 80)
        snprintf(buf, cap, "'%s'", s);
    else
        snprintf(buf, cap, "'%.40s...' (%zu characters)", s, n);
    return buf;
}

static bool check_dir(const char *opt, const char *dir, size_t max, char *why, size_t cap)
{
    char b[128];
    size_t n = strlen(dir), comp = long_component(dir);
    if (n == 0 || n > max) {
        snprintf(why, cap, "%s %s: expected a directory path of 1 to %zu characters", opt, shown(dir, b, sizeof b), max);
        return false;
    }
    if (comp) {
        snprintf(why, cap, "%s %s: a component of %zu characters; a file name has at most %d", opt,
                 shown(dir, b, sizeof b), comp, NAME_MAX);
        return false;
    }
    return true;
}

bool out_path_check(const char *dir, const char *name, const char *cache_dir, char *why, size_t cap)
{
    char b[128];
    if (dir && !check_dir("--out", dir, OUT_PATH_DIR_MAX, why, cap))
        return false;
    if (name && (int)strlen(name) > out_path_name_max()) {
        snprintf(why, cap,
                 "--name %s: expected at most %d characters (a frame is written as .<name>.<frame>.exr.tmp.<pid>.<n>, "
                 "and a file name has at most %d)",
                 shown(name, b, sizeof b), out_path_name_max(), NAME_MAX);
        return false;
    }
    if (dir && name) {
        /* "<dir>/<name>.<frame>.exr": the frame's path, in the callers' buffers. */
        size_t total = strlen(dir) + 1 + strlen(name) + (size_t)out_path_temp_overhead();
        if (total > OUT_PATH_MAX) {
            snprintf(why, cap, "--out and --name: together %zu characters with a frame's temporary name; at most %d",
                     total, OUT_PATH_MAX);
            return false;
        }
    }
    if (cache_dir && !check_dir("--cache", cache_dir, OUT_PATH_CACHE_MAX, why, cap))
        return false;
    return true;
}

/* >>housekeeping */

/* Whether s[0..n) is one or more decimal digits. */
static bool all_digits(const char *s, size_t n)
{
    if (n == 0)
        return false;
    for (size_t i = 0; i < n; i++)
        if (!isdigit((unsigned char)s[i]))
            return false;
    return true;
}

long out_path_temp_pid(const char *file)
{
    /* The last ".tmp." followed by digits, or digits "." digits, to the end. */
    const char *t = NULL;
    for (const char *p = strstr(file, ".tmp."); p; p = strstr(p + 1, ".tmp."))
        t = p;
    if (!t || t == file)
        return 0;
    const char *pid = t + 5, *dot = strchr(pid, '.');
    size_t pid_len = dot ? (size_t)(dot - pid) : strlen(pid);
    if (!all_digits(pid, pid_len) || pid_len > 9 || (dot && !all_digits(dot + 1, strlen(dot + 1))))
        return 0;
    long v = strtol(pid, NULL, 10);
    return v > 0 ? v : 0;
}

int out_dir_remove_stale_temps(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int removed = 0;
    const long self = (long)getpid();
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        long pid = out_path_temp_pid(e->d_name);
        if (pid <= 0 || pid == self || (pid_t)pid != pid)
            continue;
        if (!(kill((pid_t)pid, 0) == -1 && errno == ESRCH))
            continue; /* alive (or not ours to signal: EPERM means it exists) */
        char path[OUT_PATH_DIR_MAX + NAME_MAX + 2];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path)
            continue;
        struct stat sb;
        if (lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
            continue;
        if (unlink(path) == 0)
            removed++;
        else
            log_warn("%s: cannot remove the temporary file of an earlier run: %s", path, strerror(errno));
    }
    closedir(d);
    if (removed)
        log_info("OUTPUT: removed %d temporary file%s of runs that no longer exist from %s", removed,
                 removed == 1 ? "" : "s", dir);
    return removed;
}

long out_path_frame_index(const char *file, const char *name)
{
    size_t len = strlen(name), n = strlen(file);
    /* <name> "." digits ".exr" */
    if (n < len + 1 + 4 + 4 || strncmp(file, name, len) != 0 || file[len] != '.' || strcmp(file + n - 4, ".exr") != 0 ||
        !all_digits(file + len + 1, n - len - 1 - 4) || n - len - 1 - 4 > 9)
        return -1;
    return strtol(file + len + 1, NULL, 10);
}

bool out_dir_has_sequence(const char *dir, const char *name)
{
    DIR *d = opendir(dir);
    if (!d)
        return false;
    bool found = false;
    struct dirent *e;
    while (!found && (e = readdir(d)) != NULL)
        found = out_path_frame_index(e->d_name, name) >= 0;
    closedir(d);
    return found;
}

fs_status out_dir_remove_sequence(const char *dir, const char *name, int from, int *removed)
{
    int n = 0;
    if (removed)
        *removed = 0;
    DIR *d = opendir(dir);
    if (!d)
        return FS_OK;
    fs_status st = FS_OK;
    struct dirent *e;
    while ((e = readdir(d)) != NULL && st == FS_OK) {
        const char *f = e->d_name;
        if (out_path_frame_index(f, name) < from)
            continue;
        char path[OUT_PATH_DIR_MAX + NAME_MAX + 2];
        if (snprintf(path, sizeof path, "%s/%s", dir, f) >= (int)sizeof path)
            continue;
        struct stat sb;
        if (lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
            continue;
        if (unlink(path) == 0) {
            n++;
        } else {
            log_error("%s: cannot remove the frame of an earlier run: %s", path, strerror(errno));
            st = FS_ERR_IO;
        }
    }
    closedir(d);
    if (n)
        log_info("OUTPUT: removed %d frame%s of an earlier run (%s/%s.####.exr%s)", n, n == 1 ? "" : "s", dir, name,
                 from > 0 ? ", past the frames of this one" : "");
    if (removed)
        *removed = n;
    return st;
}
