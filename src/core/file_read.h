/* file_read.h: reading a whole text file into memory (and making directories), with the one-line errors every input reader
 * of fovsim gives (`<path>: cannot open: No such file or directory`).
 *
 * What it does NOT do: parse, or decide what a too-large file means (the caller says which status
 * to return for it, e.g. FS_ERR_SCENE for a scene file). */
#ifndef FOVSIM_FILE_READ_H
#define FOVSIM_FILE_READ_H

#include <stddef.h>
#include <sys/stat.h>

#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The one place input files are opened (scene, glTF and its buffers and images, gaze trace,
 * baseline, manifest, viewer script): `path` must be a regular file. It is checked with stat()
 * before it is opened (open() of a FIFO waits for a writer; a device such as /dev/zero reads
 * forever), opened O_NONBLOCK and checked again with fstat() (a file swapped for a FIFO in
 * between). fovsim reads no input from a pipe, FIFO, socket or device, /dev/stdin included.
 * Returns the descriptor (O_CLOEXEC), *st filled; or -1 with errno set and *why a short reason for
 * a message ("is a directory", "is a FIFO, not a regular file", strerror(errno)). Prints nothing. */
int file_open_regular(const char *path, struct stat *st, const char **why);

/* Reads `path` into a malloc'd, NUL-terminated buffer (*out, *size bytes without the NUL).
 * `what` names the expected content in messages ("a scene file", "a gaze trace"). Errors, each one
 * line via log_error: cannot open / not a regular file (file_open_regular) / cannot read -> FS_ERR_IO; larger than
 * max_bytes -> too_big_status; out of memory -> FS_ERR_NOMEM. *out is NULL on failure. */
fs_status file_read_all(const char *path, size_t max_bytes, const char *what, fs_status too_big_status, char **out,
                        size_t *size);

/* mkdir -p: creates `path` and its missing parents. One line naming the failing component and
 * FS_ERR_IO when one cannot be made or exists as something other than a directory. */
fs_status file_make_dirs(const char *path);

#ifdef __cplusplus
}
#endif

#endif
