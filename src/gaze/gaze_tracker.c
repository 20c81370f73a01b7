/* gaze_tracker.c: the eye-tracking system between the true gaze and the renderer (gaze_tracker.h,
 * docs/latency.md). */
#include "gaze/gaze_tracker.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEG2RAD (3.14159265358979323846 / 180.0)
/* A time within this fraction of a sample period before a sample time counts as at it: frame times
 * are floats (i / fps rounded to 24 bits), and a frame drawn at a sample time must see that sample. */
#define SAMPLE_EPS 1e-6

static const char *const k_loss_names[GAZE_LOSS_COUNT] = {"hold", "centre", "full"};

const char *gaze_loss_name(gaze_loss l)
{
    return l >= 0 && l < GAZE_LOSS_COUNT ? k_loss_names[l] : NULL;
}

gaze_loss gaze_loss_parse(const char *name)
{
    if (name && !strcmp(name, "center"))
        return GAZE_LOSS_CENTRE;
    for (int i = 0; name && i < GAZE_LOSS_COUNT; i++)
        if (!strcmp(name, k_loss_names[i]))
            return (gaze_loss)i;
    return GAZE_LOSS_COUNT;
}

bool gaze_tracker_is_ideal(const gaze_tracker_desc *td)
{
    return !td || (td->latency_ms == 0.0f && td->rate_hz == 0.0f && td->noise_deg == 0.0f &&
                   td->loss == GAZE_LOSS_HOLD);
}

void gaze_tracker_format(const gaze_tracker_desc *td, char *buf, int size)
{
    char rate[32] = "trace";
    if (td->rate_hz > 0.0f)
        snprintf(rate, sizeof rate, "%.7g Hz", td->rate_hz);
    snprintf(buf, (size_t)size, "latency %.7g ms, rate %s, noise %.7g deg seed %u, loss %s", td->latency_ms, rate,
             td->noise_deg, (unsigned)td->seed, gaze_loss_name(td->loss) ? gaze_loss_name(td->loss) : "?");
}

gaze_tracker_desc gaze_tracker_merge(const gaze_tracker_opts *first, const gaze_tracker_opts *second)
{
    gaze_tracker_desc out = {0};
    const gaze_tracker_opts *o[2] = {second, first}; /* first wins: applied last */
    for (int i = 0; i < 2; i++) {
        if (!o[i])
            continue;
        const gaze_tracker_desc *d = &o[i]->desc;
        out.latency_ms = o[i]->latency_set ? d->latency_ms : out.latency_ms;
        out.rate_hz = o[i]->rate_set ? d->rate_hz : out.rate_hz;
        out.noise_deg = o[i]->noise_set ? d->noise_deg : out.noise_deg;
        out.seed = o[i]->seed_set ? d->seed : out.seed;
        out.loss = o[i]->loss_set ? d->loss : out.loss;
    }
    return out;
}

/* >>noise: counter-based, so a sample's noise depends on nothing but its key */

static uint64_t mix64(uint64_t z) /* splitmix64's finaliser */
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

double gaze_tracker_normal(uint32_t seed, long sample, int axis)
{
    uint64_t key = mix64(((uint64_t)seed << 32) ^ 0x9e3779b97f4a7c15ull);
    key = mix64(key + 2u * (uint64_t)sample + (uint64_t)(axis & 1));
    /* Box-Muller from two 53-bit uniforms; u1 in (0, 1] so the log is finite. */
    double u1 = (double)((mix64(key ^ 0x632be59bd9b4e019ull) >> 11) + 1) * 0x1p-53;
    double u2 = (double)(mix64(key ^ 0x8cb92ba72f3d8dd7ull) >> 11) * 0x1p-53;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * 3.14159265358979323846 * u2);
}

void gaze_offset_deg(const display_desc *d, double dx_deg, double dy_deg, double *x, double *y)
{
    display_geom g = display_geom_of(d); /* angles from the principal point */
    const double lim = 89.9 * DEG2RAD; /* a ray at 90 degrees meets the display plane nowhere */
    double ax = atan((*x * g.w - g.cx) / g.f) + dx_deg * DEG2RAD;
    double ay = atan((g.cy - *y * g.h) / g.f) + dy_deg * DEG2RAD;
    ax = fmax(-lim, fmin(lim, ax));
    ay = fmax(-lim, fmin(lim, ay));
    *x = (g.cx + g.f * tan(ax)) / g.w;
    *y = (g.cy - g.f * tan(ay)) / g.h;
}

