/* report_html.c: see report_html.h. */
#include "output/report_html.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "output/grid_video.h"
#include "output/out_path.h"
#include "output/svg_chart.h"
#include "scene/scene.h"

#define REPORT_MAX_INPUT (256u << 20) /* bytes of a summary or CSV read back */
#define REPORT_MAX_PREVIEWS 100000

/* >>inputs */

/* DIR/NAME's text, or NULL when there is no such file (a file that cannot be read: one line, *st). */
static char *read_beside(const char *dir, const char *name, fs_status *st)
{
    char p[PATH_MAX + 64];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    if (access(p, F_OK) != 0 && errno == ENOENT)
        return NULL;
    char *text = NULL;
    size_t n;
    fs_status s = file_read_all(p, REPORT_MAX_INPUT, "a file of the run", FS_ERR_IO, &text, &n);
    if (s != FS_OK)
        *st = s;
    return text;
}

/* A CSV held in memory: its fields split in place (no field of fovsim's CSVs holds a comma; a
 * quoted one loses its quotes). */
typedef struct csv {
    char *text;
    int cols, rows;
    char **f; /* (rows + 1) x cols: the header first; a short row's missing fields are "" */
} csv;

static bool csv_parse(char *text, csv *c)
{
    memset(c, 0, sizeof *c);
    c->text = text;
    int lines = 0;
    for (char *p = text; *p; p++)
        lines += *p == '\n';
    char *nl = strchr(text, '\n');
    if (!nl)
        return false;
    c->cols = 1;
    for (char *p = text; p < nl; p++)
        c->cols += *p == ',';
    c->f = calloc((size_t)(lines + 1) * (size_t)c->cols, sizeof *c->f);
    if (!c->f)
        return false;
    int r = 0;
    for (char *line = text; *line && r <= lines; r++) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        if (end && end > line && end[-1] == '\r')
            end[-1] = '\0';
        char *q = line;
        for (int k = 0; k < c->cols; k++) {
            char *comma = q ? strchr(q, ',') : NULL;
            if (comma)
                *comma = '\0';
            if (q && q[0] == '"') {
                q++;
                size_t l = strlen(q);
                if (l && q[l - 1] == '"')
                    q[l - 1] = '\0';
            }
            c->f[(size_t)r * (size_t)c->cols + (size_t)k] = q ? q : "";
            q = comma ? comma + 1 : NULL;
        }
        if (!end)
            break;
        line = end + 1;
    }
    /* rows: the lines after the header, up to the last that is not empty */
    c->rows = 0;
    for (int i = 1; i <= lines; i++)
        if (c->f[(size_t)i * (size_t)c->cols] && c->f[(size_t)i * (size_t)c->cols][0])
            c->rows = i;
    return true;
}

static const char *csv_at(const csv *c, int row, int col)
{
    const char *s = c->f[(size_t)(row + 1) * (size_t)c->cols + (size_t)col];
    return s ? s : "";
}

/* The distinct values of column col in rows [0, rows), in order of first appearance, at most cap. */
static int csv_distinct(const csv *c, int rows, int col, const char **out, int cap)
{
    int n = 0;
    for (int r = 0; r < rows; r++) {
        const char *v = csv_at(c, r, col);
        int k = 0;
        while (k < n && strcmp(out[k], v) != 0)
            k++;
        if (k == n && n < cap)
            out[n++] = v;
    }
    return n;
}

static int csv_col(const csv *c, const char *name)
{
    for (int k = 0; k < c->cols; k++)
        if (c->f[k] && strcmp(c->f[k], name) == 0)
            return k;
    return -1;
}

static double num(const char *s)
{
    char *e;
    double v = strtod(s, &e);
    return e != s ? v : NAN;
}

/* A small whole number field (a frame, a ring), or INT_MIN when it is none. */
static int whole(const char *s)
{
    double v = num(s);
    return isfinite(v) && fabs(v) < 1e9 && v == floor(v) ? (int)v : INT_MIN;
}

/* >>page parts */

