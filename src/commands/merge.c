/* merge.c: `fovsim merge SWEEP_DIR` (sweep.c says what a sweep folder holds): every task's
 * metrics into one CSV and one JSON summary, the tasks that are missing or did not finish, and
 * the accuracy-vs-time plot of the whole sweep. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/grow.h"
#include "core/log.h"
#include "output/gnuplot.h"
#include "output/report_html.h"
#include "output/out_path.h"
#include "core/strbuf.h"
#include "metrics/metrics.h"
#include "scene/scene.h"
#include "session/session.h"
#include "commands/commands.h"
#include "commands/merge.h"
#include "commands/sweep_manifest.h"

/* One (configuration, mode) of the sweep: the accuracy-vs-time point. */
typedef struct point {
    int config; /* scene, trace, layout, TAA, tracker: the task without its chunk */
    char mode[32];
    double *ms;
    int n, cap;
    double flip, ratio;  /* sums over rows: FLIP, the per-frame coverage ratios reported (>= 0) */
    double cov_px, ref_px; /* coverage summed over pixels and rows (display pixels), method and reference */
    int rows, ratio_rows;
} point;

typedef struct points {
    point *v;
    int n, cap;
} points;

static point *point_of(points *ps, int config, const char *mode)
{
    for (int i = 0; i < ps->n; i++)
        if (ps->v[i].config == config && !strcmp(ps->v[i].mode, mode))
            return &ps->v[i];
    if (!FS_GROW_INT(ps->v, ps->cap, ps->n + 1))
        return NULL;
    point *p = &ps->v[ps->n++];
    memset(p, 0, sizeof *p);
    p->config = config;
    snprintf(p->mode, sizeof p->mode, "%s", mode);
    return p;
}

/* The index of `name` among the comma-separated columns of `header`, or -1. */
static int column(const char *header, const char *name)
{
    int i = 0;
    size_t l = strlen(name);
    for (const char *c = header; c; c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL, i++)
        if (!strncmp(c, name, l) && (c[l] == ',' || c[l] == '\n' || c[l] == '\0'))
            return i;
    return -1;
}

/* Field `i` of a CSV row (no quoting in fovsim's metrics) into out ("" for a column not
 * there); false when the row has no field i or it does not fit in out. */
static bool field(const char *row, int i, char *out, size_t n)
{
    const char *c = i >= 0 ? row : NULL;
    for (int k = 0; k < i && c; k++)
        c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL;
    out[0] = '\0';
    if (!c)
        return false;
    int len = (int)strcspn(c, ",\n");
    snprintf(out, n, "%.*s", len, c);
    return (size_t)len < n;
}

/* Whether s is a whole number as fovsim's %.9g / %d / %lld writes it (nan and inf included). */
static bool number(const char *s, bool integer)
{
    char *end;
    errno = 0;
    if (integer)
        (void)strtoll(s, &end, 10);
    else
        (void)strtod(s, &end);
    return s[0] && !*end && end != s && (!integer || errno == 0);
}

/* The values merge reads back from a task's row are what fovsim writes: an alpha mode's name, an
 * integer ring >= -1, numbers. Anything else (a hand-edited or hostile file) is refused naming
 * path:line and the column, before it reaches a CSV, a summary or a gnuplot script. */
static fs_status check_row(const char *path, int line, const char *row, int c_mode, int c_ring,
                           const int *num_cols, const metrics_column *nums, int nnum)
{
    char v[64];
    if (!field(row, c_mode, v, sizeof v) || alpha_mode_parse(v) == ALPHA_MODE_DEFAULT) {
        log_error("%s:%d: column 'mode': '%.40s' is not an alpha mode (expected one of: %s)", path, line, v,
                  alpha_mode_list());
        return FS_ERR_IO;
    }
    if (!field(row, c_ring, v, sizeof v) || !number(v, true) || strtoll(v, NULL, 10) < -1) {
        log_error("%s:%d: column 'ring': '%.40s' is not a ring number (an integer >= -1)", path, line, v);
        return FS_ERR_IO;
    }
    for (int i = 0; i < nnum; i++)
        if (!field(row, num_cols[i], v, sizeof v) || !number(v, metrics_column_flags(nums[i]) & METRICS_COLF_WHOLE)) {
            log_error("%s:%d: column '%s': '%.40s' is not a number", path, line, metrics_column_name(nums[i]), v);
            return FS_ERR_IO;
        }
    return FS_OK;
}

