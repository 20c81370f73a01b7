/* gaze_text.c: what every gaze reader shares: messages (file:line:column), lines and tokens,
 * numbers, and the raw samples that gaze_finish turns into a trace.
 *
 * The declarations and the reading model are in gaze_read.h; the formats in docs/gaze-formats.md.
 */
#include "gaze/gaze_read.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"

/* >>messages */

const char *gaze_snip(char *buf, size_t cap, const char *p, size_t n)
{
    if (n == 0)
        return "nothing";
    return log_quote(buf, cap < 46 ? cap : 46, p, n); /* at most 40 bytes */
}

fs_status gaze_fail(const pctx *c, long line, long col, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    log_error("%s:%ld:%ld: %s", c->name, line, col, msg);
    return FS_ERR_GAZE;
}

fs_status gaze_no_memory(const pctx *c)
{
    log_error("%s: out of memory reading the gaze trace", c->name);
    return FS_ERR_NOMEM;
}

const char *gaze_eye_name(gaze_eye e)
{
    switch (e) {
    case GAZE_EYE_LEFT: return "left";
    case GAZE_EYE_RIGHT: return "right";
    case GAZE_EYE_AVERAGE: return "average";
    default: return "auto";
    }
}

/* >>text */

bool gaze_next_line(line_it *it, span *line)
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

bool gaze_is_blank(span s)
{
    for (size_t i = 0; i < s.n; i++)
        if (!gaze_is_blank_char(s.p[i]))
            return false;
    return true;
}

span gaze_trim(span s)
{
    while (s.n && gaze_is_blank_char(s.p[0]))
        s.p++, s.n--;
    while (s.n && gaze_is_blank_char(s.p[s.n - 1]))
        s.n--;
    return s;
}

bool gaze_starts_with(span s, const char *pre)
{
    size_t k = strlen(pre);
    return s.n >= k && memcmp(s.p, pre, k) == 0;
}

bool gaze_ieq(const char *a, size_t n, const char *b)
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

num_result gaze_parse_num(span s, double *out)
{
    s = gaze_trim(s);
    size_t i = 0, n = s.n;
    const char *p = s.p;
    bool digits = false;
    if (i < n && (p[i] == '+' || p[i] == '-'))
        i++;
    if (i < n && !gaze_is_digit(p[i]) && p[i] != '.') {
        span rest = {p + i, n - i};
        if (gaze_ieq(rest.p, rest.n, "nan") || gaze_ieq(rest.p, rest.n, "inf") || gaze_ieq(rest.p, rest.n, "infinity"))
            return NUM_NONFINITE;
        return NUM_BAD;
    }
    while (i < n && gaze_is_digit(p[i]))
        i++, digits = true;
    if (i < n && p[i] == '.') {
        i++;
        while (i < n && gaze_is_digit(p[i]))
            i++, digits = true;
    }
    if (!digits)
        return NUM_BAD;
    if (i < n && (p[i] == 'e' || p[i] == 'E')) {
        i++;
        if (i < n && (p[i] == '+' || p[i] == '-'))
            i++;
        bool ed = false;
        while (i < n && gaze_is_digit(p[i]))
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
        if (gaze_is_digit(ch)) {
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

bool gaze_next_tok(const char **pp, const char *end, span *tok)
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

/* >>samples */

fs_status gaze_push(pctx *c, long line, long col, double t, double x, double y, double conf, bool valid)
{
    if (c->n > 0 && c->sorted_input && t < c->raw[c->n - 1].t) {
        const raw_sample *prev = &c->raw[c->n - 1];
        return gaze_fail(c, line, col, "expected time >= %.15g %s (line %ld), got %.15g %s (time goes backwards)",
                         prev->t, c->unit_name, prev->line, t, c->unit_name);
    }
    if (c->n == c->cap) {
        if (c->cap >= (1 << 29))
            return gaze_fail(c, line, 1, "expected at most %d samples, got more", 1 << 29);
        if (!FS_GROW_INT(c->raw, c->cap, c->n + 1))
            return gaze_no_memory(c);
    }
    c->raw[c->n++] = (raw_sample){.t = t, .x = (float)x, .y = (float)y, .conf = (float)conf,
                                  .tx = NAN, .ty = NAN, .valid = valid, .line = line};
    return FS_OK;
}

void gaze_set_dir(pctx *c, double tx, double ty)
{
    FS_ASSERT(c->n > 0);
    c->raw[c->n - 1].tx = (float)tx;
    c->raw[c->n - 1].ty = (float)ty;
    c->has_dir = true;
}

/* The mean direction of the valid rows raw[i..j) that have one (NaN if none has). */
static void mean_dir(const raw_sample *raw, int i, int j, float *tx, float *ty)
{
    double sx = 0, sy = 0;
    int n = 0;
    for (int k = i; k < j; k++)
        if (raw[k].valid && !isnan(raw[k].tx) && !isnan(raw[k].ty))
            sx += raw[k].tx, sy += raw[k].ty, n++;
    *tx = n ? (float)(sx / n) : NAN;
    *ty = n ? (float)(sy / n) : NAN;
}

static int cmp_raw(const void *a, const void *b)
{
    const raw_sample *p = a, *q = b;
    if (p->t != q->t)
        return p->t < q->t ? -1 : 1;
    return (p->line > q->line) - (p->line < q->line);
}

fs_status gaze_finish(pctx *c, gaze_format fmt, gaze_trace *out)
{
    if (!c->sorted_input)
        qsort(c->raw, (size_t)c->n, sizeof *c->raw, cmp_raw);
    const double t0 = c->raw[0].t;
    gaze_sample *s = malloc((size_t)c->n * sizeof *s);
    float *dir = c->has_dir ? malloc((size_t)c->n * 2 * sizeof *dir) : NULL;
    if (!s || (c->has_dir && !dir)) {
        free(s);
        free(dir);
        return gaze_no_memory(c);
    }
    int m = 0, valid = 0;
    for (int i = 0; i < c->n;) {
        double t = (c->raw[i].t - t0) * c->unit;
        if (!isfinite(t)) {
            free(s);
            free(dir);
            return gaze_fail(c, c->raw[i].line, 1, "expected a time closer to the first sample's, got %.15g %s",
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
        if (dir)
            mean_dir(c->raw, i, j, &dir[2 * m], &dir[2 * m + 1]);
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
    out->dir = dir;
    out->tan_per_x = c->tan_per_x;
    out->tan_per_y = c->tan_per_y;
    snprintf(out->geometry, sizeof out->geometry, "%s", c->geometry);
    if (valid == 0)
        log_warn("GAZE: [%s] no valid sample in %d; the gaze stays at the display centre", c->name, m);
    return FS_OK;
}
