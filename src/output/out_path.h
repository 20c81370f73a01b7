/* out_path.h: the lengths of the paths a run will write, checked with the other arguments, before
 * anything is drawn or created (README "Exit status"; a 250-character --name used to render, then
 * fail at the first write with exit 6, a truncated message and an empty output folder).
 *
 * What a run writes into DIR (--out) is `<name>.<frame:04d>.exr`, through the temporary
 * `.<name>.<frame>.exr.tmp.<host>.<pid>.<n>` (out_path_temp_name), plus fixed names (metrics.csv,
 * summary.json, their temporaries, fvvdp/...). The longest of those must be a valid file name
 * (NAME_MAX bytes), every component of DIR too, DIR must fit file_make_dirs (OUT_PATH_DIR_MAX) and
 * a frame's path the callers' buffers (OUT_PATH_MAX). The reference cache (--cache) likewise holds
 * `ref-<16 hex>.exr` and its temporaries in a buffer of OUT_PATH_CACHE_MAX. */
#ifndef FOVSIM_OUT_PATH_H
#define FOVSIM_OUT_PATH_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#define OUT_PATH_DIR_MAX 1023   /* longest output directory (file_make_dirs' buffer) */
#define OUT_PATH_MAX 1199       /* longest frame path (the commands build them in 1200 bytes) */
#define OUT_PATH_CACHE_MAX 899  /* longest cache directory (reference.c keeps it in 900 bytes) */
#define OUT_PATH_HOST_MAX 32    /* longest host name in a temporary file name (out_path_host) */
/* A temporary file older than this (by mtime) is removed whatever host wrote it: what a task
 * killed on another machine of a shared file system leaves (out_dir_remove_stale_temps). */
#define OUT_PATH_TEMP_MAX_AGE_S (24 * 60 * 60)

/* Characters the temporary name of a frame adds to --name: ".", ".<frame, up to 5 digits>.exr",
 * ".tmp.", the host (up to OUT_PATH_HOST_MAX), ".<pid>" (up to 7 digits: Linux's PID_MAX_LIMIT is
 * 4194304) and ".<n>" (up to 10). */
int out_path_temp_overhead(void);
/* The longest --name that fits in a file name. */
int out_path_name_max(void);

/* Whether frames named `name` can be written into `dir` (either may be NULL: not checked) and the
 * reference cached in `cache_dir` (NULL: not checked). On false, `why` (cap bytes) holds one line
 * naming the option and the limit, without echoing an over-long value in full. */
bool out_path_check(const char *dir, const char *name, const char *cache_dir, char *why, size_t cap);

/* >>temporary names: every file fovsim writes goes to a temporary name in the same directory, then
 * rename(2) over the final name (atomic within a directory, also on NFS), so nobody ever sees a
 * partial file under the final name. */

/* This machine's name as it appears in temporary file names: gethostname() with every character
 * outside [A-Za-z0-9-] replaced by '-' (a dot too: the name holds no '.'); a name longer than
 * OUT_PATH_HOST_MAX becomes its first 23 characters, '-' and 8 hex digits of a hash of the whole
 * name, so that long names with a common prefix (node names of a cluster) stay apart;
 * "unknown-host" when there is none. */
void out_path_host(char out[OUT_PATH_HOST_MAX + 1]);
/* The temporary name for writing `path`: `<dir>/.<base>.tmp.<host>.<pid>.<n>` (<dir>/ as in `path`,
 * host from out_path_host, <n> new for every call in this process, up to 10 digits), so that two
 * writes in flight, in this process, another process or on another machine sharing the
 * directory, never share a temporary file. False (out unusable) when it does not fit in cap bytes. */
bool out_path_temp_name(const char *path, char *out, size_t cap);
/* Writes `text` to `path` through such a temporary name and rename(2), so a reader sees the old
 * file or the whole new one, never a part. One line and FS_ERR_IO on failure, and nothing is left
 * at the temporary name. */
fs_status out_write_atomic(const char *path, const char *text);

/* >>housekeeping at the start of a run (README "Output folders"; docs/reference.md "A cache on shared storage") */

/* A temporary file name of fovsim's writers, parsed. */
typedef struct out_temp_name {
    long pid;                         /* > 0 */
    char host[OUT_PATH_HOST_MAX + 1]; /* "" in the old format */
} out_temp_name;
/* Whether `file` is a temporary name of fovsim's writers: `<anything>.tmp.<host>.<pid>.<n>`
 * (out_path_temp_name), or the old format of fovsim before names carried the host, `<anything>.tmp.<pid>` or
 * `<anything>.tmp.<pid>.<n>` (no host: taken to be this machine's); pid of 1 to 9 digits, > 0. */
bool out_path_temp_parse(const char *file, out_temp_name *t);
/* The pid of out_path_temp_parse, 0 when `file` is not such a name. */
long out_path_temp_pid(const char *file);
/* Removes from `dir` the temporary files (out_path_temp_parse) that nobody will rename any more:
 * - those of this host (or in the old format, without a host) whose process no longer exists
 *   (kill(pid, 0) fails with ESRCH): what a killed run (kill -9, a crash, a power cut) left;
 * - those of any host last modified more than OUT_PATH_TEMP_MAX_AGE_S ago: what a run killed on
 *   another machine of a shared file system left (its pid means nothing here). No write of fovsim
 *   keeps a temporary file that long.
 * Files of another host younger than that (a run on another machine writing into the same shared
 * directory) are kept, so are those of live processes here, and anything that is not a regular
 * file. A missing directory is not an error. Returns how many were removed. */
int out_dir_remove_stale_temps(const char *dir);
/* The index of a file named `<name>.<4 to 9 digits><ext>` (ext with its dot), or -1. */
long out_path_sequence_index(const char *file, const char *name, const char *ext);
/* out_path_sequence_index with ".exr": a frame of the sequence `name`. */
long out_path_frame_index(const char *file, const char *name);
/* Whether `dir` holds any such frame of `name`. */
bool out_dir_has_sequence(const char *dir, const char *name);
/* Removes the frames of `name` with an index >= `from` (regular files only) from `dir`: with 0,
 * every frame of an earlier run, so that a run leaves exactly its own sequence there, also when it
 * draws fewer frames than the last or is interrupted. FS_ERR_IO with one line when one cannot be
 * removed; *removed (may be NULL) gets the count. */
fs_status out_dir_remove_sequence(const char *dir, const char *name, int from, int *removed);

#endif
