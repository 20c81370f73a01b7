/* check_judge.c: `fovsim check --baseline` compares a new compare run with the baseline's
 * (check.h): metrics per frame, mode and ring, and the pixels of the frames, with a diff image
 * per failing frame. What it found is reported by check_report.c. */
#include "commands/check_judge.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/grow.h"
#include "core/log.h"
#include "core/strbuf.h"
#include "metrics/image_diff.h"
#include "metrics/metrics.h"
#include "output/exr_write.h"
#include "scene/scene.h"

/* >>metrics.csv */

typedef struct row {
    int frame, ring;
    char mode[32];
    double pixels, ref_coverage, v[CHECK_TIME]; /* v[m] for the metrics of the CSV (CHECK_PIXEL.. unused) */
} row;

typedef struct rows {
    row *v;
    int n;
} rows;

/* The metrics.csv column that check metric m (< CHECK_PIXEL) judges: the one of its name. How it is
 * judged comes from the column's flags (METRICS_CSV_COLUMNS, metrics/metrics.h). */
static metrics_column csv_column(int m)
{
    return metrics_column_of(check_metric_name((check_metric)m));
}

/* The columns read_rows reads: these, then the judged metrics' (F_FIXED + m). */
enum { F_FRAME, F_MODE, F_RING, F_PIXELS, F_REFCOV, F_FIXED };

static const char *read_name(int i)
{
    static const metrics_column fixed[F_FIXED] = {METRICS_COL_FRAME, METRICS_COL_MODE, METRICS_COL_RING,
                                                  METRICS_COL_PIXELS, METRICS_COL_REF_COVERAGE};
    return metrics_column_name(i < F_FIXED ? fixed[i] : csv_column(i - F_FIXED));
}

/* The index of `name` among the comma-separated columns of `header`, or -1. */
static int column(const char *header, const char *name)
{
    int i = 0;
    size_t l = strlen(name);
    for (const char *c = header; c; c = strchr(c, ',') ? strchr(c, ',') + 1 : NULL, i++)
        if (!strncmp(c, name, l) && (c[l] == ',' || c[l] == '\n' || c[l] == '\r' || c[l] == '\0'))
            return i;
    return -1;
}

static fs_status read_rows(const char *dir, rows *out)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/metrics.csv", dir);
    char *text = NULL;
    size_t size = 0;
    fs_status st = file_read_all(path, (size_t)1 << 30, "the metrics of a compare run", FS_ERR_IO, &text, &size);
    if (st != FS_OK)
        return st;
    int col[F_FIXED + CHECK_PIXEL], ncol = 0;
    for (int i = 0; i < F_FIXED + CHECK_PIXEL; i++) {
        col[i] = column(text, read_name(i));
        if (col[i] < 0) {
            log_error("%s: line 1: no column '%s' (not a metrics.csv of fovsim compare)", path,
                      read_name(i));
            free(text);
            return FS_ERR_IO;
        }
        ncol = col[i] + 1 > ncol ? col[i] + 1 : ncol;
    }
    int cap = 0, line = 1;
    out->v = NULL;
    out->n = 0;
    for (char *p = strchr(text, '\n'); p && p[1] && st == FS_OK; p = strchr(p + 1, '\n')) {
        line++;
        if (!FS_GROW_INT(out->v, cap, out->n + 1)) {
            st = FS_ERR_NOMEM;
            break;
        }
        row *r = &out->v[out->n];
        memset(r, 0, sizeof *r);
        char *f = p + 1, *end;
        const char *bad = NULL; /* the first column that is not what it should be */
        int got = 0;
        for (int c = 0; c < ncol && f && !bad; c++, got++) {
            size_t len = strcspn(f, ",\n");
            for (int i = 0; i < F_FIXED + CHECK_PIXEL; i++) {
                if (col[i] != c)
                    continue;
                const char *name = read_name(i);
                if (i == F_MODE) {
                    snprintf(r->mode, sizeof r->mode, "%.*s", (int)len, f);
                    bad = len && len < sizeof r->mode ? NULL : name;
                    continue;
                }
                double x = strtod(f, &end);
                if (end != f + len || len == 0 || !isfinite(x) ||
                    (i == F_FRAME && (x < 0 || x > MAX_FRAMES || x != (int)x)) ||
                    (i == F_RING && (x < -1 || x >= MAX_FOV_RINGS || x != (int)x)))
                    bad = name;
                else if (i == F_FRAME || i == F_RING)
                    *(i == F_FRAME ? &r->frame : &r->ring) = (int)x;
                else if (i == F_PIXELS || i == F_REFCOV)
                    *(i == F_PIXELS ? &r->pixels : &r->ref_coverage) = x;
                else
                    r->v[i - F_FIXED] = x;
            }
            f = f[len] == ',' ? f + len + 1 : NULL;
        }
        if (bad || got < ncol) {
            if (bad)
                log_error("%s:%d: column %s: expected %s", path, line, bad,
                          !strcmp(bad, "mode") ? "an alpha mode's name" : "a number as fovsim compare writes it");
            else
                log_error("%s:%d: fewer columns than the header (not a row of fovsim compare's metrics)", path, line);
            st = FS_ERR_IO;
        }
        out->n++;
    }
    if (st == FS_OK && out->n == 0) {
        log_error("%s: no rows (an interrupted compare?)", path);
        st = FS_ERR_IO;
    }
    free(text);
    return st;
}

