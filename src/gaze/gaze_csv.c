/* gaze_csv.c: the CSV readers: fovsim CSV (`t,x,y[,confidence]`) and the Pupil Labs Player export
 * gaze_positions.csv share one reader that finds its columns by name in the header.
 *
 * Formats, quirks and messages: docs/gaze-formats.md ("fovsim CSV", "Pupil Labs").
 */
#include "gaze/gaze_read.h"

#include <math.h>
#include <stdio.h>

/* >>fields */

bool gaze_csv_field(const char **pp, const char *end, span *f)
{
    const char *p = *pp;
    while (p < end && (*p == ' ' || *p == '\t'))
        p++;
    if (p < end && *p == '"') {
        const char *b = ++p;
        for (;;) {
            if (p >= end)
                return false;
            if (*p == '"') {
                if (p + 1 < end && p[1] == '"') {
                    p += 2;
                    continue;
                }
                break;
            }
            p++;
        }
        f->p = b;
        f->n = (size_t)(p - b);
        p++;
        while (p < end && *p != ',')
            p++; /* anything between the closing quote and the comma is ignored */
    } else {
        const char *b = p;
        while (p < end && *p != ',')
            p++;
        span s = gaze_trim((span){b, (size_t)(p - b)});
        *f = s;
    }
    *pp = p;
    return true;
}

/* >>header */

bool gaze_csv_header(line_it *it, span *header)
{
    for (span line = {0}; gaze_next_line(it, &line);) {
        span tl = gaze_trim(line);
        if (tl.n == 0 || tl.p[0] == '#')
            continue;
        *header = line;
        return true;
    }
    return false;
}

int gaze_csv_header_col(span header, const char *name, int *second)
{
    const char *p = header.p, *end = header.p + header.n;
    int found = -1;
    for (int k = 0;; k++) {
        span f = {0};
        if (!gaze_csv_field(&p, end, &f))
            return found;
        if (gaze_ieq(f.p, f.n, name)) {
            if (found >= 0) {
                *second = k;
                return -2;
            }
            found = k;
        }
        if (p >= end)
            break;
        p++;
    }
    return found;
}

static int header_count(span header)
{
    const char *p = header.p, *end = header.p + header.n;
    int k = 0;
    for (;;) {
        span f = {0};
        if (!gaze_csv_field(&p, end, &f))
            return -1;
        if (k < (1 << 20))
            k++;
        if (p >= end)
            break;
        p++;
    }
    return k;
}

/* >>rows */

enum { NCOLS = 7 };

typedef struct csv_cols {
    const char *names[NCOLS]; /* t, x, y, confidence (NULL: no confidence column), then Pupil Labs'
                                 gaze_point_3d_x, _y, _z (optional, may be empty) */
    int idx[NCOLS];           /* -1: absent */
    bool flip_y;          /* Pupil Labs: origin bottom-left */
} csv_cols;

static fs_status csv_rows(pctx *c, line_it *it, long header_line, int ncols, const csv_cols *cols)
{
    for (span line = {0}; gaze_next_line(it, &line);) {
        span tl = gaze_trim(line);
        if (tl.n == 0 || tl.p[0] == '#')
            continue;
        span f[NCOLS] = {{0}};
        const char *p = line.p, *end = line.p + line.n;
        int k = 0;
        for (;;) {
            span fld = {0};
            if (!gaze_csv_field(&p, end, &fld))
                return gaze_fail(c, it->no, k + 1, "expected a closing '\"' in column %d, got the end of the line",
                                 k + 1);
            for (int j = 0; j < NCOLS; j++)
                if (cols->idx[j] == k)
                    f[j] = fld;
            if (k < (1 << 20))
                k++;
            if (p >= end)
                break;
            p++;
        }
        if (k != ncols)
            return gaze_fail(c, it->no, (k < ncols ? k : ncols) + 1, "expected %d columns, got %d", ncols, k);
        double v[NCOLS] = {0, 0, 0, 1, NAN, NAN, NAN};
        for (int j = 0; j < NCOLS; j++) {
            if (cols->idx[j] < 0 || (j >= 4 && gaze_is_blank(f[j])))
                continue; /* gaze_point_3d is empty for 2D mapping */
            char g[64];
            num_result r = gaze_parse_num(f[j], &v[j]);
            if (r != NUM_OK)
                return gaze_fail(c, it->no, cols->idx[j] + 1, "expected a %snumber for column '%s', got %s",
                                 r == NUM_NONFINITE ? "finite " : "", cols->names[j],
                                 gaze_snip(g, sizeof g, f[j].p, f[j].n));
            if (j == 1 || j == 2) {
                if (!isfinite((float)v[j]) || fabs(v[j]) > 1e6)
                    return gaze_fail(c, it->no, cols->idx[j] + 1,
                                     "expected a normalised coordinate for column '%s' (|value| <= 1e6), got %s",
                                     cols->names[j], gaze_snip(g, sizeof g, f[j].p, f[j].n));
            }
            if (j == 3 && (v[j] < 0 || v[j] > 1))
                return gaze_fail(c, it->no, cols->idx[j] + 1,
                                 "expected a confidence between 0 and 1 in column '%s', got %s", cols->names[j],
                                 gaze_snip(g, sizeof g, f[j].p, f[j].n));
        }
        /* compared as float: "0.6" must pass the default threshold 0.6f */
        bool valid = cols->idx[3] < 0 || c->desc.min_confidence < 0 || (float)v[3] >= c->desc.min_confidence;
        double y = cols->flip_y ? 1.0 - v[2] : v[2];
        fs_status s = gaze_push(c, it->no, cols->idx[0] + 1, v[0], v[1], y, v[3], valid);
        if (s != FS_OK)
            return s;
        /* world camera coordinates, OpenCV's: x right, y down, z forward */
        if (v[6] > 0 && isfinite(v[4] / v[6]) && isfinite(v[5] / v[6]))
            gaze_set_dir(c, v[4] / v[6], -v[5] / v[6]);
    }
    if (c->n == 0)
        return gaze_fail(c, header_line + 1, 1, "expected a sample row after the header, got none");
    return FS_OK;
}

