/* gaze_events.c: eye-movement events of the true trace (gaze_events.h). A first I-VVT: velocity
 * over a centred window, two thresholds. */
#include "gaze/gaze_events.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEG (180.0 / 3.14159265358979323846)

static const char *const k_names[GAZE_EVENT_COUNT] = {"fixation", "saccade", "pursuit", "lost"};

const char *gaze_event_name(gaze_event e)
{
    return e >= 0 && e < GAZE_EVENT_COUNT ? k_names[e] : NULL;
}

/* The unit ray of display-normalised gaze (x, y) on display d. */
static void ray(const display_desc *d, double x, double y, double r[3])
{
    double f = 0.5 * d->width / tan(0.5 * d->hfov_deg / DEG);
    r[0] = (x - 0.5) * d->width / f;
    r[1] = (0.5 - y) * d->height / f;
    r[2] = 1.0;
    double n = sqrt(r[0] * r[0] + r[1] * r[1] + 1.0);
    for (int i = 0; i < 3; i++)
        r[i] /= n;
}

static double angle_deg(const display_desc *d, const gaze_sample *a, const gaze_sample *b)
{
    double p[3], q[3];
    ray(d, a->x, a->y, p);
    ray(d, b->x, b->y, q);
    double c[3] = {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
    return atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), p[0] * q[0] + p[1] * q[1] + p[2] * q[2]) * DEG;
}

fs_status gaze_events_classify(const gaze_trace *t, const display_desc *d, const gaze_events_desc *ed,
                               gaze_events *out)
{
    memset(out, 0, sizeof *out);
    out->desc = ed ? *ed : (gaze_events_desc){0};
    if (!(out->desc.saccade_deg_s > 0))
        out->desc.saccade_deg_s = 70.0f;
    if (!(out->desc.pursuit_deg_s > 0))
        out->desc.pursuit_deg_s = 5.0f;
    if (!(out->desc.window_ms > 0))
        out->desc.window_ms = 20.0f;
    if (!t || t->count <= 0)
        return FS_OK;
    int n = t->count;
    const gaze_sample *s = t->samples;
    out->event = calloc((size_t)n, 1);
    out->saccades = calloc((size_t)n, sizeof *out->saccades);
    if (!out->event || !out->saccades) {
        gaze_events_free(out);
        return FS_ERR_NOMEM;
    }
    out->count = n;
    double half = 0.5e-3 * out->desc.window_ms;
    int a = 0, b = 0;
    for (int i = 0; i < n; i++) {
        if (!s[i].valid) {
            out->event[i] = GAZE_EVENT_LOST;
            continue;
        }
        while (s[i].t - s[a].t > half)
            a++;
        if (b < i)
            b = i;
        while (b + 1 < n && s[b + 1].t - s[i].t <= half)
            b++;
        int lo = a, hi = b;
        while (lo < i && !s[lo].valid)
            lo++;
        while (hi > i && !s[hi].valid)
            hi--;
        if (hi == lo) {
            out->event[i] = GAZE_EVENT_FIXATION;
            continue;
        }
        double v = angle_deg(d, &s[lo], &s[hi]) / (s[hi].t - s[lo].t);
        out->event[i] = v >= out->desc.saccade_deg_s   ? GAZE_EVENT_SACCADE
                        : v >= out->desc.pursuit_deg_s ? GAZE_EVENT_PURSUIT
                                                       : GAZE_EVENT_FIXATION;
    }
    for (int i = 0; i < n; i++) {
        if (out->event[i] != GAZE_EVENT_SACCADE)
            continue;
        int j = i;
        while (j + 1 < n && out->event[j + 1] == GAZE_EVENT_SACCADE)
            j++;
        gaze_saccade *sc = &out->saccades[out->saccade_count++];
        sc->start = s[i].t;
        sc->end = s[j].t;
        sc->amplitude_deg = (float)angle_deg(d, &s[i > 0 ? i - 1 : i], &s[j + 1 < n ? j + 1 : j]);
        i = j;
    }
    return FS_OK;
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
    if (!e || e->count <= 0 || !t || t->count != e->count)
        return GAZE_EVENT_FIXATION;
    return (gaze_event)e->event[gaze_sample_index(t, time)];
}

const gaze_saccade *gaze_events_landed(const gaze_events *e, double time)
{
    const gaze_saccade *last = NULL;
    for (int i = 0; e && i < e->saccade_count && e->saccades[i].end <= time; i++)
        last = &e->saccades[i];
    return last;
}
