#include "log.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

static bool g_verbose;
static bool g_quiet_errors;

void log_set_verbose(bool on) { g_verbose = on; }
bool log_is_verbose(void) { return g_verbose; }
void log_set_quiet_errors(bool on) { g_quiet_errors = on; }

/* Length of the well-formed UTF-8 sequence at s (1..4), or 0 when it is not one (a stray or
 * truncated byte, an overlong form, a surrogate, beyond U+10FFFF) or is a C1 control (U+0080 to
 * U+009F, which some terminals obey like ESC sequences). */
static size_t utf8_printable_len(const unsigned char *s, size_t n)
{
    unsigned c = s[0];
    size_t len = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 0;
    if (len == 0 || c > 0xF4 || len > n)
        return 0;
    unsigned cp = c & (0x7Fu >> len);
    for (size_t i = 1; i < len; i++) {
        if ((s[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (s[i] & 0x3Fu);
    }
    static const unsigned min_cp[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < min_cp[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF) || cp <= 0x9F)
        return 0;
    return len;
}

void log_escape_write(FILE *f, const char *msg, size_t n)
{
    const unsigned char *s = (const unsigned char *)msg;
    for (size_t i = 0; i < n;) {
        unsigned c = s[i];
        if (c >= 0x20 && c < 0x7F) {
            fputc((int)c, f);
            i++;
            continue;
        }
        size_t len = c >= 0x80 ? utf8_printable_len(s + i, n - i) : 0;
        if (len) {
            fwrite(s + i, 1, len, f);
            i += len;
            continue;
        }
        if (c == '\n')
            fputs("\\n", f);
        else if (c == '\r')
            fputs("\\r", f);
        else if (c == '\t')
            fputs("\\t", f);
        else
            fprintf(f, "\\x%02x", c);
        i++;
    }
}

/* Length of the longest prefix of s[0..n) not longer than max that does not end inside a UTF-8
 * sequence (a cut there would show the lead byte of a character as an escape). */
static size_t utf8_cut(const char *s, size_t n, size_t max)
{
    if (n <= max)
        return n;
    size_t k = max;
    while (k > 0 && ((unsigned char)s[k] & 0xC0) == 0x80 && max - k < 4)
        k--;
    return k;
}

/* Start of the last tail bytes of s[0..n), moved forward to a character boundary. */
static size_t utf8_tail(const char *s, size_t n, size_t tail)
{
    size_t k = n > tail ? n - tail : 0;
    while (k < n && ((unsigned char)s[k] & 0xC0) == 0x80)
        k++;
    return k;
}

const char *log_quote(char *buf, size_t cap, const char *p, size_t n)
{
    if (cap < 8) {
        if (cap)
            buf[0] = '\0';
        return buf;
    }
    const size_t room = cap - 6; /* the quotes, "..." and the NUL */
    size_t o = 1, i = 0;
    buf[0] = '\'';
    for (; i < n; i++) {
        const size_t cost = p[i] ? 1 : 4; /* a NUL byte is written as \x00, as log_error shows others */
        if (o - 1 + cost > room)
            break;
        if (p[i]) {
            buf[o++] = p[i];
        } else {
            memcpy(buf + o, "\\x00", 4);
            o += 4;
        }
    }
    if (i < n) { /* cut: not inside a UTF-8 character */
        while (i > 0 && ((unsigned char)p[i] & 0xC0) == 0x80 && ((unsigned char)buf[o - 1] & 0x80)) {
            i--;
            o--;
        }
        memcpy(buf + o, "...", 3);
        o += 3;
    }
    buf[o++] = '\'';
    buf[o] = '\0';
    return buf;
}

static bool is_blank(char c) { return c == ' ' || c == '\t'; }

void log_bounded_write(FILE *f, const char *msg, size_t n)
{
    size_t written = 0; /* bytes of the message shown, for LOG_MAX_MESSAGE */
    for (size_t i = 0; i < n;) {
        size_t e = i;
        if (is_blank(msg[i]))
            while (e < n && is_blank(msg[e]))
                e++;
        else
            while (e < n && !is_blank(msg[e]))
                e++;
        const char *w = msg + i;
        size_t len = e - i;
        if (written >= LOG_MAX_MESSAGE) {
            fprintf(f, "...[%zu bytes more]", n - i);
            return;
        }
        if (len > LOG_MAX_RUN) {
            size_t head = utf8_cut(w, len, LOG_RUN_HEAD), tail = utf8_tail(w, len, LOG_RUN_TAIL);
            log_escape_write(f, w, head);
            fprintf(f, "...[%zu bytes]...", tail - head);
            log_escape_write(f, w + tail, len - tail);
            written += head + (len - tail) + 16;
        } else {
            size_t k = written + len > LOG_MAX_MESSAGE ? utf8_cut(w, len, LOG_MAX_MESSAGE - written) : len;
            log_escape_write(f, w, k);
            written += k;
            if (k < len) {
                fprintf(f, "...[%zu bytes more]", n - i - k);
                return;
            }
        }
        i = e;
    }
}

/* One line: the message is formatted, then every byte that is not printable text (control
 * characters, DEL, malformed UTF-8, C1 controls) is written as an escape (\n, \x1b, ...), so a
 * file name or JSON key quoted in a message can neither break the line nor drive the terminal. */
static char g_context[512];

void log_set_context(const char *context)
{
    snprintf(g_context, sizeof g_context, "%s", context ? context : "");
}

static void vline(const char *prefix, const char *fmt, va_list ap)
{
    char small[1024], *buf = small;
    va_list ap2;
    va_copy(ap2, ap);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    if (n >= (int)sizeof small) {
        char *big = malloc((size_t)n + 1);
        if (big) {
            vsnprintf(big, (size_t)n + 1, fmt, ap2);
            buf = big;
        } else {
            n = (int)sizeof small - 1; /* the truncated message rather than none */
        }
    }
    va_end(ap2);
    while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == '\r' || buf[n - 1] == ' ' || buf[n - 1] == '\t'))
        n--; /* a driver's or library's trailing newline is not part of the message */
    fputs(prefix, stderr);
    if (g_context[0] && prefix[0])
        log_escape_write(stderr, g_context, strlen(g_context));
    if (n > 0)
        log_bounded_write(stderr, buf, (size_t)n);
    fputc('\n', stderr);
    if (buf != small)
        free(buf);
}

void log_error(const char *fmt, ...)
{
    if (g_quiet_errors)
        return;
    va_list ap;
    va_start(ap, fmt);
    vline("fovsim: error: ", fmt, ap);
    va_end(ap);
}

void log_warn(const char *fmt, ...)
{
    if (g_quiet_errors)
        return;
    va_list ap;
    va_start(ap, fmt);
    vline("fovsim: warning: ", fmt, ap);
    va_end(ap);
}

void log_info(const char *fmt, ...)
{
    if (!g_verbose)
        return;
    va_list ap;
    va_start(ap, fmt);
    vline("", fmt, ap);
    va_end(ap);
}

#ifndef NDEBUG
void fs_assert_fail(const char *expr, const char *file, int line)
{
    fprintf(stderr, "fovsim: assertion failed: %s (%s:%d)\n", expr, file, line);
    abort();
}
#endif
