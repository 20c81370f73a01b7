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

#endif
