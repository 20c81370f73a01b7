/* gaze_eyenav.c: the EyeNavGS CSV reader (Meta Quest Pro head and both eyes, Ding et al. 2025):
 * rows alternate left, right eye; each pair is one frame. It gives a pose_trace (pose_trace.h:
 * per eye position, head and gaze orientation, FOV) and, for gaze_load, the eye-in-head gaze as a
 * monocular gaze_trace of per-sample directions. Also scene_setting.csv, the recording's scene
 * tilt, scale and initial position.
 *
 * Format, conventions, the right row's later stamp, the no-gaze case: docs/gaze-formats.md
 * ("EyeNavGS").
 */
#include "gaze/gaze_read.h"
#include "gaze/pose_trace.h"

#include "core/config.h"
#include "core/file_read.h"
#include "core/grow.h"
#include "core/stats.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

/* >>columns */

enum {
    C_VIEW, C_FOV1, C_FOV2, C_FOV3, C_FOV4, C_PX, C_PY, C_PZ, C_QX, C_QY, C_QZ, C_QW,
    C_GPX, C_GPY, C_GPZ, C_GQX, C_GQY, C_GQZ, C_GQW, C_TS, NCOL
};

static const char *const k_cols[NCOL] = {
    "ViewIndex", "FOV1", "FOV2", "FOV3", "FOV4", "PositionX", "PositionY", "PositionZ",
    "QuaternionX", "QuaternionY", "QuaternionZ", "QuaternionW", "GazePosX", "GazePosY", "GazePosZ",
    "GazeQX", "GazeQY", "GazeQZ", "GazeQW", "Timestamp"};

#define QUAT_NORM_TOL 0.05  /* the files round to 3 decimals: norms 0.9992..1.0008 */
#define MAX_POSITION 1e6
#define MAX_TIMESTAMP_MS 1e15 /* 30,000 years: keeps every difference of times finite */

bool gaze_eyenav_header(span header)
{
    int second;
    return gaze_csv_header_col(header, "ViewIndex", &second) != -1 &&
           gaze_csv_header_col(header, "GazeQW", &second) != -1 &&
           gaze_csv_header_col(header, "QuaternionW", &second) != -1 &&
           gaze_csv_header_col(header, "Timestamp", &second) != -1;
}

typedef struct en_reader {
    pctx *c;
    int idx[NCOL];  /* column of each field */
    int ncols;      /* columns in the header */
    pose_trace *out;
    int cap[2];
    double *delays; /* ms, right row after left row, per frame */
    int delay_cap;
    double left_ts, last_ts, prev_frame_ts;
    long left_line, last_line, prev_frame_line;
    bool have_left;
} en_reader;

static fs_status find_columns(en_reader *r, span header, long line)
{
    char g[64];
    r->ncols = 0;
    for (const char *p = header.p, *end = header.p + header.n;; p++) {
        span f;
        if (!gaze_csv_field(&p, end, &f))
            return gaze_fail(r->c, line, r->ncols + 1, "expected a closing '\"' in the header, got the end of the line");
        r->ncols++;
        if (p >= end)
            break;
    }
    for (int k = 0; k < NCOL; k++) {
        int second = -1;
        r->idx[k] = gaze_csv_header_col(header, k_cols[k], &second);
        if (r->idx[k] == -2)
            return gaze_fail(r->c, line, second + 1, "expected one column named '%s', got a second one", k_cols[k]);
        if (r->idx[k] < 0)
            return gaze_fail(r->c, line, 1, "expected an EyeNavGS header with a column '%s', got %s", k_cols[k],
                             gaze_snip(g, sizeof g, header.p, header.n));
    }
    return FS_OK;
}

/* >>rows */

