/* merge.h: the readers of `fovsim merge` (merge.c) that take a task's files as fovsim wrote them
 * and refuse anything else (docs/cluster.md; docs/testing.md "Security tests"): exposed for tests/fuzz/fuzz_check_merge.c.
 * Both take the whole file, NUL-terminated at text[size] (as file_read_all gives it), and name
 * `path` in their one-line messages. */
#ifndef FOVSIM_MERGE_H
#define FOVSIM_MERGE_H

#include <stddef.h>

#include "core/status.h"

struct cJSON;

/* A task's metrics.csv: the header names every column merge reads (found by name), every row has
 * the header's field count, none empty, and ends with a line break; no NUL byte; every row's mode is
 * an alpha mode's name, its ring an integer >= -1, and the values merge reads are numbers. FS_OK, or
 * FS_ERR_IO with one line naming path:line (and the column). */
fs_status merge_check_metrics(const char *path, const char *text, size_t size);

/* A task's summary.json: *out = the parsed JSON object (the caller deletes it), or NULL and
 * FS_ERR_IO with one line (path:line:column for a syntax error; an object is required). */
fs_status merge_parse_summary(const char *path, const char *text, size_t size, struct cJSON **out);

#endif
