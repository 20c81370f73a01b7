/* gaze.c: gaze trace readers (fovsim CSV, Pupil Labs, EyeLink ASC, Tobii livedata) and gaze_at.
 *
 * Every reader turns its text into raw samples (time in the file's own unit, x, y normalised,
 * validity, source line), then finish() sorts them (Tobii only), re-bases the times, averages
 * repeated timestamps and gives every invalid sample the gaze it holds, so that gaze_at is one
 * binary search. The formats and their quirks are described in docs/gaze-formats.md.
 *
 * The whole file is read into memory (at most MAX_GAZE_FILE_BYTES) and parsed in place: no line
 * length limit, NUL bytes are ordinary bytes, and a field is copied only to convert a number.
 */
#include "gaze/gaze.h"

#include "core/config.h"
#include "core/embedded.h"
#include "core/file_read.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/log.h"


/* Deepest nesting of arrays/objects accepted in a Tobii JSON line (Glasses 2 uses 1). */
#define GAZE_JSON_MAX_DEPTH 64

/* >>names */

const char *gaze_format_name(gaze_format f)
{
    switch (f) {
    case GAZE_FORMAT_AUTO: return "auto";
    case GAZE_FORMAT_CSV: return "csv";
    case GAZE_FORMAT_PUPIL: return "pupil";
    case GAZE_FORMAT_EYELINK: return "eyelink";
    case GAZE_FORMAT_TOBII: return "tobii";
    }
    return "unknown";
}

static bool ieq(const char *a, size_t n, const char *b)
{
    size_t k = strlen(b);
    if (n != k)
        return false;
    for (size_t i = 0; i < n; i++) {
        unsigned char ca = (unsigned char)a[i], cb = (unsigned char)b[i];
        if (ca >= 'A' && ca <= 'Z')
            ca = (unsigned char)(ca - 'A' + 'a');
        if (cb >= 'A' && cb <= 'Z')
            cb = (unsigned char)(cb - 'A' + 'a');
        if (ca != cb)
            return false;
    }
    return true;
}

gaze_format gaze_format_parse(const char *name)
{
    if (!name)
        return GAZE_FORMAT_AUTO;
    static const gaze_format all[] = {GAZE_FORMAT_CSV, GAZE_FORMAT_PUPIL, GAZE_FORMAT_EYELINK,
                                      GAZE_FORMAT_TOBII};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (ieq(name, strlen(name), gaze_format_name(all[i])))
            return all[i];
    return GAZE_FORMAT_AUTO;
}

static const char *eye_name(gaze_eye e)
{
    switch (e) {
    case GAZE_EYE_LEFT: return "left";
    case GAZE_EYE_RIGHT: return "right";
    case GAZE_EYE_AVERAGE: return "average";
    default: return "auto";
    }
}

/* >>context */

typedef struct span {
    const char *p;
    size_t n;
} span;

typedef struct raw_sample {
    double t;         /* in the file's unit (s, ms or us), not re-based */
    float x, y, conf; /* x, y normalised; EyeLink stores pixels until the screen size is known */
    bool valid;
    long line;        /* source line: messages, and the tie-break that keeps the Tobii sort stable */
} raw_sample;

typedef struct pctx {
    const char *name;  /* file name for messages */
    const char *text;  /* the whole file, BOM skipped */
    size_t size;
    gaze_load_desc desc;
    raw_sample *raw;
    int n, cap;
    double unit;       /* seconds per file time unit */
    const char *unit_name;
    bool sorted_input; /* false: the format interleaves streams, sort by time instead of checking */
    int screen_w, screen_h;
} pctx;

/* `got` text for messages: at most 40 bytes, non-printable bytes as '?', quoted. */
static const char *snip(char *buf, size_t cap, const char *p, size_t n)
{
    size_t k = 0, lim = 40;
    if (n == 0)
        return "nothing";
    buf[k++] = '\'';
    for (size_t i = 0; i < n && i < lim && k + 5 < cap; i++) {
        unsigned char c = (unsigned char)p[i];
        buf[k++] = (c >= 0x20 && c < 0x7f) ? (char)c : '?';
    }
    if (n > lim && k + 5 < cap) {
        memcpy(buf + k, "...", 3);
        k += 3;
    }
    buf[k++] = '\'';
    buf[k] = '\0';
    return buf;
}

static fs_status fail(const pctx *c, long line, long col, const char *fmt, ...) FS_PRINTF(4, 5);

static fs_status fail(const pctx *c, long line, long col, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    log_error("%s:%ld:%ld: %s", c->name, line, col, msg);
    return FS_ERR_GAZE;
}

static fs_status no_memory(const pctx *c)
{
    log_error("%s: out of memory reading the gaze trace", c->name);
    return FS_ERR_NOMEM;
}

/* >>text */

typedef struct line_it {
    const char *p, *end;
    long no; /* number of the line last returned, 1-based */
} line_it;

/* Next line without its "\n" or "\r\n"; false at the end of the text. */
static bool next_line(line_it *it, span *line)
{
    if (it->p >= it->end)
        return false;
    const char *b = it->p;
    const char *nl = memchr(b, '\n', (size_t)(it->end - b));
    const char *e = nl ? nl : it->end;
    it->p = nl ? nl + 1 : it->end;
    it->no++;
    if (e > b && e[-1] == '\r')
        e--;
    line->p = b;
    line->n = (size_t)(e - b);
    return true;
}

static bool is_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

static bool is_blank(span s)
{
    for (size_t i = 0; i < s.n; i++)
        if (!is_blank_char(s.p[i]))
            return false;
    return true;
}

