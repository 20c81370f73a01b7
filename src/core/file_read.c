#include "core/file_read.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/log.h"

fs_status file_read_all(const char *path, size_t max_bytes, const char *what, fs_status too_big_status, char **out,
                        size_t *size_out)
{
    *out = NULL;
    *size_out = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        log_error("%s: cannot open: %s", path, strerror(errno));
        return FS_ERR_IO;
    }
    struct stat st;
    bool have_stat = fstat(fileno(f), &st) == 0;
    if (have_stat && S_ISDIR(st.st_mode)) {
        fclose(f);
        log_error("%s: is a directory, expected %s", path, what);
        return FS_ERR_IO;
    }
    /* Regular files are read in one go (+2: room to see the end of the file without growing);
     * pipes and the like grow geometrically up to the limit. */
    size_t cap = 1 << 16, size = 0;
    if (have_stat && S_ISREG(st.st_mode) && st.st_size > 0 && (unsigned long long)st.st_size <= max_bytes)
        cap = (size_t)st.st_size + 2;
    char *text = malloc(cap);
    int err = 0;
    bool too_big = false;
    while (text) {
        if (size + 1 >= cap) {
            if (cap > max_bytes) {
                too_big = true;
                break;
            }
            size_t ncap = cap * 2 > max_bytes + 2 ? max_bytes + 2 : cap * 2;
            char *grown = realloc(text, ncap);
            if (!grown) {
                free(text);
                text = NULL;
                break;
            }
            text = grown;
            cap = ncap;
        }
        size_t got = fread(text + size, 1, cap - 1 - size, f);
        size += got;
        if (got == 0) {
            if (ferror(f))
                err = errno ? errno : EIO;
            break;
        }
    }
    fclose(f);
    if (!text) {
        log_error("%s: out of memory reading the file", path);
        return FS_ERR_NOMEM;
    }
    if (too_big || err) {
        free(text);
        if (too_big)
            log_error("%s: larger than %zu MiB, expected %s", path, max_bytes >> 20, what);
        else
            log_error("%s: cannot read: %s", path, strerror(err));
        return too_big ? too_big_status : FS_ERR_IO;
    }
    text[size] = '\0';
    *out = text;
    *size_out = size;
    return FS_OK;
}

fs_status file_make_dirs(const char *path)
{
    char buf[1024];
    if (!path[0] || snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf) {
        log_error("'%s': expected a directory path of 1 to %d characters", path, (int)sizeof buf - 1);
        return FS_ERR_IO;
    }
    for (char *p = buf + 1;; p++) {
        char c = *p;
        if (c == '/' || c == '\0') {
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST) {
                log_error("%s: cannot create directory: %s", buf, strerror(errno));
                return FS_ERR_IO;
            }
            struct stat sb;
            if (stat(buf, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
                log_error("%s: exists and is not a directory", buf);
                return FS_ERR_IO;
            }
            *p = c;
        }
        if (c == '\0')
            break;
    }
    return FS_OK;
}
