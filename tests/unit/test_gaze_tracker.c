/* test_gaze_tracker.c: the eye tracker between the true gaze and the renderer (src/gaze/gaze_tracker.c):
 * latency counted in frames through the ring math, sample-and-hold, seeded noise in degrees, loss
 * policies, and the defaults reproducing gaze_at exactly. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "core/strbuf.h"
#include "fov/fov_ring.h"
#include "frame/frame.h"
#include "gaze/gaze.h"
#include "gaze/gaze_tracker.h"
#include "test.h"

static const display_desc k_disp = {1280, 720, 90.0f, 0.0f, 0.0f};

/* A fovsim CSV trace from rows "t,x,y,confidence" appended by the callers. */
typedef struct csv {
    char *text;
    size_t len, cap;
} csv;

static void row(csv *c, double t, double x, double y, double conf)
{
    if (c->len + 128 > c->cap) {
        c->cap = c->cap ? 2 * c->cap : 1 << 16;
        c->text = realloc(c->text, c->cap);
    }
    if (!c->len)
        c->len = (size_t)sprintf(c->text, "t,x,y,confidence\n");
    c->len += (size_t)sprintf(c->text + c->len, "%.6f,%.9g,%.9g,%g\n", t, x, y, conf);
}

static bool load(csv *c, gaze_trace *t)
{
    fs_status s = gaze_parse(c->text, (long)c->len, "synthetic", &(gaze_load_desc){.min_confidence = 0.6f}, t);
    free(c->text);
    memset(c, 0, sizeof *c);
    return s == FS_OK;
}

/* A 1 kHz trace over [0, end] s: fixation at x0 until `land`, at x1 from `land` on (the saccade
 * between the two samples around `land`), y at the centre. */
static bool saccade_trace(double land, double x0, double x1, double end, gaze_trace *t)
{
    csv c = {0};
    for (int k = 0; k <= (int)lround(end * 1000); k++)
        row(&c, k / 1000.0, k / 1000.0 < land - 1e-9 ? x0 : x1, 0.5, 1);
    return load(&c, t);
}

/* The angle (degrees, gaze_deg's convention) of a normalised coordinate. */
static double angle_x(double x)
{
    double f = 0.5 * k_disp.width / tan(0.5 * k_disp.hfov_deg * 3.14159265358979323846 / 180.0);
    return atan((x - 0.5) * k_disp.width / f) * 180.0 / 3.14159265358979323846;
}

static double angle_y(double y)
{
    double f = 0.5 * k_disp.width / tan(0.5 * k_disp.hfov_deg * 3.14159265358979323846 / 180.0);
    return atan((0.5 - y) * k_disp.height / f) * 180.0 / 3.14159265358979323846;
}

/* >>defaults */

/* All options 0: exactly gaze_at, through blinks, before the start and past the end. */
TEST(ideal_tracker_is_gaze_at)
{
    csv c = {0};
    for (int k = 0; k <= 400; k++)
        row(&c, k / 240.0, 0.3 + 0.4 * sin(k * 0.05), 0.5 + 0.3 * cos(k * 0.07), k > 100 && k < 140 ? 0 : 1);
    gaze_trace t;
    CHECK(load(&c, &t));
    gaze_tracker_desc ideal = {0};
    CHECK(gaze_tracker_is_ideal(&ideal));
    int differ = 0;
    for (int i = 0; i < 3000; i++) {
        double time = -0.1 + i * 0.000713;
        bool b1, b2;
        gaze_point g = gaze_at(&t, time, &b1);
        gaze_delivery d = gaze_tracker_at(&t, &ideal, &k_disp, time, &b2);
        differ += memcmp(&g.x, &d.x, sizeof g.x) || memcmp(&g.y, &d.y, sizeof g.y) || b1 != b2 || d.full;
    }
    CHECK(differ == 0);
    gaze_free(&t);
}

/* >>latency, counted in frames through the ring math */