static span trim(span s)
{
    while (s.n && is_blank_char(s.p[0]))
        s.p++, s.n--;
    while (s.n && is_blank_char(s.p[s.n - 1]))
        s.n--;
    return s;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

static bool starts_with(span s, const char *pre)
{
    size_t k = strlen(pre);
    return s.n >= k && memcmp(s.p, pre, k) == 0;
}

static bool span_has(span s, const char *needle)
{
    size_t k = strlen(needle);
    for (size_t i = 0; i + k <= s.n; i++)
        if (s.p[i] == needle[0] && memcmp(s.p + i, needle, k) == 0)
            return true;
    return false;
}

typedef enum num_result { NUM_OK, NUM_BAD, NUM_NONFINITE } num_result;

/* A decimal number `[+-]digits[.digits][e[+-]digits]`, blanks around allowed. nan, inf and hex
 * floats, which strtod would take, are refused (NUM_NONFINITE for nan/inf and for overflow). */
static num_result parse_num(span s, double *out)
{
    s = trim(s);
    size_t i = 0, n = s.n;
    const char *p = s.p;
    bool digits = false;
    if (i < n && (p[i] == '+' || p[i] == '-'))
        i++;
    if (i < n && !is_digit(p[i]) && p[i] != '.') {
        span rest = {p + i, n - i};
        if (ieq(rest.p, rest.n, "nan") || ieq(rest.p, rest.n, "inf") || ieq(rest.p, rest.n, "infinity"))
            return NUM_NONFINITE;
        return NUM_BAD;
    }
    while (i < n && is_digit(p[i]))
        i++, digits = true;
    if (i < n && p[i] == '.') {
        i++;
        while (i < n && is_digit(p[i]))
            i++, digits = true;
    }
    if (!digits)
        return NUM_BAD;
    if (i < n && (p[i] == 'e' || p[i] == 'E')) {
        i++;
        if (i < n && (p[i] == '+' || p[i] == '-'))
            i++;
        bool ed = false;
        while (i < n && is_digit(p[i]))
            i++, ed = true;
        if (!ed)
            return NUM_BAD;
    }
    if (i != n)
        return NUM_BAD;
    /* Fast path, exact like strtod (Clinger 1990): at most 15 digits and no exponent, so the digits
     * form an exact double and so does 10^frac; one division rounds correctly. Most fields of
     * ASC and CSV files take it. */
    double m = 0;
    int nd = 0, frac = 0;
    bool dot = false, expo = false;
    for (size_t j = 0; j < n; j++) {
        char ch = p[j];
        if (is_digit(ch)) {
            m = m * 10 + (ch - '0');
            nd++;
            frac += dot;
        } else if (ch == '.') {
            dot = true;
        } else if (ch == 'e' || ch == 'E') {
            expo = true;
            break;
        }
    }
    if (!expo && nd <= 15) {
        static const double pow10[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13,
                                       1e14, 1e15};
        double v = m / pow10[frac];
        *out = p[0] == '-' ? -v : v;
        return NUM_OK;
    }
    char buf[128];
    if (n >= sizeof buf)
        return NUM_BAD; /* a 128-digit number is no coordinate */
    memcpy(buf, p, n);
    buf[n] = '\0';
    double v = strtod(buf, NULL);
    if (!isfinite(v))
        return NUM_NONFINITE;
    *out = v;
    return NUM_OK;
}

/* Whitespace-separated tokens (EyeLink). */
static bool next_tok(const char **pp, const char *end, span *tok)
{
    const char *p = *pp;
    while (p < end && (*p == ' ' || *p == '\t'))
        p++;
    if (p >= end) {
        *pp = p;
        return false;
    }
    const char *b = p;
    while (p < end && *p != ' ' && *p != '\t')
        p++;
    tok->p = b;
    tok->n = (size_t)(p - b);
    *pp = p;
    return true;
}

static bool tok_is(span t, const char *word) { return t.n == strlen(word) && memcmp(t.p, word, t.n) == 0; }

/* One CSV field from *pp, up to the next ',' or the end (where *pp is left). Blanks around are
 * trimmed; a field in double quotes may hold commas ("" inside stays as is). False on an
 * unterminated quote. */
static bool csv_field(const char **pp, const char *end, span *f)
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
        span s = trim((span){b, (size_t)(p - b)});
        *f = s;
    }
    *pp = p;
    return true;
}

/* >>samples */

static fs_status push(pctx *c, long line, long col, double t, double x, double y, double conf, bool valid)
{
    if (c->n > 0 && c->sorted_input && t < c->raw[c->n - 1].t) {
        const raw_sample *prev = &c->raw[c->n - 1];
        return fail(c, line, col, "expected time >= %.15g %s (line %ld), got %.15g %s (time goes backwards)",
                    prev->t, c->unit_name, prev->line, t, c->unit_name);
    }
    if (c->n == c->cap) {
        if (c->cap >= (1 << 29))
            return fail(c, line, 1, "expected at most %d samples, got more", 1 << 29);
        int cap = c->cap ? c->cap * 2 : 1024;
        raw_sample *r = realloc(c->raw, (size_t)cap * sizeof *r);
        if (!r)
            return no_memory(c);
        c->raw = r;
        c->cap = cap;
    }
    c->raw[c->n++] = (raw_sample){.t = t, .x = (float)x, .y = (float)y, .conf = (float)conf,
                                  .valid = valid, .line = line};
    return FS_OK;
}

static int cmp_raw(const void *a, const void *b)
{
    const raw_sample *p = a, *q = b;
    if (p->t != q->t)
        return p->t < q->t ? -1 : 1;
    return (p->line > q->line) - (p->line < q->line);
}

/* Sort (if the format needs it), re-base, average repeated timestamps, fill the held gaze of
 * invalid samples. Takes c->n >= 1. */
