#include "core/file_read.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/log.h"

static const char *kind_of(mode_t m)
{
    return S_ISDIR(m)    ? "is a directory"
           : S_ISFIFO(m) ? "is a FIFO (named pipe), not a regular file"
           : S_ISCHR(m)  ? "is a character device, not a regular file"
           : S_ISBLK(m)  ? "is a block device, not a regular file"
           : S_ISSOCK(m) ? "is a socket, not a regular file"
                         : "is not a regular file";
}

int file_open_regular(const char *path, struct stat *st, const char **why)
{
    struct stat before;
    if (stat(path, &before) != 0) {
        *why = strerror(errno);
        return -1;
    }
    if (!S_ISREG(before.st_mode)) {
        *why = kind_of(before.st_mode);
        errno = S_ISDIR(before.st_mode) ? EISDIR : EINVAL;
        return -1;
    }
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
    if (fd < 0) {
        *why = strerror(errno);
        return -1;
    }
    if (fstat(fd, st) != 0) {
        int err = errno;
        *why = strerror(err);
        close(fd);
        errno = err;
        return -1;
    }
    if (!S_ISREG(st->st_mode) || st->st_dev != before.st_dev || st->st_ino != before.st_ino) {
        *why = S_ISREG(st->st_mode) ? "was replaced while being opened" : kind_of(st->st_mode);
        close(fd);
        errno = EINVAL;
        return -1;
    }
    return fd;
}

fs_status file_read_all(const char *path, size_t max_bytes, const char *what, fs_status too_big_status, char **out,
                        size_t *size_out)
{
    *out = NULL;
    *size_out = 0;
    struct stat st;
    const char *why = "";
    int fd = file_open_regular(path, &st, &why);
    FILE *f = fd >= 0 ? fdopen(fd, "rb") : NULL;
    if (!f) {
        if (fd >= 0) {
            why = strerror(errno);
            close(fd);
        }
        if (fd >= 0 || strncmp(why, "is ", 3) != 0)
            log_error("%s: cannot open: %s", path, why);
        else
            log_error("%s: %s, expected %s", path, why, what);
        return FS_ERR_IO;
    }
    if ((unsigned long long)st.st_size > max_bytes) { /* refused by its size, unread */
        fclose(f);
        log_error("%s: larger than %zu MiB, expected %s", path, max_bytes >> 20, what);
        return too_big_status;
    }
    /* Read in one go (+2: room to see the end of the file without growing); a file that grows
     * while it is read grows the buffer geometrically up to the limit. */
    size_t cap = 1 << 16, size = 0;
    if (st.st_size > 0)
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