static const row *find_row(const rows *rs, int hint, const row *key)
{
    if (hint < rs->n && rs->v[hint].frame == key->frame && rs->v[hint].ring == key->ring &&
        !strcmp(rs->v[hint].mode, key->mode))
        return &rs->v[hint];
    for (int i = 0; i < rs->n; i++)
        if (rs->v[i].frame == key->frame && rs->v[i].ring == key->ring && !strcmp(rs->v[i].mode, key->mode))
            return &rs->v[i];
    return NULL;
}

/* >>cases and failures */

static int frame_index(const judge *j, int frame)
{
    for (int i = 0; i < j->nframes; i++)
        if (j->frames[i] == frame)
            return i;
    return -1;
}

static int image_index(const judge *j, const char *image)
{
    for (int i = 0; i < j->nimages; i++)
        if (!strcmp(j->images[i], image))
            return i;
    return -1;
}

static bool *case_of(judge *j, int frame, const char *image)
{
    int fi = frame < 0 ? -1 : frame_index(j, frame), ii = image_index(j, image);
    if (fi < 0 || ii < 0)
        return &j->case_failed[j->nframes * j->nimages];
    return &j->case_failed[fi * j->nimages + ii];
}

static fs_status add_failure(judge *j, const failure *f)
{
    if (!FS_GROW_INT(j->f, j->capf, j->nf + 1))
        return FS_ERR_NOMEM;
    j->f[j->nf++] = *f;
    if (f->frame >= 0 && !f->image[0]) /* the whole frame's: every image's case */
        for (int i = 0; i < j->nimages; i++)
            *case_of(j, f->frame, j->images[i]) = true;
    else
        *case_of(j, f->frame, f->image) = true;
    return FS_OK;
}

static fs_status structural(judge *j, int frame, const char *image, int ring, const char *fmt, const char *what)
{
    failure f = {.frame = frame, .ring = ring, .metric = CHECK_METRIC_COUNT};
    snprintf(f.image, sizeof f.image, "%s", image);
    snprintf(f.note, sizeof f.note, fmt, what);
    j->v->values++;
    j->v->failed_values++;
    return add_failure(j, &f);
}