/* >>sampling */

/* The true gaze at trace time s; whether a tracker sample there is lost (inside an invalid run;
 * never past the end, never without a trace). */
static bool sample_lost(const gaze_trace *t, double s, gaze_point *g, bool *beyond)
{
    *g = gaze_at(t, s, beyond);
    return t && t->count > 0 && g->held && !*beyond;
}

/* The last tracker sample before k that is not lost, or -1. Starts at the tracker sample of the
 * last valid trace sample before sample k's time, so a long gap costs a walk over trace samples,
 * not over every tracker sample inside it. */
static long last_good_tracker_sample(const gaze_trace *t, double rate, long k)
{
    int v = gaze_sample_index(t, (double)k / rate);
    while (v >= 0 && !t->samples[v].valid)
        v--;
    if (v < 0)
        return -1;
    long j = (long)floor(t->samples[v].t * rate + SAMPLE_EPS);
    j = j < k - 1 ? j : k - 1;
    gaze_point g;
    bool beyond;
    while (j >= 0 && sample_lost(t, (double)j / rate, &g, &beyond))
        j--;
    return j;
}

/* The trace sample at or before index i that is valid, else i. */
static long last_valid_trace_sample(const gaze_trace *t, int i)
{
    int v = i;
    while (v >= 0 && !t->samples[v].valid)
        v--;
    return v >= 0 ? v : i;
}

/* A tracker of its own rate: sample-and-hold at k / rate. */
static gaze_delivery at_rate(const gaze_trace *t, const gaze_tracker_desc *td, double tau, bool *beyond)
{
    double rate = td->rate_hz;
    long k = tau > 0.0 ? (long)floor(tau * rate + SAMPLE_EPS) : 0;
    gaze_point g;
    gaze_delivery out = {.sample = k};
    out.lost = sample_lost(t, (double)k / rate, &g, beyond);
    if (out.lost && td->loss != GAZE_LOSS_CENTRE) {
        long j = last_good_tracker_sample(t, rate, k);
        if (j >= 0) {
            bool b;
            g = gaze_at(t, (double)j / rate, &b);
            out.sample = j;
        }
    }
    out.x = g.x;
    out.y = g.y;
    return out;
}

/* The trace's own samples, interpolated as gaze_at does. */
static gaze_delivery at_trace_samples(const gaze_trace *t, double tau, bool *beyond)
{
    gaze_point g;
    gaze_delivery out = {0};
    out.lost = sample_lost(t, tau, &g, beyond);
    int i = gaze_sample_index(t, tau);
    out.sample = i < 0 ? 0 : out.lost ? last_valid_trace_sample(t, i) : i;
    out.x = g.x; /* gaze_at already holds the last valid gaze through an invalid run */
    out.y = g.y;
    return out;
}

gaze_delivery gaze_tracker_at(const gaze_trace *t, const gaze_tracker_desc *td, const display_desc *d, double time,
                              bool *beyond_end)
{
    static const gaze_tracker_desc ideal = {0};
    if (!td)
        td = &ideal;
    bool beyond = false;
    double tau = time - (double)td->latency_ms / 1000.0;
    if (tau < 0.0 && td->latency_ms > 0.0f) /* nothing delivered yet: the first sample */
        tau = 0.0;
    gaze_delivery out = td->rate_hz > 0.0f ? at_rate(t, td, tau, &beyond) : at_trace_samples(t, tau, &beyond);
    if (beyond_end)
        *beyond_end = beyond;
    if (out.lost && td->loss == GAZE_LOSS_CENTRE) {
        out.x = out.y = 0.5f;
        return out;
    }
    out.full = out.lost && td->loss == GAZE_LOSS_FULL;
    if (td->noise_deg > 0.0f && d) {
        double x = out.x, y = out.y, sd = td->noise_deg;
        gaze_offset_deg(d, sd * gaze_tracker_normal(td->seed, out.sample, 0),
                        sd * gaze_tracker_normal(td->seed, out.sample, 1), &x, &y);
        out.x = (float)fmin(fmax(x, 0.0), 1.0);
        out.y = (float)fmin(fmax(y, 0.0), 1.0);
    }
    return out;
}
