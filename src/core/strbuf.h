/* strbuf.h: a growing, NUL-terminated text buffer (shader sources, merged CSVs). An allocation
 * failure sets `oom` and makes every later append a no-op, so callers check once at the end. */
#ifndef FOVSIM_STRBUF_H
#define FOVSIM_STRBUF_H

#include <stdbool.h>
#include <stddef.h>

#include "core/log.h"

typedef struct sbuf {
    char *p; /* NULL until the first append; free() it */
    size_t len, cap;
    bool oom;
} sbuf;

void sb_append(sbuf *b, const char *s, size_t n);
void sb_puts(sbuf *b, const char *s);
void sb_printf(sbuf *b, const char *fmt, ...) FS_PRINTF(2, 3);

#endif
