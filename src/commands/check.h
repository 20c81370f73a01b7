/* check.h: `fovsim check`, renderer regression tests against a recorded baseline
 * (docs/check.md).
 *
 *   fovsim check --record DIR [SCENE] [compare's options] [--tol-METRIC SPEC ...]
 *   fovsim check --baseline DIR [--out NEXT] [--junit FILE] [--tol-METRIC SPEC ...]
 *
 * --record runs `fovsim compare` with the given options into DIR (the baseline: compare's two-part
 * frames, metrics.csv, summary.json and fovsim-run.txt) and writes DIR/check.json: the exact
 * command line, the compare options it re-runs, the fovsim version and the tolerances.
 * --baseline re-runs those options into NEXT (default DIR-next) and compares NEXT with DIR, per
 * frame, alpha mode (and the reference's pixels) and measurement ring: coverage ratio, RMSE, alpha
 * RMSE, FLIP and temporal error from metrics.csv, and the pixels of the frames (RMSE, and the
 * largest difference of ring-texel-sized 2x2 block means: image_diff.h). It prints a one-screen
 * report, writes NEXT/diff.<frame>.exr for every frame that failed, NEXT/check.json (the verdict
 * and every failure) and with --junit a JUnit XML file. FS_REGRESSION (exit 1) when anything is
 * outside its tolerance.
 *
 * check.c holds the command (options, check.json, running compare in-process); check_judge.c
 * the comparison, the report and the JUnit file. What it does NOT do: compare FovVideoVDP JODs
 * (pyfvvdp is not installed here), or look at frame times unless --tol-time is given (timing is
 * not reproducible across machines). */
#ifndef FOVSIM_CHECK_H
#define FOVSIM_CHECK_H

#include <stdbool.h>

#include "core/config.h"
#include "core/status.h"

/* >>tolerances (check_tol.c) */

typedef enum check_metric {
    CHECK_COVERAGE = 0, /* |coverage_ratio now - baseline| (either way: erosion and bloat) */
    CHECK_RMSE,         /* rmse now - baseline (only growth fails) */
    CHECK_ALPHA_RMSE,   /* alpha_rmse now - baseline */
    CHECK_FLIP,         /* flip now - baseline */
    CHECK_TEMPORAL,     /* temporal_error now - baseline (where both were measured) */
    CHECK_PIXEL,        /* the largest |block mean difference| of the frame's pixels */
    CHECK_PIXEL_RMSE,   /* the RMSE of the frame's pixels */
    CHECK_TIME,         /* median frame time now / baseline, per mode (off by default) */
    CHECK_METRIC_COUNT
} check_metric;

/* One metric's tolerances: `any` for every ring, overridden per ring and for the whole display
 * (NAN: not overridden). INFINITY = not checked ("off"). */
typedef struct check_tol {
    double any, all, ring[MAX_FOV_RINGS];
} check_tol;

typedef struct check_tols {
    check_tol t[CHECK_METRIC_COUNT];
} check_tols;

/* The defaults (docs/check.md says why). */
void check_tols_default(check_tols *t);
/* The metric's name in messages and JSON ("coverage_ratio"), and its option ("--tol-coverage"). */
const char *check_metric_name(check_metric m);
const char *check_metric_option(check_metric m);
/* The metric of an option name, or CHECK_METRIC_COUNT. */
check_metric check_metric_of_option(const char *opt);
/* Applies SPEC: a comma-separated list of VALUE (every ring), RING=VALUE (ring 0..) or all=VALUE
 * (the whole display); VALUE a number >= 0 or "off". False with one line in err on a bad SPEC. */
bool check_tol_apply(check_tol *t, const char *spec, char *err, int err_size);
/* The tolerance of ring k (-1 = the whole display). */
double check_tol_get(const check_tols *t, check_metric m, int ring);
/* The tolerances as a SPEC string per metric (what check.json holds; what check_tol_apply reads). */
void check_tol_format(const check_tol *t, char *buf, int size);

/* >>judging (check_judge.c) */

typedef struct check_judge_desc {
    const char *baseline; /* the baseline folder */
    const char *next;     /* the folder this run wrote */
    const char *label;    /* the suite's name in JUnit (the baseline folder's name) */
    const check_tols *tols;
    const char *junit;    /* --junit FILE, or NULL */
    int max_lines;        /* failures listed on stdout (the rest are in NEXT/check.json and JUnit) */
} check_judge_desc;

typedef struct check_verdict {
    int cases, failed_cases; /* frame x image cases (+ the run's own), those with a failure */
    int values, failed_values;
    char *failures_json;     /* a JSON array of every failure (malloc'd; free it) */
} check_verdict;

/* Reads every file of the baseline in `dir` that a check compares with (metrics.csv, summary.json,
 * every frame whole): FS_ERR_IO with one line naming the first one missing or damaged. */
fs_status check_baseline_validate(const char *dir);
/* Compares NEXT with the baseline, prints the report, writes the diff images and --junit.
 * FS_OK with *v filled (v->failed_values > 0: a regression); FS_ERR_IO with one line when a file of
 * either folder is missing or damaged; FS_ERR_NOMEM. */
fs_status check_judge(const check_judge_desc *d, check_verdict *v);

/* >>baseline (check.c) */

#define CHECK_MAX_ARGS 256 /* compare options a baseline holds */

struct cJSON;
/* A baseline's check.json, already parsed into root (DIR names it in messages): its compare options
 * into argv (at most CHECK_MAX_ARGS, borrowed from root; argv[0] is "compare"), its tolerances into
 * *t (the defaults where it names none) and the recording fovsim's version into *version. Every key
 * and value is checked: unknown keys, a wrong format or role, options a baseline never stores
 * (--cache, --gpu, --out, ...), bad tolerance specs: FS_ERR_USAGE with one line naming the file and
 * the JSON path. tests/fuzz/fuzz_check_merge.c feeds it. */
fs_status check_baseline_parse(const char *dir, const struct cJSON *root, const char **argv, int *argc,
                               check_tols *t, const char **version);

#endif
