/* test_camera.c: camera_path_eval and camera_path_cut_between (src/scene/scene.c). */
#include <math.h>

#include "scene/scene.h"
#include "test.h"

static camera_key key(float t, vec3 p, vec3 target, float hfov, bool cut)
{
    return (camera_key){.time = t, .position = p, .target = target, .hfov_deg = hfov, .cut = cut};
}

static float dist3(vec3 a, vec3 b) { return v3_len(v3_sub(a, b)); }

/* Five keys, unevenly spaced in time, on a curved path with a moving target. */
static camera_path curved_path(void)
{
    camera_path p = {0};
    p.keys[0] = key(0.0f, v3(0, 1.6f, 5), v3(0, 1, 0), 90, false);
    p.keys[1] = key(0.4f, v3(1, 1.8f, 4), v3(0.5f, 1, 0), 80, false);
    p.keys[2] = key(1.5f, v3(3, 2.5f, 1), v3(1, 1.2f, -1), 60, false);
    p.keys[3] = key(1.7f, v3(2, 2.0f, -2), v3(0, 1, -3), 70, false);
    p.keys[4] = key(4.0f, v3(-2, 1.0f, -6), v3(-1, 0.5f, -9), 100, false);
    p.count = 5;
    return p;
}

TEST(key_times_return_key_values)
{
    camera_path p = curved_path();
    for (int i = 0; i < p.count; i++) {
        camera_state s = camera_path_eval(&p, p.keys[i].time);
        CHECK(dist3(s.position, p.keys[i].position) <= 1e-5f);
        CHECK(dist3(s.target, p.keys[i].target) <= 1e-5f);
        CHECK_NEAR(s.hfov_deg, p.keys[i].hfov_deg, 1e-5);
    }
}

TEST(clamps_before_and_after)
{
    camera_path p = curved_path();
    camera_state a = camera_path_eval(&p, -3.0f), b = camera_path_eval(&p, 99.0f);
    CHECK(dist3(a.position, p.keys[0].position) <= 1e-6f);
    CHECK(dist3(a.target, p.keys[0].target) <= 1e-6f);
    CHECK_NEAR(a.hfov_deg, 90, 1e-6);
    CHECK(dist3(b.position, p.keys[4].position) <= 1e-6f);
    CHECK(dist3(b.target, p.keys[4].target) <= 1e-6f);
    CHECK_NEAR(b.hfov_deg, 100, 1e-6);
    camera_state n = camera_path_eval(&p, NAN);
    CHECK(dist3(n.position, p.keys[0].position) <= 1e-6f);
    camera_state inf = camera_path_eval(&p, INFINITY);
    CHECK(dist3(inf.position, p.keys[4].position) <= 1e-6f);
}

TEST(continuous_across_interior_keys)
{
    camera_path p = curved_path();
    const float e = 1e-3f;
    for (int i = 1; i < p.count - 1; i++) {
        float t = p.keys[i].time;
        camera_state a = camera_path_eval(&p, t - e), m = camera_path_eval(&p, t), b = camera_path_eval(&p, t + e);
        /* Position: small step -> small change. */
        CHECK(dist3(a.position, m.position) < 0.05f);
        CHECK(dist3(b.position, m.position) < 0.05f);
        CHECK(dist3(a.target, m.target) < 0.05f);
        CHECK(fabsf(a.hfov_deg - b.hfov_deg) < 0.2f);
        /* Velocity: the one-sided difference quotients agree (C1 with non-uniform spacing). */
        vec3 v0 = v3_scale(v3_sub(m.position, a.position), 1.0f / e);
        vec3 v1 = v3_scale(v3_sub(b.position, m.position), 1.0f / e);
        CHECK(dist3(v0, v1) < 0.05f * v3_len(v1) + 0.05f);
        vec3 w0 = v3_scale(v3_sub(m.target, a.target), 1.0f / e);
        vec3 w1 = v3_scale(v3_sub(b.target, m.target), 1.0f / e);
        CHECK(dist3(w0, w1) < 0.05f * v3_len(w1) + 0.05f);
    }
    /* And everywhere else: no jumps anywhere along the path. */
    camera_state prev = camera_path_eval(&p, 0);
    for (int k = 1; k <= 4000; k++) {
        camera_state s = camera_path_eval(&p, 4.0f * (float)k / 4000.0f);
        CHECK(dist3(s.position, prev.position) < 0.05f);
        prev = s;
    }
}

TEST(hfov_is_linear)
{
    camera_path p = curved_path();
    camera_state s = camera_path_eval(&p, 0.2f); /* halfway between keys 0 and 1 */
    CHECK_NEAR(s.hfov_deg, 85, 1e-4);
    s = camera_path_eval(&p, 1.5f + 0.05f); /* a quarter of the way from 60 to 70 */
    CHECK_NEAR(s.hfov_deg, 62.5, 1e-3);
}