/* A cell holding a JSON value: numbers as %.15g (the test reads them back), tagged with its key. */
static void json_cell(sbuf *b, const cJSON *v, const char *key)
{
    sb_puts(b, "<td");
    if (cJSON_IsNumber(v)) {
        sb_puts(b, " class=\"num\" data-k=\"");
        html_escape(b, key);
        sb_printf(b, "\">%.15g</td>", v->valuedouble);
        return;
    }
    sb_puts(b, ">");
    if (cJSON_IsString(v))
        html_escape(b, v->valuestring);
    else if (cJSON_IsBool(v))
        sb_puts(b, cJSON_IsTrue(v) ? "true" : "false");
    sb_puts(b, "</td>");
}

/* The scalars of a JSON object as rows name | value (nested objects' scalars as name.sub). */
static void settings_rows(sbuf *b, const cJSON *o, const char *prefix)
{
    for (const cJSON *v = o ? o->child : NULL; v; v = v->next) {
        char key[256];
        snprintf(key, sizeof key, "%s%s", prefix, v->string ? v->string : "");
        if (cJSON_IsObject(v)) {
            char p[260];
            snprintf(p, sizeof p, "%s.", key);
            settings_rows(b, v, p);
        } else if (!cJSON_IsArray(v)) {
            sb_puts(b, "<tr><th>");
            html_escape(b, key);
            sb_puts(b, "</th>");
            json_cell(b, v, key);
            sb_puts(b, "</tr>\n");
        }
    }
}

/* The header of a summary field: what it is and which way is better. */
static const char *field_label(const char *f)
{
    static const char *const k[][2] = {
        {"frame_ms_median", "frame ms (median; lower is better)"}, {"relative_time", "relative time"},
        {"fvvdp_jod", "FovVideoVDP JOD (higher is better)"}, {"outer_deg", "outer (deg)"},
        {"coverage_ratio", "coverage / reference (1 = same)"}, {"rmse", "RMSE (lower is better)"},
        {"alpha_rmse", "alpha RMSE (lower is better)"}, {"flip", "FLIP (lower is better)"},
        {"psnr", "PSNR dB (higher is better)"}, {"temporal_error", "temporal error (lower is better)"},
        {"static_flicker", "static flicker (lower is better)"}, {"coverage_px", "coverage px (summed)"},
        {"ref_coverage_px", "reference coverage px (summed)"}};
    for (size_t i = 0; i < sizeof k / sizeof *k; i++)
        if (strcmp(k[i][0], f) == 0)
            return k[i][1];
    return f;
}

/* The fields of `o` that are columns: every member but `skip` and arrays; the first object with
 * the most such fields sets the columns. */
static int columns_of(const cJSON *list, const char *skip, const char **cols, int cap)
{
    int best = 0;
    for (const cJSON *o = list ? list->child : NULL; o; o = o->next) {
        const char *c[64];
        int n = 0;
        for (const cJSON *v = o->child; v && n < 64; v = v->next)
            if (v->string && !cJSON_IsArray(v) && !cJSON_IsObject(v) && strcmp(v->string, skip) != 0)
                c[n++] = v->string;
        if (n > best) {
            best = n < cap ? n : cap;
            memcpy(cols, c, sizeof *c * (size_t)best);
        }
    }
    return best;
}

static void field_cell(sbuf *b, const cJSON *o, const char *f, const char *key, int span)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, f);
    if (span > 1)
        sb_printf(b, "<td rowspan=\"%d\"", span);
    else
        sb_puts(b, "<td");
    if (cJSON_IsNumber(v)) {
        sb_puts(b, " class=\"num\" data-k=\"");
        html_escape(b, key);
        sb_printf(b, "\">%.15g</td>", v->valuedouble);
    } else if (cJSON_IsString(v)) {
        sb_puts(b, ">");
        html_escape(b, v->valuestring);
        sb_puts(b, "</td>");
    } else {
        sb_puts(b, ">n/a</td>");
    }
}

/* compare's post-saccade foveal error (summary.json modes[].post_saccade, docs/latency.md "After a
 * saccade"): a row per mode, over all post-saccade frames and per frame after the landing. */
