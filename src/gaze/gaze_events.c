/* gaze_events.c: fixation / saccade / smooth pursuit / lost per sample of the true gaze trace
 * (gaze_events.h; the method, its sources and its limits: docs/latency.md "Eye-movement events").
 *
 * I-VVT, the velocity-velocity threshold method of Komogortsev & Karpov 2013 ("Automated
 * classification and scoring of smooth pursuit eye movements in the presence of fixations and
 * saccades", Behav Res Methods 45:203-215): a sample at or above the saccade threshold is saccade,
 * between the two thresholds smooth pursuit, below both fixation. The velocity is measured as in
 * Olsen 2012 ("The Tobii I-VT Fixation Filter", Tobii Technology): the angle between the first and
 * the last sample of a 20 ms window centred on the sample, over the time between them. The window
 * never reaches across an invalid sample or a gap longer than Olsen's 75 ms "max gap length", so a
 * blink edge or a pause between recording blocks is never read as a movement.
 * One rule of our own against the windowed velocity's blur and noise: a run shorter than the window
 * is not an event of its own (settle_short_run). The defaults are ours, not the papers' (why: the
 * docs).
 */
#include "gaze/gaze_events.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#define DEG2RAD (3.14159265358979323846 / 180.0)
#define RAD2DEG (180.0 / 3.14159265358979323846)

/* Defaults (docs/latency.md justifies each). */
#define DEFAULT_SACCADE_DEG_S 70.0f
#define DEFAULT_PURSUIT_DEG_S 10.0f
#define DEFAULT_WINDOW_MS 20.0f
/* Consecutive valid samples further apart than this are separate runs (Olsen 2012's gap fill-in
 * limit: a longer gap is data loss, not a movement to interpolate across). */
#define MAX_GAP_S 0.075

static const char *const k_event_names[GAZE_EVENT_COUNT] = {"fixation", "saccade", "pursuit", "lost"};

const char *gaze_event_name(gaze_event e)
{
    return e >= 0 && e < GAZE_EVENT_COUNT ? k_event_names[e] : NULL;
}

gaze_event gaze_event_parse(const char *name)
{
    for (int e = 0; name && e < GAZE_EVENT_COUNT; e++)
        if (!strcmp(name, k_event_names[e]))
            return (gaze_event)e;
    return GAZE_EVENT_COUNT;
}

/* >>geometry */

typedef struct ray {
    double x, y, z;
} ray;

/* The unit gaze ray of a normalised display position: (tan theta_x, tan theta_y, 1) normalised, the
 * per-axis angles being frame_record's gaze_deg. The display is sanitised as fov_ring does. */
static ray gaze_ray(const display_desc *d, double x, double y)
{
    display_geom g = display_geom_of(d); /* from the principal point: straight ahead */
    ray r = {(x * g.w - g.cx) / g.f, (g.cy - y * g.h) / g.f, 1.0};
    double n = sqrt(r.x * r.x + r.y * r.y + 1.0);
    return (ray){r.x / n, r.y / n, r.z / n};
}

/* The angle between two rays in degrees; atan2 of |a x b| and a . b stays exact for tiny angles,
 * where acos of the dot product loses everything below ~1e-4 degrees. */
static double ray_angle_deg(ray a, ray b)
{
    double cx = a.y * b.z - a.z * b.y, cy = a.z * b.x - a.x * b.z, cz = a.x * b.y - a.y * b.x;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), a.x * b.x + a.y * b.y + a.z * b.z) * RAD2DEG;
}

/* >>desc */

static bool desc_value_ok(float v)
{
    return isfinite(v) && v >= 0.0f;
}

/* Fills the defaults in; false (and one line) for a negative or non-finite value or thresholds in
 * the wrong order. */
