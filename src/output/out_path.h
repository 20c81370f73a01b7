/* out_path.h: the lengths of the paths a run will write, checked with the other arguments, before
 * anything is drawn or created (issue 17, defect 8: a 250-character --name used to render, then
 * fail at the first write with exit 6, a truncated message and an empty output folder).
 *
 * What a run writes into DIR (--out) is `<name>.<frame:04d>.exr`, through the temporary
 * `.<name>.<frame>.exr.tmp.<pid>.<n>` (exr_write.h), plus fixed names (metrics.csv, summary.json,
 * their temporaries, fvvdp/...). The longest of those must be a valid file name (NAME_MAX bytes),
 * every component of DIR too, DIR must fit file_make_dirs (OUT_PATH_DIR_MAX) and a frame's path
 * the callers' buffers (OUT_PATH_MAX). The reference cache (--cache) likewise holds
 * `ref-<16 hex>.exr` and its temporaries in a buffer of OUT_PATH_CACHE_MAX. */
#ifndef FOVSIM_OUT_PATH_H
#define FOVSIM_OUT_PATH_H

#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#define OUT_PATH_DIR_MAX 1023   /* longest output directory (file_make_dirs' buffer) */
#define OUT_PATH_MAX 1199       /* longest frame path (run.c and compare.c build them in 1200 bytes) */
#define OUT_PATH_CACHE_MAX 899  /* longest cache directory (reference.c keeps it in 900 bytes) */

/* Characters the temporary name of a frame adds to --name: ".", ".<frame, up to 5 digits>.exr",
 * ".tmp.", the pid (up to 7 digits: Linux's PID_MAX_LIMIT is 4194304) and ".<n>" (up to 10). */
int out_path_temp_overhead(void);
/* The longest --name that fits in a file name. */
int out_path_name_max(void);

/* Whether frames named `name` can be written into `dir` (either may be NULL: not checked) and the
 * reference cached in `cache_dir` (NULL: not checked). On false, `why` (cap bytes) holds one line
 * naming the option and the limit, without echoing an over-long value in full. */
bool out_path_check(const char *dir, const char *name, const char *cache_dir, char *why, size_t cap);

/* >>housekeeping at the start of a run (issue 17, defect 9) */

/* The pid in a temporary file name of fovsim's writers: `<anything>.tmp.<pid>` or
 * `<anything>.tmp.<pid>.<n>` (exr_write, png_write, metrics.csv, summary.json, plots), pid > 0;
 * 0 when `file` is not such a name. */
long out_path_temp_pid(const char *file);
/* Removes from `dir` the temporary files (out_path_temp_pid) of processes that no longer exist
 * (kill(pid, 0) fails with ESRCH): what a killed run (kill -9, a crash, a power cut) left. Files of
 * live processes (another run writing into the same directory) are kept, and so is anything that
 * is not a regular file. A missing directory is not an error. Returns how many were removed. */
int out_dir_remove_stale_temps(const char *dir);
/* The frame index of a file named `<name>.<1 to 9 digits>.exr`, or -1. */
long out_path_frame_index(const char *file, const char *name);
/* Whether `dir` holds any such frame of `name`. */
bool out_dir_has_sequence(const char *dir, const char *name);
/* Removes the frames of `name` with an index >= `from` (regular files only) from `dir`: with 0,
 * every frame of an earlier run, so that a run leaves exactly its own sequence there, also when it
 * draws fewer frames than the last or is interrupted. FS_ERR_IO with one line when one cannot be
 * removed; *removed (may be NULL) gets the count. */
fs_status out_dir_remove_sequence(const char *dir, const char *name, int from, int *removed);

#endif
