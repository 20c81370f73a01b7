/* fmath: the matrices every frame depends on. */
#include "core/fmath.h"
#include "test.h"

static void apply(mat4 m, vec3 p, float out[4])
{
    for (int r = 0; r < 4; r++)
        out[r] = m.m[r] * p.x + m.m[4 + r] * p.y + m.m[8 + r] * p.z + m.m[12 + r];
}

TEST(look_at_puts_target_on_the_view_axis)
{
    vec3 eye = v3(3, 2, 5), target = v3(-1, 0.5f, -4);
    mat4 v = m4_look_at(eye, target, v3(0, 1, 0));
    vec3 t = m4_point(v, target);
    CHECK_NEAR(t.x, 0, 1e-5);
    CHECK_NEAR(t.y, 0, 1e-5);
    CHECK(t.z < 0); /* in front: -Z */
    vec3 e = m4_point(v, eye);
    CHECK_NEAR(v3_len(e), 0, 1e-5);
    /* Straight down does not produce NaN. */
    mat4 d = m4_look_at(v3(0, 10, 0), v3(0, 0, 0), v3(0, 1, 0));
    for (int i = 0; i < 16; i++)
        CHECK(isfinite(d.m[i]));
}

TEST(perspective_maps_the_horizontal_fov_edge_to_ndc_one)
{
    float hfov = 90.0f * (float)FS_PI / 180.0f;
    mat4 p = m4_perspective_hfov(hfov, 16.0f / 9.0f, 0.1f, 100.0f);
    float c[4];
    apply(p, v3(5, 0, -5), c); /* 45 degrees right */
    CHECK_NEAR(c[0] / c[3], 1.0, 1e-5);
    apply(p, v3(0, 0, -0.1f), c);
    CHECK_NEAR(c[2] / c[3], -1.0, 1e-4);
    apply(p, v3(0, 0, -100), c);
    CHECK_NEAR(c[2] / c[3], 1.0, 1e-4);
    /* Vertical extent follows the aspect ratio. */
    apply(p, v3(0, 5.0f * 9.0f / 16.0f, -5), c);
    CHECK_NEAR(c[1] / c[3], 1.0, 1e-5);
}

TEST(invert_and_trs)
{
    float t[3] = {1, -2, 3}, q[4] = {0.2f, 0.3f, -0.1f, 0.927362f}, s[3] = {2, 3, 0.5f};
    float l = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++)
        q[i] /= l;
    mat4 m = m4_trs(t, q, s), inv;
    CHECK(m4_invert(m, &inv));
    mat4 id = m4_mul(m, inv);
    for (int i = 0; i < 16; i++)
        CHECK_NEAR(id.m[i], (i % 5 == 0) ? 1.0 : 0.0, 1e-5);
    mat4 sing = m4_scale(v3(1, 0, 1));
    CHECK(!m4_invert(sing, &inv));
    /* Normal matrix keeps normals perpendicular under non-uniform scale. */
    mat4 ns = m4_normal_matrix(m4_scale(v3(4, 1, 1)));
    vec3 n = m4_dir(ns, v3_norm_or(v3(1, 1, 0), v3(0, 1, 0)));
    vec3 tangent = m4_dir(m4_scale(v3(4, 1, 1)), v3(1, -1, 0));
    CHECK_NEAR(v3_dot(n, tangent), 0, 1e-5);
    /* Translation of the TRS lands in the last column. */
    CHECK_NEAR(m.m[12], 1, 0);
    CHECK_NEAR(m.m[13], -2, 0);
    CHECK_NEAR(m.m[14], 3, 0);
}

TEST(norm_or_falls_back)
{
    vec3 f = v3_norm_or(v3(0, 0, 0), v3(0, 1, 0));
    CHECK(f.y == 1.0f);
    f = v3_norm_or(v3(NAN, 0, 0), v3(1, 0, 0));
    CHECK(f.x == 1.0f);
    f = v3_norm_or(v3(1e-30f, 0, 0), v3(0, 1, 0)); /* denormal length squared */
    CHECK(isfinite(f.x) && isfinite(f.y));
}

/* A random axis-aligned box: centre within +-spread/2 on each axis, half size up to `half`. */
static void random_box(unsigned *seed, float spread, float half, vec3 *lo, vec3 *hi)
{
    float c[3], h[3];
    for (int i = 0; i < 3; i++) {
        *seed = *seed * 1664525u + 1013904223u;
        c[i] = ((float)(*seed >> 8) / 16777216.0f - 0.5f) * spread;
        *seed = *seed * 1664525u + 1013904223u;
        h[i] = (float)(*seed >> 8) / 16777216.0f * half;
    }
    *lo = v3(c[0] - h[0], c[1] - h[1], c[2] - h[2]);
    *hi = v3(c[0] + h[0], c[1] + h[1], c[2] + h[2]);
}