/* The row's fields as numbers, by column name. */
static fs_status row_values(en_reader *r, long line, span text, double v[NCOL])
{
    span f[NCOL] = {{0}};
    int k = 0;
    for (const char *p = text.p, *end = text.p + text.n;; p++) {
        span fld;
        if (!gaze_csv_field(&p, end, &fld))
            return gaze_fail(r->c, line, k + 1, "expected a closing '\"' in column %d, got the end of the line", k + 1);
        for (int j = 0; j < NCOL; j++)
            if (r->idx[j] == k)
                f[j] = fld;
        if (k < (1 << 20))
            k++;
        if (p >= end)
            break;
    }
    if (k != r->ncols)
        return gaze_fail(r->c, line, (k < r->ncols ? k : r->ncols) + 1, "expected %d columns, got %d", r->ncols, k);
    for (int j = 0; j < NCOL; j++) {
        char g[64];
        num_result nr = gaze_parse_num(f[j], &v[j]);
        if (nr != NUM_OK)
            return gaze_fail(r->c, line, r->idx[j] + 1, "expected a %snumber for column '%s', got %s",
                             nr == NUM_NONFINITE ? "finite " : "", k_cols[j], gaze_snip(g, sizeof g, f[j].p, f[j].n));
    }
    return FS_OK;
}

/* A unit quaternion at v[at..at+4) (norm within QUAT_NORM_TOL), renormalised. */
static fs_status row_quat(en_reader *r, long line, const double *v, int at, pose_quat *q)
{
    pose_quat raw = {v[at], v[at + 1], v[at + 2], v[at + 3]};
    double n = sqrt(raw.x * raw.x + raw.y * raw.y + raw.z * raw.z + raw.w * raw.w);
    if (!(fabs(n - 1) <= QUAT_NORM_TOL))
        return gaze_fail(r->c, line, r->idx[at] + 1, "expected a unit quaternion in columns '%s'..'%s' (norm 1 +- %g), "
                         "got norm %.6g", k_cols[at], k_cols[at + 3], QUAT_NORM_TOL, n);
    *q = pose_qnorm(raw);
    return FS_OK;
}

static fs_status row_checks(en_reader *r, long line, const double *v)
{
    const double h = 0.5 * 3.14159265358979323846;
    if (v[C_VIEW] != 0 && v[C_VIEW] != 1)
        return gaze_fail(r->c, line, r->idx[C_VIEW] + 1, "expected ViewIndex 0 (left eye) or 1 (right eye), got %.15g",
                         v[C_VIEW]);
    bool fov_ok = v[C_FOV1] < v[C_FOV2] && v[C_FOV3] < v[C_FOV4];
    for (int j = C_FOV1; j <= C_FOV4; j++)
        fov_ok = fov_ok && fabs(v[j]) < h;
    if (!fov_ok)
        return gaze_fail(r->c, line, r->idx[C_FOV1] + 1, "expected field-of-view angles in radians, FOV1 < FOV2 and "
                         "FOV3 < FOV4, each within +-pi/2 (XrFovf left, right, down, up), got %g, %g, %g, %g",
                         v[C_FOV1], v[C_FOV2], v[C_FOV3], v[C_FOV4]);
    static const int pos_cols[] = {C_PX, C_PY, C_PZ, C_GPX, C_GPY, C_GPZ};
    for (size_t k = 0; k < sizeof pos_cols / sizeof pos_cols[0]; k++) {
        int j = pos_cols[k];
        if (fabs(v[j]) > MAX_POSITION)
            return gaze_fail(r->c, line, r->idx[j] + 1, "expected a position within +-%g for column '%s', got %.15g",
                             MAX_POSITION, k_cols[j], v[j]);
    }
    if (fabs(v[C_TS]) > MAX_TIMESTAMP_MS)
        return gaze_fail(r->c, line, r->idx[C_TS] + 1, "expected a Timestamp within +-%g ms, got %.15g",
                         MAX_TIMESTAMP_MS, v[C_TS]);
    if (v[C_TS] < r->last_ts)
        return gaze_fail(r->c, line, r->idx[C_TS] + 1, "expected Timestamp >= %.15g ms (line %ld), got %.15g ms (time "
                         "goes backwards)", r->last_ts, r->last_line, v[C_TS]);
    return FS_OK;
}