/* The structure of a task's metrics.csv (docs/cluster.md), before a value is read: the header
 * names every column merge reads; every row has as many fields as the header, none empty, and
 * ends with a line break (a file cut mid-row lacks it). One line with file:line and FS_ERR_IO
 * otherwise. `text` is the whole file. */
static fs_status check_task_csv(const char *path, const char *text, size_t size)
{
    if (strlen(text) != size) {
        log_error("%s: holds a NUL byte (not a text file: a damaged or foreign metrics.csv)", path);
        return FS_ERR_IO;
    }
    static const metrics_column k_read[] = {METRICS_COL_MODE,     METRICS_COL_RING,           METRICS_COL_FRAME_MS,
                                            METRICS_COL_FLIP,     METRICS_COL_COVERAGE_RATIO, METRICS_COL_PIXELS,
                                            METRICS_COL_COVERAGE, METRICS_COL_REF_COVERAGE};
    size_t hl = strcspn(text, "\n");
    char header[2048];
    snprintf(header, sizeof header, "%.*s", (int)(hl < sizeof header ? hl : sizeof header - 1), text);
    for (size_t k = 0; k < sizeof k_read / sizeof k_read[0]; k++)
        if (column(header, metrics_column_name(k_read[k])) < 0) {
            log_error("%s:1: the header has no column '%s' (expected the header of fovsim compare's metrics.csv)",
                      path, metrics_column_name(k_read[k]));
            return FS_ERR_IO;
        }
    int want = 1;
    for (const char *c = header; *c; c++)
        want += *c == ',';
    int line = 1;
    for (const char *row = text; *row; line++) {
        size_t len = strcspn(row, "\n");
        if (row[len] != '\n') {
            log_error("%s:%d: the row is cut short (no line break after it): the task's metrics were not written "
                      "whole; run the task again", path, line);
            return FS_ERR_IO;
        }
        int fields = 1, empty = -1;
        for (size_t i = 0, start = 0; i <= len; i++)
            if (i == len || row[i] == ',') {
                if (i == start && empty < 0)
                    empty = fields;
                fields += i < len;
                start = i + 1;
            }
        if (fields != want) {
            log_error("%s:%d: %d fields, the header has %d (a damaged or foreign metrics.csv)", path, line, fields,
                      want);
            return FS_ERR_IO;
        }
        if (empty > 0 && line > 1) {
            char name[64];
            field(header, empty - 1, name, sizeof name);
            log_error("%s:%d: field %d (%s) is empty", path, line, empty, name);
            return FS_ERR_IO;
        }
        row += len + 1;
    }
    return FS_OK;
}

/* The numbers merge reads from a row (check_row checks each). */
static const metrics_column k_nums[] = {METRICS_COL_FRAME_MS, METRICS_COL_FLIP,     METRICS_COL_COVERAGE_RATIO,
                                        METRICS_COL_PIXELS,   METRICS_COL_COVERAGE, METRICS_COL_REF_COVERAGE};
enum { NUMS = (int)(sizeof k_nums / sizeof k_nums[0]) };

fs_status merge_check_metrics(const char *path, const char *text, size_t size)
{
    fs_status st = check_task_csv(path, text, size);
    if (st != FS_OK)
        return st;
    char header[2048];
    size_t hl = strcspn(text, "\n");
    snprintf(header, sizeof header, "%.*s", (int)(hl < sizeof header ? hl : sizeof header - 1), text);
    int num_cols[NUMS];
    for (int i = 0; i < NUMS; i++)
        num_cols[i] = column(header, metrics_column_name(k_nums[i]));
    int c_mode = column(header, metrics_column_name(METRICS_COL_MODE));
    int c_ring = column(header, metrics_column_name(METRICS_COL_RING)), line = 1;
    /* Rows end with a line break (check_task_csv); field() stops at it. */
    for (const char *row = text + hl + (text[hl] == '\n'); *row && st == FS_OK; row += strcspn(row, "\n") + 1)
        st = check_row(path, ++line, row, c_mode, c_ring, num_cols, k_nums, NUMS);
    return st;
}

