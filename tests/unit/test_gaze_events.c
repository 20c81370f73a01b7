/* test_gaze_events.c: the eye-movement classifier (src/gaze/gaze_events.c): synthetic traces with
 * events of known times, amplitudes and speeds at several sample rates; blinks, gaps, one-sample and
 * repeated-time traces; the committed labelled trace (tests/data/gaze_events_labelled.csv); the
 * agreement with EyeLink's own saccade events in the shared recordings (FOVSIM_SHARED); random
 * traces. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gaze/gaze.h"
#include "gaze/gaze_events.h"
#include "test.h"

#define PI 3.14159265358979323846
#define EYELINK_DIR "gaze/eyelink_asc_eyelinker/"

static const display_desc k_disp = {1280, 720, 90.0f, 0.0f, 0.0f};

/* >>synthetic traces */

/* A trace built in memory from per-axis angles (gaze_deg's convention), so tests control validity,
 * repeated times and garbage positions directly. */
typedef struct builder {
    gaze_trace t;
    int cap;
    unsigned rng;
} builder;

static double focal(void)
{
    return 0.5 * k_disp.width / tan(0.5 * k_disp.hfov_deg * PI / 180.0);
}

/* A uniform number in (0, 1) from a fixed LCG: the traces are the same on every machine. */
static double uniform(builder *b)
{
    b->rng = b->rng * 1664525u + 1013904223u;
    return ((b->rng >> 8) + 0.5) / 16777216.0;
}

static double gauss(builder *b)
{
    return sqrt(-2.0 * log(uniform(b))) * cos(2.0 * PI * uniform(b));
}

static void add_raw(builder *b, double t, double x, double y, bool valid)
{
    if (b->t.count == b->cap) {
        b->cap = b->cap ? 2 * b->cap : 1024;
        b->t.samples = realloc(b->t.samples, (size_t)b->cap * sizeof *b->t.samples);
    }
    b->t.samples[b->t.count++] = (gaze_sample){t, (float)x, (float)y, valid ? 1.0f : 0.0f, valid};
    b->t.valid_count += valid;
    b->t.duration = t;
}

/* A valid sample at angles (ax, ay) degrees plus Gaussian noise of `noise` degrees per axis. */
static void add_deg(builder *b, double t, double ax, double ay, double noise)
{
    ax += noise * gauss(b);
    ay += noise * gauss(b);
    double f = focal();
    add_raw(b, t, 0.5 + f * tan(ax * PI / 180.0) / k_disp.width, 0.5 - f * tan(ay * PI / 180.0) / k_disp.height,
            true);
}

/* The minimum-jerk position (0..1) at fraction s of a movement: the bell-shaped velocity profile of
 * a saccade, peak 1.875 amplitude / duration. */
static double min_jerk(double s)
{
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    return s * s * s * (10 - 15 * s + 6 * s * s);
}

/* Main-sequence duration in seconds of a saccade of `amp` degrees (Carpenter 1988). */
static double main_seq_s(double amp)
{
    return (2.2 * amp + 21.0) / 1000.0;
}

/* Horizontal: fixation at x0 until t0, a saccade of main-sequence duration to x1, fixation to `end`. */
static void saccade_trace(builder *b, double rate, double t0, double x0, double x1, double end, double noise)
{
    double dur = main_seq_s(fabs(x1 - x0));
    for (int k = 0; k <= (int)lround(end * rate); k++) {
        double t = k / rate;
        add_deg(b, t, x0 + (x1 - x0) * min_jerk((t - t0) / dur), 0.0, noise);
    }
}

static gaze_events classify(const gaze_trace *t, const gaze_events_desc *ed)
{
    gaze_events e;
    CHECK(gaze_events_classify(t, &k_disp, ed, &e) == FS_OK);
    return e;
}

static int count_event(const gaze_events *e, gaze_event ev)
{
    int n = 0;
    for (int i = 0; i < e->count; i++)
        n += e->event[i] == ev;
    return n;
}