TEST(cut_key_is_never_blended)
{
    camera_path p = {0};
    p.keys[0] = key(0, v3(0, 1, 0), v3(0, 1, -10), 90, false);
    p.keys[1] = key(1, v3(1, 1, 0), v3(1, 1, -10), 80, false);
    p.keys[2] = key(2, v3(50, 9, 50), v3(50, 9, 0), 40, true);
    p.keys[3] = key(3, v3(52, 9, 50), v3(52, 9, 0), 50, false);
    p.count = 4;
    /* Just before the cut: the previous key held, nothing of the cut key leaks in. */
    camera_state before = camera_path_eval(&p, 2.0f - 1e-4f);
    CHECK(dist3(before.position, p.keys[1].position) <= 1e-6f);
    CHECK(dist3(before.target, p.keys[1].target) <= 1e-6f);
    CHECK_NEAR(before.hfov_deg, 80, 1e-6);
    camera_state mid = camera_path_eval(&p, 1.5f);
    CHECK(dist3(mid.position, p.keys[1].position) <= 1e-6f);
    /* At the cut: exactly the cut key. */
    camera_state at = camera_path_eval(&p, 2.0f);
    CHECK(dist3(at.position, p.keys[2].position) <= 1e-6f);
    CHECK(dist3(at.target, p.keys[2].target) <= 1e-6f);
    CHECK_NEAR(at.hfov_deg, 40, 1e-6);

    /* The spline before the cut does not see keys after it and vice versa: moving keys on one
     * side changes nothing on the other. */
    camera_state s01 = camera_path_eval(&p, 0.5f), s23 = camera_path_eval(&p, 2.5f);
    camera_path q = p;
    q.keys[2].position = v3(-100, -100, -100);
    q.keys[3].position = v3(-200, 5, 5);
    camera_state q01 = camera_path_eval(&q, 0.5f);
    CHECK(dist3(s01.position, q01.position) <= 1e-6f);
    camera_path r = p;
    r.keys[0].position = v3(9, 9, 9);
    r.keys[1].position = v3(-30, 40, 7);
    camera_state r23 = camera_path_eval(&r, 2.5f);
    CHECK(dist3(s23.position, r23.position) <= 1e-6f);
    /* The first segment of a spline is the two-key case: straight line between them. */
    CHECK_NEAR(s23.position.y, 9, 1e-5);
    CHECK_NEAR(s23.position.z, 50, 1e-5);
    CHECK(s23.position.x > 50 && s23.position.x < 52);
}

TEST(cut_between)
{
    camera_path p = {0};
    p.keys[0] = key(0, v3(0, 0, 0), v3(0, 0, -1), 0, false);
    p.keys[1] = key(1, v3(1, 0, 0), v3(1, 0, -1), 0, false);
    p.keys[2] = key(2, v3(5, 0, 0), v3(5, 0, -1), 0, true);
    p.keys[3] = key(3, v3(6, 0, 0), v3(6, 0, -1), 0, false);
    p.count = 4;
    CHECK(camera_path_cut_between(&p, 1.9f, 2.0f));  /* (t0, t1] includes t1 */
    CHECK(camera_path_cut_between(&p, 1.0f, 2.5f));
    CHECK(!camera_path_cut_between(&p, 2.0f, 2.1f)); /* excludes t0 */
    CHECK(!camera_path_cut_between(&p, 0.0f, 1.99f));
    CHECK(!camera_path_cut_between(&p, 2.5f, 3.0f));
    CHECK(!camera_path_cut_between(&p, 0.5f, 1.5f)); /* key 1 is no cut */
    p.keys[2].cut = false;
    CHECK(!camera_path_cut_between(&p, 1.0f, 2.5f));
}

TEST(one_key_is_constant)
{
    camera_path p = {0};
    p.keys[0] = key(0.5f, v3(1, 2, 3), v3(4, 5, 6), 0, false);
    p.count = 1;
    for (float t = -2; t <= 5; t += 0.25f) {
        camera_state s = camera_path_eval(&p, t);
        CHECK(dist3(s.position, v3(1, 2, 3)) == 0);
        CHECK(dist3(s.target, v3(4, 5, 6)) == 0);
        CHECK(s.hfov_deg == 0); /* 0 = the display's, passed through */
    }
    CHECK(!camera_path_cut_between(&p, -1, 10));
}

/* A straight dolly along +Z with collinear keys: z must never decrease and x, y never leave the
 * line, however unevenly the keys are spaced in time and distance. */
static void check_monotone_dolly(const float *times, const float *zs, int n)
{
    camera_path p = {0};
    for (int i = 0; i < n; i++)
        p.keys[i] = key(times[i], v3(0.5f, 1.6f, zs[i]), v3(0.5f, 1.6f, -50), 0, false);
    p.count = n;
    float prev = -INFINITY;
    const int steps = 20000;
    for (int k = 0; k <= steps; k++) {
        float t = times[0] + (times[n - 1] - times[0]) * (float)k / (float)steps;
        camera_state s = camera_path_eval(&p, t);
        CHECK(s.position.z >= prev - 1e-5f);
        CHECK(s.position.z >= zs[0] - 1e-5f && s.position.z <= zs[n - 1] + 1e-5f);
        CHECK_NEAR(s.position.x, 0.5, 1e-5);
        CHECK_NEAR(s.position.y, 1.6, 1e-5);
        CHECK_NEAR(s.target.z, -50, 1e-5);
        prev = s.position.z;
    }
}