/* Frames after the landing whose true gaze the composite shows from a coarse ring (not ring 0),
 * with the rings drawn around the delivered gaze. */
static int coarse_frames_after_landing(const gaze_trace *t, const gaze_tracker_desc *td, double fps, double land)
{
    fov_layout l = fov_layout_auto(&k_disp, 0.0f, 0.0f);
    int n = 0;
    for (int k = 0; k / fps < 1.0; k++) {
        double time = k / fps;
        if (time < land)
            continue;
        gaze_point truth = gaze_at(t, time, NULL);
        gaze_delivery sys = gaze_tracker_at(t, td, &k_disp, time, NULL);
        float ecc = fov_eccentricity_deg(&k_disp, sys.x * k_disp.width, sys.y * k_disp.height,
                                         truth.x * k_disp.width, truth.y * k_disp.height);
        n += fov_composite_weight(&l, ecc).ring > 0;
    }
    return n;
}

TEST(saccade_latency_counts_frames)
{
    const double land = 0.5;
    gaze_trace t;
    CHECK(saccade_trace(land, 0.3, 0.7, 1.0, &t)); /* about 38 degrees */
    fov_layout l = fov_layout_auto(&k_disp, 0.0f, 0.0f);
    CHECK(l.count > 1 && l.rings[0].outer_deg < 20.0f); /* the jump leaves the fovea */
    static const double fps[] = {24, 60, 90};
    static const float lat[] = {0, 20, 50, 80, 150};
    static const float rates[] = {0, 1000, 250};
    for (int r = 0; r < 3; r++)
        for (int f = 0; f < 3; f++)
            for (int i = 0; i < 5; i++) {
                gaze_tracker_desc td = {.latency_ms = lat[i], .rate_hz = rates[r]};
                int want = (int)ceil(lat[i] * fps[f] / 1000.0 - 1e-9);
                int got = coarse_frames_after_landing(&t, &td, fps[f], land);
                if (got != want)
                    fprintf(stderr, "  rate %g, %g fps, %g ms: %d frames in a coarse ring, want %d\n", rates[r],
                            fps[f], lat[i], got, want);
                CHECK(got == want);
            }
    gaze_free(&t);
}

/* Before t = latency nothing has been delivered: the first sample. */
TEST(latency_before_first_sample)
{
    gaze_trace t;
    CHECK(saccade_trace(0.02, 0.2, 0.8, 0.2, &t));
    gaze_tracker_desc td = {.latency_ms = 100};
    gaze_delivery d = gaze_tracker_at(&t, &td, &k_disp, 0.05, NULL);
    CHECK(d.x == 0.2f && !d.lost);
    d = gaze_tracker_at(&t, &td, &k_disp, 0.15, NULL);
    CHECK(d.x == 0.8f);
    gaze_free(&t);
}

/* >>sampling */

/* 90 Hz on a 240 Hz trace: the delivered gaze changes only at tracker sample times (+ latency),
 * holds each sample's true gaze, and changes at every sample of a moving trace. */