/* >>fixation, saccade, pursuit */

TEST(names)
{
    CHECK(!strcmp(gaze_event_name(GAZE_EVENT_FIXATION), "fixation"));
    CHECK(!strcmp(gaze_event_name(GAZE_EVENT_SACCADE), "saccade"));
    CHECK(!strcmp(gaze_event_name(GAZE_EVENT_PURSUIT), "pursuit"));
    CHECK(!strcmp(gaze_event_name(GAZE_EVENT_LOST), "lost"));
    CHECK(gaze_event_name(GAZE_EVENT_COUNT) == NULL);
    CHECK(gaze_event_name((gaze_event)-1) == NULL);
    for (int e = 0; e < GAZE_EVENT_COUNT; e++)
        CHECK(gaze_event_parse(gaze_event_name((gaze_event)e)) == (gaze_event)e);
    CHECK(gaze_event_parse("Saccade") == GAZE_EVENT_COUNT && gaze_event_parse("") == GAZE_EVENT_COUNT);
    CHECK(gaze_event_parse(NULL) == GAZE_EVENT_COUNT);
}

TEST(defaults_filled_in)
{
    builder b = {.rng = 1};
    add_deg(&b, 0, 0, 0, 0);
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.desc.saccade_deg_s == 70.0f && e.desc.pursuit_deg_s == 10.0f && e.desc.window_ms == 20.0f);
    gaze_events_free(&e);
    e = classify(&b.t, &(gaze_events_desc){.saccade_deg_s = 100.0f});
    CHECK(e.desc.saccade_deg_s == 100.0f && e.desc.pursuit_deg_s == 10.0f);
    gaze_events_free(&e);
    gaze_free(&b.t);
}

/* Fixation with tracker noise of 0.03 deg RMS (a video tracker) at 30 to 2000 Hz, and a slow
 * drift: fixation throughout, no saccade. */
TEST(fixation_with_noise)
{
    static const double rates[] = {30, 60, 250, 500, 1000, 2000};
    for (size_t r = 0; r < sizeof rates / sizeof rates[0]; r++) {
        builder b = {.rng = 7};
        for (int k = 0; k < (int)(2.0 * rates[r]); k++)
            add_deg(&b, k / rates[r], 3.0 + 0.3 * k / rates[r], -2.0, 0.03);
        gaze_events e = classify(&b.t, NULL);
        CHECK(e.count == b.t.count);
        CHECK(e.saccade_count == 0);
        CHECK(count_event(&e, GAZE_EVENT_FIXATION) == e.count);
        if (count_event(&e, GAZE_EVENT_FIXATION) != e.count)
            fprintf(stderr, "  at %g Hz: %d of %d fixation\n", rates[r], count_event(&e, GAZE_EVENT_FIXATION), e.count);
        gaze_events_free(&e);
        gaze_free(&b.t);
    }
}

/* One 10 deg saccade (43 ms, main sequence) at 30 Hz to 2000 Hz: one saccade, its samples saccade,
 * start and end within a window plus a sample period of the movement, its amplitude 10 deg. */
