/* test_compare_saccade.c: which frames compare counts as post-saccade (src/commands/compare_saccade.c):
 * the k-th frame at or after a landing, within 150 ms, not in the next saccade; the sums behind
 * summary.json's post_saccade (means, coverage as a ratio of sums, per frame after the landing). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands/compare_saccade.h"
#include "core/strbuf.h"
#include "test.h"

/* A 1 kHz trace at y 0.5: fixation at x 0.3, a 30 ms saccade to 0.7 ending at `land` s, fixation,
 * and a second saccade starting at `second` s back to 0.3. */
static bool saccades(gaze_trace *t, double land, double second)
{
    sbuf b = {0};
    sb_puts(&b, "t,x,y\n");
    for (int k = 0; k <= 1500; k++) {
        double s = k / 1000.0, x;
        if (s < land - 0.03)
            x = 0.3;
        else if (s < land)
            x = 0.3 + 0.4 * (s - (land - 0.03)) / 0.03;
        else if (s < second)
            x = 0.7;
        else if (s < second + 0.03)
            x = 0.7 - 0.4 * (s - second) / 0.03;
        else
            x = 0.3;
        sb_printf(&b, "%.3f,%.9f,0.5\n", s, x);
    }
    fs_status st = gaze_parse(b.p, (long)b.len, "saccades", NULL, t);
    free(b.p);
    return st == FS_OK;
}

static session *session_with(const gaze_trace *t)
{
    session *s = calloc(1, sizeof *s);
    s->gaze = *t;
    s->pl.width = 320;
    s->pl.height = 180;
    s->sc.display.hfov_deg = 90.0f;
    return s;
}

/* The trace of saccades(land, second), a session holding it and the study at fps. */
typedef struct fixture {
    gaze_trace t;
    session *s;
    saccade_study ss;
} fixture;

static bool fixture_begin(fixture *fx, double land, double second, float fps)
{
    memset(fx, 0, sizeof *fx);
    if (!saccades(&fx->t, land, second))
        return false;
    fx->s = session_with(&fx->t);
    return saccade_study_begin(&fx->ss, fx->s, fps) == FS_OK;
}

static void fixture_end(fixture *fx)
{
    saccade_study_end(&fx->ss);
    free(fx->s);
    gaze_free(&fx->t);
}

TEST(post_saccade_frames)
{
    fixture fx;
    CHECK(fixture_begin(&fx, 0.633, 1.2, 24.0f));
    const saccade_study *ss = &fx.ss;
    const gaze_trace *t = &fx.t;
    CHECK(ss->on && ss->frames_after == 4); /* ceil(150 ms * 24 fps) */
    CHECK(ss->ev.saccade_count == 2);
    double land = ss->ev.saccade_count ? ss->ev.saccades[0].end : 0.0;
    CHECK(land > 0.6 && land < 0.66);
    int first = (int)ceil(land * 24.0 - 1e-6), last_post = -1;
    for (int i = 0; i < 28; i++) { /* up to 1.125 s: before the second saccade */
        float time = (float)i / 24.0f;
        saccade_frame f = saccade_study_frame(ss, t, time);
        bool in_saccade = f.event == GAZE_EVENT_SACCADE;
        bool want = !in_saccade && i >= first && time - land < 0.150;
        CHECK((f.post >= 0) == want);
        if (f.post >= 0) {
            CHECK(f.post == i - first && f.saccade == 0);
            CHECK(fabs(f.ms_after - (time - land) * 1e3) < 1e-3);
            last_post = i;
        }
        if (i < first - 1)
            CHECK(f.post < 0 && f.saccade < 0);
    }
    int want_last = first;
    while ((float)(want_last + 1) / 24.0f - land < 0.150)
        want_last++;
    CHECK(last_post == want_last && last_post >= first + 2); /* 3 or 4 frames within 150 ms at 24 fps */
    fixture_end(&fx);
}