/* The tracker gave nothing: the writer substitutes GazeQ identity and GazePos 0. */
static bool gaze_missing(const double *v)
{
    return v[C_GQX] == 0 && v[C_GQY] == 0 && v[C_GQZ] == 0 && v[C_GQW] == 1 && v[C_GPX] == 0 && v[C_GPY] == 0 &&
           v[C_GPZ] == 0;
}

static fs_status push_sample(en_reader *r, int eye, long line, const double *v, double ts)
{
    pose_trace *o = r->out;
    if (!FS_GROW_INT(o->eye[eye], r->cap[eye], o->count + 1))
        return gaze_no_memory(r->c);
    pose_sample *s = &o->eye[eye][o->count];
    *s = (pose_sample){.t = ts, .pos = {v[C_PX], v[C_PY], v[C_PZ]}, .gaze_valid = !gaze_missing(v), .line = line};
    for (int k = 0; k < 4; k++)
        s->fov[k] = (float)v[C_FOV1 + k];
    fs_status st = row_quat(r, line, v, C_QX, &s->head);
    if (st == FS_OK)
        st = row_quat(r, line, v, C_GQX, &s->gaze);
    return st;
}

/* A right row closes the frame its left row opened; the frame's time is the left row's. */
static fs_status close_frame(en_reader *r, long line, const double *v)
{
    if (r->out->count > 0 && !(r->left_ts > r->prev_frame_ts))
        return gaze_fail(r->c, r->left_line, r->idx[C_TS] + 1, "expected Timestamp > %.15g ms (the previous frame, "
                         "line %ld), got %.15g ms", r->prev_frame_ts, r->prev_frame_line, r->left_ts);
    if (!FS_GROW_INT(r->delays, r->delay_cap, r->out->count + 1))
        return gaze_no_memory(r->c);
    r->delays[r->out->count] = v[C_TS] - r->left_ts;
    fs_status s = push_sample(r, POSE_RIGHT, line, v, r->left_ts);
    if (s != FS_OK)
        return s;
    r->out->count++;
    r->prev_frame_ts = r->left_ts;
    r->prev_frame_line = r->left_line;
    r->have_left = false;
    return FS_OK;
}

static fs_status one_row(en_reader *r, long line, span text)
{
    double v[NCOL];
    fs_status s = row_values(r, line, text, v);
    if (s == FS_OK)
        s = row_checks(r, line, v);
    if (s != FS_OK)
        return s;
    r->last_ts = v[C_TS];
    r->last_line = line;
    if (v[C_VIEW] == 0) {
        if (r->have_left)
            return gaze_fail(r->c, line, r->idx[C_VIEW] + 1, "expected ViewIndex 1 (the right eye of the frame at "
                             "line %ld), got 0", r->left_line);
        r->have_left = true;
        r->left_ts = v[C_TS];
        r->left_line = line;
        return push_sample(r, POSE_LEFT, line, v, v[C_TS]);
    }
    if (!r->have_left)
        return gaze_fail(r->c, line, r->idx[C_VIEW] + 1, "expected ViewIndex 0 (a frame starts with its left-eye "
                         "row), got 1");
    return close_frame(r, line, v);
}

/* >>finish */

/* Head signs continuous per eye (the first with w >= 0), each gaze in its head's hemisphere. */
static void make_signs_continuous(pose_sample *s, int n)
{
    for (int i = 0; i < n; i++) {
        pose_quat ref = i ? s[i - 1].head : (pose_quat){0, 0, 0, 1};
        pose_quat *h = &s[i].head, *g = &s[i].gaze;
        if (h->x * ref.x + h->y * ref.y + h->z * ref.z + h->w * ref.w < 0)
            *h = (pose_quat){-h->x, -h->y, -h->z, -h->w};
        if (g->x * h->x + g->y * h->y + g->z * h->z + g->w * h->w < 0)
            *g = (pose_quat){-g->x, -g->y, -g->z, -g->w};
    }
}