TEST(saccade_of_known_amplitude)
{
    static const double rates[] = {30, 60, 250, 500, 1000, 2000};
    const double t0 = 0.5, dur = main_seq_s(10.0);
    for (size_t r = 0; r < sizeof rates / sizeof rates[0]; r++) {
        builder b = {.rng = 3};
        saccade_trace(&b, rates[r], t0, -5.0, 5.0, 1.0, 0.02);
        gaze_events e = classify(&b.t, NULL);
        double tol = 0.010 + 1.0 / rates[r];
        CHECK(e.saccade_count == 1);
        if (e.saccade_count == 1) {
            const gaze_saccade *s = &e.saccades[0];
            CHECK(s->start >= t0 - tol && s->start <= t0 + 0.010);
            CHECK(s->end >= t0 + dur - 0.010 && s->end <= t0 + dur + tol);
            CHECK_NEAR(s->amplitude_deg, 10.0, 0.2);
            /* the window's average over the bell: below the true peak 1.875 A / D = 436 deg/s; at
             * 30 and 60 Hz the central difference spans 33-67 ms, more than the whole saccade */
            CHECK(s->peak_deg_s > (rates[r] >= 250 ? 250.0 : 140.0) && s->peak_deg_s <= 440.0);
        }
        int inside = 0, inside_sac = 0, outside = 0, outside_fix = 0;
        for (int i = 0; i < e.count; i++) {
            double t = b.t.samples[i].t;
            if (t > t0 + 0.008 && t < t0 + dur - 0.008)
                inside++, inside_sac += e.event[i] == GAZE_EVENT_SACCADE;
            if (t < t0 - tol - 0.001 || t > t0 + dur + tol + 0.001)
                outside++, outside_fix += e.event[i] == GAZE_EVENT_FIXATION;
        }
        CHECK(inside_sac == inside);
        CHECK(outside_fix == outside);
        if (e.saccade_count != 1 || inside_sac != inside || outside_fix != outside)
            fprintf(stderr, "  at %g Hz: %d saccades, %d/%d inside, %d/%d outside\n", rates[r], e.saccade_count,
                    inside_sac, inside, outside_fix, outside);
        gaze_events_free(&e);
        gaze_free(&b.t);
    }
}

/* Smooth pursuit at 15 deg/s for 1 s between fixations, at 30 to 2000 Hz: pursuit (all of it but
 * the window-long edges), no saccade; at 5 deg/s (below the band) it is fixation. */
TEST(pursuit_at_15_deg_s)
{
    static const double rates[] = {30, 60, 250, 1000, 2000};
    for (size_t r = 0; r < sizeof rates / sizeof rates[0]; r++) {
        for (int slow = 0; slow < 2; slow++) {
            double speed = slow ? 5.0 : 15.0;
            builder b = {.rng = 5};
            for (int k = 0; k <= (int)(2.0 * rates[r]); k++) {
                double t = k / rates[r], tp = t < 0.5 ? 0 : t > 1.5 ? 1.0 : t - 0.5;
                add_deg(&b, t, -7.5 + speed * tp, 1.0, 0.02);
            }
            gaze_events e = classify(&b.t, NULL);
            CHECK(e.saccade_count == 0);
            int in = 0, in_pursuit = 0, out = 0, out_fix = 0;
            for (int i = 0; i < e.count; i++) {
                double t = b.t.samples[i].t;
                if (t > 0.52 && t < 1.48)
                    in++, in_pursuit += e.event[i] == (slow ? GAZE_EVENT_FIXATION : GAZE_EVENT_PURSUIT);
                if (t < 0.48 || t > 1.52)
                    out++, out_fix += e.event[i] == GAZE_EVENT_FIXATION;
            }
            CHECK(in_pursuit == in);
            CHECK(out_fix == out);
            if (in_pursuit != in || out_fix != out)
                fprintf(stderr, "  %g deg/s at %g Hz: %d/%d in, %d/%d out\n", speed, rates[r], in_pursuit, in,
                        out_fix, out);
            gaze_events_free(&e);
            gaze_free(&b.t);
        }
    }
}

/* >>loss, gaps, degenerate traces */

/* A blink (120 ms invalid, garbage positions) across which the eye moved 8 deg: the invalid
 * samples lost, everything else fixation, no saccade out of the blink's edges. */
TEST(blink_is_lost_not_saccade)
{
    builder b = {.rng = 11};
    for (int k = 0; k < 1000; k++) {
        double t = k / 1000.0;
        if (t >= 0.4 && t < 0.52)
            add_raw(&b, t, k % 2 ? -0.3 : 1.4, 0.0, false);
        else
            add_deg(&b, t, t < 0.4 ? -4.0 : 4.0, 0.0, 0.02);
    }
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.saccade_count == 0);
    CHECK(count_event(&e, GAZE_EVENT_LOST) == 120);
    CHECK(count_event(&e, GAZE_EVENT_FIXATION) == 880);
    for (int i = 0; i < e.count; i++)
        if ((e.event[i] == GAZE_EVENT_LOST) == b.t.samples[i].valid)
            CHECK(!"lost exactly where invalid");
    gaze_events_free(&e);
    gaze_free(&b.t);
}