TEST(sample_and_hold_90_on_240)
{
    csv c = {0};
    for (int k = 0; k <= 480; k++)
        row(&c, k / 240.0, 0.2 + 0.3 * k / 480.0, 0.5 + 0.2 * sin(k * 0.03), 1);
    gaze_trace t;
    CHECK(load(&c, &t));
    static const float lat[] = {0, 30};
    for (int li = 0; li < 2; li++) {
        gaze_tracker_desc td = {.rate_hz = 90, .latency_ms = lat[li]};
        double L = lat[li] / 1000.0, step = 1.0 / 4000;
        gaze_delivery prev = gaze_tracker_at(&t, &td, &k_disp, 0.0, NULL);
        int changes = 0, off_sample = 0, wrong_value = 0;
        for (int i = 1; i <= 8000; i++) {
            double a = (i - 1) * step, b = i * step;
            gaze_delivery d = gaze_tracker_at(&t, &td, &k_disp, b, NULL);
            if (d.x != prev.x || d.y != prev.y) {
                changes++;
                /* a sample time k / 90 + L in (a, b] */
                long k = (long)floor((b - L) * 90.0 + 1e-6);
                off_sample += !(k / 90.0 + L > a - 1e-9 && k / 90.0 + L <= b + 1e-9);
            }
            long k = (long)floor((b - L) * 90.0 + 1e-6);
            gaze_point g = gaze_at(&t, k < 0 ? 0.0 : k / 90.0, NULL);
            wrong_value += d.x != g.x || d.y != g.y;
            prev = d;
        }
        CHECK(off_sample == 0);
        CHECK(wrong_value == 0);
        int want = (int)floor((2.0 - L) * 90.0 + 1e-6); /* samples 1 .. at 2 s - L */
        if (changes != want)
            fprintf(stderr, "  latency %g: %d changes, want %d\n", lat[li], changes, want);
        CHECK(changes == want);
    }
    gaze_free(&t);
}

/* >>noise */

#define NOISE_N 10000

/* The delivered angles of NOISE_N tracker samples of a fixation at (x, y). */
static void noise_run(uint32_t seed, float sd, double x, double y, bool reverse, double *ax, double *ay)
{
    csv c = {0};
    row(&c, 0, x, y, 1);
    row(&c, NOISE_N / 1000.0, x, y, 1);
    gaze_trace t;
    CHECK(load(&c, &t));
    gaze_tracker_desc td = {.rate_hz = 1000, .noise_deg = sd, .seed = seed};
    for (int j = 0; j < NOISE_N; j++) {
        int i = reverse ? NOISE_N - 1 - j : j;
        gaze_delivery d = gaze_tracker_at(&t, &td, &k_disp, i / 1000.0, NULL);
        CHECK(d.sample == i);
        ax[i] = angle_x(d.x) - angle_x(x);
        ay[i] = angle_y(d.y) - angle_y(y);
    }
    gaze_free(&t);
}

static void mean_sd(const double *v, int n, double *mean, double *sd)
{
    double s = 0, s2 = 0;
    for (int i = 0; i < n; i++)
        s += v[i];
    *mean = s / n;
    for (int i = 0; i < n; i++)
        s2 += (v[i] - *mean) * (v[i] - *mean);
    *sd = sqrt(s2 / (n - 1));
}

TEST(noise_is_seeded_and_has_its_sd)
{
    static double ax[NOISE_N], ay[NOISE_N], bx[NOISE_N], by[NOISE_N];
    /* Off-centre too: 35 degrees out, a small-angle mapping would be 1/cos^2 = 1.5x off. */
    static const double at[][2] = {{0.5, 0.5}, {0.85, 0.3}};
    for (int p = 0; p < 2; p++) {
        noise_run(7, 0.5f, at[p][0], at[p][1], false, ax, ay);
        double m, sd;
        mean_sd(ax, NOISE_N, &m, &sd);
        CHECK(fabs(sd - 0.5) < 0.025 && fabs(m) < 0.03);
        mean_sd(ay, NOISE_N, &m, &sd);
        CHECK(fabs(sd - 0.5) < 0.025 && fabs(m) < 0.03);
        /* the same seed, asked in the opposite order: bit for bit */
        noise_run(7, 0.5f, at[p][0], at[p][1], true, bx, by);
        CHECK(!memcmp(ax, bx, sizeof ax) && !memcmp(ay, by, sizeof ay));
    }
    noise_run(8, 0.5f, 0.5, 0.5, false, bx, by);
    noise_run(7, 0.5f, 0.5, 0.5, false, ax, ay);
    int same = 0;
    for (int i = 0; i < NOISE_N; i++)
        same += ax[i] == bx[i];
    CHECK(same < NOISE_N / 100);
    /* x and y independent */
    double sxy = 0;
    for (int i = 0; i < NOISE_N; i++)
        sxy += ax[i] * ay[i];
    CHECK(fabs(sxy / NOISE_N / 0.25) < 0.05);
}