/* Samples without gaze hold the eye-in-head rotation of the last valid one before (the first valid
 * one when the trace starts without), so pose_at stays one lookup. Returns the valid count. */
static int fill_held_gaze(pose_sample *s, int n)
{
    int first = 0, valid = 0;
    while (first < n && !s[first].gaze_valid)
        first++;
    pose_quat rel = first < n ? pose_eye_in_head(s[first].head, s[first].gaze) : (pose_quat){0, 0, 0, 1};
    for (int i = 0; i < n; i++) {
        if (s[i].gaze_valid) {
            rel = pose_eye_in_head(s[i].head, s[i].gaze);
            valid++;
        } else {
            s[i].gaze = pose_qnorm(pose_qmul(s[i].head, rel));
        }
    }
    return valid;
}

static void finish(en_reader *r, bool warn_no_gaze)
{
    pose_trace *o = r->out;
    const double t0 = o->eye[POSE_LEFT][0].t;
    for (int e = 0; e < 2; e++) {
        for (int i = 0; i < o->count; i++)
            o->eye[e][i].t = (o->eye[e][i].t - t0) * 1e-3;
        make_signs_continuous(o->eye[e], o->count);
        o->gaze_valid_count[e] = fill_held_gaze(o->eye[e], o->count);
    }
    o->time_offset = t0 * 1e-3;
    o->duration = o->eye[POSE_LEFT][o->count - 1].t;
    o->has_gaze = o->gaze_valid_count[0] + o->gaze_valid_count[1] > 0;
    qsort(r->delays, (size_t)o->count, sizeof *r->delays, stats_cmp_double);
    o->r_delay_median = stats_quantile(r->delays, o->count, 0.5) * 1e-3;
    o->r_delay_max = r->delays[o->count - 1] * 1e-3;
    if (!o->has_gaze && warn_no_gaze)
        log_warn("GAZE: [%s] no eye tracking in this recording (GazeQ identity and GazePos 0 on every row): head pose "
                 "only, no gaze to replay", o->path);
}

/* >>trace */

/* The recording's scene: `user<ID>_<scene>.csv` -> `<scene>` (false without a '_'). */
static bool scene_name_of(const char *path, char *buf, size_t cap)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *us = strchr(base, '_');
    if (!us || !us[1])
        return false;
    size_t n = strlen(us + 1);
    if (n > 4 && gaze_ieq(us + 1 + n - 4, 4, ".csv"))
        n -= 4;
    if (n == 0 || n >= cap)
        return false;
    memcpy(buf, us + 1, n);
    buf[n] = '\0';
    return true;
}

static fs_status read_trace(pctx *c, const pose_load_desc *desc, pose_trace *out, bool warn_no_gaze)
{
    en_reader r = {.c = c, .out = out, .last_ts = -INFINITY};
    line_it it = {c->text, c->text + c->size, 0};
    span header = {0};
    if (!gaze_csv_header(&it, &header))
        return gaze_fail(c, 1, 1, "expected an EyeNavGS header (ViewIndex,FOV1,...,Timestamp), got an empty file");
    fs_status s = find_columns(&r, header, it.no);
    long header_line = it.no;
    for (span line = {0}; s == FS_OK && gaze_next_line(&it, &line);)
        if (!gaze_is_blank(line))
            s = one_row(&r, it.no, line);
    if (s == FS_OK && r.have_left)
        s = gaze_fail(c, r.left_line, 1, "expected the right-eye row (ViewIndex 1) after this left-eye row, got the end "
                      "of the file");
    if (s == FS_OK && out->count == 0)
        s = gaze_fail(c, header_line + 1, 1, "expected a row after the header, got none");
    if (s == FS_OK) {
        finish(&r, warn_no_gaze);
        if (desc && desc->scene) {
            out->scene = *desc->scene;
            out->has_scene = true;
        }
    }
    free(r.delays);
    return s;
}