static fs_status finish(pctx *c, gaze_format fmt, gaze_trace *out)
{
    if (!c->sorted_input)
        qsort(c->raw, (size_t)c->n, sizeof *c->raw, cmp_raw);
    const double t0 = c->raw[0].t;
    gaze_sample *s = malloc((size_t)c->n * sizeof *s);
    if (!s)
        return no_memory(c);
    int m = 0, valid = 0;
    for (int i = 0; i < c->n;) {
        double t = (c->raw[i].t - t0) * c->unit;
        if (!isfinite(t)) {
            free(s);
            return fail(c, c->raw[i].line, 1, "expected a time closer to the first sample's, got %.15g %s",
                        c->raw[i].t, c->unit_name);
        }
        /* Repeats (Pupil Labs: one row per eye pairing; EyeLink at 2000 Hz): average the valid rows
         * if any is valid, else all rows. */
        double sx = 0, sy = 0, sc = 0, ax = 0, ay = 0, ac = 0;
        int nv = 0, na = 0, j = i;
        for (; j < c->n && (c->raw[j].t - t0) * c->unit == t; j++) {
            const raw_sample *r = &c->raw[j];
            ax += r->x, ay += r->y, ac += r->conf, na++;
            if (r->valid)
                sx += r->x, sy += r->y, sc += r->conf, nv++;
        }
        gaze_sample *o = &s[m++];
        o->t = t;
        o->valid = nv > 0;
        o->x = (float)(nv ? sx / nv : ax / na);
        o->y = (float)(nv ? sy / nv : ay / na);
        o->confidence = (float)(nv ? sc / nv : ac / na);
        valid += o->valid;
        i = j;
    }
    /* Invalid samples hold the last valid gaze before them (the first valid one when the trace
     * starts invalid; the centre when there is none), stored in their x, y. */
    int first = 0;
    while (first < m && !s[first].valid)
        first++;
    float hx = first < m ? s[first].x : 0.5f, hy = first < m ? s[first].y : 0.5f;
    for (int i = 0; i < m; i++) {
        if (s[i].valid) {
            hx = s[i].x;
            hy = s[i].y;
        } else {
            s[i].x = hx;
            s[i].y = hy;
        }
    }
    const double duration = s[m - 1].t;
    if (m < c->n) {
        gaze_sample *shrunk = realloc(s, (size_t)m * sizeof *s);
        if (shrunk)
            s = shrunk;
    }
    out->samples = s;
    out->count = m;
    out->valid_count = valid;
    out->duration = duration;
    out->time_offset = t0 * c->unit;
    out->format = fmt;
    out->screen_w = c->screen_w;
    out->screen_h = c->screen_h;
    if (valid == 0)
        log_warn("GAZE: [%s] no valid sample in %d; the gaze stays at the display centre", c->name, m);
    return FS_OK;
}

/* >>csv  (fovsim CSV and Pupil Labs gaze_positions.csv share the reader) */

