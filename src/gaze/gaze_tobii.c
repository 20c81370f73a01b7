/* gaze_tobii.c: the Tobii Pro Glasses 2 livedata.json reader: one JSON object per line, several
 * streams interleaved and out of time order; the gaze records ({"ts", "s", "gp"} without "eye")
 * become samples, sorted by time in gaze_finish.
 *
 * Records, validity and messages: docs/gaze-formats.md ("Tobii Pro Glasses 2 livedata.json").
 */
#include "gaze/gaze_read.h"

#include <math.h>

/* Deepest nesting of arrays/objects accepted in a Tobii JSON line (Glasses 2 uses 1). */
#define GAZE_JSON_MAX_DEPTH 64

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

static bool is_hex(char c) { return gaze_is_digit(c) || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F'); }

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
    else if (p < e && gaze_is_digit(*p))
        while (p < e && gaze_is_digit(*p))
            p++;
    else
        return j_fail(j, s, "a number");
    if (p < e && *p == '.') {
        p++;
        if (p >= e || !gaze_is_digit(*p))
            return j_fail(j, p, "a digit after '.'");
        while (p < e && gaze_is_digit(*p))
            p++;
    }
    if (p < e && (*p == 'e' || *p == 'E')) {
        p++;
        if (p < e && (*p == '+' || *p == '-'))
            p++;
        if (p >= e || !gaze_is_digit(*p))
            return j_fail(j, p, "a digit in the exponent");
        while (p < e && gaze_is_digit(*p))
            p++;
    }
    j->p = p;
    if (out) {
        double v;
        if (gaze_parse_num((span){s, (size_t)(p - s)}, &v) != NUM_OK)
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
        if (*j->p == '-' || gaze_is_digit(*j->p))
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
            if (gaze_tok_is(key, "ts") && !r->ts)
                r->ts = val;
            else if (gaze_tok_is(key, "s") && !r->s)
                r->s = val;
            else if (gaze_tok_is(key, "gp") && !r->gp)
                r->gp = val;
            else if (gaze_tok_is(key, "eye"))
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
    return gaze_fail(c, line, (long)(at - j->b) + 1, "expected %s, got %s", j->err_what ? j->err_what : "JSON",
                     at < j->e ? gaze_snip(g, sizeof g, at, (size_t)(j->e - at)) : "the end of the line");
}

fs_status gaze_parse_tobii(pctx *c, gaze_trace *out)
{
    c->unit = 1e-6;
    c->unit_name = "us";
    c->sorted_input = false; /* streams interleave: sort by ts, never report backwards time */
    line_it it = {c->text, c->text + c->size, 0};
    long records = 0;
    for (span line = {0}; gaze_next_line(&it, &line);) {
        if (gaze_is_blank(line))
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
            return gaze_fail(c, it.no, 1, "expected a \"ts\" (microseconds) in the gaze record, got none");
        j.p = r.ts;
        if (!j_number(&j, &ts)) {
            j.err_what = "a number for \"ts\" (microseconds)";
            return j_report(c, it.no, &j);
        }
        if (!r.s)
            return gaze_fail(c, it.no, 1, "expected a status \"s\" in the gaze record, got none");
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
            return gaze_fail(c, it.no, (long)(r.gp - line.p) + 1,
                             "expected \"gp\" in normalised coordinates, got %g, %g", gx, gy);
        bool valid = st == 0;
        fs_status s = gaze_push(c, it.no, (long)(r.ts - line.p) + 1, ts, valid ? gx : 0, valid ? gy : 0, 1.0, valid);
        if (s != FS_OK)
            return s;
    }
    if (records == 0)
        return gaze_fail(c, 1, 1, "expected Tobii gaze records (objects with \"gp\"), got none");
    return gaze_finish(c, GAZE_FORMAT_TOBII, out);
}