/* The frame rate changes when the system is asked, not what a sample's noise is. */
TEST(noise_independent_of_frame_rate)
{
    gaze_trace t;
    CHECK(saccade_trace(0.5, 0.4, 0.6, 1.0, &t));
    gaze_tracker_desc td = {.rate_hz = 120, .noise_deg = 1.0f, .seed = 3, .latency_ms = 25};
    int mismatched = 0, compared = 0;
    for (int k = 0; k < 90; k++) { /* 90 fps against 1000 fps */
        gaze_delivery a = gaze_tracker_at(&t, &td, &k_disp, k / 90.0, NULL);
        for (int j = 0; j < 1000; j++) {
            gaze_delivery b = gaze_tracker_at(&t, &td, &k_disp, j / 1000.0, NULL);
            if (b.sample == a.sample) {
                compared++;
                mismatched += a.x != b.x || a.y != b.y;
            }
        }
    }
    CHECK(compared > 500 && mismatched == 0);
    /* the noise moves the gaze */
    gaze_delivery n = gaze_tracker_at(&t, &td, &k_disp, 0.2, NULL);
    CHECK(n.x != 0.4f);
    gaze_free(&t);
}

TEST(offset_deg_is_exact)
{
    double x = 0.9, y = 0.2;
    double a0 = angle_x(x), b0 = angle_y(y);
    gaze_offset_deg(&k_disp, 10.0, -5.0, &x, &y);
    CHECK_NEAR(angle_x(x) - a0, 10.0, 1e-9);
    CHECK_NEAR(angle_y(y) - b0, -5.0, 1e-9);
}

/* >>loss */

/* 100 Hz tracker on a trace with a gap (0.4 .. 0.6 s invalid) over a saccade 0.3 -> 0.7. */
static bool gap_trace(gaze_trace *t)
{
    csv c = {0};
    for (int k = 0; k <= 1000; k++) {
        double s = k / 1000.0;
        row(&c, s, s < 0.5 ? 0.3 : 0.7, 0.5, s > 0.4 + 1e-9 && s < 0.6 - 1e-9 ? 0 : 1);
    }
    return load(&c, t);
}

TEST(loss_policies)
{
    gaze_trace t;
    CHECK(gap_trace(&t));
    gaze_tracker_desc hold = {.rate_hz = 100, .loss = GAZE_LOSS_HOLD};
    gaze_tracker_desc centre = {.rate_hz = 100, .loss = GAZE_LOSS_CENTRE};
    gaze_tracker_desc full = {.rate_hz = 100, .loss = GAZE_LOSS_FULL};
    int lost = 0;
    for (int i = 0; i < 100; i++) {
        double time = i / 100.0 + 0.005;
        bool in_gap = time > 0.41 && time < 0.6;
        gaze_delivery h = gaze_tracker_at(&t, &hold, &k_disp, time, NULL);
        gaze_delivery c = gaze_tracker_at(&t, &centre, &k_disp, time, NULL);
        gaze_delivery f = gaze_tracker_at(&t, &full, &k_disp, time, NULL);
        lost += h.lost;
        CHECK(h.lost == in_gap && c.lost == in_gap && f.lost == in_gap);
        CHECK(!h.full && !c.full && f.full == in_gap);
        if (in_gap) {
            CHECK(h.x == 0.3f && h.sample == 40); /* the last good sample, at 0.40 s */
            CHECK(c.x == 0.5f && c.y == 0.5f);
        } else {
            CHECK(h.x == (time < 0.5 ? 0.3f : 0.7f) && c.x == h.x && f.x == h.x);
        }
    }
    CHECK(lost == 19);
    /* the trace's own samples: lost inside the gap too */
    gaze_tracker_desc own = {.loss = GAZE_LOSS_FULL};
    CHECK(gaze_tracker_at(&t, &own, &k_disp, 0.5, NULL).full);
    CHECK(!gaze_tracker_at(&t, &own, &k_disp, 0.3, NULL).full);
    /* past the end: held, never lost */
    CHECK(!gaze_tracker_at(&t, &full, &k_disp, 5.0, NULL).lost);
    gaze_free(&t);
}