static bool desc_resolve(const gaze_events_desc *in, gaze_events_desc *out)
{
    gaze_events_desc d = in ? *in : (gaze_events_desc){0};
    if (!desc_value_ok(d.saccade_deg_s) || !desc_value_ok(d.pursuit_deg_s) || !desc_value_ok(d.window_ms)) {
        log_error("gaze events: expected thresholds and window >= 0 (0 = default), got saccade %g deg/s, "
                  "pursuit %g deg/s, window %g ms",
                  (double)d.saccade_deg_s, (double)d.pursuit_deg_s, (double)d.window_ms);
        return false;
    }
    d.saccade_deg_s = d.saccade_deg_s > 0.0f ? d.saccade_deg_s : DEFAULT_SACCADE_DEG_S;
    d.pursuit_deg_s = d.pursuit_deg_s > 0.0f ? d.pursuit_deg_s : DEFAULT_PURSUIT_DEG_S;
    d.window_ms = d.window_ms > 0.0f ? d.window_ms : DEFAULT_WINDOW_MS;
    if (d.pursuit_deg_s >= d.saccade_deg_s) {
        log_error("gaze events: expected the pursuit threshold below the saccade threshold, got pursuit %g "
                  "deg/s, saccade %g deg/s",
                  (double)d.pursuit_deg_s, (double)d.saccade_deg_s);
        return false;
    }
    *out = d;
    return true;
}

/* >>velocity */

/* Per sample: its ray, its run of valid samples [run_lo, run_hi], and the window [lo, hi] its
 * velocity spans (lo == hi: no velocity, fixation). */
typedef struct work {
    ray *r;
    int *run_lo, *run_hi, *lo, *hi;
    double *vel; /* deg/s; < 0 for lost samples */
} work;

static bool sample_usable(const gaze_sample *s)
{
    return s->valid && isfinite(s->x) && isfinite(s->y) && isfinite(s->t);
}

/* Splits the samples into runs of usable samples without a gap (MAX_GAP_S) or time going back. */
static void find_runs(const gaze_trace *t, work *w)
{
    int n = t->count;
    for (int i = 0; i < n;) {
        if (!sample_usable(&t->samples[i])) {
            w->run_lo[i] = w->run_hi[i] = i;
            i++;
            continue;
        }
        int b = i;
        while (b + 1 < n && sample_usable(&t->samples[b + 1]) &&
               t->samples[b + 1].t - t->samples[b].t <= MAX_GAP_S && t->samples[b + 1].t >= t->samples[b].t)
            b++;
        for (int k = i; k <= b; k++) {
            w->run_lo[k] = i;
            w->run_hi[k] = b;
        }
        i = b + 1;
    }
}

/* The windows of the samples of the run [a, b]: the samples within half a window of each, at least
 * one neighbour on each side where the run has one (a 30 Hz trace has none within 10 ms), shrinking
 * at the run's ends. Both edges only move forward: linear in the run's length for any window. */
static void run_windows(const gaze_trace *t, work *w, int a, int b, double half_s)
{
    const gaze_sample *s = t->samples;
    int lo = a, hi = a;
    for (int i = a; i <= b; i++) {
        while (s[i].t - s[lo].t > half_s)
            lo++;
        hi = hi < i ? i : hi;
        while (hi < b && s[hi + 1].t - s[i].t <= half_s)
            hi++;
        w->lo[i] = lo == i && i > a ? i - 1 : lo;
        w->hi[i] = hi == i && i < b ? i + 1 : hi;
    }
}

static void velocities(const gaze_trace *t, const display_desc *d, const gaze_events_desc *ed, work *w)
{
    for (int i = 0; i < t->count; i++) {
        const gaze_sample *s = &t->samples[i];
        bool ok = sample_usable(s);
        w->r[i] = ok ? gaze_ray(d, s->x, s->y) : (ray){0, 0, 1};
        w->vel[i] = ok ? 0.0 : -1.0;
        w->lo[i] = w->hi[i] = i;
    }
    for (int i = 0; i < t->count; i = w->run_hi[i] + 1)
        if (w->vel[i] >= 0.0)
            run_windows(t, w, i, w->run_hi[i], 0.5e-3 * ed->window_ms);
    for (int i = 0; i < t->count; i++) {
        double dt = t->samples[w->hi[i]].t - t->samples[w->lo[i]].t;
        if (w->vel[i] >= 0.0 && dt > 0.0) /* repeated times: no movement measurable, fixation */
            w->vel[i] = ray_angle_deg(w->r[w->lo[i]], w->r[w->hi[i]]) / dt;
    }
}

