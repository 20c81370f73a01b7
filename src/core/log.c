#include "log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static bool g_verbose;
static bool g_quiet_errors;

void log_set_verbose(bool on) { g_verbose = on; }
bool log_is_verbose(void) { return g_verbose; }
void log_set_quiet_errors(bool on) { g_quiet_errors = on; }

static void vline(const char *prefix, const char *fmt, va_list ap)
{
    fputs(prefix, stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
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
