/* gaze.c: the gaze.h API: format names, format detection, gaze_parse/gaze_load (which hand the
 * text to one reader per format), gaze_free, the built-in traces and gaze_at resampling.
 *
 * The readers: gaze_csv.c (fovsim CSV, Pupil Labs), gaze_eyelink.c (EyeLink ASC), gaze_tobii.c
 * (Tobii livedata.json), over the shared parts in gaze_text.c (gaze_read.h). The formats and their
 * quirks are described in docs/gaze-formats.md.
 *
 * The whole file is read into memory (at most MAX_GAZE_FILE_BYTES) and parsed in place.
 */
#include "gaze/gaze_read.h"

#include "core/config.h"
#include "core/embedded.h"
#include "core/file_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* >>names */

const char *gaze_format_name(gaze_format f)
{
    switch (f) {
    case GAZE_FORMAT_AUTO: return "auto";
    case GAZE_FORMAT_CSV: return "csv";
    case GAZE_FORMAT_PUPIL: return "pupil";
    case GAZE_FORMAT_EYELINK: return "eyelink";
    case GAZE_FORMAT_TOBII: return "tobii";
    case GAZE_FORMAT_EYENAV: return "eyenav";
    }
    return "unknown";
}

gaze_format gaze_format_parse(const char *name)
{
    if (!name)
        return GAZE_FORMAT_AUTO;
    static const gaze_format all[] = {GAZE_FORMAT_CSV, GAZE_FORMAT_PUPIL, GAZE_FORMAT_EYELINK,
                                      GAZE_FORMAT_TOBII, GAZE_FORMAT_EYENAV};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (gaze_ieq(name, strlen(name), gaze_format_name(all[i])))
            return all[i];
    return GAZE_FORMAT_AUTO;
}

/* >>detect */

static const char *const k_asc_words[] = {"MSG",  "START", "END",    "SAMPLES", "EVENTS", "PRESCALER",
                                          "VPRESCALER", "PUPIL", "INPUT", "BUTTON", "SFIX", "EFIX",
                                          "SSACC", "ESACC", "SBLINK", "EBLINK"};

static bool span_has(span s, const char *needle)
{
    size_t k = strlen(needle);
    for (size_t i = 0; i + k <= s.n; i++)
        if (s.p[i] == needle[0] && memcmp(s.p + i, needle, k) == 0)
            return true;
    return false;
}

static bool has_col(span header, const char *name)
{
    int second;
    return gaze_csv_header_col(header, name, &second) != -1;
}

static fs_status detect(pctx *c, gaze_format *fmt)
{
    *fmt = GAZE_FORMAT_AUTO;
    line_it it = {c->text, c->text + c->size, 0};
    span first = {0}, line;
    bool have_first = false;
    while (gaze_next_line(&it, &line)) {
        if (!gaze_is_blank(line)) {
            first = gaze_trim(line);
            have_first = true;
            break;
        }
    }
    char g[64];
    if (!have_first)
        return gaze_fail(c, 1, 1, "expected a gaze trace (fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink ASC, "
                                  "Tobii livedata.json or EyeNavGS CSV), got an empty file");
    if (first.p[0] == '{' && span_has(first, "\"ts\"")) {
        *fmt = GAZE_FORMAT_TOBII;
        return FS_OK;
    }
    if (gaze_starts_with(first, "**")) {
        *fmt = GAZE_FORMAT_EYELINK;
        return FS_OK;
    }
    const char *p = first.p, *end = first.p + first.n;
    span w = {0};
    gaze_next_tok(&p, end, &w);
    for (size_t i = 0; i < sizeof k_asc_words / sizeof k_asc_words[0]; i++)
        if (gaze_tok_is(w, k_asc_words[i])) {
            *fmt = GAZE_FORMAT_EYELINK;
            return FS_OK;
        }
    /* Sample lines alone (cut out of an ASC file): a number, then at least 3 more fields, no comma. */
    if (gaze_is_digit(first.p[0]) && !memchr(first.p, ',', first.n)) {
        int k = 1;
        while (gaze_next_tok(&p, end, &w))
            k++;
        if (k >= 4) {
            *fmt = GAZE_FORMAT_EYELINK;
            return FS_OK;
        }
    }
    /* CSV: the header is the first line that is not a '#' comment. */
    line_it hi = {c->text, c->text + c->size, 0};
    span header = {0};
    if (gaze_csv_header(&hi, &header)) {
        bool npx = has_col(header, "norm_pos_x") && has_col(header, "norm_pos_y");
        if (npx && (has_col(header, "pupil_timestamp") || has_col(header, "diameter")))
            return gaze_fail(c, hi.no, 1, "expected Pupil Labs gaze_positions.csv, got pupil_positions.csv (pupil "
                                          "positions in the eye camera images, not gaze)");
        if (npx && (has_col(header, "gaze_timestamp") ||
                    (has_col(header, "timestamp") && has_col(header, "base_data")))) {
            *fmt = GAZE_FORMAT_PUPIL;
            return FS_OK;
        }
        if (gaze_eyenav_header(header)) {
            *fmt = GAZE_FORMAT_EYENAV;
            return FS_OK;
        }
        if (has_col(header, "t") && has_col(header, "x") && has_col(header, "y")) {
            *fmt = GAZE_FORMAT_CSV;
            return FS_OK;
        }
    }
    return gaze_fail(c, 1, 1, "expected a gaze trace (fovsim CSV, Pupil Labs gaze_positions.csv, EyeLink ASC, Tobii "
                              "livedata.json or EyeNavGS CSV), got %s", gaze_snip(g, sizeof g, first.p, first.n));
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
        case GAZE_FORMAT_CSV: s = gaze_parse_csv(&c, out); break;
        case GAZE_FORMAT_PUPIL: s = gaze_parse_pupil(&c, out); break;
        case GAZE_FORMAT_EYELINK: s = gaze_parse_eyelink(&c, out); break;
        case GAZE_FORMAT_TOBII: s = gaze_parse_tobii(&c, out); break;
        case GAZE_FORMAT_EYENAV: s = gaze_parse_eyenav(&c, out); break;
        default:
            FS_ASSERT(!"gaze_load_desc.format out of range");
            s = gaze_fail(&c, 1, 1, "expected a known gaze format, got format number %d", (int)fmt);
            break;
        }
    }
    free(c.raw);
    if (s != FS_OK) {
        free(out->samples);
        free(out->dir);
        out->samples = NULL;
        out->dir = NULL;
        out->count = out->valid_count = 0;
        return s;
    }
    if (fmt == GAZE_FORMAT_EYELINK)
        log_info("GAZE: [%s] EyeLink %dx%d, eye %s", out->path, out->screen_w, out->screen_h,
                 gaze_eye_name(c.desc.eye));
    if (fmt == GAZE_FORMAT_EYENAV)
        log_info("GAZE: [%s] EyeNavGS, %d frames, eye-in-head gaze of eye %s", out->path, out->count,
                 gaze_eye_name(c.desc.eye));
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
    free(t->dir);
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
    /* Invalid samples carry the gaze they hold (gaze_finish()), so every case is one lookup. */
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

int gaze_sample_index(const gaze_trace *t, double time)
{
    if (!t || !t->samples || t->count <= 0)
        return -1;
    int lo = 0, hi = t->count; /* s[lo].t <= time < s[hi].t, s[count].t = infinity */
    if (!(time >= t->samples[0].t))
        return 0;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (t->samples[mid].t <= time)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
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