/* A saccade that starts within 150 ms of the last landing ends that landing's frames. */
TEST(next_saccade_ends_the_window)
{
    fixture fx;
    CHECK(fixture_begin(&fx, 0.5, 0.56, 100.0f));
    int post = 0, in_second = 0;
    for (int i = 0; i < 100; i++) {
        float time = (float)i / 100.0f;
        saccade_frame f = saccade_study_frame(&fx.ss, &fx.t, time);
        post += f.post >= 0 && f.saccade == 0;
        in_second += f.event == GAZE_EVENT_SACCADE && time > 0.55 && f.post >= 0;
    }
    CHECK(post >= 3 && post <= 7); /* 0.5 .. ~0.56 s at 100 fps */
    CHECK(in_second == 0);
    fixture_end(&fx);
}

TEST(sums_and_results)
{
    fixture fx;
    CHECK(fixture_begin(&fx, 0.633, 1.2, 24.0f));
    saccade_study *ss = &fx.ss;
    saccade_frame f0 = {GAZE_EVENT_FIXATION, 0, 0, 30.0}, f1 = {GAZE_EVENT_FIXATION, 1, 0, 71.0};
    ring_metrics a = {.pixels = 100, .coverage = 0.5, .ref_coverage = 1.0, .rmse = 0.2, .flip = 0.4};
    ring_metrics b = {.pixels = 300, .coverage = 1.0, .ref_coverage = 1.0, .rmse = 0.1, .flip = 0.2};
    saccade_study_add(ss, 1, "hashed", 16, 0.667f, &f0, &a);
    saccade_study_add(ss, 1, "hashed", 17, 0.708f, &f1, &b);
    saccade_frame none = {GAZE_EVENT_FIXATION, -1, -1, 0.0};
    saccade_study_add(ss, 1, "hashed", 18, 0.75f, &none, &b); /* not post-saccade: ignored */
    post_result all = saccade_study_result(ss, 1, -1), k0 = saccade_study_result(ss, 1, 0);
    CHECK(all.frames == 2 && fabs(all.rmse - 0.15) < 1e-12 && fabs(all.flip - 0.3) < 1e-12);
    CHECK(fabs(all.coverage_ratio - (50.0 + 300.0) / 400.0) < 1e-12); /* ratio of sums, not mean of ratios */
    CHECK(k0.frames == 1 && fabs(k0.coverage_ratio - 0.5) < 1e-12);
    CHECK(saccade_study_result(ss, 0, -1).frames == 0 && saccade_study_result(ss, 0, -1).rmse == -1.0);
    CHECK(ss->csv.p && strstr(ss->csv.p, "\n16,0.666999996,hashed,0,") != NULL);
    CHECK(ss->csv.p && !strstr(ss->csv.p, "\n18,"));
    saccade_study_count(ss, &f0);
    saccade_study_count(ss, &f1);
    CHECK(ss->landings == 1 && ss->event_frames[GAZE_EVENT_FIXATION] == 2);
    fixture_end(&fx);
}

/* Without a trace: nothing classified, every frame a fixation, nothing written. */
TEST(no_trace)
{
    session *s = calloc(1, sizeof *s);
    s->pl.width = 64;
    s->pl.height = 64;
    s->sc.display.hfov_deg = 90.0f;
    saccade_study ss;
    CHECK(saccade_study_begin(&ss, s, 24.0f) == FS_OK);
    CHECK(!ss.on);
    saccade_frame f = saccade_study_frame(&ss, &s->gaze, 1.0);
    CHECK(f.event == GAZE_EVENT_FIXATION && f.post == -1);
    CHECK(saccade_study_write(&ss, "/nonexistent/dir") == FS_OK);
    saccade_study_end(&ss);
    free(s);
}

int main(void)
{
    RUN(post_saccade_frames);
    RUN(next_saccade_ends_the_window);
    RUN(sums_and_results);
    RUN(no_trace);
    return test_summary();
}