static void post_saccade_table(sbuf *b, const cJSON *sum)
{
    const cJSON *modes = cJSON_GetObjectItemCaseSensitive(sum, "modes"), *m0 = modes ? modes->child : NULL;
    const cJSON *p0 = m0 ? cJSON_GetObjectItemCaseSensitive(m0, "post_saccade") : NULL;
    if (!p0)
        return;
    static const char *const k_f[] = {"frames", "rmse", "flip", "coverage_ratio"};
    int nk = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(p0, "by_frame_after_landing"));
    sb_puts(b, "<h2>After saccades</h2>\n<p>Within 5&deg; of the true gaze, the frames of the first 150 ms after "
               "each saccade lands (all of them, then the k-th frame after the landing): frames, RMSE, FLIP, "
               "coverage / reference.</p>\n<table class=\"summary\"><thead><tr><th>mode</th><th colspan=\"4\">all"
               "</th>");
    for (int k = 0; k < nk; k++)
        sb_printf(b, "<th colspan=\"4\">k = %d</th>", k);
    sb_puts(b, "</tr></thead>\n<tbody>\n");
    int mi = 0;
    for (const cJSON *m = m0; m; m = m->next, mi++) {
        const cJSON *p = cJSON_GetObjectItemCaseSensitive(m, "post_saccade");
        const cJSON *by = cJSON_GetObjectItemCaseSensitive(p, "by_frame_after_landing");
        const char *mode = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(m, "mode"));
        sb_puts(b, "<tr><th>");
        html_escape(b, mode ? mode : "?");
        sb_puts(b, "</th>");
        for (int k = -1; k < nk; k++) {
            const cJSON *o = k < 0 ? p : cJSON_GetArrayItem(by, k);
            for (size_t f = 0; f < sizeof k_f / sizeof *k_f; f++) {
                char key[128];
                if (k < 0)
                    snprintf(key, sizeof key, "modes.%d.post_saccade.%s", mi, k_f[f]);
                else
                    snprintf(key, sizeof key, "modes.%d.post_saccade.by_frame_after_landing.%d.%s", mi, k, k_f[f]);
                field_cell(b, o, k_f[f], key, 1);
            }
        }
        sb_puts(b, "</tr>\n");
    }
    sb_puts(b, "</tbody></table>\n");
}

/* compare's summary.json as a table: per mode its fields, then a row per ring with every field;
 * cells keyed "PREFIXmodes.M.F" and "PREFIXmodes.M.rings.K.F" (ring -1: the whole display). */
static void summary_table(sbuf *b, const cJSON *sum, const char *prefix)
{
    const cJSON *modes = cJSON_GetObjectItemCaseSensitive(sum, "modes");
    const char *mc[64], *rc[64];
    int nmc = columns_of(modes, "mode", mc, 64), nrc = 0;
    for (const cJSON *m = modes ? modes->child : NULL; m; m = m->next) {
        const char *c[64];
        int n = columns_of(cJSON_GetObjectItemCaseSensitive(m, "rings"), "", c, 64);
        if (n > nrc) {
            nrc = n;
            memcpy(rc, c, sizeof *c * (size_t)n);
        }
    }
    sb_puts(b, "<table class=\"summary\"><thead><tr><th>mode</th>");
    for (int k = 0; k < nmc + nrc; k++) {
        sb_puts(b, "<th>");
        html_escape(b, field_label(k < nmc ? mc[k] : rc[k - nmc]));
        sb_puts(b, "</th>");
    }
    sb_puts(b, "</tr></thead>\n<tbody>\n");
    int mi = 0;
    for (const cJSON *m = modes ? modes->child : NULL; m; m = m->next, mi++) {
        const cJSON *rings = cJSON_GetObjectItemCaseSensitive(m, "rings");
        int span = cJSON_GetArraySize(rings) > 0 ? cJSON_GetArraySize(rings) : 1;
        const char *mode = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(m, "mode"));
        char col[8], key[256];
        alpha_mode_colour(alpha_mode_parse(mode ? mode : ""), col);
        sb_printf(b, "<tr><th rowspan=\"%d\"><span class=\"sw\" style=\"background:%s\"></span>", span, col);
        html_escape(b, mode ? mode : "?");
        sb_puts(b, "</th>");
        for (int k = 0; k < nmc; k++) {
            snprintf(key, sizeof key, "%smodes.%d.%s", prefix, mi, mc[k]);
            field_cell(b, m, mc[k], key, span);
        }
        int ri = 0;
        for (const cJSON *r = rings ? rings->child : NULL; r; r = r->next, ri++) {
            if (ri)
                sb_puts(b, "<tr>");
            for (int k = 0; k < nrc; k++) {
                snprintf(key, sizeof key, "%smodes.%d.rings.%d.%s", prefix, mi, ri, rc[k]);
                field_cell(b, r, rc[k], key, 1);
            }
            sb_puts(b, "</tr>\n");
        }
        if (!ri)
            sb_puts(b, "</tr>\n");
    }
    sb_puts(b, "</tbody></table>\n<p>ring -1 is the whole display; -1 elsewhere: not measured.</p>\n");
}

