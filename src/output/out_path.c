/* out_path.c: output path lengths, checked before a run starts (see out_path.h). */
#include "output/out_path.h"

#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/config.h"
#include "core/hash.h"
#include "core/log.h"

#ifndef NAME_MAX
#define NAME_MAX 255
#endif

int out_path_temp_overhead(void)
{
    char digits[32];
    int frame = snprintf(digits, sizeof digits, "%04d", MAX_FRAMES - 1);
    /* "." name "." frame ".exr" ".tmp." host "." pid "." n */
    return 1 + 1 + frame + 4 + 5 + OUT_PATH_HOST_MAX + 1 + 7 + 1 + 10;
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
                 "--name %s: expected at most %d characters (a frame is written as .<name>.<frame>.exr.tmp.<host>.<pid>.<n>, "
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

/* >>temporary names */

/* c when it is one of [A-Za-z0-9-], else '-'. */
static char host_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ? c : '-';
}

void out_path_host(char out[OUT_PATH_HOST_MAX + 1])
{
    char raw[256];
    if (gethostname(raw, sizeof raw) != 0)
        raw[0] = '\0';
    raw[sizeof raw - 1] = '\0'; /* POSIX leaves a truncated name unterminated */
    size_t n = strlen(raw);
    if (n == 0) {
        snprintf(out, OUT_PATH_HOST_MAX + 1, "unknown-host");
        return;
    }
    /* Longer: the first 23 characters, '-' and 8 hex digits of a hash of the whole name (32). */
    enum { KEEP = OUT_PATH_HOST_MAX - 9 };
    size_t keep = n <= OUT_PATH_HOST_MAX ? n : KEEP;
    for (size_t i = 0; i < keep; i++)
        out[i] = host_char(raw[i]);
    out[keep] = '\0';
    if (n > OUT_PATH_HOST_MAX)
        snprintf(out + KEEP, OUT_PATH_HOST_MAX + 1 - KEEP, "-%08" PRIx32, (uint32_t)hash_str(HASH_FNV_INIT, raw));
}

/* Numbers the temporary files of this process (32 bits: at most 10 digits, as
 * out_path_temp_overhead counts). */
static atomic_uint g_temp_seq;

