/* gaze_eyelink.c: the SR Research EyeLink ASC reader (text written by edf2asc from an .edf
 * recording): sample lines inside START..END blocks, the screen size from DISPLAY_COORDS or
 * GAZE_COORDS, mono, binocular and remote-mode files.
 *
 * Line rules, eye choice and messages: docs/gaze-formats.md ("EyeLink ASC").
 */
#include "gaze/gaze_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/grow.h"
#include "core/stats.h"

/* >>blocks */

enum { EYE_L = 1, EYE_R = 2 };

/* LEFT/RIGHT words among the tokens after the first one. */
static int eyes_of(span line)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    int eyes = 0;
    gaze_next_tok(&p, end, &t);
    while (gaze_next_tok(&p, end, &t)) {
        if (gaze_tok_is(t, "LEFT"))
            eyes |= EYE_L;
        else if (gaze_tok_is(t, "RIGHT"))
            eyes |= EYE_R;
    }
    return eyes;
}

/* Whether the word is among the line's tokens after the first. */
static bool has_word(span line, const char *word)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    gaze_next_tok(&p, end, &t);
    while (gaze_next_tok(&p, end, &t))
        if (gaze_tok_is(t, word))
            return true;
    return false;
}

/* The eye(s) recorded in a block against the eye asked for. */
static fs_status check_block_eyes(pctx *c, long line, int eyes)
{
    gaze_eye want = c->desc.eye;
    if ((want == GAZE_EYE_LEFT && eyes == EYE_R) || (want == GAZE_EYE_RIGHT && eyes == EYE_L))
        return gaze_fail(c, line, 1, "expected a recording of the %s eye (eye = %s), got the %s eye only",
                         gaze_eye_name(want), gaze_eye_name(want), eyes == EYE_L ? "left" : "right");
    return FS_OK;
}

/* >>lines */

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
    while (k < 4 && gaze_next_tok(&p, end, &t)) {
        k++;
        if (k < 3)
            continue;
        el_coords *dst = gaze_tok_is(t, "DISPLAY_COORDS") ? disp : gaze_tok_is(t, "GAZE_COORDS") ? gaze : NULL;
        if (!dst)
            continue;
        double v[4];
        for (int i = 0; i < 4; i++) {
            span nt = {0};
            char g[64];
            if (!gaze_next_tok(&p, end, &nt) || gaze_parse_num(nt, &v[i]) != NUM_OK)
                return gaze_fail(c, line_no, k + 1 + i, "expected 4 numbers (left top right bottom) after %.*s, got %s",
                                 (int)t.n, t.p, gaze_snip(g, sizeof g, nt.p, nt.n));
        }
        if (dst->set)
            return FS_OK; /* the first one counts */
        double w = v[2] - v[0] + 1, h = v[3] - v[1] + 1;
        if (!(w >= 1 && w <= 100000 && h >= 1 && h <= 100000))
            return gaze_fail(c, line_no, k + 1, "expected a screen of 1 to 100000 pixels a side in %.*s, got %g x %g",
                             (int)t.n, t.p, w, h);
        *dst = (el_coords){true, v[0], v[1], v[2], v[3], line_no};
        return FS_OK;
    }
    return FS_OK;
}

/* >>resolution: the viewing distance from EyeLink's pixels per degree (docs/gaze-formats.md) */

typedef struct el_res {
    int i;        /* raw sample index */
    double rx, ry; /* pixels per degree at the sample (per-sample RES fields) or over a block (END ... RES) */
    int end;      /* block: raw samples [i, end); -1 for a sample */
} el_res;

typedef struct el_state {
    el_res *res;
    int n, cap;
    bool vel, has_res; /* the SAMPLES line declares VEL / RES fields (5 monocular values are ambiguous) */
    int block_start;   /* raw index of the current block's first sample */
} el_state;

static fs_status add_res(pctx *c, el_state *st, el_res r)
{
    if (!(r.rx > 0 && r.ry > 0 && r.rx < 1e6 && r.ry < 1e6))
        return FS_OK; /* '.', 0 or junk: no resolution for this sample */
    if (st->n == st->cap && !FS_GROW_INT(st->res, st->cap, st->n + 1))
        return gaze_no_memory(c);
    st->res[st->n++] = r;
    return FS_OK;
}

/* The resolution fields of a sample line with nv values (v[], have[]), if it has them:
 * `<positions> [velocities] [xres yres]` before the flags. */
static bool sample_res(const el_state *st, int nv, const double *v, const bool *have, double *rx, double *ry)
{
    int at = nv == 7 ? 5 : nv == 8 ? 6 : nv == 12 ? 10 : nv == 5 && st->has_res && !st->vel ? 3 : -1;
    if (at < 0 || !have[at] || !have[at + 1])
        return false;
    *rx = v[at];
    *ry = v[at + 1];
    return true;
}