/* Two recording blocks 2 s apart (EyeLink) with the gaze 12 deg elsewhere in the second: no saccade
 * across them (the 3 deg jump inside the second block is one). A 100 ms dropout across which the
 * gaze moved 10 deg: no saccade. A 50 ms hole (below the 75 ms gap) across which it jumps 10 deg is
 * still read as a movement. */
TEST(gap_is_not_saccade)
{
    builder b = {.rng = 13};
    for (int k = 0; k < 500; k++)
        add_deg(&b, k / 500.0, -6.0, 2.0, 0.02);
    for (int k = 0; k < 500; k++)
        add_deg(&b, 3.0 + k / 500.0, k < 250 ? 6.0 : 9.0, -3.0, 0.02);
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.saccade_count == 1); /* the 3 deg jump inside the second block, instantaneous */
    gaze_events_free(&e);
    gaze_free(&b.t);

    builder c = {.rng = 17};
    for (int k = 0; k < 1000; k++) {
        double t = k / 1000.0;
        if (t < 0.45 || t > 0.55)
            add_deg(&c, t, t < 0.5 ? 0.0 : 10.0, 0.0, 0.02);
    }
    e = classify(&c.t, NULL);
    CHECK(e.saccade_count == 0); /* 100 ms > 75 ms: a gap */
    gaze_events_free(&e);
    gaze_free(&c.t);

    builder d = {.rng = 19};
    for (int k = 0; k < 1000; k++) {
        double t = k / 1000.0;
        if (t < 0.475 || t > 0.525)
            add_deg(&d, t, t < 0.5 ? 0.0 : 10.0, 0.0, 0.02);
    }
    e = classify(&d.t, NULL);
    CHECK(e.saccade_count == 1); /* 50 ms < 75 ms: 10 deg in 50 ms is 200 deg/s */
    if (e.saccade_count == 1)
        CHECK_NEAR(e.saccades[0].amplitude_deg, 10.0, 0.2);
    gaze_events_free(&e);
    gaze_free(&d.t);
}

TEST(one_sample_and_empty)
{
    builder b = {.rng = 1};
    add_deg(&b, 0, 1, 1, 0);
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.count == 1 && e.event[0] == GAZE_EVENT_FIXATION && e.saccade_count == 0);
    CHECK(gaze_events_at(&e, &b.t, -1.0) == GAZE_EVENT_FIXATION);
    CHECK(gaze_events_at(&e, &b.t, 5.0) == GAZE_EVENT_FIXATION);
    CHECK(gaze_events_landed(&e, 5.0) == NULL);
    gaze_events_free(&e);
    b.t.samples[0].valid = false;
    e = classify(&b.t, NULL);
    CHECK(e.count == 1 && e.event[0] == GAZE_EVENT_LOST);
    CHECK(gaze_events_at(&e, &b.t, 0.0) == GAZE_EVENT_LOST);
    gaze_events_free(&e);
    gaze_free(&b.t);

    gaze_trace empty = {0};
    e = classify(&empty, NULL);
    CHECK(e.count == 0 && e.event == NULL && e.saccade_count == 0);
    CHECK(gaze_events_at(&e, &empty, 0.0) == GAZE_EVENT_FIXATION);
    CHECK(gaze_events_landed(&e, 1.0) == NULL);
    gaze_events_free(&e);
}

/* Repeated and irregular times (as a hand-built trace may have; the readers average repeats): a
 * fixation stays fixation, the saccade is still one. */