/* >>classify */

static gaze_event threshold_event(double v, const gaze_events_desc *ed)
{
    if (v < 0.0)
        return GAZE_EVENT_LOST;
    if (v >= ed->saccade_deg_s)
        return GAZE_EVENT_SACCADE;
    return v >= ed->pursuit_deg_s ? GAZE_EVENT_PURSUIT : GAZE_EVENT_FIXATION;
}

/* The time run [a, b] covers, up to the next sample of its run of valid samples. */
static double run_span(const gaze_trace *t, const work *w, int a, int b)
{
    int end = b < w->run_hi[b] ? b + 1 : b;
    return t->samples[end].t - t->samples[a].t;
}

/* A run [a, b] of `what` shorter than the window is noise in the windowed velocity, not an event of
 * its own: a short pursuit run joins a saccade it touches (what is left of its flank) or else is
 * fixation; a short fixation run between pursuit on both sides is pursuit. */
static void settle_short_run(const gaze_trace *t, const work *w, double window_s, unsigned char *ev, int a, int b)
{
    if (run_span(t, w, a, b) >= window_s)
        return;
    int before = a > w->run_lo[a] ? ev[a - 1] : GAZE_EVENT_LOST, after = b < w->run_hi[b] ? ev[b + 1] : GAZE_EVENT_LOST;
    gaze_event to = (gaze_event)ev[a];
    if (ev[a] == GAZE_EVENT_PURSUIT)
        to = before == GAZE_EVENT_SACCADE || after == GAZE_EVENT_SACCADE ? GAZE_EVENT_SACCADE : GAZE_EVENT_FIXATION;
    else if (ev[a] == GAZE_EVENT_FIXATION && before == GAZE_EVENT_PURSUIT && after == GAZE_EVENT_PURSUIT)
        to = GAZE_EVENT_PURSUIT;
    for (int k = a; k <= b; k++)
        ev[k] = (unsigned char)to;
}

/* Settles each maximal run of event `what` inside one run of valid samples (settle_short_run). */
static void for_runs(const gaze_trace *t, const work *w, const gaze_events_desc *ed, unsigned char *ev,
                     gaze_event what)
{
    for (int i = 0; i < t->count;) {
        if (ev[i] != what) {
            i++;
            continue;
        }
        int b = i;
        while (b + 1 <= w->run_hi[i] && ev[b + 1] == what)
            b++;
        settle_short_run(t, w, 1e-3 * ed->window_ms, ev, i, b);
        i = b + 1;
    }
}

static void classify(const gaze_trace *t, const work *w, const gaze_events_desc *ed, unsigned char *ev)
{
    for (int i = 0; i < t->count; i++)
        ev[i] = (unsigned char)threshold_event(w->vel[i], ed);
    for_runs(t, w, ed, ev, GAZE_EVENT_PURSUIT);
    for_runs(t, w, ed, ev, GAZE_EVENT_FIXATION);
}

/* >>saccades */

/* The saccade [a, b]: its amplitude from the first sample of a's window to the last of b's (the
 * window's edges are where the movement that made them saccadic began and ended), its peak the
 * highest windowed velocity in it. */
static gaze_saccade make_saccade(const gaze_trace *t, const work *w, int a, int b)
{
    gaze_saccade s = {t->samples[a].t, t->samples[b].t, 0.0f, 0.0f};
    s.amplitude_deg = (float)ray_angle_deg(w->r[w->lo[a]], w->r[w->hi[b]]);
    for (int k = a; k <= b; k++)
        s.peak_deg_s = fmaxf(s.peak_deg_s, (float)w->vel[k]);
    return s;
}