TEST(non_uniform_dolly_never_runs_backwards)
{
    /* Speeds 1 then 10: plain time-based Catmull-Rom would back up in the first segment. */
    check_monotone_dolly((const float[]){0, 1, 2}, (const float[]){0, 1, 11}, 3);
    /* Clustered keys in time, far apart in space, and the reverse. */
    check_monotone_dolly((const float[]){0, 0.1f, 0.2f, 4}, (const float[]){0, 0.1f, 10, 11}, 4);
    check_monotone_dolly((const float[]){0, 3.8f, 3.9f, 4}, (const float[]){0, 0.2f, 9, 30}, 4);
    /* The fence scene's geometric dolly (1.5 m -> 40 m). */
    check_monotone_dolly((const float[]){0, 1, 2, 3, 4}, (const float[]){1.5f, 3.4f, 7.75f, 17.6f, 40}, 5);
    /* A pause (two equal keys) must stop, not wander off and come back. */
    check_monotone_dolly((const float[]){0, 1, 2, 3}, (const float[]){0, 2, 2, 5}, 4);
}

TEST(even_motion_is_reproduced_exactly)
{
    /* Keys moving at a constant 3 units/s with uneven time spacing: interior segments are exactly
     * linear in time (the tangents are velocities, not index differences). */
    const float times[] = {0, 0.3f, 1.0f, 1.2f, 2.5f, 4.0f};
    camera_path p = {0};
    for (int i = 0; i < 6; i++)
        p.keys[i] = key(times[i], v3(3 * times[i], 0, 0), v3(0, 0, -1), 0, false);
    p.count = 6;
    for (float t = 0.3f; t <= 2.5f; t += 0.01f) {
        camera_state s = camera_path_eval(&p, t);
        CHECK_NEAR(s.position.x, 3 * t, 1e-4);
    }
}

TEST(degenerate_paths)
{
    camera_path empty = {0};
    camera_state s = camera_path_eval(&empty, 1.0f);
    CHECK(isfinite(s.position.x) && isfinite(s.target.z));
    CHECK(!camera_path_cut_between(&empty, 0, 1));
    /* Equal times from a hand-built path: finite, no division by zero. */
    camera_path p = {0};
    p.keys[0] = key(1, v3(0, 0, 0), v3(0, 0, -1), 0, false);
    p.keys[1] = key(1, v3(1, 0, 0), v3(1, 0, -1), 0, false);
    p.keys[2] = key(2, v3(2, 0, 0), v3(2, 0, -1), 0, false);
    p.count = 3;
    for (float t = 0; t <= 3; t += 0.125f) {
        s = camera_path_eval(&p, t);
        CHECK(isfinite(s.position.x) && isfinite(s.position.y) && isfinite(s.position.z));
    }
}

/* Two equal keys hold the camera exactly (docs/metrics.md "Still camera"): the built-in wind scene's two keys gave
 * positions an ulp off the key between them, and its frames' view-projections differed. Also a
 * still span followed by a move: the still span is the key itself. */
TEST(two_equal_keys_hold_the_key_exactly)
{
    camera_path p = {0};
    p.keys[0] = key(0.0f, v3(0, 1.7f, 5), v3(0, 2.5f, -4), 0, false);
    p.keys[1] = key(4.0f, v3(0, 1.7f, 5), v3(0, 2.5f, -4), 0, false);
    p.count = 2;
    int off = 0;
    for (int f = 0; f <= 96; f++) {
        camera_state s = camera_path_eval(&p, (float)f / 24.0f);
        off += memcmp(&s.position, &p.keys[0].position, sizeof s.position) != 0 ||
               memcmp(&s.target, &p.keys[0].target, sizeof s.target) != 0;
    }
    CHECK(off == 0);
    p.keys[2] = key(6.0f, v3(3, 1.7f, 5), v3(3, 2.5f, -4), 0, false);
    p.count = 3;
    off = 0;
    for (int f = 0; f <= 96; f++) {
        camera_state s = camera_path_eval(&p, (float)f / 24.0f);
        off += memcmp(&s.position, &p.keys[0].position, sizeof s.position) != 0;
    }
    CHECK(off == 0);
    camera_state m = camera_path_eval(&p, 5.0f); /* the moving span still moves */
    CHECK(m.position.x > 0.5f && m.position.x < 2.5f);
}

int main(void)
{
    RUN(key_times_return_key_values);
    RUN(clamps_before_and_after);
    RUN(continuous_across_interior_keys);
    RUN(hfov_is_linear);
    RUN(cut_key_is_never_blended);
    RUN(cut_between);
    RUN(one_key_is_constant);
    RUN(non_uniform_dolly_never_runs_backwards);
    RUN(even_motion_is_reproduced_exactly);
    RUN(degenerate_paths);
    RUN(two_equal_keys_hold_the_key_exactly);
    return test_summary();
}