/* 0-based index of the column called `name` in a header line, -1 if none, -2 if twice. */
static int header_col(span header, const char *name, int *second)
{
    const char *p = header.p, *end = header.p + header.n;
    int found = -1;
    for (int k = 0;; k++) {
        span f = {0};
        if (!csv_field(&p, end, &f))
            return found;
        if (ieq(f.p, f.n, name)) {
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
        if (!csv_field(&p, end, &f))
            return -1;
        if (k < (1 << 20))
            k++;
        if (p >= end)
            break;
        p++;
    }
    return k;
}

typedef struct csv_cols {
    const char *names[4]; /* t, x, y, confidence (NULL: no confidence column) */
    int idx[4];           /* -1: absent */
    bool flip_y;          /* Pupil Labs: origin bottom-left */
} csv_cols;

static fs_status csv_rows(pctx *c, line_it *it, long header_line, int ncols, const csv_cols *cols)
{
    for (span line = {0}; next_line(it, &line);) {
        span tl = trim(line);
        if (tl.n == 0 || tl.p[0] == '#')
            continue;
        span f[4] = {{0}};
        const char *p = line.p, *end = line.p + line.n;
        int k = 0;
        for (;;) {
            span fld = {0};
            if (!csv_field(&p, end, &fld))
                return fail(c, it->no, k + 1, "expected a closing '\"' in column %d, got the end of the line", k + 1);
            for (int j = 0; j < 4; j++)
                if (cols->idx[j] == k)
                    f[j] = fld;
            if (k < (1 << 20))
                k++;
            if (p >= end)
                break;
            p++;
        }
        if (k != ncols)
            return fail(c, it->no, (k < ncols ? k : ncols) + 1, "expected %d columns, got %d", ncols, k);
        double v[4] = {0, 0, 0, 1};
        for (int j = 0; j < 4; j++) {
            if (cols->idx[j] < 0)
                continue;
            char g[64];
            num_result r = parse_num(f[j], &v[j]);
            if (r != NUM_OK)
                return fail(c, it->no, cols->idx[j] + 1, "expected a %snumber for column '%s', got %s",
                            r == NUM_NONFINITE ? "finite " : "", cols->names[j], snip(g, sizeof g, f[j].p, f[j].n));
            if (j == 1 || j == 2) {
                if (!isfinite((float)v[j]) || fabs(v[j]) > 1e6)
                    return fail(c, it->no, cols->idx[j] + 1,
                                "expected a normalised coordinate for column '%s' (|value| <= 1e6), got %s",
                                cols->names[j], snip(g, sizeof g, f[j].p, f[j].n));
            }
            if (j == 3 && (v[j] < 0 || v[j] > 1))
                return fail(c, it->no, cols->idx[j] + 1, "expected a confidence between 0 and 1 in column '%s', got %s",
                            cols->names[j], snip(g, sizeof g, f[j].p, f[j].n));
        }
        /* compared as float: "0.6" must pass the default threshold 0.6f */
        bool valid = cols->idx[3] < 0 || c->desc.min_confidence < 0 || (float)v[3] >= c->desc.min_confidence;
        double y = cols->flip_y ? 1.0 - v[2] : v[2];
        fs_status s = push(c, it->no, cols->idx[0] + 1, v[0], v[1], y, v[3], valid);
        if (s != FS_OK)
            return s;
    }
    if (c->n == 0)
        return fail(c, header_line + 1, 1, "expected a sample row after the header, got none");
    return FS_OK;
}

/* The header line of a CSV file: the first line that is neither blank nor a '#' comment. */
static bool csv_header(line_it *it, span *header)
{
    for (span line = {0}; next_line(it, &line);) {
        span tl = trim(line);
        if (tl.n == 0 || tl.p[0] == '#')
            continue;
        *header = line;
        return true;
    }
    return false;
}

/* Finds the columns of `names` (NULL ends the required ones at index 3); reports missing or
 * doubled ones. */
static fs_status csv_find_cols(pctx *c, long line, span header, csv_cols *cols, const char *want)
{
    char g[64];
    for (int j = 0; j < 4; j++) {
        cols->idx[j] = -1;
        if (!cols->names[j])
            continue;
        int second = -1;
        int k = header_col(header, cols->names[j], &second);
        if (k == -2)
            return fail(c, line, second + 1, "expected one column named '%s', got a second one", cols->names[j]);
        if (k < 0 && j < 3)
            return fail(c, line, 1, "expected a header naming the columns %s, got %s", want,
                        snip(g, sizeof g, header.p, header.n));
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
        return fail(c, it->no, 1, "expected a closing '\"' in the header, got the end of the line");
    c->unit = 1.0;
    c->unit_name = "s";
    fs_status s = csv_rows(c, it, it->no, ncols, cols);
    return s != FS_OK ? s : finish(c, format, out);
}

static fs_status parse_csv(pctx *c, gaze_trace *out)
{
    line_it it = {c->text, c->text + c->size, 0};
    span header = {0};
    if (!csv_header(&it, &header))
        return fail(c, 1, 1, "expected a header line 't,x,y', got an empty file");
    csv_cols cols = {.names = {"t", "x", "y", "confidence"}};
    fs_status s = csv_find_cols(c, it.no, header, &cols, "t, x and y");
    if (s != FS_OK)
        return s;
    return csv_body(c, &it, header, &cols, GAZE_FORMAT_CSV, out);
}

static fs_status parse_pupil(pctx *c, gaze_trace *out)
{
    line_it it = {c->text, c->text + c->size, 0};
    span header = {0};
    if (!csv_header(&it, &header))
        return fail(c, 1, 1, "expected the header of a Pupil Labs gaze_positions.csv, got an empty file");
    int dummy;
    /* Player before v1.8 called the column `timestamp`. */
    const char *tname = header_col(header, "gaze_timestamp", &dummy) != -1 ? "gaze_timestamp" : "timestamp";
    csv_cols cols = {.names = {tname, "norm_pos_x", "norm_pos_y", "confidence"}, .flip_y = true};
    fs_status s = csv_find_cols(c, it.no, header, &cols, "gaze_timestamp, norm_pos_x and norm_pos_y");
    if (s != FS_OK)
        return s;
    return csv_body(c, &it, header, &cols, GAZE_FORMAT_PUPIL, out);
}

/* >>eyelink */

enum { EYE_L = 1, EYE_R = 2 };

/* LEFT/RIGHT words among the tokens after the first one. */
static int eyes_of(span line)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    int eyes = 0;
    next_tok(&p, end, &t);
    while (next_tok(&p, end, &t)) {
        if (tok_is(t, "LEFT"))
            eyes |= EYE_L;
        else if (tok_is(t, "RIGHT"))
            eyes |= EYE_R;
    }
    return eyes;
}

/* The eye(s) recorded in a block against the eye asked for. */
static fs_status check_block_eyes(pctx *c, long line, int eyes)
{
    gaze_eye want = c->desc.eye;
    if ((want == GAZE_EYE_LEFT && eyes == EYE_R) || (want == GAZE_EYE_RIGHT && eyes == EYE_L))
        return fail(c, line, 1, "expected a recording of the %s eye (eye = %s), got the %s eye only",
                    eye_name(want), eye_name(want), eyes == EYE_L ? "left" : "right");
    return FS_OK;
}

/* A flag field of a sample line: '.' and capital letters ("...", ".C.C.", "I..", "..........R.."). */
static bool is_flags(span t)
{
    if (t.n < 2)
        return false;
    for (size_t i = 0; i < t.n; i++)
        if (t.p[i] != '.' && !(t.p[i] >= 'A' && t.p[i] <= 'Z'))
            return false;
    return true;
}

typedef struct el_coords {
    bool set;
    double l, t, r, b;
    long line;
} el_coords;

static fs_status el_msg(pctx *c, long line_no, span line, el_coords *disp, el_coords *gaze)
{
    /* MSG <time> [<offset>] DISPLAY_COORDS <left> <top> <right> <bottom> */
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    int k = 0;
    while (k < 4 && next_tok(&p, end, &t)) {
        k++;
        if (k < 3)
            continue;
        el_coords *dst = tok_is(t, "DISPLAY_COORDS") ? disp : tok_is(t, "GAZE_COORDS") ? gaze : NULL;
        if (!dst)
            continue;
        double v[4];
        for (int i = 0; i < 4; i++) {
            span nt = {0};
            char g[64];
            if (!next_tok(&p, end, &nt) || parse_num(nt, &v[i]) != NUM_OK)
                return fail(c, line_no, k + 1 + i, "expected 4 numbers (left top right bottom) after %.*s, got %s",
                            (int)t.n, t.p, snip(g, sizeof g, nt.p, nt.n));
        }
        if (dst->set)
            return FS_OK; /* the first one counts */
        double w = v[2] - v[0] + 1, h = v[3] - v[1] + 1;
        if (!(w >= 1 && w <= 100000 && h >= 1 && h <= 100000))
            return fail(c, line_no, k + 1, "expected a screen of 1 to 100000 pixels a side in %.*s, got %g x %g",
                        (int)t.n, t.p, w, h);
        *dst = (el_coords){true, v[0], v[1], v[2], v[3], line_no};
        return FS_OK;
    }
    return FS_OK;
}

/* One sample line: `time x y pupil [xR yR pupilR] [velocities] [resolution] flags [remote fields]`.
 * The values are counted up to the flag field: 3, 5 or 7 are monocular, 6, 8, 10 or 12 binocular. */
static fs_status el_sample(pctx *c, long line_no, span line)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    char g[64];
    double tm;
    next_tok(&p, end, &t);
    if (parse_num(t, &tm) != NUM_OK)
        return fail(c, line_no, 1, "expected a sample time in ms, got %s", snip(g, sizeof g, t.p, t.n));
    double v[12] = {0};
    bool have[12] = {0};
    int nv = 0;
    while (next_tok(&p, end, &t)) {
        double x = 0;
        bool dot = t.n == 1 && t.p[0] == '.';
        num_result r = dot ? NUM_OK : parse_num(t, &x);
        if (r != NUM_OK) {
            if (is_flags(t))
                break;
            return fail(c, line_no, nv + 2, "expected a %snumber or '.' in a sample, got %s",
                        r == NUM_NONFINITE ? "finite " : "", snip(g, sizeof g, t.p, t.n));
        }
        if (nv < 12) {
            v[nv] = x;
            have[nv] = !dot;
        }
        if (nv < 1000)
            nv++;
    }
    bool mono = nv == 3 || nv == 5 || nv == 7;
    bool bino = nv == 6 || nv == 8 || nv == 10 || nv == 12;
    if (!mono && !bino)
        return fail(c, line_no, nv + 2, "expected 3 (monocular) or 6 (binocular) values after the sample time, got %d",
                    nv);
    bool lv = have[0] && have[1];
    double x = 0, y = 0;
    bool valid;
    if (mono) {
        valid = lv;
        x = v[0], y = v[1]; /* which eye it is was checked on the START/SAMPLES line */
    } else {
        bool rv = have[3] && have[4];
        switch (c->desc.eye) {
        case GAZE_EYE_LEFT:
            valid = lv, x = v[0], y = v[1];
            break;
        case GAZE_EYE_RIGHT:
            valid = rv, x = v[3], y = v[4];
            break;
        case GAZE_EYE_AVERAGE:
            valid = lv && rv, x = 0.5 * (v[0] + v[3]), y = 0.5 * (v[1] + v[4]);
            break;
        default: /* AUTO: the eyes that are valid */
            valid = lv || rv;
            x = lv && rv ? 0.5 * (v[0] + v[3]) : lv ? v[0] : v[3];
            y = lv && rv ? 0.5 * (v[1] + v[4]) : lv ? v[1] : v[4];
            break;
        }
    }
    if (!valid)
        x = y = 0;
    if (!isfinite((float)x) || !isfinite((float)y) || fabs(x) > 1e7 || fabs(y) > 1e7)
        return fail(c, line_no, 2, "expected gaze in pixels (|value| <= 1e7), got %g, %g", x, y);
    return push(c, line_no, 1, tm, x, y, 1.0, valid);
}

