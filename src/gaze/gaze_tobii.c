/* gaze_tobii.c: the Tobii Pro Glasses 2 livedata.json reader: one JSON object per line, several
 * streams interleaved and out of time order; the gaze records ({"ts", "s", "gp"} without "eye")
 * become samples, sorted by time in gaze_finish.
 *
 * Each line goes through cJSON (cJSON_ParseWithLengthOpts), which says where it stopped; the rest
 * of the line must be blank. Errors keep `file:line:column`: the byte where cJSON stopped for a
 * syntax error, the position of the key for a bad gaze record (see key_col).
 *
 * Records, validity and messages: docs/gaze-formats.md ("Tobii Pro Glasses 2 livedata.json").
 */
#include "gaze/gaze_read.h"

#include "core/config.h"
#include "core/grow.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* >>lines */

/* cJSON returns NULL for a line it could not allocate as for a syntax error; its allocations go
 * through this while a line is parsed, so running out of memory is reported as such (exit 9).
 * cJSON's hooks are global: this relies on traces being loaded before any other thread starts
 * (fovsim's only threads are the EXR writers, which do not use cJSON). */
static bool g_json_oom;
static void *json_malloc(size_t n)
{
    void *p = malloc(n);
    if (!p)
        g_json_oom = true;
    return p;
}

static cJSON *parse_tracked(const char *p, size_t n, const char **end)
{
    cJSON_Hooks hooks = {json_malloc, free};
    cJSON_InitHooks(&hooks);
    cJSON *v = cJSON_ParseWithLengthOpts(p, n, end, false);
    cJSON_InitHooks(NULL); /* back to malloc and free (realloc too) for everyone else */
    return v;
}

/* cJSON over a line. cJSON reports where it stopped, but a parse that runs out of input stops at
 * the last byte too, so it is handed the byte after the line as well when there is one ('\r' or
 * '\n', a blank to cJSON): running out then stops at offset line.n, "the end of the line". A last
 * line without a line end that fails on its last byte is parsed again from a copy that has one.
 * *stop: where cJSON stopped (success: just after the value), as an offset into the line. */
static fs_status parse_line(const pctx *c, span line, cJSON **out, size_t *stop)
{
    const char *end = NULL;
    bool line_end = line.p + line.n < c->text + c->size;
    g_json_oom = false;
    *out = parse_tracked(line.p, line.n + line_end, &end);
    if (!*out && g_json_oom)
        return gaze_no_memory(c);
    *stop = end ? (size_t)(end - line.p) : 0;
    if (*out || line_end || *stop + 1 < line.n)
        return FS_OK;
    char *copy = malloc(line.n + 1);
    if (!copy)
        return gaze_no_memory(c);
    memcpy(copy, line.p, line.n);
    copy[line.n] = '\n';
    *out = parse_tracked(copy, line.n + 1, &end);
    *stop = end ? (size_t)(end - copy) : 0;
    free(copy);
    if (!*out && g_json_oom)
        return gaze_no_memory(c);
    return FS_OK;
}

/* Offset of the '"' that closes the string opening at offset i, or line.n. */
static size_t string_end(span line, size_t i)
{
    for (i++; i < line.n && line.p[i] != '"'; i++)
        if (line.p[i] == '\\')
            i++;
    return i < line.n ? i : line.n;
}

/* cJSON hands a number's characters to strtod, which also reads what RFC 8259 forbids: leading
 * zeros (`01`, which some readers take for octal), `1.`, `-.5`. livedata.json has none and this
 * reader refused them before it used cJSON, so a line cJSON accepted is checked once more: every
 * number outside the strings must follow the grammar. Returns the offset of the first that does
 * not, or -1. (cJSON checked the rest, so outside strings only numbers hold '-' and digits.) */
