/* log.h: one-line diagnostics on stderr.
 *
 * Every line starts with an upper-case module tag, as in `SCENE: [forest.json] 3 assets`.
 * Errors are always printed; info lines only with --verbose (log_set_verbose). Errors go through
 * log_error so tests can silence them (log_set_quiet_errors) when they feed bad input on purpose.
 * Does not format paths or know about files; callers put file:line in the message.
 */
#ifndef FOVSIM_LOG_H
#define FOVSIM_LOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define FS_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define FS_PRINTF(a, b)
#endif

void log_set_verbose(bool on);
bool log_is_verbose(void);
/* Text put before the message of every error and warning line (NULL or "": none), e.g.
 * "sweep.json: task 3: " while a sweep checks each task's options with the CLI's own parser. */
void log_set_context(const char *context);
/* Tests that feed bad input on purpose can silence the expected error lines. */
void log_set_quiet_errors(bool on);

/* Every message below is one line: after formatting, bytes that are not printable text (control
 * characters incl. newline and ESC, DEL, malformed UTF-8, C1 controls) are written escaped
 * (\n, \r, \t, \x1b, ...), so input quoted in a message (file names, JSON keys, glTF URIs) cannot
 * break the line, forge another one or send terminal escape sequences. Well-formed UTF-8 passes. */

/* Writes msg[0..n) to f escaped as described above (no newline added). */
void log_escape_write(FILE *f, const char *msg, size_t n);

/* Messages are also bounded (an 8 MB glTF data: URI once made an 11 MB line): in every error,
 * warning and info line, a run of more than LOG_MAX_RUN bytes without a blank (a quoted URI, key,
 * field or path) is shown as its first LOG_RUN_HEAD bytes, `...[N bytes]...` and its last
 * LOG_RUN_TAIL bytes, and a message longer than LOG_MAX_MESSAGE bytes after that ends with
 * `...[N bytes more]`. Quoting input on purpose goes through log_quote, which shortens more. */
#define LOG_MAX_RUN 256
#define LOG_RUN_HEAD 160
#define LOG_RUN_TAIL 48
#define LOG_MAX_MESSAGE 4096

/* Writes msg[0..n) to f escaped and bounded as described above (no newline added). */
void log_bounded_write(FILE *f, const char *msg, size_t n);

/* The one way messages quote input (a field, a key, a URI): 'text' in single quotes, at most
 * cap - 6 bytes of it (cut at a UTF-8 character boundary), followed by ... when cut. Bytes are
 * left as they are: log_error escapes them. Returns buf, which must hold at least 8 bytes. */
const char *log_quote(char *buf, size_t cap, const char *p, size_t n);

/* `fovsim: error: <msg>` on stderr, one line (a newline is appended). */
void log_error(const char *fmt, ...) FS_PRINTF(1, 2);
/* `fovsim: warning: <msg>` on stderr, always shown. */
void log_warn(const char *fmt, ...) FS_PRINTF(1, 2);
/* `<msg>` on stderr, only when verbose. */
void log_info(const char *fmt, ...) FS_PRINTF(1, 2);

/* Programmer errors (broken preconditions): abort with file:line in debug builds. */
#ifdef NDEBUG
#define FS_ASSERT(c) ((void)0)
#else
void fs_assert_fail(const char *expr, const char *file, int line);
#define FS_ASSERT(c) ((c) ? (void)0 : fs_assert_fail(#c, __FILE__, __LINE__))
#endif

#ifdef __cplusplus
}
#endif

#endif