static fs_status parse_eyelink(pctx *c, gaze_trace *out)
{
    /* Samples count only inside START..END blocks, so numeric lines elsewhere (calibration
     * coefficients) are never taken for samples; a file without any START (samples cut out of an
     * ASC file) is one block. */
    bool has_start = starts_with((span){c->text, c->size}, "START");
    for (const char *q = c->text; !has_start && q < c->text + c->size;) {
        const char *nl = memchr(q, '\n', (size_t)(c->text + c->size - q));
        if (!nl)
            break;
        q = nl + 1;
        has_start = starts_with((span){q, (size_t)(c->text + c->size - q)}, "START");
    }
    c->unit = 1e-3;
    c->unit_name = "ms";
    line_it it = {c->text, c->text + c->size, 0};
    el_coords disp = {0}, gz = {0};
    bool in_block = !has_start;
    long skipped = 0;
    fs_status s = FS_OK;
    for (span line; s == FS_OK && next_line(&it, &line);) {
        if (line.n == 0)
            continue;
        if (is_digit(line.p[0])) {
            if (in_block)
                s = el_sample(c, it.no, line);
            else
                skipped++;
            continue;
        }
        const char *p = line.p, *end = line.p + line.n;
        span w = {0};
        if (!next_tok(&p, end, &w))
            continue;
        if (tok_is(w, "MSG")) {
            s = el_msg(c, it.no, line, &disp, &gz);
        } else if (tok_is(w, "START")) {
            in_block = true;
            s = check_block_eyes(c, it.no, eyes_of(line));
        } else if (tok_is(w, "END")) {
            in_block = !has_start;
        } else if (tok_is(w, "SAMPLES")) {
            span kind = {0};
            if (next_tok(&p, end, &kind) && (tok_is(kind, "HREF") || tok_is(kind, "PUPIL")))
                s = fail(c, it.no, 2, "expected GAZE samples (screen pixels; edf2asc's default), got %.*s",
                         (int)kind.n, kind.p);
            int e = eyes_of(line);
            if (s == FS_OK && e)
                s = check_block_eyes(c, it.no, e);
        }
        /* Everything else is an event (SFIX, EFIX, SSACC, ESACC, SBLINK, EBLINK, INPUT, BUTTON),
         * a header line (**), or calibration output: skipped. */
    }
    if (s != FS_OK)
        return s;
    if (c->n == 0)
        return fail(c, 1, 1, "expected EyeLink sample lines inside START..END blocks, got none%s",
                    skipped ? "" : " (converted with edf2asc -ns, events only?)");
    const el_coords *sc = disp.set ? &disp : gz.set ? &gz : NULL;
    if (!sc)
        return fail(c, 1, 1, "expected a DISPLAY_COORDS or GAZE_COORDS message giving the screen size, got none");
    double w = sc->r - sc->l + 1, h = sc->b - sc->t + 1;
    for (int i = 0; i < c->n; i++) {
        raw_sample *r = &c->raw[i];
        if (r->valid) {
            r->x = (float)((r->x - sc->l) / w);
            r->y = (float)((r->y - sc->t) / h);
        }
    }
    c->screen_w = (int)lround(w);
    c->screen_h = (int)lround(h);
    if (skipped)
        log_info("GAZE: [%s] %ld numeric lines outside START..END blocks skipped", c->name, skipped);
    return finish(c, GAZE_FORMAT_EYELINK, out);
}

/* >>tobii  (one JSON object per line; a small strict scanner, no allocation per line) */

typedef struct jscan {
    const char *p, *b, *e; /* cursor, line begin, line end */
    const char *err_at;
    const char *err_what;
} jscan;

static bool j_fail(jscan *j, const char *at, const char *what)
{
    j->err_at = at;
    j->err_what = what;
    return false;
}

static void j_ws(jscan *j)
{
    while (j->p < j->e && (*j->p == ' ' || *j->p == '\t'))
        j->p++;
}

