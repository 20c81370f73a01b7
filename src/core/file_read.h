/* file_read.h: reading a whole text file into memory (and making directories), with the one-line errors every input reader
 * of fovsim gives (`<path>: cannot open: No such file or directory`).
 *
 * What it does NOT do: parse, or decide what a too-large file means (the caller says which status
 * to return for it, e.g. FS_ERR_SCENE for a scene file). */
#ifndef FOVSIM_FILE_READ_H
#define FOVSIM_FILE_READ_H

#include <stddef.h>

#include "core/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reads `path` into a malloc'd, NUL-terminated buffer (*out, *size bytes without the NUL).
 * `what` names the expected content in messages ("a scene file", "a gaze trace"). Errors, each one
 * line via log_error: cannot open / is a directory / cannot read -> FS_ERR_IO; larger than
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