/* The distance D (pixels) at which a flat screen shows k = 180 res / pi pixels per degree at offset
 * u from its centre: res = (pi/180) (D^2 + u^2) / D, the larger root. NaN if none. */
static double distance_px(double res, double u2)
{
    double k = res * 180.0 / 3.14159265358979323846, disc = k * k - 4 * u2;
    return disc >= 0 ? 0.5 * (k + sqrt(disc)) : NAN;
}

/* Median of the finite values of v[0..n) (sorted in place); NaN if none. */
static double median(double *v, int n)
{
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(v[i]))
            v[m++] = v[i];
    if (!m)
        return NAN;
    qsort(v, (size_t)m, sizeof *v, stats_cmp_double);
    return stats_quantile(v, m, 0.5);
}

/* One estimate of D along an axis from r (axis 0 = x): a sample's offset, or for a block average
 * the mean squared offset of its valid samples (the mean of res(u) is (pi/180)(D + mean(u^2)/D)). */
static double res_distance(const pctx *c, const el_res *r, int axis, double w, double h)
{
    double res = axis ? r->ry : r->rx, size = axis ? h : w, u2 = 0;
    int n = 0;
    for (int i = r->i; i < (r->end < 0 ? r->i + 1 : r->end); i++) {
        if (!c->raw[i].valid)
            continue;
        double u = ((axis ? c->raw[i].y : c->raw[i].x) - 0.5) * size;
        u2 += u * u;
        n++;
    }
    return n || r->end >= 0 ? distance_px(res, n ? u2 / n : 0) : NAN;
}

/* tan_per_x/y from the resolutions: the median distance of the per-sample values when there are
 * any, else of the block averages. The samples are normalised already; w, h: the screen. */
static fs_status el_geometry(pctx *c, el_state *st, double w, double h)
{
    int samples = 0;
    for (int i = 0; i < st->n; i++)
        samples += st->res[i].end < 0;
    const size_t cap = st->n > 0 ? (size_t)st->n : 1;
    double *d = malloc(2 * cap * sizeof *d);
    if (!d)
        return gaze_no_memory(c);
    int m = 0;
    for (int i = 0; i < st->n; i++) {
        if ((st->res[i].end < 0) != (samples > 0))
            continue;
        d[m] = res_distance(c, &st->res[i], 0, w, h);
        d[cap + m++] = res_distance(c, &st->res[i], 1, w, h);
    }
    double dx = median(d, m), dy = median(d + cap, m);
    free(d);
    if (m && dx > 0 && dy > 0) {
        c->tan_per_x = w / dx;
        c->tan_per_y = h / dy;
        snprintf(c->geometry, sizeof c->geometry, "EyeLink %gx%g px seen from %.0f px (x), %.0f px (y): median of %d %s",
                 w, h, dx, dy, m, samples ? "per-sample resolutions" : "block resolutions (END ... RES)");
    }
    return FS_OK;
}

/* `END <time> SAMPLES EVENTS RES <xres> <yres>`: the block's average resolution. */
static fs_status el_end(pctx *c, el_state *st, span line)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    while (gaze_next_tok(&p, end, &t)) {
        if (!gaze_tok_is(t, "RES"))
            continue;
        span a = {0}, b = {0};
        double rx, ry;
        if (gaze_next_tok(&p, end, &a) && gaze_next_tok(&p, end, &b) && gaze_parse_num(a, &rx) == NUM_OK &&
            gaze_parse_num(b, &ry) == NUM_OK && c->n > st->block_start)
            return add_res(c, st, (el_res){st->block_start, rx, ry, c->n});
    }
    return FS_OK;
}

/* One sample line: `time x y pupil [xR yR pupilR] [velocities] [resolution] flags [remote fields]`.
 * The values are counted up to the flag field: 3, 5 or 7 are monocular, 6, 8, 10 or 12 binocular. */