/* A whole CSV as a table; cells keyed "NAME.ROW.COLUMN". */
static void csv_table(sbuf *b, const csv *c, const char *name)
{
    sb_puts(b, "<table class=\"csv\"><thead><tr>");
    for (int k = 0; k < c->cols; k++) {
        sb_puts(b, "<th>");
        html_escape(b, c->f[k] ? c->f[k] : "");
        sb_puts(b, "</th>");
    }
    sb_puts(b, "</tr></thead>\n<tbody>\n");
    for (int r = 0; r < c->rows; r++) {
        sb_puts(b, "<tr>");
        for (int k = 0; k < c->cols; k++) {
            sb_puts(b, "<td data-k=\"");
            html_escape(b, name);
            sb_printf(b, ".%d.", r);
            html_escape(b, c->f[k] ? c->f[k] : "");
            sb_puts(b, "\">");
            html_escape(b, csv_at(c, r, k));
            sb_puts(b, "</td>");
        }
        sb_puts(b, "</tr>\n");
    }
    sb_puts(b, "</tbody></table>\n");
}

/* The video, or the scrubber over the previews. */
static fs_status pictures(sbuf *b, const char *dir)
{
    sb_puts(b, "<h2>The grid over time</h2>\n");
    if (grid_video_has_video(dir)) {
        sb_puts(b, "<video id=\"video\" src=\"video.mp4\" controls loop muted preload=\"metadata\"></video>\n");
        return FS_OK;
    }
    int *idx = malloc(sizeof(int) * REPORT_MAX_PREVIEWS);
    if (!idx)
        return FS_ERR_NOMEM;
    int n = grid_video_previews(dir, idx, REPORT_MAX_PREVIEWS);
    n = n < REPORT_MAX_PREVIEWS ? n : REPORT_MAX_PREVIEWS;
    if (n == 0) {
        sb_puts(b, "<p>No video.mp4 and no previews in this folder.</p>\n");
    } else {
        sb_printf(b, "<p>No video.mp4 here (--video off, no ffmpeg, or it failed): the frames' previews. "
                     "<input type=\"range\" id=\"scrub\" min=\"0\" max=\"%d\" value=\"0\"> frame <span id=\"frameno\">"
                     "%d</span></p>\n<img id=\"frame\" src=\"preview/frame.%04d.png\" alt=\"the grid of a frame\">\n"
                     "<script type=\"application/json\" id=\"frames\">[", n - 1, idx[0], idx[0]);
        for (int i = 0; i < n; i++)
            sb_printf(b, "%s%d", i ? "," : "", idx[i]);
        sb_puts(b, "]</script>\n");
    }
    free(idx);
    return FS_OK;
}