TEST(box_culling_is_conservative)
{
    mat4 vp = m4_mul(m4_perspective_hfov((float)FS_PI / 2, 16.0f / 9.0f, 0.1f, 100.0f),
                     m4_look_at(v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0)));
    CHECK(!m4_box_outside_clip(vp, v3(-1, -1, -6), v3(1, 1, -4)));     /* straight ahead */
    CHECK(m4_box_outside_clip(vp, v3(-1, -1, 4), v3(1, 1, 6)));        /* behind the camera */
    CHECK(m4_box_outside_clip(vp, v3(20, -1, -6), v3(22, 1, -4)));     /* far to the right */
    CHECK(m4_box_outside_clip(vp, v3(-1, -1, -300), v3(1, 1, -200)));  /* beyond the far plane */
    CHECK(!m4_box_outside_clip(vp, v3(-50, -50, -50), v3(50, 50, 50))); /* around the camera */
    /* A box straddling a frustum corner (every corner outside some plane, none all outside the
     * same one) is kept: conservative. */
    CHECK(!m4_box_outside_clip(vp, v3(4, 2.5f, -6), v3(8, 6, -4)));
    /* Random boxes: whenever a box is culled, none of many points inside it is in the frustum. */
    unsigned seed = 7;
    int culled = 0;
    for (int k = 0; k < 2000; k++) {
        vec3 lo, hi;
        random_box(&seed, 60.0f, 3.0f, &lo, &hi);
        if (!m4_box_outside_clip(vp, lo, hi))
            continue;
        culled++;
        for (int s = 0; s < 64; s++) {
            vec3 q = v3(lo.x + (hi.x - lo.x) * (float)(s & 3) / 3, lo.y + (hi.y - lo.y) * (float)((s >> 2) & 3) / 3,
                        lo.z + (hi.z - lo.z) * (float)(s >> 4) / 3);
            float v[4];
            for (int r = 0; r < 4; r++)
                v[r] = vp.m[r] * q.x + vp.m[4 + r] * q.y + vp.m[8 + r] * q.z + vp.m[12 + r];
            bool inside = fabsf(v[0]) <= v[3] && fabsf(v[1]) <= v[3] && fabsf(v[2]) <= v[3];
            CHECK(!inside);
        }
    }
    CHECK(culled > 100);
}

/* The screen rectangle of a box holds the image of every point of the box, is exact for a box seen
 * head-on, and is refused for a box reaching behind the eye or a non-finite projection. */
TEST(box_screen_rect_bounds_the_box_image)
{
    const float W = 640, H = 360;
    mat4 vp = m4_mul(m4_perspective_hfov((float)FS_PI / 2, W / H, 0.1f, 100.0f),
                     m4_look_at(v3(0, 0, 0), v3(0, 0, -1), v3(0, 1, 0)));
    float r[4];
    /* A flat square 1 m wide at 2 m, head-on: hfov 90 gives a focal length of W / 2 pixels. */
    CHECK(m4_box_screen_rect(vp, v3(-0.5f, -0.5f, -2), v3(0.5f, 0.5f, -2), W, H, r));
    CHECK_NEAR(r[0], 320 - 80, 1e-3);
    CHECK_NEAR(r[2], 320 + 80, 1e-3);
    CHECK_NEAR(r[1], 180 - 80, 1e-3); /* y down: the top edge (y = +0.5) has the smaller row */
    CHECK_NEAR(r[3], 180 + 80, 1e-3);
    const float keep[4] = {1, 2, 3, 4};
    memcpy(r, keep, sizeof r);
    CHECK(!m4_box_screen_rect(vp, v3(-1, -1, -3), v3(1, 1, 1), W, H, r)); /* reaches behind the eye */
    CHECK(memcmp(r, keep, sizeof r) == 0);
    CHECK(!m4_box_screen_rect(vp, v3(NAN, 0, -3), v3(1, 1, -2), W, H, r));
    unsigned seed = 11;
    int tested = 0;
    for (int k = 0; k < 500; k++) {
        vec3 lo, hi;
        random_box(&seed, 20.0f, 2.0f, &lo, &hi);
        if (!m4_box_screen_rect(vp, lo, hi, W, H, r))
            continue;
        tested++;
        for (int s = 0; s < 27; s++) {
            vec3 q = v3(lo.x + (hi.x - lo.x) * (float)(s % 3) / 2, lo.y + (hi.y - lo.y) * (float)(s / 3 % 3) / 2,
                        lo.z + (hi.z - lo.z) * (float)(s / 9) / 2);
            float v[4];
            for (int i = 0; i < 4; i++)
                v[i] = vp.m[i] * q.x + vp.m[4 + i] * q.y + vp.m[8 + i] * q.z + vp.m[12 + i];
            float x = (0.5f + 0.5f * v[0] / v[3]) * W, y = (0.5f - 0.5f * v[1] / v[3]) * H;
            /* Relative slack: a corner point recomputed as lo + (hi - lo) rounds differently. */
            float ex = 1e-3f + 1e-5f * fabsf(x), ey = 1e-3f + 1e-5f * fabsf(y);
            CHECK(v[3] > 0 && x >= r[0] - ex && x <= r[2] + ex && y >= r[1] - ey && y <= r[3] + ey);
        }
    }
    CHECK(tested > 100);
}

int main(void)
{
    RUN(look_at_puts_target_on_the_view_axis);
    RUN(perspective_maps_the_horizontal_fov_edge_to_ndc_one);
    RUN(invert_and_trs);
    RUN(norm_or_falls_back);
    RUN(box_culling_is_conservative);
    RUN(box_screen_rect_bounds_the_box_image);
    return test_summary();
}