TEST(repeated_and_irregular_times)
{
    builder b = {.rng = 23};
    double t = 0;
    for (int k = 0; k < 1200; k++) {
        double x = -5.0 + 10.0 * min_jerk((t - 0.6) / main_seq_s(10.0));
        add_deg(&b, t, x, 0.0, 0.02);
        if (k % 7 == 3)
            add_deg(&b, t, x, 0.0, 0.02); /* the same time twice */
        t += (k % 3 == 0 ? 0.5 : 1.2) / 1000.0;
    }
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.saccade_count == 1);
    if (e.saccade_count == 1)
        CHECK_NEAR(e.saccades[0].amplitude_deg, 10.0, 0.2);
    CHECK(count_event(&e, GAZE_EVENT_PURSUIT) == 0);
    gaze_events_free(&e);

    for (int i = 0; i < b.t.count; i++) /* every sample at one time: no velocity measurable */
        b.t.samples[i].t = 0.25;
    e = classify(&b.t, NULL);
    CHECK(count_event(&e, GAZE_EVENT_FIXATION) == e.count && e.saccade_count == 0);
    gaze_events_free(&e);
    gaze_free(&b.t);
}

TEST(bad_parameters)
{
    builder b = {.rng = 1};
    add_deg(&b, 0, 0, 0, 0);
    static const gaze_events_desc bad[] = {
        {.saccade_deg_s = 20.0f, .pursuit_deg_s = 20.0f},
        {.saccade_deg_s = 5.0f}, /* below the default pursuit threshold */
        {.pursuit_deg_s = -1.0f},
        {.window_ms = NAN},
        {.saccade_deg_s = INFINITY},
    };
    log_set_quiet_errors(true);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        gaze_events e;
        CHECK(gaze_events_classify(&b.t, &k_disp, &bad[i], &e) == FS_ERR_USAGE);
        CHECK(e.count == 0 && e.event == NULL && e.saccades == NULL);
    }
    log_set_quiet_errors(false);
    gaze_free(&b.t);
}

/* >>lookups */

TEST(event_at_and_landed)
{
    builder b = {.rng = 29};
    saccade_trace(&b, 1000, 0.3, 0.0, 8.0, 1.0, 0.02);
    for (int k = 1; k <= 1000; k++) /* a second saccade back at 1.3 s */
        add_deg(&b, 1.0 + k / 1000.0, 8.0 - 12.0 * min_jerk((k / 1000.0 - 0.3) / main_seq_s(12.0)), 0.0, 0.02);
    gaze_events e = classify(&b.t, NULL);
    CHECK(e.saccade_count == 2);
    if (e.saccade_count == 2) {
        const gaze_saccade *s0 = &e.saccades[0], *s1 = &e.saccades[1];
        CHECK(s0->end < s1->start);
        CHECK_NEAR(s1->amplitude_deg, 12.0, 0.2);
        CHECK(gaze_events_landed(&e, s0->end - 1e-6) == NULL);
        CHECK(gaze_events_landed(&e, s0->end) == s0);
        CHECK(gaze_events_landed(&e, s1->start) == s0);
        CHECK(gaze_events_landed(&e, s1->end) == s1);
        CHECK(gaze_events_landed(&e, 99.0) == s1);
        CHECK(gaze_events_at(&e, &b.t, 0.5 * (s0->start + s0->end)) == GAZE_EVENT_SACCADE);
        CHECK(gaze_events_at(&e, &b.t, 0.1) == GAZE_EVENT_FIXATION);
        CHECK(gaze_events_at(&e, &b.t, 0.5 * (s1->start + s1->end) + 0.0003) == GAZE_EVENT_SACCADE);
        CHECK(gaze_events_at(&e, &b.t, -1.0) == e.event[0]);
        CHECK(gaze_events_at(&e, &b.t, 99.0) == e.event[e.count - 1]);
    }
    gaze_events_free(&e);
    gaze_free(&b.t);
}

/* >>labelled trace */

/* The committed synthetic trace, labelled as built (tests/data/make_gaze_events_labelled.py): the
 * fovsim CSV reader loads it ignoring the `event` column; the classifier agrees on >= 95 %. */