bool out_path_temp_name(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    int dir_len = slash ? (int)(slash - path) + 1 : 0;
    char host[OUT_PATH_HOST_MAX + 1];
    out_path_host(host);
    unsigned n = atomic_fetch_add_explicit(&g_temp_seq, 1, memory_order_relaxed);
    int len = snprintf(out, cap, "%.*s.%s.tmp.%s.%ld.%u", dir_len, path, path + dir_len, host, (long)getpid(), n);
    return len >= 0 && (size_t)len < cap;
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

/* The start of the '.'-separated field of `s` that ends at `end`, or NULL when no '.' precedes it. */
static const char *field_before(const char *s, const char *end)
{
    const char *p = end;
    while (p > s && p[-1] != '.')
        p--;
    return p > s ? p : NULL;
}

/* Whether ".tmp." ends right before `field`, with something before it. */
static bool tmp_before(const char *s, const char *field)
{
    return field && field - s >= 6 && !memcmp(field - 5, ".tmp.", 5);
}

static bool host_ok(const char *h, size_t n)
{
    if (n == 0 || n > OUT_PATH_HOST_MAX)
        return false;
    for (size_t i = 0; i < n; i++)
        if (host_char(h[i]) != h[i])
            return false;
    return true;
}

static bool pid_ok(const char *p, size_t n, long *pid)
{
    if (!all_digits(p, n) || n > 9)
        return false;
    *pid = strtol(p, NULL, 10);
    return *pid > 0;
}

bool out_path_temp_parse(const char *file, out_temp_name *t)
{
    /* From the end: ... ".tmp." host "." pid "." n, else ".tmp." pid "." n, else ".tmp." pid. */
    const char *end = file + strlen(file);
    const char *n = field_before(file, end);
    const char *b = n ? field_before(file, n - 1) : NULL;
    const char *a = b ? field_before(file, b - 1) : NULL;
    memset(t, 0, sizeof *t);
    if (tmp_before(file, a) && host_ok(a, (size_t)(b - 1 - a)) && pid_ok(b, (size_t)(n - 1 - b), &t->pid) &&
        all_digits(n, (size_t)(end - n))) {
        memcpy(t->host, a, (size_t)(b - 1 - a));
        return true;
    }
    if (tmp_before(file, b) && pid_ok(b, (size_t)(n - 1 - b), &t->pid) && all_digits(n, (size_t)(end - n)))
        return true;
    if (tmp_before(file, n) && pid_ok(n, (size_t)(end - n), &t->pid))
        return true;
    memset(t, 0, sizeof *t);
    return false;
}

long out_path_temp_pid(const char *file)
{
    out_temp_name t;
    return out_path_temp_parse(file, &t) ? t.pid : 0;
}

int out_dir_remove_stale_temps(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    int dead = 0, old = 0;
    const long self = (long)getpid();
    char here[OUT_PATH_HOST_MAX + 1];
    out_path_host(here);
    const time_t now = time(NULL);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        out_temp_name t;
        if (!out_path_temp_parse(e->d_name, &t))
            continue;
        char path[OUT_PATH_DIR_MAX + NAME_MAX + 2];
        if (snprintf(path, sizeof path, "%s/%s", dir, e->d_name) >= (int)sizeof path)
            continue;
        struct stat sb;
        if (lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
            continue;
        /* A clock ahead of ours (another machine, the file server) makes a file look younger:
         * the age is generous for that too. */
        bool aged = difftime(now, sb.st_mtime) > OUT_PATH_TEMP_MAX_AGE_S;
        bool ours = !t.host[0] || !strcmp(t.host, here);
        /* Alive, or not ours to signal (EPERM means it exists): kept. */
        bool gone = ours && t.pid != self && (pid_t)t.pid == t.pid && kill((pid_t)t.pid, 0) == -1 && errno == ESRCH;
        if (!aged && !gone)
            continue;
        if (unlink(path) == 0)
            *(gone ? &dead : &old) += 1;
        else
            log_warn("%s: cannot remove the temporary file of an earlier run: %s", path, strerror(errno));
    }
    closedir(d);
    if (dead)
        log_info("OUTPUT: removed %d temporary file%s of runs that no longer exist from %s", dead,
                 dead == 1 ? "" : "s", dir);
    if (old)
        log_info("OUTPUT: removed %d temporary file%s older than %d h (of runs on any machine) from %s", old,
                 old == 1 ? "" : "s", OUT_PATH_TEMP_MAX_AGE_S / 3600, dir);
    return dead + old;
}

long out_path_sequence_index(const char *file, const char *name, const char *ext)
{
    size_t len = strlen(name), n = strlen(file), el = strlen(ext);
    /* <name> "." 4 to 9 digits <ext> */
    if (n < len + 1 + 4 + el || strncmp(file, name, len) != 0 || file[len] != '.' || strcmp(file + n - el, ext) != 0 ||
        !all_digits(file + len + 1, n - len - 1 - el) || n - len - 1 - el > 9)
        return -1;
    return strtol(file + len + 1, NULL, 10);
}

long out_path_frame_index(const char *file, const char *name)
{
    return out_path_sequence_index(file, name, ".exr");
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

fs_status out_write_atomic(const char *path, const char *text)
{
    char tmp[4200];
    if (!out_path_temp_name(path, tmp, sizeof tmp)) {
        log_error("%s: cannot write: the path is too long", path);
        return FS_ERR_IO;
    }
    FILE *f = fopen(tmp, "w");
    bool ok = f && fputs(text, f) >= 0;
    ok = f && fclose(f) == 0 && ok;
    if (!ok || rename(tmp, path) != 0) {
        log_error("%s: cannot write: %s", path, strerror(errno));
        unlink(tmp);
        return FS_ERR_IO;
    }
    return FS_OK;
}