/* Judges one value: `change` is what the tolerance bounds (|d|, d or the value itself). */
static fs_status judge_value(judge *j, int frame, const char *image, int ring, check_metric m, double base, double now,
                             double change)
{
    double tol = check_tol_get(j->d->tols, m, ring);
    if (isinf(tol))
        return FS_OK;
    j->v->values++;
    if (!j->have_worst[m] || change > j->worst[m]) {
        j->worst[m] = change;
        j->worst_tol[m] = tol;
        j->have_worst[m] = true;
    }
    if (change <= tol)
        return FS_OK;
    j->v->failed_values++;
    failure f = {.frame = frame, .ring = ring, .metric = m, .base = base, .now = now, .tol = tol};
    snprintf(f.image, sizeof f.image, "%s", image);
    return add_failure(j, &f);
}

/* >>metrics */

static fs_status judge_rows(judge *j, const rows *base, const rows *now)
{
    fs_status st = FS_OK;
    for (int i = 0; i < base->n && st == FS_OK; i++) {
        const row *b = &base->v[i], *n = find_row(now, i, b);
        if (!n) {
            st = structural(j, b->frame, b->mode, b->ring, "%s", "the baseline's row is missing in this run");
            continue;
        }
        if (b->pixels != n->pixels) {
            st = structural(j, b->frame, b->mode, b->ring, "%s", "the ring holds another number of pixels");
            continue;
        }
        if (b->pixels == 0) /* a ring off screen for this gaze: nothing measured */
            continue;
        /* The coverage ratio is judged only where both runs' reference holds enough coverage for
         * a ratio: compare's own rule (metrics.h METRICS_MIN_REF_TEXELS; the pixel checks still see
         * the rest). metrics.csv writes -1 where its run's reference holds less. */
        bool cov = metrics_coverage_ratio_rests(fmin(b->ref_coverage, n->ref_coverage) * b->pixels,
                                                b->ring >= 0 ? j->block[b->ring] : 1);
        for (int m = 0; m < CHECK_PIXEL && st == FS_OK; m++) {
            double x = b->v[m], y = n->v[m];
            unsigned flags = metrics_column_flags(csv_column(m));
            if ((flags & METRICS_COLF_RESTS) && !cov)
                continue;
            if ((flags & METRICS_COLF_UNMEASURED) && (x < 0.0 || y < 0.0)) /* e.g. a first frame, after a cut */
                continue;
            st = judge_value(j, b->frame, b->mode, b->ring, (check_metric)m, x, y,
                             (flags & METRICS_COLF_EITHER_WAY) ? fabs(y - x) : y - x);
        }
    }
    for (int i = 0; i < now->n && st == FS_OK; i++)
        if (!find_row(base, i, &now->v[i]))
            st = structural(j, now->v[i].frame, now->v[i].mode, now->v[i].ring, "%s",
                            "this run has a row the baseline lacks");
    return st;
}

/* summary.json of a folder (cJSON tree; NULL with a message on failure). */
static cJSON *read_summary(const char *dir, fs_status *st)
{
    char path[1300];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    char *text = NULL;
    size_t size = 0;
    *st = file_read_all(path, (size_t)1 << 26, "the summary of a compare run", FS_ERR_IO, &text, &size);
    if (*st != FS_OK)
        return NULL;
    cJSON *root = cJSON_Parse(text);
    free(text);
    if (!cJSON_IsObject(root) || !cJSON_IsString(cJSON_GetObjectItemCaseSensitive(root, "rings")) ||
        !cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(root, "modes"))) {
        log_error("%s: not a summary.json of fovsim compare (expected an object with \"rings\" and \"modes\")", path);
        cJSON_Delete(root);
        *st = FS_ERR_IO;
        return NULL;
    }
    return root;
}

static double mode_time(const cJSON *summary, const char *mode)
{
    const cJSON *m;
    cJSON_ArrayForEach(m, cJSON_GetObjectItemCaseSensitive(summary, "modes"))
    {
        const cJSON *name = cJSON_GetObjectItemCaseSensitive(m, "mode"),
                    *ms = cJSON_GetObjectItemCaseSensitive(m, "frame_ms_median");
        if (cJSON_IsString(name) && !strcmp(name->valuestring, mode) && cJSON_IsNumber(ms))
            return ms->valuedouble;
    }
    return NAN;
}