static int read_labels(const char *path, unsigned char *lab, int cap)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    char line[256];
    int n = 0;
    if (!fgets(line, sizeof line, f) || !strstr(line, ",event")) {
        fclose(f);
        return -1;
    }
    while (n < cap && fgets(line, sizeof line, f)) {
        char *c = strrchr(line, ',');
        if (c)
            c[1 + strcspn(c + 1, "\r\n")] = '\0';
        lab[n++] = (unsigned char)(c ? gaze_event_parse(c + 1) : GAZE_EVENT_COUNT);
    }
    fclose(f);
    return n;
}

TEST(labelled_trace_agrees)
{
    const char *path = test_source_path("tests/data/gaze_events_labelled.csv");
    gaze_trace t;
    CHECK(gaze_load(path, NULL, &t) == FS_OK);
    static unsigned char lab[4096];
    int n = read_labels(path, lab, 4096);
    CHECK(n == t.count && n > 1000);
    if (n != t.count || n <= 1000) {
        gaze_free(&t);
        return;
    }
    gaze_events e = classify(&t, NULL);
    int agree = 0, per[GAZE_EVENT_COUNT] = {0}, per_n[GAZE_EVENT_COUNT] = {0};
    for (int i = 0; i < n; i++) {
        CHECK(lab[i] < GAZE_EVENT_COUNT);
        agree += e.event[i] == lab[i];
        per_n[lab[i] % GAZE_EVENT_COUNT]++;
        per[lab[i] % GAZE_EVENT_COUNT] += e.event[i] == lab[i];
    }
    printf("labelled trace: %d of %d samples agree (%.1f %%): fixation %d/%d, saccade %d/%d, pursuit %d/%d, "
           "lost %d/%d; %d saccades\n",
           agree, n, 100.0 * agree / n, per[0], per_n[0], per[1], per_n[1], per[2], per_n[2], per[3], per_n[3],
           e.saccade_count);
    CHECK(agree >= 0.95 * n);
    for (int k = 0; k < GAZE_EVENT_COUNT; k++) /* each kind mostly right, not just the majority */
        CHECK(per[k] >= 0.8 * per_n[k]);
    CHECK(e.saccade_count == 4); /* three saccades and the catch-up */
    gaze_events_free(&e);
    gaze_free(&t);
}

/* >>EyeLink's own events */

/* EyeLink's parser marks saccades in the ASC file (SSACC / ESACC lines, per eye); its RES (pixels
 * per degree at the screen centre) on the END lines gives the display the recording was made on. */
typedef struct el_events {
    double start[1024], end[1024], amp[1024]; /* ms, tracker clock; degrees */
    int n;
    double res; /* mean pixels per degree, x */
} el_events;

static bool read_eyelink_events(const char *path, char eye, el_events *ev)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return false;
    char line[512];
    double res_sum = 0;
    int res_n = 0;
    ev->n = 0;
    while (fgets(line, sizeof line, f)) {
        char e;
        double s, en, d, x0, y0, x1, y1, amp, pv, rx, ry;
        if (sscanf(line, "ESACC %c %lf %lf %lf %lf %lf %lf %lf %lf %lf", &e, &s, &en, &d, &x0, &y0, &x1, &y1, &amp,
                   &pv) == 10 &&
            e == eye && ev->n < 1024) {
            ev->start[ev->n] = s;
            ev->end[ev->n] = en;
            ev->amp[ev->n++] = amp;
        }
        const char *r = strstr(line, "RES");
        if (!strncmp(line, "END", 3) && r && sscanf(r + 3, "%lf %lf", &rx, &ry) == 2)
            res_sum += rx, res_n++;
    }
    fclose(f);
    ev->res = res_n ? res_sum / res_n : 0;
    return res_n > 0;
}

typedef struct agreement {
    int samples, agree, el_sac, both_sac, el_big, el_big_found;
    double amp_err; /* mean |our amplitude - EyeLink's| over the saccades >= 2 deg found, degrees */
} agreement;