static fs_status el_sample(pctx *c, el_state *st, long line_no, span line)
{
    const char *p = line.p, *end = line.p + line.n;
    span t = {0};
    char g[64];
    double tm;
    gaze_next_tok(&p, end, &t);
    if (gaze_parse_num(t, &tm) != NUM_OK)
        return gaze_fail(c, line_no, 1, "expected a sample time in ms, got %s", gaze_snip(g, sizeof g, t.p, t.n));
    double v[12] = {0};
    bool have[12] = {0};
    int nv = 0;
    while (gaze_next_tok(&p, end, &t)) {
        double x = 0;
        bool dot = t.n == 1 && t.p[0] == '.';
        num_result r = dot ? NUM_OK : gaze_parse_num(t, &x);
        if (r != NUM_OK) {
            if (is_flags(t))
                break;
            return gaze_fail(c, line_no, nv + 2, "expected a %snumber or '.' in a sample, got %s",
                             r == NUM_NONFINITE ? "finite " : "", gaze_snip(g, sizeof g, t.p, t.n));
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
        return gaze_fail(c, line_no, nv + 2,
                         "expected 3 (monocular) or 6 (binocular) values after the sample time, got %d", nv);
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
        return gaze_fail(c, line_no, 2, "expected gaze in pixels (|value| <= 1e7), got %g, %g", x, y);
    fs_status s = gaze_push(c, line_no, 1, tm, x, y, 1.0, valid);
    double rx, ry;
    if (s == FS_OK && valid && sample_res(st, nv, v, have, &rx, &ry))
        s = add_res(c, st, (el_res){c->n - 1, rx, ry, -1});
    return s;
}

/* >>reader */

static fs_status el_finish(pctx *c, el_state *st, const el_coords *disp, const el_coords *gz, long skipped);

fs_status gaze_parse_eyelink(pctx *c, gaze_trace *out)
{
    /* Samples count only inside START..END blocks, so numeric lines elsewhere (calibration
     * coefficients) are never taken for samples; a file without any START (samples cut out of an
     * ASC file) is one block. */
    bool has_start = gaze_starts_with((span){c->text, c->size}, "START");
    for (const char *q = c->text; !has_start && q < c->text + c->size;) {
        const char *nl = memchr(q, '\n', (size_t)(c->text + c->size - q));
        if (!nl)
            break;
        q = nl + 1;
        has_start = gaze_starts_with((span){q, (size_t)(c->text + c->size - q)}, "START");
    }
    c->unit = 1e-3;
    c->unit_name = "ms";
    line_it it = {c->text, c->text + c->size, 0};
    el_coords disp = {0}, gz = {0};
    bool in_block = !has_start;
    long skipped = 0;
    el_state st = {0};
    fs_status s = FS_OK;
    for (span line; s == FS_OK && gaze_next_line(&it, &line);) {
        if (line.n == 0)
            continue;
        if (gaze_is_digit(line.p[0])) {
            if (in_block)
                s = el_sample(c, &st, it.no, line);
            else
                skipped++;
            continue;
        }
        const char *p = line.p, *end = line.p + line.n;
        span w = {0};
        if (!gaze_next_tok(&p, end, &w))
            continue;
        if (gaze_tok_is(w, "MSG")) {
            s = el_msg(c, it.no, line, &disp, &gz);
        } else if (gaze_tok_is(w, "START")) {
            in_block = true;
            st.block_start = c->n;
            s = check_block_eyes(c, it.no, eyes_of(line));
        } else if (gaze_tok_is(w, "END")) {
            in_block = !has_start;
            s = el_end(c, &st, line);
        } else if (gaze_tok_is(w, "SAMPLES")) {
            span kind = {0};
            if (gaze_next_tok(&p, end, &kind) && (gaze_tok_is(kind, "HREF") || gaze_tok_is(kind, "PUPIL")))
                s = gaze_fail(c, it.no, 2, "expected GAZE samples (screen pixels; edf2asc's default), got %.*s",
                              (int)kind.n, kind.p);
            int e = eyes_of(line);
            st.vel = has_word(line, "VEL");
            st.has_res = has_word(line, "RES");
            if (s == FS_OK && e)
                s = check_block_eyes(c, it.no, e);
        }
        /* Everything else is an event (SFIX, EFIX, SSACC, ESACC, SBLINK, EBLINK, INPUT, BUTTON),
         * a header line (**), or calibration output: skipped. */
    }
    if (s == FS_OK)
        s = el_finish(c, &st, &disp, &gz, skipped);
    free(st.res);
    return s == FS_OK ? gaze_finish(c, GAZE_FORMAT_EYELINK, out) : s;
}

/* After the last line: the screen size, the samples normalised to it, the viewing distance. */
static fs_status el_finish(pctx *c, el_state *st, const el_coords *disp, const el_coords *gz, long skipped)
{
    if (c->n == 0)
        return gaze_fail(c, 1, 1, "expected EyeLink sample lines inside START..END blocks, got none%s",
                         skipped ? "" : " (converted with edf2asc -ns, events only?)");
    const el_coords *sc = disp->set ? disp : gz->set ? gz : NULL;
    if (!sc)
        return gaze_fail(c, 1, 1, "expected a DISPLAY_COORDS or GAZE_COORDS message giving the screen size, got none");
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
    return el_geometry(c, st, w, h);
}