static long bad_number_at(span line)
{
    const char *p = line.p;
    const size_t n = line.n;
    for (size_t i = 0; i < n; i++) {
        if (p[i] == '"')
            i = string_end(line, i);
        if (i >= n || (p[i] != '-' && !gaze_is_digit(p[i])))
            continue;
        const size_t b = i;
        if (p[i] == '-')
            i++;
        if (i < n && p[i] == '0')
            i++;
        else if (i < n && gaze_is_digit(p[i]))
            while (i < n && gaze_is_digit(p[i]))
                i++;
        else
            return (long)b;
        if (i < n && p[i] == '.') {
            if (++i >= n || !gaze_is_digit(p[i]))
                return (long)b;
            while (i < n && gaze_is_digit(p[i]))
                i++;
        }
        if (i < n && (p[i] == 'e' || p[i] == 'E')) {
            if (++i < n && (p[i] == '+' || p[i] == '-'))
                i++;
            if (i >= n || !gaze_is_digit(p[i]))
                return (long)b;
            while (i < n && gaze_is_digit(p[i]))
                i++;
        }
        if (i < n && (gaze_is_digit(p[i]) || p[i] == '.')) /* `01`, `1.5.2`: strtod read on */
            return (long)b;
        i--;
    }
    return -1;
}

/* What is open at offset `at`, where cJSON stopped on a line it read up to there: arrays and
 * objects (*depth; cJSON fails on a '[' or '{' at CJSON_NESTING_LIMIT of them, and nowhere else
 * with that many open). True when `at` lies in a string that the line does not close (cJSON then
 * stops at the string's first byte). */
static bool open_at(span line, size_t at, int *depth)
{
    *depth = 0;
    for (size_t i = 0; i < at && i < line.n; i++) {
        if (line.p[i] == '"') {
            const size_t e = string_end(line, i);
            if (e >= at)
                return e >= line.n;
            i = e;
        } else if (line.p[i] == '[' || line.p[i] == '{') {
            ++*depth;
        } else if (line.p[i] == ']' || line.p[i] == '}') {
            --*depth;
        }
    }
    return false;
}

/* 1-based column of a member's key, for a message about its value. cJSON keeps no positions, so
 * this searches the line text for the first `"key"` followed by ':' (blanks between); that could
 * be a nested object's key of the same name, which Tobii records do not have. Column 1 when there
 * is none. Only error paths call it. */
static long key_col(span line, const char *key)
{
    const size_t k = strlen(key);
    for (size_t i = 0; i + k + 2 <= line.n; i++) {
        if (line.p[i] != '"' || memcmp(line.p + i + 1, key, k) != 0 || line.p[i + k + 1] != '"')
            continue;
        size_t j = i + k + 2;
        while (j < line.n && (unsigned char)line.p[j] <= ' ')
            j++;
        if (j < line.n && line.p[j] == ':')
            return (long)i + 1;
    }
    return 1;
}

/* A value for a message: its JSON text as gaze_snip shows it. */
static const char *describe(const cJSON *v, char *buf, size_t cap)
{
    if (cJSON_IsNumber(v) && !isfinite(v->valuedouble))
        return "a number beyond the range of a double";
    char *text = cJSON_PrintUnformatted(v);
    if (!text)
        return "a value (out of memory to show it)";
    const char *shown = gaze_snip(buf, cap, text, strlen(text));
    cJSON_free(text);
    return shown;
}

static bool finite_number(const cJSON *v) { return cJSON_IsNumber(v) && isfinite(v->valuedouble); }

/* >>records */

/* The number member `key` of a gaze record (`what` names it in messages). */
static fs_status record_number(pctx *c, long no, span line, const cJSON *rec, const char *key, const char *what,
                               double *v)
{
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(rec, key);
    char g[64];
    if (!m)
        return gaze_fail(c, no, 1, "expected %s in the gaze record, got none", what);
    if (!finite_number(m))
        return gaze_fail(c, no, key_col(line, key), "expected a number for %s, got %s", what, describe(m, g, sizeof g));
    *v = m->valuedouble;
    return FS_OK;
}

/* The gaze directions: gp3 records ({"gidx", "s", "gp3": [x, y, z]}, mm, scene camera coordinates)
 * joined to the gp samples of the same gidx once every line is read. */
typedef struct gidx_dir {
    double gidx;
    float tx, ty;
} gidx_dir;

typedef struct tobii_state {
    double *gidx;    /* per raw sample: its record's gidx, NaN without */
    gidx_dir *dirs;  /* from the valid gp3 records */
    int n_gidx, cap_gidx, n_dirs, cap_dirs;
    long records;
} tobii_state;

static double opt_number(const cJSON *rec, const char *key)
{
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(rec, key);
    return finite_number(m) ? m->valuedouble : NAN;
}