static void trace_reset(pose_trace *t, const char *name)
{
    memset(t, 0, sizeof *t);
    snprintf(t->path, sizeof t->path, "%s", name ? name : "<memory>");
    t->scene = (pose_scene){.tilt = {0, 0, 0, 1}, .scale = 1};
}

static fs_status parse_into(const char *text, long size, const char *name, const pose_load_desc *desc,
                            pose_trace *out, bool warn_no_gaze)
{
    trace_reset(out, name);
    if (size < 0 || (!text && size > 0)) {
        log_error("%s: no text to parse", out->path);
        return FS_ERR_GAZE;
    }
    pctx c = {.name = out->path, .text = text ? text : "", .size = (size_t)size};
    if (c.size >= 3 && memcmp(c.text, "\xEF\xBB\xBF", 3) == 0)
        c.text += 3, c.size -= 3;
    fs_status s = read_trace(&c, desc, out, warn_no_gaze);
    if (s != FS_OK) {
        char keep[sizeof out->path];
        memcpy(keep, out->path, sizeof keep);
        pose_free(out);
        trace_reset(out, keep);
    }
    return s;
}

fs_status pose_parse(const char *text, long size, const char *name, const pose_load_desc *desc, pose_trace *out)
{
    FS_ASSERT(out);
    return parse_into(text, size, name, desc, out, true);
}

void pose_free(pose_trace *t)
{
    if (!t)
        return;
    free(t->eye[0]);
    free(t->eye[1]);
    memset(t, 0, sizeof *t);
}

/* >>load */

/* scene_setting.csv in the recording's folder, its row named by the file name; nothing (info line)
 * when either is missing. */
static fs_status scene_beside(pose_trace *t)
{
    char scene[64], setting[sizeof t->path + 32];
    const char *slash = strrchr(t->path, '/');
    int dir = slash ? (int)(slash - t->path) + 1 : 0;
    snprintf(setting, sizeof setting, "%.*sscene_setting.csv", dir, t->path);
    struct stat st;
    if (!scene_name_of(t->path, scene, sizeof scene) || stat(setting, &st) != 0) {
        log_info("GAZE: [%s] no scene settings (%s beside a user<ID>_<scene>.csv): the recording's world is used as is",
                 t->path, setting);
        return FS_OK;
    }
    char *text;
    size_t size;
    fs_status s = file_read_all(setting, 1u << 20, "EyeNavGS scene settings", FS_ERR_GAZE, &text, &size);
    if (s == FS_OK)
        s = pose_scene_find(text, size, setting, scene, &t->scene);
    free(text);
    if (s != FS_OK)
        return s;
    t->has_scene = true;
    const pose_scene *sc = &t->scene;
    log_info("GAZE: [%s] scene '%s' from %s: tilt (%g, %g, %g, %g), scale %g, initial position (%g, %g, %g)", t->path,
             sc->name, setting, sc->tilt.x, sc->tilt.y, sc->tilt.z, sc->tilt.w, sc->scale, sc->initial.x,
             sc->initial.y, sc->initial.z);
    return FS_OK;
}

fs_status pose_load(const char *path, const pose_load_desc *desc, pose_trace *out)
{
    FS_ASSERT(out);
    trace_reset(out, path);
    if (!path) {
        log_error("GAZE: no file name given");
        return FS_ERR_IO;
    }
    char *text;
    size_t size;
    fs_status s = file_read_all(path, MAX_GAZE_FILE_BYTES, "an EyeNavGS recording", FS_ERR_GAZE, &text, &size);
    if (s != FS_OK)
        return s;
    s = pose_parse(text, (long)size, path, desc, out);
    free(text);
    if (s == FS_OK && !(desc && desc->scene))
        s = scene_beside(out);
    if (s != FS_OK) {
        pose_free(out);
        trace_reset(out, path);
        return s;
    }
    log_info("GAZE: [%s] EyeNavGS, %d frames over %.2f s, right rows %.1f ms (median) after their left rows%s",
             out->path, out->count, out->duration, out->r_delay_median * 1e3, out->has_gaze ? "" : ", no gaze");
    return FS_OK;
}