/* Display pixels per ring texel of each ring of the layout text "OUTER:SCALE:BIAS,..." (SCALE 1 or
 * 1/N; "off" or anything else: 1). */
static void ring_blocks(const char *layout, int *block)
{
    for (int k = 0; k < MAX_FOV_RINGS; k++)
        block[k] = 1;
    const char *p = layout;
    for (int k = 0; k < MAX_FOV_RINGS && p && *p; k++) {
        const char *c = strchr(p, ':'), *comma = strchr(p, ',');
        if (!c || (comma && comma < c))
            break;
        if (!strncmp(c + 1, "1/", 2))
            block[k] = atoi(c + 3) >= 1 && atoi(c + 3) <= 1 << MAX_FOV_SCALE_LOG2 ? atoi(c + 3) : 1;
        p = comma ? comma + 1 : NULL;
    }
}

/* >>pixels */

static const char *const k_channels[5] = {"R", "G", "B", "A", "coverage"};

static const float *plane(const exr_image *img, const char *image, const char *ch)
{
    char name[96];
    snprintf(name, sizeof name, "%s.%s", image, ch);
    return exr_image_channel(img, name);
}

/* Writes NEXT/diff.<frame>.exr: R, G, B the largest |difference| over images and channels (grey,
 * white = 1), A = 1, <image>.<channel> each |difference|, ring.id. */
static fs_status write_diff(const judge *j, int frame, const exr_image *b, const exr_image *n, const float *ring_id)
{
    int w = b->width, h = b->height;
    size_t np = (size_t)w * (size_t)h;
    exr_image img;
    if (!exr_image_init(&img, w, h))
        return FS_ERR_NOMEM;
    bool ok = true;
    float *grey[4];
    for (int c = 0; c < 4; c++)
        ok = ok && (grey[c] = exr_image_add_channel(&img, k_channels[c])) != NULL;
    for (int i = 0; i < j->nimages && ok; i++)
        for (int c = 0; c < 5 && ok; c++) {
            const float *x = plane(b, j->images[i], k_channels[c]), *y = plane(n, j->images[i], k_channels[c]);
            char name[96];
            snprintf(name, sizeof name, "%s.%s", j->images[i], k_channels[c]);
            float *o = x && y ? exr_image_add_channel(&img, name) : NULL;
            ok = !x || !y || o;
            for (size_t p = 0; o && p < np; p++) {
                o[p] = fabsf(y[p] - x[p]);
                grey[0][p] = fmaxf(grey[0][p], o[p]);
            }
        }
    float *r = ok ? exr_image_add_channel(&img, "ring.id") : NULL;
    ok = ok && r;
    for (size_t p = 0; ok && p < np; p++) {
        grey[1][p] = grey[2][p] = grey[0][p];
        grey[3][p] = 1.0f;
        r[p] = ring_id[p];
    }
    char path[1300];
    snprintf(path, sizeof path, "%s/diff.%04d.exr", j->d->next, frame);
    exr_image_set_string(&img, "fovsim:baseline", j->d->baseline);
    exr_image_set_int(&img, "fovsim:frame", frame);
    exr_image_set_string(&img, "fovsim:channels", "|this run - baseline| per <image>.<channel>; RGB: the largest of "
                         "them (white = 1); ring.id: measurement ring");
    fs_status st = ok ? exr_write_file(path, &img, EXR_COMPRESS_ZIP) : FS_ERR_NOMEM;
    exr_image_free(&img);
    return st;
}