/* metrics.csv's coverage ratio per frame, one chart per ring, one line per mode. */
static void coverage_charts(sbuf *b, const csv *c)
{
    int cf = csv_col(c, "frame"), cm = csv_col(c, "mode"), cr = csv_col(c, "ring"), cv = csv_col(c, "coverage_ratio");
    if (cf < 0 || cm < 0 || cr < 0 || cv < 0 || c->rows == 0)
        return;
    sb_puts(b, "<h2>Coverage over time</h2>\n<p>Each mode's coverage in a ring over the reference's, per frame "
               "(1 = the same as the reference; gaps where the reference holds too little to compare).</p>\n");
    const char *modes[64];
    int nm = csv_distinct(c, c->rows, cm, modes, 64), rmin = INT_MAX, rmax = INT_MIN;
    for (int r = 0; r < c->rows; r++) {
        int ring = whole(csv_at(c, r, cr));
        if (ring == INT_MIN)
            continue;
        rmin = ring < rmin ? ring : rmin;
        rmax = ring > rmax ? ring : rmax;
    }
    if (rmin > rmax || rmax - rmin > 64) /* no rings, or not compare's metrics.csv */
        return;
    double *x = malloc(sizeof(double) * (size_t)c->rows * 2);
    if (!x) {
        b->oom = true;
        return;
    }
    double *y = x + c->rows;
    for (int ring = rmin; ring <= rmax; ring++) {
        svg_series se[64];
        char cols[64][8];
        int used = 0;
        for (int k = 0; k < nm; k++) {
            int n0 = used, n = 0;
            for (int r = 0; r < c->rows; r++)
                if (whole(csv_at(c, r, cr)) == ring && strcmp(csv_at(c, r, cm), modes[k]) == 0) {
                    double v = num(csv_at(c, r, cv));
                    x[used + n] = num(csv_at(c, r, cf));
                    y[used + n] = v >= 0 ? v : NAN;
                    n++;
                }
            used += n;
            alpha_mode_colour(alpha_mode_parse(modes[k]), cols[k]);
            se[k] = (svg_series){.name = modes[k], .colour = cols[k], .x = x + n0, .y = y + n0, .n = n,
                                 .line = true, .points = n < 2};
        }
        char title[64], id[32];
        if (ring < 0)
            snprintf(title, sizeof title, "the whole display");
        else
            snprintf(title, sizeof title, "ring %d", ring);
        snprintf(id, sizeof id, "coverage-ring%d", ring);
        svg_chart(b, &(svg_chart_desc){.title = title, .xlabel = "frame", .ylabel = "coverage / reference",
                                       .series = se, .count = nm, .id = id, .x_whole = true});
    }
    free(x);
}

/* accuracy.csv: error against median frame time per mode, the Pareto front (the `pareto` column
 * when it has one, else computed: no other point is both faster and more accurate) as a line. */
