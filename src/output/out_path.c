/* out_path.c: output path lengths, checked before a run starts (see out_path.h). */
#include "output/out_path.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

#include "core/config.h"

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