static bool is_hex(char c) { return is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

/* A string at j->p (which is '"'); `out` gets its raw content. */
static bool j_string(jscan *j, span *out)
{
    const char *s = ++j->p;
    while (j->p < j->e) {
        unsigned char ch = (unsigned char)*j->p;
        if (ch == '"') {
            if (out)
                *out = (span){s, (size_t)(j->p - s)};
            j->p++;
            return true;
        }
        if (ch < 0x20)
            return j_fail(j, j->p, "a string character (control characters must be escaped)");
        if (ch == '\\') {
            j->p++;
            if (j->p >= j->e)
                break;
            char esc = *j->p;
            if (esc == 'u') {
                for (int i = 0; i < 4; i++)
                    if (++j->p >= j->e || !is_hex(*j->p))
                        return j_fail(j, j->p < j->e ? j->p : j->e, "4 hex digits after \\u");
            } else if (!(esc == '"' || esc == '\\' || esc == '/' || esc == 'b' || esc == 'f' || esc == 'n' ||
                         esc == 'r' || esc == 't')) {
                return j_fail(j, j->p, "an escape character (\" \\ / b f n r t u)");
            }
        }
        j->p++;
    }
    return j_fail(j, j->e, "'\"' to close the string");
}

/* A JSON number (RFC 8259 grammar) at j->p. */
static bool j_number(jscan *j, double *out)
{
    const char *s = j->p, *p = j->p, *e = j->e;
    if (p < e && *p == '-')
        p++;
    if (p < e && *p == '0')
        p++;
    else if (p < e && is_digit(*p))
        while (p < e && is_digit(*p))
            p++;
    else
        return j_fail(j, s, "a number");
    if (p < e && *p == '.') {
        p++;
        if (p >= e || !is_digit(*p))
            return j_fail(j, p, "a digit after '.'");
        while (p < e && is_digit(*p))
            p++;
    }
    if (p < e && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < e && (*p == '+' || *p == '-'))
            p++;
        if (p >= e || !is_digit(*p))
            return j_fail(j, p, "a digit in the exponent");
        while (p < e && is_digit(*p))
            p++;
    }
    j->p = p;
    if (out) {
        double v;
        if (parse_num((span){s, (size_t)(p - s)}, &v) != NUM_OK)
            return j_fail(j, s, "a finite number of at most 127 characters");
        *out = v;
    }
    return true;
}

static bool j_value(jscan *j, int depth);

static bool j_word(jscan *j, const char *w)
{
    size_t k = strlen(w);
    if ((size_t)(j->e - j->p) < k || memcmp(j->p, w, k) != 0)
        return j_fail(j, j->p, "a JSON value");
    j->p += k;
    return true;
}

static bool j_container(jscan *j, int depth, char close)
{
    if (depth >= GAZE_JSON_MAX_DEPTH)
        return j_fail(j, j->p, "at most 64 nested arrays and objects");
    j->p++;
    j_ws(j);
    if (j->p < j->e && *j->p == close) {
        j->p++;
        return true;
    }
    for (;;) {
        j_ws(j);
        if (close == '}') {
            if (j->p >= j->e || *j->p != '"')
                return j_fail(j, j->p, "a key string");
            if (!j_string(j, NULL))
                return false;
            j_ws(j);
            if (j->p >= j->e || *j->p != ':')
                return j_fail(j, j->p, "':' after the key");
            j->p++;
            j_ws(j);
        }
        if (!j_value(j, depth + 1))
            return false;
        j_ws(j);
        if (j->p < j->e && *j->p == ',') {
            j->p++;
            continue;
        }
        if (j->p < j->e && *j->p == close) {
            j->p++;
            return true;
        }
        return j_fail(j, j->p, close == '}' ? "',' or '}'" : "',' or ']'");
    }
}

static bool j_value(jscan *j, int depth)
{
    if (j->p >= j->e)
        return j_fail(j, j->p, "a JSON value");
    switch (*j->p) {
    case '{': return j_container(j, depth, '}');
    case '[': return j_container(j, depth, ']');
    case '"': return j_string(j, NULL);
    case 't': return j_word(j, "true");
    case 'f': return j_word(j, "false");
    case 'n': return j_word(j, "null");
    default:
        if (*j->p == '-' || is_digit(*j->p))
            return j_number(j, NULL);
        return j_fail(j, j->p, "a JSON value");
    }
}

/* The members of the top-level object that a gaze record needs (value positions, NULL if absent). */
typedef struct tobii_rec {
    const char *ts, *s, *gp;
    bool eye;
} tobii_rec;

static bool j_record(jscan *j, tobii_rec *r)
{
    j_ws(j);
    if (j->p >= j->e || *j->p != '{')
        return j_fail(j, j->p, "a JSON object '{' (livedata.json has one per line)");
    j->p++;
    j_ws(j);
    if (j->p < j->e && *j->p == '}') {
        j->p++;
    } else {
        for (;;) {
            j_ws(j);
            span key = {0};
            if (j->p >= j->e || *j->p != '"')
                return j_fail(j, j->p, "a key string");
            if (!j_string(j, &key))
                return false;
            j_ws(j);
            if (j->p >= j->e || *j->p != ':')
                return j_fail(j, j->p, "':' after the key");
            j->p++;
            j_ws(j);
            const char *val = j->p;
            if (!j_value(j, 1))
                return false;
            if (tok_is(key, "ts") && !r->ts)
                r->ts = val;
            else if (tok_is(key, "s") && !r->s)
                r->s = val;
            else if (tok_is(key, "gp") && !r->gp)
                r->gp = val;
            else if (tok_is(key, "eye"))
                r->eye = true;
            j_ws(j);
            if (j->p < j->e && *j->p == ',') {
                j->p++;
                continue;
            }
            if (j->p < j->e && *j->p == '}') {
                j->p++;
                break;
            }
            return j_fail(j, j->p, "',' or '}'");
        }
    }
    j_ws(j);
    if (j->p < j->e)
        return j_fail(j, j->p, "the end of the line after the object");
    return true;
}

static fs_status j_report(pctx *c, long line, const jscan *j)
{
    char g[64];
    const char *at = j->err_at ? j->err_at : j->b;
    return fail(c, line, (long)(at - j->b) + 1, "expected %s, got %s", j->err_what ? j->err_what : "JSON",
                at < j->e ? snip(g, sizeof g, at, (size_t)(j->e - at)) : "the end of the line");
}