static fs_status judge_frame(judge *j, int frame)
{
    char bp[1300], np_[1300];
    snprintf(bp, sizeof bp, "%s/compare.%04d.exr", j->d->baseline, frame);
    snprintf(np_, sizeof np_, "%s/compare.%04d.exr", j->d->next, frame);
    exr_image b = {0}, n = {0};
    if (access(np_, F_OK) != 0) /* fewer frames now (a shorter camera path): a difference, not an error */
        return structural(j, frame, "", -1, "%s", "this run has no such frame");
    fs_status st = exr_read_part(bp, 1, &b);
    if (st == FS_OK)
        st = exr_read_part(np_, 1, &n);
    const float *rid = st == FS_OK ? exr_image_channel(&b, "ring.id") : NULL;
    if (st == FS_OK && !rid) {
        log_error("%s: part 'layers' has no channel ring.id (not a frame of fovsim compare)", bp);
        st = FS_ERR_IO;
    }
    size_t np = st == FS_OK ? (size_t)b.width * (size_t)b.height : 0;
    int *region = st == FS_OK ? malloc(sizeof(int) * np) : NULL;
    if (st == FS_OK && !region)
        st = FS_ERR_NOMEM;
    int nr = 1;
    for (size_t p = 0; p < np; p++) {
        region[p] = rid[p] >= 0.0f && rid[p] < MAX_FOV_RINGS ? (int)rid[p] : 0;
        nr = region[p] + 1 > nr ? region[p] + 1 : nr;
    }
    if (st == FS_OK && (n.width != b.width || n.height != b.height)) {
        char what[64];
        snprintf(what, sizeof what, "%dx%d, the baseline's %dx%d", n.width, n.height, b.width, b.height);
        st = structural(j, frame, "", -1, "frame size %s", what);
        np = 0; /* nothing more to compare */
    }
    for (int i = 0; i < j->nimages && np && st == FS_OK; i++) {
        const char *im = j->images[i];
        if (!plane(&b, im, "R"))
            continue; /* an image the baseline frame lacks: its rows in metrics.csv say so */
        image_diff all = {0};
        for (int k = 0; k < nr && st == FS_OK; k++) {
            image_diff dk = {0};
            for (int c = 0; c < 5 && st == FS_OK; c++) {
                const float *x = plane(&b, im, k_channels[c]), *y = plane(&n, im, k_channels[c]);
                if (!x || !y) {
                    char what[96];
                    snprintf(what, sizeof what, "%s.%s", im, k_channels[c]);
                    st = structural(j, frame, im, -1, x ? "channel %s is missing in this run" :
                                    "channel %s is missing in the baseline", what);
                    np = 0;
                    break;
                }
                image_diff_add(&dk, y, x, b.width, b.height, 2 * j->block[k], region, k);
            }
            if (!np || dk.count == 0)
                continue;
            all.sq_sum += dk.sq_sum;
            all.count += dk.count;
            all.max_block = fmax(all.max_block, dk.max_block);
            st = judge_value(j, frame, im, k, CHECK_PIXEL, 0.0, dk.max_block, dk.max_block);
            if (st == FS_OK)
                st = judge_value(j, frame, im, k, CHECK_PIXEL_RMSE, 0.0, image_diff_rmse(&dk), image_diff_rmse(&dk));
        }
        if (np && st == FS_OK)
            st = judge_value(j, frame, im, -1, CHECK_PIXEL, 0.0, all.max_block, all.max_block);
        if (np && st == FS_OK)
            st = judge_value(j, frame, im, -1, CHECK_PIXEL_RMSE, 0.0, image_diff_rmse(&all), image_diff_rmse(&all));
    }
    bool failed = false;
    int fi = frame_index(j, frame);
    for (int i = 0; i < j->nimages && fi >= 0; i++)
        failed = failed || j->case_failed[fi * j->nimages + i];
    if (st == FS_OK && failed && b.width == n.width && b.height == n.height && (st = write_diff(j, frame, &b, &n, rid)) == FS_OK)
        j->diffs[j->ndiffs++] = frame;
    free(region);
    exr_image_free(&b);
    exr_image_free(&n);
    return st;
}

