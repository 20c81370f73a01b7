/* check_tol.c: the metrics `fovsim check` judges (names, options, default tolerances) and their
 * tolerance specs (check.h, "tolerances"). The lowest of check's files: check.c, check_judge.c and
 * check_report.c read it, and it reads none of them. */
#include "commands/check.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* >>tolerances */

static const struct {
    const char *name, *option;
    double def; /* the default; docs/check.md "Tolerances" says why each */
} k_metrics[CHECK_METRIC_COUNT] = {
    [CHECK_COVERAGE] = {"coverage_ratio", "--tol-coverage", 0.05},
    [CHECK_RMSE] = {"rmse", "--tol-rmse", 0.01},
    [CHECK_ALPHA_RMSE] = {"alpha_rmse", "--tol-alpha-rmse", 0.01},
    [CHECK_FLIP] = {"flip", "--tol-flip", 0.01},
    [CHECK_TEMPORAL] = {"temporal_error", "--tol-temporal", 0.01},
    [CHECK_PIXEL] = {"pixel_2x2", "--tol-pixel", 0.75},
    [CHECK_PIXEL_RMSE] = {"pixel_rmse", "--tol-pixel-rmse", 0.05},
    [CHECK_TIME] = {"frame_time_ratio", "--tol-time", INFINITY},
};

void check_tols_default(check_tols *t)
{
    for (int m = 0; m < CHECK_METRIC_COUNT; m++) {
        t->t[m].any = k_metrics[m].def;
        t->t[m].all = NAN;
        for (int k = 0; k < MAX_FOV_RINGS; k++)
            t->t[m].ring[k] = NAN;
    }
}

const char *check_metric_name(check_metric m)
{
    return (unsigned)m < CHECK_METRIC_COUNT ? k_metrics[m].name : "rows";
}

const char *check_metric_option(check_metric m)
{
    return (unsigned)m < CHECK_METRIC_COUNT ? k_metrics[m].option : "";
}

check_metric check_metric_of_option(const char *opt)
{
    int m = 0;
    while (m < CHECK_METRIC_COUNT && strcmp(opt, k_metrics[m].option) != 0)
        m++;
    return (check_metric)m;
}

bool check_tol_apply(check_tol *t, const char *spec, char *err, int err_size)
{
    check_tol out = *t;
    const char *p = spec;
    for (;;) {
        size_t len = strcspn(p, ",");
        char item[64], *eq, *end;
        if (len == 0 || len >= sizeof item) {
            snprintf(err, (size_t)err_size, "expected VALUE, RING=VALUE or all=VALUE separated by commas, got '%s'",
                     spec);
            return false;
        }
        memcpy(item, p, len);
        item[len] = '\0';
        const char *val = (eq = strchr(item, '=')) ? eq + 1 : item;
        int ring = -2; /* -2: every ring, -1: the whole display */
        if (eq) {
            *eq = '\0';
            long k = strtol(item, &end, 10);
            if (!strcmp(item, "all"))
                ring = -1;
            else if (end != item && !*end && k >= 0 && k < MAX_FOV_RINGS)
                ring = (int)k;
            else {
                snprintf(err, (size_t)err_size, "'%s': expected a ring 0 to %d or all before '='", item,
                         MAX_FOV_RINGS - 1);
                return false;
            }
        }
        /* Decimal only: strtod also reads hex ("0x10" = 16), inf and nan, none of which a
         * tolerance is written as. */
        bool decimal = val[0] != '\0' && strspn(val, "0123456789.eE+-") == strlen(val);
        double v = decimal ? strtod(val, &end) : 0.0;
        if (!strcmp(val, "off"))
            v = INFINITY;
        else if (!decimal || end == val || *end || !isfinite(v) || v < 0.0) {
            snprintf(err, (size_t)err_size, "'%.40s': expected a decimal number >= 0 or off", val);
            return false;
        }
        if (ring == -2)
            out.any = v;
        else if (ring == -1)
            out.all = v;
        else
            out.ring[ring] = v;
        if (!p[len])
            break;
        p += len + 1;
    }
    *t = out;
    return true;
}

double check_tol_get(const check_tols *t, check_metric m, int ring)
{
    const check_tol *c = &t->t[m];
    double v = ring < 0 ? c->all : ring < MAX_FOV_RINGS ? c->ring[ring] : NAN;
    return isnan(v) ? c->any : v;
}

static void put_value(char *buf, int size, double v)
{
    if (isinf(v))
        snprintf(buf, (size_t)size, "off");
    else
        snprintf(buf, (size_t)size, "%.9g", v);
}

void check_tol_format(const check_tol *t, char *buf, int size)
{
    char v[32];
    put_value(v, sizeof v, t->any);
    int o = snprintf(buf, (size_t)size, "%s", v);
    for (int k = -1; k < MAX_FOV_RINGS && o < size; k++) {
        double x = k < 0 ? t->all : t->ring[k];
        if (isnan(x))
            continue;
        put_value(v, sizeof v, x);
        if (k < 0)
            o += snprintf(buf + o, (size_t)(size - o), ",all=%s", v);
        else
            o += snprintf(buf + o, (size_t)(size - o), ",%d=%s", k, v);
    }
}