static fs_status parse_tobii(pctx *c, gaze_trace *out)
{
    c->unit = 1e-6;
    c->unit_name = "us";
    c->sorted_input = false; /* streams interleave: sort by ts, never report backwards time */
    line_it it = {c->text, c->text + c->size, 0};
    long records = 0;
    for (span line = {0}; next_line(&it, &line);) {
        if (is_blank(line))
            continue;
        jscan j = {line.p, line.p, line.p + line.n, NULL, NULL};
        tobii_rec r = {0};
        if (!j_record(&j, &r))
            return j_report(c, it.no, &j);
        if (!r.gp || r.eye)
            continue; /* another stream (ac, gy, pts, vts, per-eye gd/pc/pd, gp3...) */
        records++;
        double ts, st, gx, gy;
        if (!r.ts)
            return fail(c, it.no, 1, "expected a \"ts\" (microseconds) in the gaze record, got none");
        j.p = r.ts;
        if (!j_number(&j, &ts)) {
            j.err_what = "a number for \"ts\" (microseconds)";
            return j_report(c, it.no, &j);
        }
        if (!r.s)
            return fail(c, it.no, 1, "expected a status \"s\" in the gaze record, got none");
        j.p = r.s;
        if (!j_number(&j, &st)) {
            j.err_what = "a number for the status \"s\"";
            return j_report(c, it.no, &j);
        }
        /* "gp": [x, y] */
        j.p = r.gp;
        bool ok = j.p < j.e && *j.p == '[';
        if (ok) {
            j.p++;
            j_ws(&j);
            ok = j_number(&j, &gx);
            j_ws(&j);
            ok = ok && j.p < j.e && *j.p == ',';
            if (ok) {
                j.p++;
                j_ws(&j);
                ok = j_number(&j, &gy);
                j_ws(&j);
                ok = ok && j.p < j.e && *j.p == ']';
            }
        }
        if (!ok) {
            j.err_at = j.p;
            j.err_what = "\"gp\" as [x, y], two numbers";
            return j_report(c, it.no, &j);
        }
        if (!isfinite((float)gx) || !isfinite((float)gy) || fabs(gx) > 1e6 || fabs(gy) > 1e6)
            return fail(c, it.no, (long)(r.gp - line.p) + 1, "expected \"gp\" in normalised coordinates, got %g, %g",
                        gx, gy);
        bool valid = st == 0;
        fs_status s = push(c, it.no, (long)(r.ts - line.p) + 1, ts, valid ? gx : 0, valid ? gy : 0, 1.0, valid);
        if (s != FS_OK)
            return s;
    }
    if (records == 0)
        return fail(c, 1, 1, "expected Tobii gaze records (objects with \"gp\"), got none");
    return finish(c, GAZE_FORMAT_TOBII, out);
}

/* >>detect */

static const char *const k_asc_words[] = {"MSG",  "START", "END",    "SAMPLES", "EVENTS", "PRESCALER",
                                          "VPRESCALER", "PUPIL", "INPUT", "BUTTON", "SFIX", "EFIX",
                                          "SSACC", "ESACC", "SBLINK", "EBLINK"};

static fs_status detect(pctx *c, gaze_format *fmt)
{
    *fmt = GAZE_FORMAT_AUTO;
    line_it it = {c->text, c->text + c->size, 0};
    span first = {0}, line;
    bool have_first = false;
    while (next_line(&it, &line)) {
        if (!is_blank(line)) {
            first = trim(line);
            have_first = true;
            break;
        }
    }
    char g[64];
    if (!have_first)
        return fail(c, 1, 1, "expected a gaze trace (fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink ASC or "
                             "Tobii livedata.json), got an empty file");
    if (first.p[0] == '{' && span_has(first, "\"ts\"")) {
        *fmt = GAZE_FORMAT_TOBII;
        return FS_OK;
    }
    if (starts_with(first, "**")) {
        *fmt = GAZE_FORMAT_EYELINK;
        return FS_OK;
    }
    const char *p = first.p, *end = first.p + first.n;
    span w = {0};
    next_tok(&p, end, &w);
    for (size_t i = 0; i < sizeof k_asc_words / sizeof k_asc_words[0]; i++)
        if (tok_is(w, k_asc_words[i])) {
            *fmt = GAZE_FORMAT_EYELINK;
            return FS_OK;
        }
    /* Sample lines alone (cut out of an ASC file): a number, then at least 3 more fields, no comma. */
    if (is_digit(first.p[0]) && !memchr(first.p, ',', first.n)) {
        int k = 1;
        while (next_tok(&p, end, &w))
            k++;
        if (k >= 4) {
            *fmt = GAZE_FORMAT_EYELINK;
            return FS_OK;
        }
    }
    /* CSV: the header is the first line that is not a '#' comment. */
    line_it hi = {c->text, c->text + c->size, 0};
    span header = {0};
    if (csv_header(&hi, &header)) {
        int d;
        bool npx = header_col(header, "norm_pos_x", &d) != -1 && header_col(header, "norm_pos_y", &d) != -1;
        if (npx && (header_col(header, "pupil_timestamp", &d) != -1 || header_col(header, "diameter", &d) != -1))
            return fail(c, hi.no, 1, "expected Pupil Labs gaze_positions.csv, got pupil_positions.csv (pupil "
                                     "positions in the eye camera images, not gaze)");
        if (npx && (header_col(header, "gaze_timestamp", &d) != -1 ||
                    (header_col(header, "timestamp", &d) != -1 && header_col(header, "base_data", &d) != -1))) {
            *fmt = GAZE_FORMAT_PUPIL;
            return FS_OK;
        }
        if (header_col(header, "t", &d) != -1 && header_col(header, "x", &d) != -1 &&
            header_col(header, "y", &d) != -1) {
            *fmt = GAZE_FORMAT_CSV;
            return FS_OK;
        }
    }
    return fail(c, 1, 1, "expected a gaze trace (fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink ASC or Tobii "
                         "livedata.json), got %s", snip(g, sizeof g, first.p, first.n));
}

/* >>load */