/* A full frame: every ring's footprint the display at one pixel per pixel; the layout's ring
 * count kept (the renderer's targets); the true gaze kept apart. */
TEST(full_res_frame)
{
    fov_layout l = fov_layout_auto(&k_disp, 0.0f, 0.0f);
    frame_record fr = {0};
    fr.view_proj = m4_identity();
    frame_record_set_gaze(&fr, &l, &k_disp, 0.3f, 0.5f);
    CHECK(fr.true_gaze[0] == 0.3f && fr.true_gaze_px[0] == fr.gaze_px[0] && !fr.full_res);
    CHECK(fr.ring_rect[0].block == 1 && fr.ring_rect[0].x1 < k_disp.width); /* a fovea, not the display */
    frame_record_set_true_gaze(&fr, &k_disp, 0.7f, 0.5f);
    CHECK(fr.gaze[0] == 0.3f && fr.true_gaze[0] == 0.7f && fr.true_gaze_deg[0] > 15.0f);
    frame_record_set_full_res(&fr, &k_disp);
    CHECK(fr.full_res && fr.ring_count == l.count);
    for (int i = 0; i < fr.ring_count; i++)
        CHECK(fr.ring_rect[i].x0 == 0 && fr.ring_rect[i].y0 == 0 && fr.ring_rect[i].x1 == k_disp.width &&
              fr.ring_rect[i].y1 == k_disp.height && fr.ring_rect[i].block == 1 &&
              fr.ring_rect[i].width == k_disp.width);
}

/* >>options */

TEST(names_and_merge)
{
    CHECK(gaze_loss_parse("hold") == GAZE_LOSS_HOLD && gaze_loss_parse("centre") == GAZE_LOSS_CENTRE);
    CHECK(gaze_loss_parse("center") == GAZE_LOSS_CENTRE && gaze_loss_parse("full") == GAZE_LOSS_FULL);
    CHECK(gaze_loss_parse("hld") == GAZE_LOSS_COUNT && gaze_loss_parse(NULL) == GAZE_LOSS_COUNT);
    CHECK(!strcmp(gaze_loss_name(GAZE_LOSS_FULL), "full") && gaze_loss_name(GAZE_LOSS_COUNT) == NULL);
    gaze_tracker_opts cli = {.desc = {.latency_ms = 0, .noise_deg = 2}, .latency_set = true};
    gaze_tracker_opts sc = {.desc = {.latency_ms = 50, .rate_hz = 120, .noise_deg = 1, .loss = GAZE_LOSS_FULL},
                            .latency_set = true, .rate_set = true, .loss_set = true};
    gaze_tracker_desc m = gaze_tracker_merge(&cli, &sc);
    CHECK(m.latency_ms == 0 && m.rate_hz == 120 && m.noise_deg == 0 && m.loss == GAZE_LOSS_FULL);
    char buf[160];
    gaze_tracker_format(&m, buf, sizeof buf);
    CHECK(!strcmp(buf, "latency 0 ms, rate 120 Hz, noise 0 deg seed 0, loss full"));
}

int main(void)
{
    RUN(ideal_tracker_is_gaze_at);
    RUN(saccade_latency_counts_frames);
    RUN(latency_before_first_sample);
    RUN(sample_and_hold_90_on_240);
    RUN(noise_is_seeded_and_has_its_sd);
    RUN(noise_independent_of_frame_rate);
    RUN(offset_deg_is_exact);
    RUN(loss_policies);
    RUN(full_res_frame);
    RUN(names_and_merge);
    return test_summary();
}