/* A valid gp3 record with a point in front of the camera to a direction. Glasses 2 scene camera
 * coordinates: x to the wearer's LEFT, y up, z forward (checked against gp: docs/gaze-formats.md),
 * so theta_x (right positive) is atan(-x / z). Anything else about the record is not checked:
 * the stream is optional. */
static fs_status tobii_gp3(pctx *c, tobii_state *st, const cJSON *rec)
{
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(rec, "gp3");
    const cJSON *x = cJSON_IsArray(g) ? g->child : NULL, *y = x ? x->next : NULL, *z = y ? y->next : NULL;
    double gidx = opt_number(rec, "gidx");
    if (!finite_number(x) || !finite_number(y) || !finite_number(z) || !(z->valuedouble > 0) || isnan(gidx) ||
        opt_number(rec, "s") != 0)
        return FS_OK;
    double tx = -x->valuedouble / z->valuedouble, ty = y->valuedouble / z->valuedouble;
    if (!isfinite((float)tx) || !isfinite((float)ty))
        return FS_OK;
    if (st->n_dirs == st->cap_dirs && !FS_GROW_INT(st->dirs, st->cap_dirs, st->n_dirs + 1))
        return gaze_no_memory(c);
    st->dirs[st->n_dirs++] = (gidx_dir){gidx, (float)tx, (float)ty};
    return FS_OK;
}

static int cmp_gidx(const void *a, const void *b)
{
    const gidx_dir *p = a, *q = b;
    return (p->gidx > q->gidx) - (p->gidx < q->gidx);
}

/* Each gp sample gets the direction of the gp3 record with its gidx, if there is one. */
static void join_dirs(pctx *c, tobii_state *st)
{
    if (!st->n_dirs)
        return;
    qsort(st->dirs, (size_t)st->n_dirs, sizeof *st->dirs, cmp_gidx);
    for (int i = 0; i < c->n && i < st->n_gidx; i++) {
        const gidx_dir key = {st->gidx[i], 0, 0};
        const gidx_dir *d = isnan(key.gidx) ? NULL : bsearch(&key, st->dirs, (size_t)st->n_dirs, sizeof key, cmp_gidx);
        if (d) {
            c->raw[i].tx = d->tx;
            c->raw[i].ty = d->ty;
            c->has_dir = true;
        }
    }
    if (c->has_dir)
        snprintf(c->geometry, sizeof c->geometry, "directions from gp3 (scene camera, joined to gp by gidx)");
}

/* One gaze record (an object with "gp" and no "eye") to a sample; gp3 records are kept for their
 * directions; other streams are skipped. */
static fs_status tobii_record(pctx *c, tobii_state *st, long no, span line, const cJSON *rec)
{
    const cJSON *gp = cJSON_GetObjectItemCaseSensitive(rec, "gp");
    if (cJSON_GetObjectItemCaseSensitive(rec, "eye"))
        return FS_OK; /* per-eye gd/pc/pd */
    if (!gp)
        return cJSON_GetObjectItemCaseSensitive(rec, "gp3") ? tobii_gp3(c, st, rec) : FS_OK; /* ac, gy, pts, vts... */
    st->records++;
    double ts, status;
    fs_status s = record_number(c, no, line, rec, "ts", "\"ts\" (microseconds)", &ts);
    if (s == FS_OK)
        s = record_number(c, no, line, rec, "s", "the status \"s\"", &status);
    if (s != FS_OK)
        return s;
    char g[64];
    const cJSON *x = cJSON_IsArray(gp) ? gp->child : NULL, *y = x ? x->next : NULL;
    if (!finite_number(x) || !finite_number(y) || y->next) {
        const cJSON *shown = cJSON_IsNumber(x) && !finite_number(x)   ? x /* 1e999: cJSON prints null */
                             : cJSON_IsNumber(y) && !finite_number(y) ? y
                                                                      : gp;
        return gaze_fail(c, no, key_col(line, "gp"), "expected \"gp\" as [x, y], two numbers, got %s",
                         describe(shown, g, sizeof g));
    }
    const double gx = x->valuedouble, gy = y->valuedouble;
    if (!isfinite((float)gx) || !isfinite((float)gy) || fabs(gx) > 1e6 || fabs(gy) > 1e6)
        return gaze_fail(c, no, key_col(line, "gp"), "expected \"gp\" in normalised coordinates, got %g, %g",
                         gx, gy);
    const bool valid = status == 0;
    /* column 1: it only serves the time-goes-backwards message, which Tobii files never get (sorted) */
    s = gaze_push(c, no, 1, ts, valid ? gx : 0, valid ? gy : 0, 1.0, valid);
    if (s == FS_OK && st->n_gidx == st->cap_gidx && !FS_GROW_INT(st->gidx, st->cap_gidx, st->n_gidx + 1))
        return gaze_no_memory(c);
    if (s == FS_OK)
        st->gidx[st->n_gidx++] = opt_number(rec, "gidx");
    return s;
}