static void accuracy_chart(sbuf *b, const csv *c, const char *err, const char *label)
{
    int cx = csv_col(c, "frame_ms_median"), cy = csv_col(c, err), cm = csv_col(c, "mode"),
        cp = csv_col(c, "pareto");
    if (cx < 0 || cy < 0 || cm < 0 || c->rows == 0)
        return;
    int n = c->rows;
    double *x = malloc(sizeof(double) * (size_t)n * 4);
    if (!x) {
        b->oom = true;
        return;
    }
    double *y = x + n, *fx = y + n, *fy = fx + n;
    svg_series se[65];
    char cols[64][8];
    const char *modes[64];
    int nm = csv_distinct(c, n, cm, modes, 64), used = 0;
    for (int k = 0; k < nm; k++) {
        int n0 = used;
        for (int r = 0; r < n; r++)
            if (strcmp(csv_at(c, r, cm), modes[k]) == 0) {
                x[used] = num(csv_at(c, r, cx));
                y[used] = num(csv_at(c, r, cy));
                used++;
            }
        alpha_mode_colour(alpha_mode_parse(modes[k]), cols[k]);
        se[k] = (svg_series){.name = modes[k], .colour = cols[k], .x = x + n0, .y = y + n0, .n = used - n0,
                             .points = true};
    }
    int nf = 0;
    for (int r = 0; r < n; r++) {
        double xr = num(csv_at(c, r, cx)), yr = num(csv_at(c, r, cy));
        bool front = true;
        if (cp >= 0) {
            front = num(csv_at(c, r, cp)) == 1;
        } else {
            for (int q = 0; q < n && front; q++) {
                double xq = num(csv_at(c, q, cx)), yq = num(csv_at(c, q, cy));
                front = !(xq <= xr && yq <= yr && (xq < xr || yq < yr));
            }
        }
        if (front && isfinite(xr) && isfinite(yr)) {
            int i = nf++; /* sorted by time */
            while (i > 0 && fx[i - 1] > xr) {
                fx[i] = fx[i - 1], fy[i] = fy[i - 1];
                i--;
            }
            fx[i] = xr, fy[i] = yr;
        }
    }
    se[nm] = (svg_series){.name = "Pareto front", .colour = "#000000", .x = fx, .y = fy, .n = nf, .line = true};
    sb_puts(b, "<h2>Accuracy against cost</h2>\n");
    char yl[200];
    snprintf(yl, sizeof yl, strstr(label, "lower is better") ? "%s" : "%s (lower is better)", label);
    svg_chart(b, &(svg_chart_desc){.title = "accuracy vs frame time", .xlabel = "frame time, median (ms; lower is "
                                   "better)", .ylabel = yl, .width = 760, .height = 380, .series = se,
                                   .count = nm + 1, .id = "accuracy"});
    free(x);
}

/* >>the page */

static const char k_style[] =
    "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;margin:.5em 0}"
    "td,th{border:1px solid #ccc;padding:2px 6px;font-size:12px}td.num{text-align:right}"
    "th{background:#f4f4f4;text-align:left}video,#frame{max-width:100%;border:1px solid #ccc}"
    ".sw{display:inline-block;width:10px;height:10px;margin-right:4px}svg.chart{display:block;margin:.5em 0}"
    "</style>\n";

/* Marks the page as built (data-ok) or failed (data-error) for people and the browser test. */
static const char k_script[] =
    "<script>\n"
    "window.onerror = function (m) { document.body.dataset.error = String(m); };\n"
    "(function () {\n"
    "  var s = document.getElementById('scrub');\n"
    "  if (s) {\n"
    "    var frames = JSON.parse(document.getElementById('frames').textContent);\n"
    "    var img = document.getElementById('frame'), no = document.getElementById('frameno');\n"
    "    s.addEventListener('input', function () {\n"
    "      var f = frames[Number(s.value)];\n"
    "      img.src = 'preview/frame.' + String(f).padStart(4, '0') + '.png';\n"
    "      no.textContent = String(f);\n"
    "    });\n"
    "  }\n"
    "  function bad(img) { document.body.dataset.error = 'cannot load ' + img.getAttribute('src'); }\n"
    "  document.querySelectorAll('img').forEach(function (img) {\n"
    "    img.addEventListener('error', function () { bad(img); });\n"
    "    if (img.complete && img.naturalWidth === 0) bad(img);\n"
    "  });\n"
    "  document.body.dataset.ok = '1';\n"
    "})();\n"
    "</script>\n";

