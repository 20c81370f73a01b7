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
                        size_t header_cap, FILE *csv, points *ps)
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
    if (!header[0]) { /* the merged file's header: the sweep's columns, then the tasks' */
        snprintf(header, header_cap, "%s", text);
        fputs("task,scene,gaze,rings,taa,", csv);
        if (m->has_tracker) /* only then: merged sweeps without a tracker read as before */
            fputs("gaze_latency,gaze_rate,gaze_noise,gaze_loss,", csv);
        fprintf(csv, "%s\n", header);
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
        fprintf(csv, "%s%.*s\n", prefix, (int)len, row);
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
    return st;
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

/* >>the merged files, written as they are gathered */

/* A file of the merge written while the tasks are read, under a temporary name renamed to its
 * own when whole, so that memory holds one task's files, never the sweep's, and a merge that
 * fails leaves the earlier files as they were. */
typedef struct out_stream {
    FILE *f;
    char path[PATH_MAX + 32], tmp[PATH_MAX + 128];
} out_stream;

static fs_status stream_open(out_stream *o, const char *dir, const char *name)
{
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    o->f = out_path_temp_name(o->path, o->tmp, sizeof o->tmp) ? fopen(o->tmp, "w") : NULL;
    if (!o->f) {
        log_error("%s: cannot write: %s", o->path, strerror(errno));
        return FS_ERR_IO;
    }
    return FS_OK;
}

/* keep: rename it into place (when everything went well), else remove it. */
static fs_status stream_close(out_stream *o, bool keep)
{
    if (!o->f)
        return FS_OK;
    bool ok = !ferror(o->f);
    ok = fclose(o->f) == 0 && ok;
    o->f = NULL;
    if (keep && ok && rename(o->tmp, o->path) == 0)
        return FS_OK;
    unlink(o->tmp);
    if (keep) {
        log_error("%s: cannot write: %s", o->path, strerror(errno));
        return FS_ERR_IO;
    }
    return FS_OK;
}

/* A JSON string (quoted and escaped by cJSON). */
static void json_string(FILE *f, const char *s)
{
    cJSON *j = cJSON_CreateString(s);
    char *t = j ? cJSON_PrintUnformatted(j) : NULL;
    fputs(t ? t : "null", f);
    cJSON_free(t);
    cJSON_Delete(j);
}

/* accuracy.csv's lines of the points (one configuration's: its tasks are consecutive), then frees
 * their frame times. */
static void flush_points(const sweep_manifest *m, points *ps, FILE *acc)
{
    for (int i = 0; i < ps->n; i++) {
        point *p = &ps->v[i];
        int c = p->config, e = c % m->ntracker;
        c /= m->ntracker;
        int t = c % m->ntaa, r = (c /= m->ntaa) % m->nrings, g = (c /= m->nrings) % m->ngaze, s = c / m->ngaze;
        char tc[256], sc[128], gz[128];
        tracker_columns(m, e, tc, sizeof tc);
        qsort(p->ms, (size_t)p->n, sizeof *p->ms, stats_cmp_double);
        short_of(m->scenes[s], sc, sizeof sc);
        short_of(m->gaze[g], gz, sizeof gz);
        /* The whole display: texels are display pixels (metrics_coverage_ratio_rests, block 1). */
        fprintf(acc, "%s,%s,%s,%s,%s%s,%.4f,%.6f,%.5f,%d,%.5f,%.3f\n", sc, gz, m->rings[r], m->taa[t], tc, p->mode,
                stats_quantile(p->ms, p->n, 0.5), p->flip / p->rows, p->ratio_rows ? p->ratio / p->ratio_rows : -1.0,
                p->rows, metrics_coverage_ratio_of_sums(p->cov_px, p->ref_px, 1), p->ref_px);
        free(p->ms);
    }
    ps->n = 0;
}

/* Task k's entry of summary.json's "results", its summary.json inside. */
static fs_status write_result(const sweep_manifest *m, const sweep_task *k, bool first, FILE *out)
{
    cJSON *r = cJSON_CreateObject();
    cJSON_AddStringToObject(r, "task", k->name);
    cJSON_AddStringToObject(r, "scene", m->scenes[k->scene]);
    cJSON_AddStringToObject(r, "gaze", m->gaze[k->gaze] ? m->gaze[k->gaze] : "centre");
    cJSON_AddStringToObject(r, "rings", m->rings[k->rings]);
    cJSON_AddStringToObject(r, "taa", m->taa[k->taa]);
    for (int a = 0; m->has_tracker && a < SWEEP_TRACKER_AXES; a++) {
        const char *v = sweep_tracker_value(m, k->tracker, a);
        cJSON_AddStringToObject(r, sweep_tracker_key(a), v ? v : "default");
    }
    cJSON_AddNumberToObject(r, "first_frame", k->first);
    if (k->end)
        cJSON_AddNumberToObject(r, "end_frame", k->end);
    cJSON *ts = NULL;
    fs_status st = task_summary(m, k, &ts);
    cJSON_AddItemToObject(r, "summary", ts ? ts : cJSON_CreateNull());
    char *text = st == FS_OK ? cJSON_PrintUnformatted(r) : NULL;
    if (st == FS_OK && !text)
        st = FS_ERR_NOMEM;
    if (text)
        fprintf(out, "%s\n    %s", first ? "" : ",", text);
    cJSON_free(text);
    cJSON_Delete(r);
    return st;
}

/* >>merge */

#define MERGE_MISSING_SHOWN 20       /* missing tasks listed without --list-missing */
#define MERGE_REPORT_MAX_TASKS 500   /* report.html (one table per task) up to this many tasks */

typedef struct merge_run {
    const char *dir;
    sweep_manifest m;
    sweep_ident *id;
    out_stream csv, sum, acc;
    points ps, modes; /* the points of the configuration being read; every mode seen (for the plot) */
    char header[2048];
    char exe[160];    /* the executable that wrote the first complete task (its record's line) */
    int exe_task;
    int *absent;      /* missing (2 i) or incomplete (2 i + 1) tasks */
    int nabsent, cap_absent, done, config;
} merge_run;

/* Every task of the same sweep was written by one executable; merge compares them with each other,
 * not with the one merging (a fovsim rebuilt after the sweep still merges it). */
static fs_status same_executable(merge_run *r, int i, const char *exe)
{
    if (!r->exe[0]) {
        snprintf(r->exe, sizeof r->exe, "%s", exe);
        r->exe_task = i;
    } else if (strcmp(r->exe, exe) != 0) {
        log_error("%s: task %d (%s) was written by another fovsim than task %d (fovsim: '%s' there, '%s' in task "
                  "%d): results of two builds are not merged; run the sweep again with one fovsim", r->dir, i,
                  r->m.tasks[i].name, r->exe_task, exe, r->exe, r->exe_task);
        return FS_ERR_USAGE;
    }
    return FS_OK;
}

/* Task i: recorded as absent, refused (another configuration than the manifest's), or gathered. */
static fs_status merge_task(merge_run *r, int i)
{
    const sweep_manifest *m = &r->m;
    const sweep_task *k = &m->tasks[i];
    sweep_task_check c;
    fs_status st = sweep_task_status(m, k, r->id, true, &c);
    if (st != FS_OK)
        return st;
    if (c.state == TASK_TODO || c.state == TASK_INCOMPLETE) {
        if (!FS_GROW_INT(r->absent, r->cap_absent, r->nabsent + 1))
            return FS_ERR_NOMEM;
        r->absent[r->nabsent++] = 2 * i + (c.state == TASK_INCOMPLETE);
        return FS_OK;
    }
    if (c.state == TASK_STALE) {
        log_error("%s: task %d (%s) holds another configuration than the manifest (%s); fovsim sweep draws it "
                  "again", r->dir, i, k->name, c.why);
        return FS_ERR_USAGE;
    }
    if ((st = same_executable(r, i, c.exe)) != FS_OK)
        return st;
    int config = (((k->scene * m->ngaze + k->gaze) * m->nrings + k->rings) * m->ntaa + k->taa) * m->ntracker +
                 k->tracker;
    if (config != r->config) /* the configuration before is whole: its points go out */
        flush_points(m, &r->ps, r->acc.f);
    r->config = config;
    char sc[128], gz[128], prefix[1024];
    short_of(m->scenes[k->scene], sc, sizeof sc);
    short_of(m->gaze[k->gaze], gz, sizeof gz);
    int pl = snprintf(prefix, sizeof prefix, "%s,%s,%s,%s,%s,", k->name, sc, gz, m->rings[k->rings], m->taa[k->taa]);
    tracker_columns(m, k->tracker, prefix + pl, sizeof prefix - (size_t)pl);
    st = gather(m, k, prefix, config, r->header, sizeof r->header, r->csv.f, &r->ps);
    for (int p = 0; p < r->ps.n && st == FS_OK; p++)
        if (!point_of(&r->modes, 0, r->ps.v[p].mode))
            st = FS_ERR_NOMEM;
    if (st == FS_OK)
        st = write_result(m, k, r->done == 0, r->sum.f);
    r->done += st == FS_OK;
    return st;
}

/* The missing and incomplete tasks: all with --list-missing, else the first MERGE_MISSING_SHOWN and
 * how many more; and summary.json's list of them. */
static void report_absent(const merge_run *r, bool all)
{
    int shown = all || r->nabsent <= MERGE_MISSING_SHOWN ? r->nabsent : MERGE_MISSING_SHOWN;
    for (int j = 0; j < shown; j++) {
        int i = r->absent[j] / 2;
        printf("task %d (%s): %s\n", i, r->m.tasks[i].name,
               r->absent[j] % 2 ? "incomplete (started, not finished)" : "missing");
    }
    if (shown < r->nabsent)
        printf("... and %d more (fovsim merge %s --list-missing lists them all)\n", r->nabsent - shown, r->dir);
}

static fs_status merge_finish(merge_run *r, fs_status st)
{
    flush_points(&r->m, &r->ps, r->acc.f);
    FILE *f = r->sum.f;
    fprintf(f, "\n  ],\n  \"tasks\": %d,\n  \"complete\": %d,\n  \"missing_or_incomplete\": [", r->m.ntasks, r->done);
    for (int j = 0; j < r->nabsent; j++) {
        fputs(j ? ", " : "", f);
        json_string(f, r->m.tasks[r->absent[j] / 2].name);
    }
    fputs("]\n}\n", f);
    /* metrics.csv and accuracy.csv only when a task finished (as before: no header-only files) */
    fs_status s1 = stream_close(&r->csv, st == FS_OK && r->done > 0);
    fs_status s2 = stream_close(&r->acc, st == FS_OK && r->done > 0 && s1 == FS_OK);
    fs_status s3 = stream_close(&r->sum, st == FS_OK && s1 == FS_OK && s2 == FS_OK);
    return st != FS_OK ? st : s1 != FS_OK ? s1 : s2 != FS_OK ? s2 : s3;
}

static fs_status merge_run_all(merge_run *r)
{
    fs_status st = stream_open(&r->csv, r->dir, "metrics.csv");
    if (st == FS_OK)
        st = stream_open(&r->acc, r->dir, "accuracy.csv");
    if (st == FS_OK)
        st = stream_open(&r->sum, r->dir, "summary.json");
    if (st != FS_OK) {
        stream_close(&r->csv, false);
        stream_close(&r->acc, false);
        return st;
    }
    fputs("scene,gaze,rings,taa,", r->acc.f);
    if (r->m.has_tracker)
        fputs("gaze_latency,gaze_rate,gaze_noise,gaze_loss,", r->acc.f);
    fputs("mode,frame_ms_median,flip_mean,coverage_ratio_mean,frames,coverage_ratio,ref_coverage_px\n", r->acc.f);
    fputs("{\n  \"sweep\": ", r->sum.f);
    json_string(r->sum.f, r->m.out);
    fputs(",\n  \"results\": [", r->sum.f);
    r->config = -1;
    for (int i = 0; i < r->m.ntasks && st == FS_OK; i++)
        st = merge_task(r, i);
    return merge_finish(r, st);
}

static void merge_help(void)
{
    printf("usage: fovsim merge SWEEP_DIR [--list-missing]\n\n"
           "Gathers every task of a sweep (fovsim sweep) into SWEEP_DIR/metrics.csv (each task's rows,\n"
           "after the columns task, scene, gaze, rings, taa), SWEEP_DIR/summary.json (each task's\n"
           "summary, and the tasks missing or incomplete) and the accuracy-vs-time plot of the\n"
           "whole sweep, SWEEP_DIR/accuracy.png (points in accuracy.csv). Refuses a task whose folder\n"
           "holds another configuration than the manifest's. Lists the first %d tasks that are missing\n"
           "or did not finish (--list-missing: all of them), and then exits 11. docs/cluster.md\n",
           MERGE_MISSING_SHOWN);
}

fs_status cmd_merge(int argc, char **argv)
{
    merge_run r = {0};
    bool list_missing = false;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            merge_help();
            return FS_OK;
        }
        if (!strcmp(argv[i], "--list-missing")) {
            list_missing = true;
            continue;
        }
        if (argv[i][0] == '-' || r.dir) {
            log_error("fovsim merge: unexpected argument '%s' (see fovsim merge --help)", argv[i]);
            return FS_ERR_USAGE;
        }
        r.dir = argv[i];
    }
    if (!r.dir) {
        log_error("fovsim merge: expected a sweep's folder (see fovsim merge --help)");
        return FS_ERR_USAGE;
    }
    const char *dir = r.dir;
    fs_status st = sweep_manifest_load_dir(dir, &r.m);
    if (st == FS_OK)
        st = sweep_build_tasks(&r.m);
    if (st == FS_OK && !(r.id = sweep_ident_new()))
        st = FS_ERR_NOMEM;
    if (st == FS_OK)
        st = merge_run_all(&r);
    if (st == FS_OK && r.done > 0)
        st = plot(dir, &r.modes, r.m.has_tracker ? SWEEP_TRACKER_AXES : 0);
    if (st == FS_OK && r.m.ntasks <= MERGE_REPORT_MAX_TASKS)
        st = report_html_write(&(report_html_desc){.dir = dir, .kind = "merge", .acc_error = "flip_mean",
                                                   .acc_error_label = "FLIP vs reference (mean over frames)"});
    else if (st == FS_OK) /* it reads summary.json back whole: memory would grow with the sweep */
        printf("(no report.html for a sweep of more than %d tasks: summary.json and accuracy.csv hold them)\n",
               MERGE_REPORT_MAX_TASKS);
    if (st == FS_OK) {
        report_absent(&r, list_missing);
        printf("merged %d of %d tasks into %s/metrics.csv, summary.json and accuracy.csv%s\n", r.done, r.m.ntasks,
               dir, r.done ? "" : " (no task has finished)");
        if (r.nabsent) {
            log_error("%s: %d of %d tasks missing or incomplete (listed above); run the sweep again to finish them",
                      dir, r.nabsent, r.m.ntasks);
            st = FS_ERR_INCOMPLETE;
        }
    }
    for (int i = 0; i < r.ps.n; i++)
        free(r.ps.v[i].ms);
    free(r.ps.v);
    free(r.modes.v);
    free(r.absent);
    sweep_ident_free(r.id);
    sweep_manifest_free(&r.m);
    return st;
}