/* Saccade vs not, over the valid samples; EyeLink's saccades of >= 2 deg found (overlapping one of ours). */
static agreement eyelink_agreement(const char *file, gaze_eye eye_sel, char eye)
{
    agreement a = {0};
    char rel[256];
    snprintf(rel, sizeof rel, EYELINK_DIR "%s", file);
    static el_events ev;
    gaze_trace t;
    if (!read_eyelink_events(test_shared_path(rel), eye, &ev) ||
        gaze_load(test_shared_path(rel), &(gaze_load_desc){.eye = eye_sel}, &t) != FS_OK)
        return a;
    /* 1024 px at ev.res px/deg at the centre: focal length res * 180 / pi px */
    double hfov = 2.0 * atan(512.0 / (ev.res * 180.0 / PI)) * 180.0 / PI;
    display_desc d = {t.screen_w, t.screen_h, (float)hfov, 0.0f, 0.0f};
    gaze_events e;
    CHECK(gaze_events_classify(&t, &d, NULL, &e) == FS_OK);
    int k = 0;
    for (int i = 0; i < e.count && e.count == t.count; i++) {
        if (e.event[i] == GAZE_EVENT_LOST)
            continue;
        double ms = round((t.samples[i].t + t.time_offset) * 1000.0);
        while (k < ev.n && ev.end[k] < ms)
            k++;
        bool el = k < ev.n && ev.start[k] <= ms;
        bool ours = e.event[i] == GAZE_EVENT_SACCADE;
        a.samples++;
        a.agree += el == ours;
        a.el_sac += el;
        a.both_sac += el && ours;
    }
    for (int j = 0; j < ev.n; j++) {
        if (ev.amp[j] < 2.0)
            continue;
        a.el_big++;
        for (int s = 0; s < e.saccade_count; s++) {
            double s0 = (e.saccades[s].start + t.time_offset) * 1000.0, s1 = (e.saccades[s].end + t.time_offset) * 1000.0;
            if (s0 <= ev.end[j] + 0.5 && s1 >= ev.start[j] - 0.5) {
                a.el_big_found++;
                a.amp_err += fabs(e.saccades[s].amplitude_deg - ev.amp[j]);
                break;
            }
        }
    }
    a.amp_err /= a.el_big_found ? a.el_big_found : 1;
    printf("%s eye %c (%.2f px/deg, hfov %.2f deg): saccade-vs-not agreement %d/%d = %.2f %%; EyeLink saccade "
           "samples also ours %d/%d; EyeLink saccades >= 2 deg found %d/%d, amplitude off by %.2f deg on average; "
           "%d saccades of ours, %d of EyeLink\n",
           file, eye, ev.res, hfov, a.agree, a.samples, 100.0 * a.agree / (a.samples ? a.samples : 1), a.both_sac,
           a.el_sac, a.el_big_found, a.el_big, a.amp_err, e.saccade_count, ev.n);
    gaze_events_free(&e);
    gaze_free(&t);
    return a;
}

TEST(eyelink_saccades_agree)
{
    /* The bound: 97 % on the head-fixed recordings (a few saccades in 2-4 s); 93 % on the remote one,
     * a reading task with a saccade every ~250 ms (11 % of its samples), where our 20 ms window starts
     * saccades 2-6 ms before EyeLink's parser and ends them up to 15 ms after (docs/latency.md). */
    static const struct {
        const char *file;
        gaze_eye sel;
        char eye;
        double min_agree;
    } k[] = {
        {"mono1000.asc", GAZE_EYE_AUTO, 'R', 0.97},
        {"bino500.asc", GAZE_EYE_RIGHT, 'R', 0.97},
        {"mono250.asc", GAZE_EYE_AUTO, 'L', 0.97},
        {"binoRemote500.asc", GAZE_EYE_RIGHT, 'R', 0.93},
    };
    FILE *probe = fopen(test_shared_path(EYELINK_DIR "mono1000.asc"), "r");
    if (!probe) {
        printf("skipped: %s missing (set FOVSIM_SHARED)\n", test_shared_path(EYELINK_DIR "mono1000.asc"));
        return;
    }
    fclose(probe);
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++) {
        agreement a = eyelink_agreement(k[i].file, k[i].sel, k[i].eye);
        CHECK(a.samples > 500);
        CHECK(a.agree >= k[i].min_agree * a.samples);
        CHECK(a.both_sac >= 0.5 * a.el_sac); /* not just "never saccade" */
        CHECK(a.el_big_found == a.el_big && a.el_big > 0);
        CHECK(a.amp_err < 0.5); /* EyeLink sums per-sample pixels over its own RES; we take the rays' angle */
    }
}