/* The saccade runs, each inside one run of valid samples (two runs' saccades across a gap are two). */
static fs_status list_saccades(const gaze_trace *t, const work *w, gaze_events *out)
{
    int n = t->count, cap = 0;
    for (int i = 0; i < n;) {
        if (out->event[i] != GAZE_EVENT_SACCADE) {
            i++;
            continue;
        }
        int b = i;
        while (b + 1 <= w->run_hi[i] && out->event[b + 1] == GAZE_EVENT_SACCADE)
            b++;
        if (out->saccade_count == cap) {
            cap = cap ? 2 * cap : 16;
            gaze_saccade *g = realloc(out->saccades, (size_t)cap * sizeof *g);
            if (!g)
                return FS_ERR_NOMEM;
            out->saccades = g;
        }
        out->saccades[out->saccade_count++] = make_saccade(t, w, i, b);
        i = b + 1;
    }
    return FS_OK;
}

/* >>api */

static void work_free(work *w)
{
    free(w->r);
    free(w->run_lo);
    free(w->run_hi);
    free(w->lo);
    free(w->hi);
    free(w->vel);
}

static bool work_alloc(work *w, int n)
{
    size_t m = (size_t)n;
    w->r = malloc(m * sizeof *w->r);
    w->run_lo = malloc(m * sizeof *w->run_lo);
    w->run_hi = malloc(m * sizeof *w->run_hi);
    w->lo = malloc(m * sizeof *w->lo);
    w->hi = malloc(m * sizeof *w->hi);
    w->vel = malloc(m * sizeof *w->vel);
    return w->r && w->run_lo && w->run_hi && w->lo && w->hi && w->vel;
}

fs_status gaze_events_classify(const gaze_trace *t, const display_desc *d, const gaze_events_desc *ed,
                               gaze_events *out)
{
    memset(out, 0, sizeof *out);
    if (!desc_resolve(ed, &out->desc))
        return FS_ERR_USAGE;
    if (!t || t->count <= 0 || !t->samples)
        return FS_OK;
    display_desc disp = d ? *d : (display_desc){.width = 1280, .height = 720, .hfov_deg = 90.0f};
    work w = {0};
    out->event = malloc((size_t)t->count);
    fs_status s = out->event && work_alloc(&w, t->count) ? FS_OK : FS_ERR_NOMEM;
    if (s == FS_OK) {
        out->count = t->count;
        find_runs(t, &w);
        velocities(t, &disp, &out->desc, &w);
        classify(t, &w, &out->desc, out->event);
        s = list_saccades(t, &w, out);
    }
    work_free(&w);
    if (s != FS_OK) {
        log_error("gaze events: out of memory classifying %d samples of %s", t->count, t->path);
        gaze_events_free(out);
    }
    return s;
}

void gaze_events_free(gaze_events *e)
{
    if (!e)
        return;
    free(e->event);
    free(e->saccades);
    memset(e, 0, sizeof *e);
}

gaze_event gaze_events_at(const gaze_events *e, const gaze_trace *t, double time)
{
    if (!e || !t || e->count <= 0 || t->count <= 0)
        return GAZE_EVENT_FIXATION;
    int i = gaze_sample_index(t, time);
    i = i < 0 ? 0 : i >= e->count ? e->count - 1 : i;
    return (gaze_event)e->event[i];
}

const gaze_saccade *gaze_events_landed(const gaze_events *e, double time)
{
    if (!e || e->saccade_count <= 0 || !(e->saccades[0].end <= time))
        return NULL;
    int lo = 0, hi = e->saccade_count - 1; /* saccades[lo].end <= time holds */
    while (lo < hi) {
        int mid = lo + (hi - lo + 1) / 2;
        if (e->saccades[mid].end <= time)
            lo = mid;
        else
            hi = mid - 1;
    }
    return &e->saccades[lo];
}