/* >>readers */

/* Finds the columns of `names` (NULL ends the required ones at index 3); reports missing or
 * doubled ones. */
static fs_status csv_find_cols(pctx *c, long line, span header, csv_cols *cols, const char *want)
{
    char g[64];
    for (int j = 0; j < NCOLS; j++) {
        cols->idx[j] = -1;
        if (!cols->names[j])
            continue;
        int second = -1;
        int k = gaze_csv_header_col(header, cols->names[j], &second);
        if (k == -2)
            return gaze_fail(c, line, second + 1, "expected one column named '%s', got a second one", cols->names[j]);
        if (k < 0 && j < 3)
            return gaze_fail(c, line, 1, "expected a header naming the columns %s, got %s", want,
                             gaze_snip(g, sizeof g, header.p, header.n));
        cols->idx[j] = k;
    }
    return FS_OK;
}

/* The rows after a CSV header (times in seconds), then the finished trace. */
static fs_status csv_body(pctx *c, line_it *it, span header, const csv_cols *cols, gaze_format format,
                          gaze_trace *out)
{
    int ncols = header_count(header);
    if (ncols < 0)
        return gaze_fail(c, it->no, 1, "expected a closing '\"' in the header, got the end of the line");
    c->unit = 1.0;
    c->unit_name = "s";
    fs_status s = csv_rows(c, it, it->no, ncols, cols);
    if (c->has_dir)
        snprintf(c->geometry, sizeof c->geometry, "directions from gaze_point_3d (world camera, pinhole)");
    return s != FS_OK ? s : gaze_finish(c, format, out);
}

fs_status gaze_parse_csv(pctx *c, gaze_trace *out)
{
    line_it it = {c->text, c->text + c->size, 0};
    span header = {0};
    if (!gaze_csv_header(&it, &header))
        return gaze_fail(c, 1, 1, "expected a header line 't,x,y', got an empty file");
    csv_cols cols = {.names = {"t", "x", "y", "confidence"}};
    fs_status s = csv_find_cols(c, it.no, header, &cols, "t, x and y");
    if (s != FS_OK)
        return s;
    return csv_body(c, &it, header, &cols, GAZE_FORMAT_CSV, out);
}

fs_status gaze_parse_pupil(pctx *c, gaze_trace *out)
{
    line_it it = {c->text, c->text + c->size, 0};
    span header = {0};
    if (!gaze_csv_header(&it, &header))
        return gaze_fail(c, 1, 1, "expected the header of a Pupil Labs gaze_positions.csv, got an empty file");
    int dummy;
    /* Player before v1.8 called the column `timestamp`. */
    const char *tname = gaze_csv_header_col(header, "gaze_timestamp", &dummy) != -1 ? "gaze_timestamp" : "timestamp";
    csv_cols cols = {.names = {tname, "norm_pos_x", "norm_pos_y", "confidence", "gaze_point_3d_x", "gaze_point_3d_y",
                               "gaze_point_3d_z"},
                     .flip_y = true};
    fs_status s = csv_find_cols(c, it.no, header, &cols, "gaze_timestamp, norm_pos_x and norm_pos_y");
    if (s != FS_OK)
        return s;
    return csv_body(c, &it, header, &cols, GAZE_FORMAT_PUPIL, out);
}