/* Appends task k's metrics rows (prefixed) to csv, and its ring -1 rows to the points. */
static fs_status gather(const sweep_manifest *m, const sweep_task *k, const char *prefix, int config, char *header,
                        size_t header_cap, sbuf *csv, points *ps)
{
    char dir[PATH_MAX + 300], path[PATH_MAX + 320];
    sweep_task_dir(m, k, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/metrics.csv", dir);
    char *text = NULL;
    size_t size = 0;
    fs_status st = file_read_all(path, (size_t)1 << 31, "a task's metrics", FS_ERR_IO, &text, &size);
    if (st != FS_OK)
        return st;
    if ((st = merge_check_metrics(path, text, size)) != FS_OK) {
        free(text);
        return st;
    }
    char *nl = strchr(text, '\n');
    if (!nl) {
        log_error("%s: expected a header line and rows", path);
        free(text);
        return FS_ERR_IO;
    }
    *nl = '\0';
    if (!header[0]) {
        snprintf(header, header_cap, "%s", text);
    } else if (strcmp(header, text) != 0) {
        log_error("%s: its columns differ from the other tasks' (written by another fovsim?)", path);
        free(text);
        return FS_ERR_IO;
    }
    int c[METRICS_COL_COUNT];
    for (int i = 0; i < METRICS_COL_COUNT; i++)
        c[i] = column(header, metrics_column_name((metrics_column)i));
    int c_mode = c[METRICS_COL_MODE], c_ring = c[METRICS_COL_RING], c_ms = c[METRICS_COL_FRAME_MS],
        c_flip = c[METRICS_COL_FLIP], c_ratio = c[METRICS_COL_COVERAGE_RATIO], c_px = c[METRICS_COL_PIXELS],
        c_cov = c[METRICS_COL_COVERAGE], c_ref = c[METRICS_COL_REF_COVERAGE];
    /* Every row was checked (merge_check_metrics): read it. */
    for (char *row = nl + 1; *row && st == FS_OK;) {
        char *end = strchr(row, '\n');
        size_t len = end ? (size_t)(end - row) : strlen(row);
        sb_append(csv, prefix, strlen(prefix));
        sb_append(csv, row, len);
        sb_append(csv, "\n", 1);
        char ring[16], mode[32], v[64];
        field(row, c_ring, ring, sizeof ring);
        field(row, c_mode, mode, sizeof mode);
        if (!strcmp(ring, "-1")) {
            point *p = point_of(ps, config, mode);
            if (!p || !FS_GROW_INT(p->ms, p->cap, p->n + 1)) {
                st = FS_ERR_NOMEM;
                break;
            }
            field(row, c_ms, v, sizeof v);
            p->ms[p->n++] = atof(v);
            field(row, c_flip, v, sizeof v);
            p->flip += atof(v);
            /* A per-frame ratio of -1 was not reported (too little reference coverage, metrics.h) */
            field(row, c_ratio, v, sizeof v);
            if (atof(v) >= 0.0) {
                p->ratio += atof(v);
                p->ratio_rows++;
            }
            field(row, c_px, v, sizeof v);
            double px = atof(v);
            field(row, c_cov, v, sizeof v);
            p->cov_px += atof(v) * px;
            field(row, c_ref, v, sizeof v);
            p->ref_px += atof(v) * px;
            p->rows++;
        }
        row = end ? end + 1 : row + len;
    }
    free(text);
    return csv->oom ? FS_ERR_NOMEM : st;
}

/* The task's summary.json as a JSON object into *out. A file that cannot be read, is not JSON or
 * not an object is refused with one line (file:line:column for a syntax error), never merged as
 * null (docs/cluster.md). */
static fs_status task_summary(const sweep_manifest *m, const sweep_task *k, cJSON **out)
{
    char dir[PATH_MAX + 300], path[PATH_MAX + 320];
    sweep_task_dir(m, k, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/summary.json", dir);
    char *text = NULL;
    size_t size = 0;
    *out = NULL;
    fs_status st = file_read_all(path, 1 << 24, "a task's summary", FS_ERR_IO, &text, &size);
    if (st != FS_OK)
        return st;
    st = merge_parse_summary(path, text, size, out);
    free(text);
    return st;
}

fs_status merge_parse_summary(const char *path, const char *text, size_t size, cJSON **out)
{
    *out = NULL;
    const char *end = NULL;
    cJSON *j = cJSON_ParseWithLengthOpts(text, size + 1, &end, true);
    if (!j || !cJSON_IsObject(j)) {
        size_t off = !j && end && end >= text ? (size_t)(end - text) : 0;
        int line = 1, col = 1;
        for (size_t i = 0; i < off && i < size; i++)
            text[i] == '\n' ? (line++, col = 1) : col++;
        if (j)
            log_error("%s: expected a JSON object (fovsim compare's summary)", path);
        else
            log_error("%s:%d:%d: not valid JSON (a damaged summary: run the task again)", path, line, col);
        cJSON_Delete(j);
        return FS_ERR_IO;
    }
    *out = j;
    return FS_OK;
}

static void short_of(const char *s, char *out, size_t n)
{
    const char *b = !s ? "centre" : strrchr(s, '/') ? strrchr(s, '/') + 1 : s;
    snprintf(out, n, "%s", b);
}

/* `skip`: columns before the mode beyond the four of every sweep (the tracker's). */
static fs_status plot(const char *dir, const points *ps, int skip)
{
    if (!gnuplot_available()) {
        printf("(gnuplot is not installed: no accuracy.png; the points are in %s/accuracy.csv)\n", dir);
        return FS_OK;
    }
    /* gnuplot runs in DIR: the script names its files relative to it, and each mode (checked
     * against fovsim's mode names when read) is a quoted gnuplot string. */
    sbuf gp = {0};
    sb_puts(&gp, "set datafile separator ','\nset title 'fovsim sweep: error vs frame time, one point per "
                 "configuration and mode'\nset xlabel 'frame time, median (ms; lower is better)'\n"
                 "set ylabel 'FLIP vs reference (mean over frames; lower is better)'\nset grid\nset key outside right top\nplot ");
    /* One series per mode, in the order they first appear. */
    for (int i = 0, first = 1; i < ps->n; i++) {
        bool seen = false;
        for (int j = 0; j < i; j++)
            seen = seen || !strcmp(ps->v[j].mode, ps->v[i].mode);
        if (seen)
            continue;
        sb_puts(&gp, first ? "" : ", \\\n     ");
        char using[64], value[64];
        snprintf(using, sizeof using, "'accuracy.csv' u %d:(strcol(%d) eq ", 6 + skip, 5 + skip);
        snprintf(value, sizeof value, " ? $%d : NaN) w p pt 7 ps 1.3 lc rgb ", 7 + skip);
        sb_puts(&gp, using);
        gnuplot_str(&gp, ps->v[i].mode);
        char col[8]; /* each mode its own colour in every plot (FS_ALPHA_MODES) */
        sb_puts(&gp, value);
        gnuplot_str(&gp, alpha_mode_colour(alpha_mode_parse(ps->v[i].mode), col));
        sb_puts(&gp, " t ");
        gnuplot_str(&gp, ps->v[i].mode);
        first = 0;
    }
    sb_puts(&gp, "\n");
    fs_status st = gnuplot_png(dir, "accuracy", 1100, 750, &gp);
    free(gp.p);
    return st;
}

static int cmp_double(const void *a, const void *b)
{
    return stats_cmp_double(a, b);
}

/* A task's tracker columns ("50,default,0.5,hold,"), or "" for a sweep without tracker axes. */
static void tracker_columns(const sweep_manifest *m, int e, char *out, size_t n)
{
    size_t o = 0;
    out[0] = '\0';
    for (int a = 0; m->has_tracker && a < SWEEP_TRACKER_AXES && o < n; a++) {
        const char *v = sweep_tracker_value(m, e, a);
        int w = snprintf(out + o, n - o, "%s,", v ? v : "default");
        o += w > 0 ? (size_t)w : 0;
    }
}

fs_status cmd_merge(int argc, char **argv)
{
    const char *dir = NULL;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: fovsim merge SWEEP_DIR\n\n"
                   "Gathers every task of a sweep (fovsim sweep) into SWEEP_DIR/metrics.csv (each task's rows,\n"
                   "after the columns task, scene, gaze, rings, taa), SWEEP_DIR/summary.json (each task's\n"
                   "summary, and the tasks missing or incomplete) and the accuracy-vs-time plot of the\n"
                   "whole sweep, SWEEP_DIR/accuracy.png (points in accuracy.csv). Lists the tasks that are\n"
                   "missing or did not finish, and then exits 11. docs/cluster.md\n");
            return FS_OK;
        }
        if (argv[i][0] == '-' || dir) {
            log_error("fovsim merge: unexpected argument '%s' (see fovsim merge --help)", argv[i]);
            return FS_ERR_USAGE;
        }
        dir = argv[i];
    }
    if (!dir) {
        log_error("fovsim merge: expected a sweep's folder (see fovsim merge --help)");
        return FS_ERR_USAGE;
    }
    sweep_manifest m;
    fs_status st = sweep_manifest_load_dir(dir, &m);
    if (st == FS_OK)
        st = sweep_build_tasks(&m);
    sbuf csv = {0}, acc = {0};
    points ps = {0};
    char header[2048] = "";
    cJSON *sum = cJSON_CreateObject(), *results = cJSON_CreateArray(), *missing = cJSON_CreateArray();
    int done = 0, absent = 0;
    for (int i = 0; i < m.ntasks && st == FS_OK; i++) {
        const sweep_task *k = &m.tasks[i];
        sweep_task_state s = sweep_task_status(&m, k);
        if (s != TASK_DONE) {
            printf("task %d (%s): %s\n", i, k->name, s == TASK_TODO ? "missing" : "incomplete (started, not finished)");
            cJSON_AddItemToArray(missing, cJSON_CreateString(k->name));
            absent++;
            continue;
        }
        char sc[128], gz[128], prefix[1024];
        short_of(m.scenes[k->scene], sc, sizeof sc);
        short_of(m.gaze[k->gaze], gz, sizeof gz);
        int pl = snprintf(prefix, sizeof prefix, "%s,%s,%s,%s,%s,", k->name, sc, gz, m.rings[k->rings], m.taa[k->taa]);
        tracker_columns(&m, k->tracker, prefix + pl, sizeof prefix - (size_t)pl);
        int config = (((k->scene * m.ngaze + k->gaze) * m.nrings + k->rings) * m.ntaa + k->taa) * m.ntracker + k->tracker;
        st = gather(&m, k, prefix, config, header, sizeof header, &csv, &ps);
        cJSON *r = cJSON_CreateObject();
        cJSON_AddStringToObject(r, "task", k->name);
        cJSON_AddStringToObject(r, "scene", m.scenes[k->scene]);
        cJSON_AddStringToObject(r, "gaze", m.gaze[k->gaze] ? m.gaze[k->gaze] : "centre");
        cJSON_AddStringToObject(r, "rings", m.rings[k->rings]);
        cJSON_AddStringToObject(r, "taa", m.taa[k->taa]);
        for (int a = 0; m.has_tracker && a < SWEEP_TRACKER_AXES; a++) {
            const char *v = sweep_tracker_value(&m, k->tracker, a);
            cJSON_AddStringToObject(r, sweep_tracker_key(a), v ? v : "default");
        }
        cJSON_AddNumberToObject(r, "first_frame", k->first);
        if (k->end)
            cJSON_AddNumberToObject(r, "end_frame", k->end);
        cJSON *ts = NULL;
        if (st == FS_OK)
            st = task_summary(&m, k, &ts);
        cJSON_AddItemToObject(r, "summary", ts ? ts : cJSON_CreateNull());
        cJSON_AddItemToArray(results, r);
        done++;
    }
    if (st == FS_OK && done > 0) {
        char path[PATH_MAX + 32];
        sbuf all = {0};
        const char *cols = "task,scene,gaze,rings,taa,";
        sb_append(&all, cols, strlen(cols));
        if (m.has_tracker) /* only then: merged sweeps without a tracker read as before */
            sb_puts(&all, "gaze_latency,gaze_rate,gaze_noise,gaze_loss,");
        sb_append(&all, header, strlen(header));
        sb_append(&all, "\n", 1);
        sb_append(&all, csv.p, csv.len);
        snprintf(path, sizeof path, "%s/metrics.csv", dir);
        st = all.oom ? FS_ERR_NOMEM : out_write_atomic(path, all.p);
        free(all.p);
        /* accuracy.csv: one point per configuration and mode */
        const char *ah = "mode,frame_ms_median,flip_mean,coverage_ratio_mean,frames,coverage_ratio,ref_coverage_px\n";
        sb_puts(&acc, "scene,gaze,rings,taa,");
        if (m.has_tracker)
            sb_puts(&acc, "gaze_latency,gaze_rate,gaze_noise,gaze_loss,");
        sb_append(&acc, ah, strlen(ah));
        for (int i = 0; i < ps.n && st == FS_OK; i++) {
            point *p = &ps.v[i];
            int c = p->config, e = c % m.ntracker;
            c /= m.ntracker;
            int t = c % m.ntaa, r = (c /= m.ntaa) % m.nrings, g = (c /= m.nrings) % m.ngaze, s = c / m.ngaze;
            char tc[256];
            tracker_columns(&m, e, tc, sizeof tc);
            qsort(p->ms, (size_t)p->n, sizeof *p->ms, cmp_double);
            char sc[128], gz[128], line[1024];
            short_of(m.scenes[s], sc, sizeof sc);
            short_of(m.gaze[g], gz, sizeof gz);
            /* The whole display: texels are display pixels (metrics_coverage_ratio_rests, block 1). */
            int l = snprintf(line, sizeof line, "%s,%s,%s,%s,%s%s,%.4f,%.6f,%.5f,%d,%.5f,%.3f\n", sc, gz, m.rings[r],
                             m.taa[t], tc, p->mode, stats_quantile(p->ms, p->n, 0.5), p->flip / p->rows,
                             p->ratio_rows ? p->ratio / p->ratio_rows : -1.0, p->rows,
                             metrics_coverage_ratio_of_sums(p->cov_px, p->ref_px, 1), p->ref_px);
            sb_append(&acc, line, (size_t)l);
        }
        snprintf(path, sizeof path, "%s/accuracy.csv", dir);
        if (st == FS_OK)
            st = acc.oom ? FS_ERR_NOMEM : out_write_atomic(path, acc.p);
        if (st == FS_OK)
            st = plot(dir, &ps, m.has_tracker ? SWEEP_TRACKER_AXES : 0);
    }
    if (st == FS_OK) {
        cJSON_AddStringToObject(sum, "sweep", m.out);
        cJSON_AddNumberToObject(sum, "tasks", m.ntasks);
        cJSON_AddNumberToObject(sum, "complete", done);
        cJSON_AddItemToObject(sum, "missing_or_incomplete", missing);
        cJSON_AddItemToObject(sum, "results", results);
        missing = results = NULL;
        char *text = cJSON_Print(sum), path[PATH_MAX + 32];
        snprintf(path, sizeof path, "%s/summary.json", dir);
        st = text ? out_write_atomic(path, text) : FS_ERR_NOMEM;
        cJSON_free(text);
    }
    if (st == FS_OK)
        st = report_html_write(&(report_html_desc){.dir = dir, .kind = "merge", .acc_error = "flip_mean",
                                                   .acc_error_label = "FLIP vs reference (mean over frames)"});
    if (st == FS_OK) {
        printf("merged %d of %d tasks into %s/metrics.csv, summary.json and accuracy.csv%s\n", done, m.ntasks, dir,
               done ? "" : " (no task has finished)");
        if (absent) {
            log_error("%s: %d of %d tasks missing or incomplete (listed above); run the sweep again to finish them",
                      dir, absent, m.ntasks);
            st = FS_ERR_INCOMPLETE;
        }
    }
    cJSON_Delete(sum);
    cJSON_Delete(missing);
    cJSON_Delete(results);
    for (int i = 0; i < ps.n; i++)
        free(ps.v[i].ms);
    free(ps.v);
    free(csv.p);
    free(acc.p);
    sweep_manifest_free(&m);
    return st;
}
