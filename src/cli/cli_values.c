/* cli_values.c: an option's number, range-checked, with one message naming the option and the
 * range. The lowest of the command line's files: the parser (cli.c), the option table's setters
 * (cli_options.c) and the commands with options of their own (sweep) read it. */
#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli/cli_internal.h"
#include "core/log.h"

bool cli_parse_int(const char *opt, const char *v, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long x = strtol(v, &end, 10);
    if (errno || end == v || *end || x < lo || x > hi) {
        log_error("%s: expected an integer in [%d, %d], got '%s'", opt, lo, hi, v);
        return false;
    }
    *out = (int)x;
    return true;
}

/* A number for an option used as a 32-bit float, range-checked as that float: a value that is in
 * range as a double but rounds to 0 or to a denormal (1e-300, 1e-40) would reach the renderer as
 * 0, which every consumer reads as "use the default", or be flushed to 0 on a GPU.
 * (lo, hi], or [lo, hi] with lo_closed. */
bool cli_parse_float_in(const char *opt, const char *v, float lo, bool lo_closed, float hi, float *out,
                        const char *expected)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    float f = (float)x;
    bool ok = !errno && end != v && !*end && isfinite(x) && isfinite(f) && (lo_closed ? f >= lo : f > lo) && f <= hi &&
              (x == 0.0 || isnormal(f));
    if (!ok) {
        bool tiny = !errno && end != v && !*end && (lo_closed ? x >= lo : x > lo) && x <= hi &&
                    x != 0.0 && !isnormal(f); /* in range as a double, not as the float */
        char range[96];
        snprintf(range, sizeof range, "a number in %c%g, %g]", lo_closed ? '[' : '(', lo, hi);
        log_error("%s: expected %s, got '%s'%s", opt, expected ? expected : range, v,
                  tiny ? " (too small for the 32-bit float it is used as)" : "");
        return false;
    }
    *out = f;
    return true;
}