/* >>gaze trace */

/* The chosen eye's (or both eyes' mean) gaze direction in the head; 0 when it has none, else the
 * eyes used (bit 0 left, bit 1 right). */
static int frame_dir(const pose_trace *t, int i, gaze_eye eye, pose_v3 *d)
{
    const pose_sample *l = &t->eye[POSE_LEFT][i], *r = &t->eye[POSE_RIGHT][i];
    int used = (eye != GAZE_EYE_RIGHT && l->gaze_valid) | (eye != GAZE_EYE_LEFT && r->gaze_valid) << 1;
    if (eye == GAZE_EYE_AVERAGE && used != 3)
        return 0;
    pose_v3 s = {0, 0, 0};
    for (int e = 0; e < 2; e++) {
        if (!(used >> e & 1))
            continue;
        pose_v3 de = pose_gaze_dir(t->eye[e][i].head, t->eye[e][i].gaze);
        s = (pose_v3){s.x + de.x, s.y + de.y, s.z + de.z};
    }
    double n = sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    *d = (pose_v3){s.x / n, s.y / n, s.z / n};
    return n > 0 && -d->z > 1e-6 ? used : 0; /* in front of the eye: the only directions a tangent holds */
}

/* Normalised coordinates of a direction in the field of view of the eyes used (both: the mean
 * angles), the eye's image with origin top-left. */
static void fov_xy(const pose_trace *t, int i, int used, double tx, double ty, double *x, double *y)
{
    const float *l = t->eye[POSE_LEFT][i].fov, *r = t->eye[POSE_RIGHT][i].fov;
    double f[4];
    for (int k = 0; k < 4; k++)
        f[k] = used == 1 ? l[k] : used == 2 ? r[k] : 0.5 * ((double)l[k] + r[k]);
    double tl = tan(f[POSE_FOV_LEFT]), tr = tan(f[POSE_FOV_RIGHT]), td = tan(f[POSE_FOV_DOWN]), tu = tan(f[POSE_FOV_UP]);
    *x = (tx - tl) / (tr - tl);
    *y = (tu - ty) / (tu - td);
}

fs_status gaze_parse_eyenav(pctx *c, gaze_trace *out)
{
    pose_trace t;
    fs_status s = parse_into(c->text, (long)c->size, c->name, NULL, &t, false);
    if (s != FS_OK)
        return s;
    if (!t.has_gaze) {
        pose_free(&t);
        return gaze_fail(c, 2, 1, "expected eye tracking in the EyeNavGS recording, got head pose only (GazeQ identity "
                         "and GazePos 0 on every row): no gaze to replay");
    }
    c->unit = 1e-3;
    c->unit_name = "ms";
    for (int i = 0; i < t.count && s == FS_OK; i++) {
        const pose_sample *l = &t.eye[POSE_LEFT][i];
        pose_v3 d = {0, 0, -1};
        int used = frame_dir(&t, i, c->desc.eye, &d);
        bool valid = used != 0;
        double tx = d.x / -d.z, ty = d.y / -d.z, x = 0.5, y = 0.5;
        if (valid)
            fov_xy(&t, i, used, tx, ty, &x, &y);
        s = gaze_push(c, l->line, 1, (t.time_offset + l->t) * 1e3, x, y, 1, valid);
        if (s == FS_OK && valid)
            gaze_set_dir(c, tx, ty);
    }
    pose_free(&t);
    const char *which = c->desc.eye == GAZE_EYE_LEFT ? "the left eye's" : c->desc.eye == GAZE_EYE_RIGHT ?
                        "the right eye's" : "both eyes' mean";
    snprintf(c->geometry, sizeof c->geometry, "EyeNavGS eye-in-head directions, %s (conj(head) * gaze, -z forward)",
             which);
    return s != FS_OK ? s : gaze_finish(c, GAZE_FORMAT_EYENAV, out);
}
