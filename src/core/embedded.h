/* embedded.h: files compiled into the binary (shaders/ and scenes/builtin/), see cmake/embed.cmake.
 * Paths are relative to the source root, e.g. "shaders/forward.frag". Data is NUL-terminated. */
#ifndef FOVSIM_EMBEDDED_H
#define FOVSIM_EMBEDDED_H

#include <stddef.h>

typedef struct embedded_file {
    const char *path;
    const char *data;
    size_t size; /* bytes, without the terminating NUL */
} embedded_file;

extern const embedded_file embedded_files[]; /* ends with {NULL, NULL, 0} */
extern const int embedded_file_count;

/* The embedded file at `path`, or NULL. */
const embedded_file *embedded_find(const char *path);

#endif