fs_status gaze_parse(const char *text, long size, const char *name, const gaze_load_desc *desc, gaze_trace *out)
{
    FS_ASSERT(out);
    FS_ASSERT(size >= 0 && (text || size == 0));
    char keep[sizeof out->path];
    snprintf(keep, sizeof keep, "%s", name ? name : "<memory>");
    memset(out, 0, sizeof *out);
    memcpy(out->path, keep, sizeof keep);
    if (size < 0 || (!text && size > 0)) {
        log_error("%s: no text to parse", out->path);
        return FS_ERR_GAZE;
    }
    pctx c = {.name = out->path, .text = text ? text : "", .size = (size_t)size, .sorted_input = true};
    c.desc = desc ? *desc : (gaze_load_desc){0};
    if (c.desc.min_confidence == 0 || isnan(c.desc.min_confidence))
        c.desc.min_confidence = 0.6f;
    if ((unsigned)c.desc.eye > GAZE_EYE_AVERAGE) {
        FS_ASSERT(!"gaze_load_desc.eye out of range");
        c.desc.eye = GAZE_EYE_AUTO;
    }
    if (c.size >= 3 && memcmp(c.text, "\xEF\xBB\xBF", 3) == 0) /* UTF-8 byte order mark (Excel) */
        c.text += 3, c.size -= 3;

    gaze_format fmt = c.desc.format;
    fs_status s = FS_OK;
    if (fmt == GAZE_FORMAT_AUTO)
        s = detect(&c, &fmt);
    if (s == FS_OK) {
        switch (fmt) {
        case GAZE_FORMAT_CSV: s = parse_csv(&c, out); break;
        case GAZE_FORMAT_PUPIL: s = parse_pupil(&c, out); break;
        case GAZE_FORMAT_EYELINK: s = parse_eyelink(&c, out); break;
        case GAZE_FORMAT_TOBII: s = parse_tobii(&c, out); break;
        default:
            FS_ASSERT(!"gaze_load_desc.format out of range");
            s = fail(&c, 1, 1, "expected a known gaze format, got format number %d", (int)fmt);
            break;
        }
    }
    free(c.raw);
    if (s != FS_OK) {
        free(out->samples);
        out->samples = NULL;
        out->count = out->valid_count = 0;
        return s;
    }
    if (fmt == GAZE_FORMAT_EYELINK)
        log_info("GAZE: [%s] EyeLink %dx%d, eye %s", out->path, out->screen_w, out->screen_h, eye_name(c.desc.eye));
    return FS_OK;
}

fs_status gaze_load(const char *path, const gaze_load_desc *desc, gaze_trace *out)
{
    FS_ASSERT(out);
    memset(out, 0, sizeof *out);
    if (!path) {
        log_error("GAZE: no file name given");
        return FS_ERR_IO;
    }
    /* "builtin:NAME" is gaze_paths/NAME.csv, compiled into the binary. */
    if (strncmp(path, "builtin:", 8) == 0) {
        char rel[256];
        snprintf(rel, sizeof rel, "gaze_paths/%s.csv", path + 8);
        const embedded_file *e = embedded_find(rel);
        if (!e) {
            log_error("%s: no built-in gaze trace of that name (built-in: %s)", path, gaze_builtin_list());
            return FS_ERR_IO;
        }
        return gaze_parse(e->data, (long)e->size, path, desc, out);
    }
    char *text;
    size_t size;
    fs_status rs = file_read_all(path, MAX_GAZE_FILE_BYTES, "a gaze trace", FS_ERR_GAZE, &text, &size);
    if (rs != FS_OK)
        return rs;
    fs_status s = gaze_parse(text, (long)size, path, desc, out);
    free(text);
    return s;
}

void gaze_free(gaze_trace *t)
{
    if (!t)
        return;
    free(t->samples);
    memset(t, 0, sizeof *t);
}

/* >>resample */

static float clamp01(double v)
{
    if (!(v >= 0))
        return 0.0f; /* also NaN, which a loaded trace never holds */
    return v > 1 ? 1.0f : (float)v;
}

gaze_point gaze_at(const gaze_trace *t, double time, bool *beyond_end)
{
    gaze_point g = {0.5f, 0.5f, true};
    if (beyond_end)
        *beyond_end = false;
    if (!t || !t->samples || t->count <= 0)
        return g;
    const gaze_sample *s = t->samples;
    const int n = t->count;
    if (isnan(time))
        time = 0;
    if (time > s[n - 1].t && beyond_end)
        *beyond_end = true;
    if (t->valid_count == 0)
        return g;
    /* Invalid samples carry the gaze they hold (finish()), so every case is one lookup. */
    const gaze_sample *a;
    double x, y;
    bool held;
    if (time <= s[0].t || time >= s[n - 1].t) {
        a = time <= s[0].t ? &s[0] : &s[n - 1];
        g.x = clamp01(a->x);
        g.y = clamp01(a->y);
        g.held = !(time == a->t && a->valid); /* before the start, past the end: held */
        return g;
    }
    /* s[lo].t <= time < s[hi].t, hi = lo + 1 */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (s[mid].t <= time)
            lo = mid;
        else
            hi = mid;
    }
    a = &s[lo];
    const gaze_sample *b = &s[hi];
    if (time == a->t) {
        x = a->x, y = a->y, held = !a->valid;
    } else if (a->valid && b->valid) {
        double f = (time - a->t) / (b->t - a->t);
        x = a->x + f * ((double)b->x - a->x);
        y = a->y + f * ((double)b->y - a->y);
        held = false;
    } else {
        x = a->x, y = a->y, held = true; /* into or inside an invalid run: hold */
    }
    g.x = clamp01(x);
    g.y = clamp01(y);
    g.held = held;
    return g;
}

const char *gaze_builtin_list(void)
{
    static char list[512];
    if (!list[0]) {
        size_t o = 0;
        for (int i = 0; i < embedded_file_count; i++) {
            const char *p = embedded_files[i].path;
            if (strncmp(p, "gaze_paths/", 11) != 0)
                continue;
            int n = snprintf(list + o, sizeof list - o, "%s%.*s", o ? ", " : "", (int)(strlen(p) - 15), p + 11);
            if (n < 0 || (size_t)n >= sizeof list - o)
                break;
            o += (size_t)n;
        }
    }
    return list;
}