/* >>the whole comparison */

fs_status check_baseline_validate(const char *dir)
{
    rows base = {0};
    fs_status st = read_rows(dir, &base);
    cJSON *summary = st == FS_OK ? read_summary(dir, &st) : NULL;
    for (int i = 0; i < base.n && st == FS_OK; i++) {
        if (i && base.v[i].frame == base.v[i - 1].frame)
            continue;
        char path[1300];
        snprintf(path, sizeof path, "%s/compare.%04d.exr", dir, base.v[i].frame);
        exr_image img = {0};
        st = exr_read_part(path, 1, &img);
        if (st == FS_OK && !exr_image_channel(&img, "ring.id")) {
            log_error("%s: part 'layers' has no channel ring.id (not a frame of fovsim compare)", path);
            st = FS_ERR_IO;
        }
        exr_image_free(&img);
    }
    cJSON_Delete(summary);
    free(base.v);
    return st;
}

fs_status check_judge(const check_judge_desc *d, check_verdict *v)
{
    memset(v, 0, sizeof *v);
    judge j = {.d = d, .v = v};
    rows base = {0}, now = {0};
    fs_status st = read_rows(d->baseline, &base);
    if (st == FS_OK)
        st = read_rows(d->next, &now);
    cJSON *sb = st == FS_OK ? read_summary(d->baseline, &st) : NULL;
    cJSON *sn = st == FS_OK ? read_summary(d->next, &st) : NULL;
    if (st == FS_OK && (!(j.frames = malloc(sizeof(int) * (size_t)base.n)) ||
                        !(j.diffs = malloc(sizeof(int) * (size_t)base.n))))
        st = FS_ERR_NOMEM;
    for (int i = 0; i < base.n && st == FS_OK; i++) {
        if (frame_index(&j, base.v[i].frame) < 0)
            j.frames[j.nframes++] = base.v[i].frame;
        if (image_index(&j, base.v[i].mode) < 0 && j.nimages < ALPHA_MODE_COUNT)
            snprintf(j.images[j.nimages++], sizeof j.images[0], "%s", base.v[i].mode);
    }
    if (st == FS_OK) {
        qsort(j.frames, (size_t)j.nframes, sizeof *j.frames, check_cmp_int);
        snprintf(j.images[j.nimages++], sizeof j.images[0], "reference");
        ring_blocks(cJSON_GetObjectItemCaseSensitive(sb, "rings")->valuestring, j.block);
        v->cases = j.nframes * j.nimages + 1;
        if (!(j.case_failed = calloc((size_t)v->cases, sizeof(bool))))
            st = FS_ERR_NOMEM;
    }
    if (st == FS_OK)
        st = judge_rows(&j, &base, &now);
    for (int i = 0; i + 1 < j.nimages && st == FS_OK && !isinf(check_tol_get(d->tols, CHECK_TIME, -1)); i++) {
        double tb = mode_time(sb, j.images[i]), tn = mode_time(sn, j.images[i]);
        if (tb > 0.0 && tn > 0.0)
            st = judge_value(&j, -1, j.images[i], -1, CHECK_TIME, tb, tn, tn / tb);
    }
    for (int i = 0; i < j.nframes && st == FS_OK; i++)
        st = judge_frame(&j, j.frames[i]);
    if (st == FS_OK) {
        for (int c = 0; c < v->cases; c++)
            v->failed_cases += j.case_failed[c];
        check_report_print(&j);
        if (d->junit)
            st = check_report_junit(&j);
    }
    if (st == FS_OK && !(v->failures_json = check_report_failures_json(&j)))
        st = FS_ERR_NOMEM;
    cJSON_Delete(sb);
    cJSON_Delete(sn);
    free(base.v);
    free(now.v);
    free(j.frames);
    free(j.diffs);
    free(j.case_failed);
    free(j.f);
    return st;
}