fs_status report_html_write(const report_html_desc *d)
{
    fs_status st = FS_OK;
    bool compare = strcmp(d->kind, "compare") == 0 || strcmp(d->kind, "demo") == 0;
    char *sum_text = read_beside(d->dir, "summary.json", &st);
    char *metrics_text = compare && st == FS_OK ? read_beside(d->dir, "metrics.csv", &st) : NULL;
    char *acc_text = st == FS_OK ? read_beside(d->dir, "accuracy.csv", &st) : NULL;
    char *md_text = st == FS_OK ? read_beside(d->dir, "accuracy.md", &st) : NULL;
    cJSON *sum = sum_text ? cJSON_Parse(sum_text) : NULL;
    csv metrics = {0}, acc = {0};
    bool have_metrics = metrics_text && csv_parse(metrics_text, &metrics);
    bool have_acc = acc_text && csv_parse(acc_text, &acc);
    sbuf b = {0};
    sb_puts(&b, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>fovsim ");
    html_escape(&b, d->kind);
    sb_puts(&b, ": ");
    html_escape(&b, d->dir);
    sb_printf(&b, "</title>\n%s</head>\n<body>\n<h1>fovsim ", k_style);
    html_escape(&b, d->kind);
    sb_puts(&b, "</h1>\n<p>Folder <code>");
    html_escape(&b, d->dir);
    sb_puts(&b, "</code>; this page reads the files beside it.</p>\n");
    if (st == FS_OK && sum_text && !sum)
        log_warn("%s/summary.json: not JSON; report.html has no summary table", d->dir);
    /* settings */
    sb_puts(&b, "<h2>Settings</h2>\n");
    if (sum) {
        sb_puts(&b, "<table class=\"settings\">\n");
        settings_rows(&b, sum, "");
        if (d->fps > 0)
            sb_printf(&b, "<tr><th>fps</th><td class=\"num\">%g</td></tr>\n", d->fps);
        sb_puts(&b, "</table>\n");
    }
    if (md_text) { /* bench --accuracy: accuracy.md's list of what was measured how */
        sb_puts(&b, "<ul class=\"settings\">\n");
        for (char *line = md_text; line && *line;) {
            char *end = strchr(line, '\n');
            if (end)
                *end = '\0';
            if (line[0] == '-' && line[1] == ' ') {
                sb_puts(&b, "<li>");
                html_escape(&b, line + 2);
                sb_puts(&b, "</li>\n");
            }
            line = end ? end + 1 : NULL;
        }
        sb_puts(&b, "</ul>\n");
    }
    if (compare && st == FS_OK)
        st = pictures(&b, d->dir);
    if (sum && cJSON_GetObjectItemCaseSensitive(sum, "modes")) {
        sb_puts(&b, "<h2>Summary</h2>\n<p>From summary.json: means over the measured frames per ring; coverage "
                    "is the ratio of the sums.</p>\n");
        summary_table(&b, sum, "");
        post_saccade_table(&b, sum);
    }
    const cJSON *results = sum ? cJSON_GetObjectItemCaseSensitive(sum, "results") : NULL;
    int ti = 0;
    for (const cJSON *r = results ? results->child : NULL; r; r = r->next, ti++) { /* a merged sweep's tasks */
        const cJSON *ts = cJSON_GetObjectItemCaseSensitive(r, "summary");
        sb_puts(&b, "<h2>Task ");
        html_escape(&b, cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(r, "task")) ? cJSON_GetStringValue(
                                                                                               cJSON_GetObjectItemCaseSensitive(r, "task"))
                                                                                         : "?");
        sb_puts(&b, "</h2>\n<table class=\"settings\">\n");
        char prefix[64];
        snprintf(prefix, sizeof prefix, "results.%d.", ti);
        settings_rows(&b, r, prefix);
        sb_puts(&b, "</table>\n");
        if (ts && cJSON_GetObjectItemCaseSensitive(ts, "modes")) {
            snprintf(prefix, sizeof prefix, "results.%d.summary.", ti);
            summary_table(&b, ts, prefix);
        }
    }
    if (have_metrics)
        coverage_charts(&b, &metrics);
    if (have_acc) {
        accuracy_chart(&b, &acc, d->acc_error ? d->acc_error : "flip",
                       d->acc_error_label ? d->acc_error_label : "FLIP vs reference (mean; lower is better)");
        sb_puts(&b, "<h2>accuracy.csv</h2>\n");
        csv_table(&b, &acc, "accuracy");
    }
    sb_puts(&b, k_script);
    sb_puts(&b, "</body></html>\n");
    cJSON_Delete(sum);
    free(metrics.f);
    free(acc.f);
    free(sum_text);
    free(metrics_text);
    free(acc_text);
    free(md_text);
    char path[PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/report.html", d->dir);
    if (st == FS_OK)
        st = b.oom ? FS_ERR_NOMEM : out_write_atomic(path, b.p);
    free(b.p);
    return st;
}