/* >>reader */

/* One line to a JSON object (*rec, for the caller to cJSON_Delete), or a message. */
static fs_status read_line(pctx *c, long no, span line, cJSON **rec)
{
    char g[64];
    const span t = gaze_trim(line);
    if (line.n > MAX_TOBII_RECORD_BYTES) /* before cJSON builds its tree (about 40 bytes a byte) */
        return gaze_fail(c, no, 1, "expected a Tobii record of at most %u bytes (MAX_TOBII_RECORD_BYTES), got a line "
                         "of %zu bytes", (unsigned)MAX_TOBII_RECORD_BYTES, line.n);
    if (t.p[0] != '{')
        return gaze_fail(c, no, (long)(t.p - line.p) + 1,
                         "expected a JSON object '{' (livedata.json has one per line), got %s",
                         gaze_snip(g, sizeof g, t.p, t.n));
    size_t stop = 0;
    fs_status s = parse_line(c, line, rec, &stop);
    if (s != FS_OK)
        return s;
    span rest = {line.p + stop, stop < line.n ? line.n - stop : 0};
    if (!*rec) {
        int depth = 0;
        if (open_at(line, stop, &depth))
            return gaze_fail(c, no, (long)line.n + 1, "expected '\"' to close the string, got the end of the line");
        if (rest.n && (*rest.p == '[' || *rest.p == '{') && depth >= CJSON_NESTING_LIMIT)
            return gaze_fail(c, no, (long)stop + 1, "expected at most %d nested arrays and objects (cJSON's limit), "
                             "got more", CJSON_NESTING_LIMIT);
        if (rest.n)
            return gaze_fail(c, no, (long)stop + 1, "expected valid JSON (one object per line), got %s",
                             gaze_snip(g, sizeof g, rest.p, rest.n));
        /* ran out: the line's last bytes show what was left open (or, for `,}`, the key missing) */
        const size_t k = line.n < 24 ? line.n : 24;
        return gaze_fail(c, no, (long)line.n + 1, "expected valid JSON (one object per line), got the end of the "
                         "line after %s", gaze_snip(g, sizeof g, line.p + line.n - k, k));
    }
    rest = gaze_trim(rest);
    if (rest.n)
        return gaze_fail(c, no, (long)(rest.p - line.p) + 1, "expected the end of the line after the object, got %s",
                         gaze_snip(g, sizeof g, rest.p, rest.n));
    long bad = bad_number_at(line);
    if (bad >= 0)
        return gaze_fail(c, no, bad + 1, "expected a JSON number (no leading zeros, digits on both sides of '.'), "
                         "got %s", gaze_snip(g, sizeof g, line.p + bad, line.n - (size_t)bad));
    return FS_OK;
}

fs_status gaze_parse_tobii(pctx *c, gaze_trace *out)
{
    c->unit = 1e-6;
    c->unit_name = "us";
    c->sorted_input = false; /* streams interleave: sort by ts, never report backwards time */
    line_it it = {c->text, c->text + c->size, 0};
    tobii_state st = {0};
    fs_status s = FS_OK;
    for (span line = {0}; s == FS_OK && gaze_next_line(&it, &line);) {
        if (gaze_is_blank(line))
            continue;
        cJSON *rec = NULL;
        s = read_line(c, it.no, line, &rec);
        if (s == FS_OK)
            s = tobii_record(c, &st, it.no, line, rec);
        cJSON_Delete(rec);
    }
    if (s == FS_OK && st.records == 0)
        s = gaze_fail(c, 1, 1, "expected Tobii gaze records (objects with \"gp\"), got none");
    if (s == FS_OK)
        join_dirs(c, &st);
    free(st.gidx);
    free(st.dirs);
    return s == FS_OK ? gaze_finish(c, GAZE_FORMAT_TOBII, out) : s;
}