/* >>random traces */

/* Random traces (rates, repeats, gaps, invalid runs, positions off the display, random thresholds):
 * no crash, every sample a valid event, lost exactly where invalid, saccades in time order, inside
 * the trace, on saccade samples, and found by gaze_events_landed. */
static void random_trace(builder *b, int n)
{
    double t = 0;
    bool valid = true;
    for (int i = 0; i < n; i++) {
        double u = uniform(b);
        t += u < 0.05 ? 0.0 : u < 0.08 ? 0.5 + 3 * uniform(b) : 0.0005 + 0.05 * uniform(b);
        if (uniform(b) < 0.05)
            valid = !valid;
        add_raw(b, t, -0.5 + 2 * uniform(b) * (uniform(b) < 0.5 ? 0.1 : 1.0), -0.5 + 2 * uniform(b), valid);
    }
}

static void check_events(const builder *b, const gaze_events *e)
{
    CHECK(e->count == b->t.count);
    for (int i = 0; i < e->count; i++) {
        CHECK(e->event[i] < GAZE_EVENT_COUNT);
        CHECK((e->event[i] == GAZE_EVENT_LOST) == !b->t.samples[i].valid);
    }
    for (int s = 0; s < e->saccade_count; s++) {
        const gaze_saccade *g = &e->saccades[s];
        CHECK(g->start <= g->end && g->start >= 0 && g->end <= b->t.duration);
        CHECK(s == 0 || e->saccades[s - 1].end <= g->start);
        CHECK(isfinite(g->amplitude_deg) && g->amplitude_deg >= 0 && g->peak_deg_s > 0);
        int i = gaze_sample_index(&b->t, g->end), sac = 0; /* the last of the samples at g->end */
        for (; i >= 0 && b->t.samples[i].t == g->end; i--)
            sac += e->event[i] == GAZE_EVENT_SACCADE;
        CHECK(sac > 0);
        const gaze_saccade *l = gaze_events_landed(e, g->end);
        CHECK(l && l->end == g->end);
    }
}

TEST(random_traces)
{
    builder b = {.rng = 12345};
    for (int iter = 0; iter < 300; iter++) {
        b.t.count = b.t.valid_count = 0;
        random_trace(&b, (int)(uniform(&b) * 400));
        gaze_events_desc ed = {0};
        if (iter % 3 == 1)
            ed = (gaze_events_desc){(float)(20 + 200 * uniform(&b)), (float)(1 + 15 * uniform(&b)),
                                    (float)(1 + 60 * uniform(&b))};
        gaze_events e = classify(&b.t, &ed);
        check_events(&b, &e);
        gaze_events_free(&e);
    }
    gaze_free(&b.t);
}

int main(void)
{
    RUN(names);
    RUN(defaults_filled_in);
    RUN(fixation_with_noise);
    RUN(saccade_of_known_amplitude);
    RUN(pursuit_at_15_deg_s);
    RUN(blink_is_lost_not_saccade);
    RUN(gap_is_not_saccade);
    RUN(one_sample_and_empty);
    RUN(repeated_and_irregular_times);
    RUN(bad_parameters);
    RUN(event_at_and_landed);
    RUN(labelled_trace_agrees);
    RUN(eyelink_saccades_agree);
    RUN(random_traces);
    return test_summary();
}
