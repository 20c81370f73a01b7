/* exr_internal.h: what the EXR files share (internal to src/output/; the public contract is
 * exr_write.h).
 *
 * exr_image.c holds the exr_image in memory, exr_write.c the writer (and the stream behind every
 * Core context), exr_read.c the reader, exr_writer_thread.c the writer threads, exr_views.c the
 * multi-view convention (two eyes in one file).
 */
#ifndef FOVSIM_EXR_INTERNAL_H
#define FOVSIM_EXR_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include <openexr.h>

#include "output/exr_write.h"

/* Our own stream behind each Core context: we open the file ourselves (so a failure to create
 * the temporary file names the real errno), and the error handler keeps the first message of the
 * Core for the one-line diagnostic instead of letting it print to stderr. */
typedef struct exr_stream {
    int fd;
    char msg[256]; /* first error reported by the Core, "" if none */
    struct exr_stream *prev_bound; /* reader: what exr_stream_bind replaced (see tl_stream) */
} exr_stream;

/* Whether a custom attribute may not use `name` (the format or OpenEXR gives it a meaning). */
bool exr_is_reserved_attr(const char *name);

/* Binds `s` as this thread's stream for exr_stream_error_handler; returns the one it replaced,
 * for exr_stream_unbind. */
exr_stream *exr_stream_bind(exr_stream *s);
void exr_stream_unbind(exr_stream *prev);
/* The Core's error handler: keeps the first message in the bound stream. */
void exr_stream_error_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg);
/* The reason for a failed Core call: its own message if it gave one, else the generic text. */
const char *exr_reason(const exr_stream *s, exr_result_t rv);

/* 1..9, 0 or less meaning EXR_ZIP_LEVEL_DEFAULT. */
int exr_clamp_zip_level(int level);
/* exr_write_file with a deflate level, and logging nothing: on failure `err` (err_size bytes)
 * holds the one-line message. */
fs_status exr_write_file_quiet(const char *path, const exr_image *img, exr_compression_kind compression,
                               int zip_level, char *err, size_t err_size);

#endif
