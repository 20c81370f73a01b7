/* test_principal_point.c: an off-centre principal point (core/display.h) in every pixel <-> angle
 * computation. The key check: a display with its principal point off-centre is exactly a CROP of
 * a larger centred display with the same focal length, so eccentricities, ring footprints, the VRS
 * rate map, the metrics' ring masks, gaze placement by angle and the frame's gaze angles and
 * projection on the crop equal the big display's, shifted by the crop's corner. Plus the OpenXR
 * angles mapping (round trip) and the off-axis projection's frustum edges. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/display.h"
#include "fov/fov_ring.h"
#include "fov/vrs_map.h"
#include "frame/frame.h"
#include "gaze/gaze.h"
#include "metrics/metrics.h"
#include "scene/scene.h"
#include "test.h"

#define RAD (FS_PI / 180.0)

/* The big centred display and the crop [X0, X0 + CW) x [Y0, Y0 + CH) of it. Corner and size are
 * multiples of 32, so ring blocks (up to 8) and VRS tiles (16, 32) align on both. */
enum { W0 = 640, H0 = 480, X0 = 96, Y0 = 64, CW = 320, CH = 224 };
static const display_desc k_big = {W0, H0, 90.0f, 0.0f, 0.0f};

/* The crop as a display of its own: the big one's principal point in the crop's pixels and the
 * hfov that gives the big one's focal length at the crop's width. */
static display_desc crop_display(void)
{
    display_geom g = display_geom_of(&k_big);
    display_desc c = {CW, CH, (float)(2.0 * atan(0.5 * CW / g.f) / RAD), (float)(g.cx - X0 - 0.5 * CW),
                      (float)(g.cy - Y0 - 0.5 * CH)};
    return c;
}

/* Deterministic pseudo-random numbers in [0, 1). */
static double rnd(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (double)(*s >> 8) / 16777216.0;
}

/* A gaze inside the crop, big-display pixels. */
static void crop_gaze(unsigned *s, float *gx, float *gy)
{
    *gx = (float)(X0 + 0.5 + (CW - 1) * rnd(s));
    *gy = (float)(Y0 + 0.5 + (CH - 1) * rnd(s));
}

TEST(crop_display_is_what_the_test_thinks)
{
    display_desc c = crop_display();
    display_geom b = display_geom_of(&k_big), g = display_geom_of(&c);
    CHECK_NEAR(g.f, b.f, 1e-4);
    CHECK_NEAR(g.cx + X0, b.cx, 1e-9);
    CHECK_NEAR(g.cy + Y0, b.cy, 1e-9);
    CHECK(c.ppx != 0.0f && c.ppy != 0.0f); /* really off-centre */
    /* The ray pair: pixel -> direction -> pixel. */
    double v[3], px, py;
    display_ray(&g, 17.25, 203.5, v);
    CHECK(display_pixel(&g, v, &px, &py));
    CHECK_NEAR(px, 17.25, 1e-9);
    CHECK_NEAR(py, 203.5, 1e-9);
    double behind[3] = {0.1, 0.2, 0.5};
    CHECK(!display_pixel(&g, behind, &px, &py));
    /* The view axis lands on the principal point. */
    double axis[3] = {0.0, 0.0, -1.0};
    CHECK(display_pixel(&g, axis, &px, &py));
    CHECK_NEAR(px, 0.5 * CW + c.ppx, 1e-9);
    CHECK_NEAR(py, 0.5 * CH + c.ppy, 1e-9);
}

TEST(eccentricity_equals_the_big_displays)
{
    display_desc c = crop_display();
    unsigned s = 1;
    double worst = 0.0;
    for (int i = 0; i < 20000; i++) {
        float gx, gy, px, py;
        crop_gaze(&s, &gx, &gy);
        crop_gaze(&s, &px, &py);
        double eb = fov_eccentricity_deg(&k_big, gx, gy, px, py);
        double ec = fov_eccentricity_deg(&c, gx - X0, gy - Y0, px - X0, py - Y0);
        worst = fmax(worst, fabs(eb - ec));
    }
    CHECK(worst <= 1e-5);
    /* Not shift-invariant without the principal point: the crop as a centred display differs. */
    display_desc centred = c;
    centred.ppx = centred.ppy = 0.0f;
    CHECK(fabs(fov_eccentricity_deg(&centred, 10, 10, 300, 200) - fov_eccentricity_deg(&k_big, 106, 74, 396, 264)) > 0.1);
}

static bool rect_inside_crop(const fov_ring_rect *r)
{
    return r->x0 >= X0 && r->y0 >= Y0 && r->x1 <= X0 + CW && r->y1 <= Y0 + CH;
}

/* Footprint checks of one ring: equal to the big one's shifted where that lies inside the crop;
 * else inside the big one's (clipped to the crop) and holding every crop pixel within the ring. */
static int check_footprint(const display_desc *c, const fov_layout *l, int i, float gx, float gy)
{
    fov_ring_rect b = fov_ring_footprint(&k_big, l, i, gx, gy, FOV_MARGIN_BLOCKS);
    fov_ring_rect r = fov_ring_footprint(c, l, i, gx - X0, gy - Y0, FOV_MARGIN_BLOCKS);
    if (rect_inside_crop(&b)) {
        CHECK(r.x0 == b.x0 - X0 && r.y0 == b.y0 - Y0 && r.x1 == b.x1 - X0 && r.y1 == b.y1 - Y0);
        CHECK(r.block == b.block && r.width == b.width && r.height == b.height);
        return 1;
    }
    CHECK(r.x0 >= (b.x0 > X0 ? b.x0 : X0) - X0 && r.x1 <= (b.x1 < X0 + CW ? b.x1 : X0 + CW) - X0);
    CHECK(r.y0 >= (b.y0 > Y0 ? b.y0 : Y0) - Y0 && r.y1 <= (b.y1 < Y0 + CH ? b.y1 : Y0 + CH) - Y0);
    for (int y = 0; y < CH; y += 3)
        for (int x = 0; x < CW; x += 3)
            if (fov_eccentricity_deg(c, gx - X0, gy - Y0, x + 0.5f, y + 0.5f) <= l->rings[i].outer_deg)
                CHECK(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1);
    return 0;
}

static fov_layout layout_of(const char *spec)
{
    fov_layout l;
    char err[128];
    CHECK(fov_layout_parse(spec, &k_big, &l, err, sizeof err) == FS_OK);
    return l;
}

TEST(ring_footprints_equal_the_big_displays)
{
    display_desc c = crop_display();
    fov_layout l = layout_of("6:1:0,14:1/2:0,30:1/4:0,*:1/8:0");
    unsigned s = 2;
    int exact = 0, clipped = 0;
    for (int k = 0; k < 60; k++) {
        float gx, gy;
        crop_gaze(&s, &gx, &gy);
        for (int i = 0; i < l.count - 1; i++) {
            int e = check_footprint(&c, &l, i, gx, gy);
            exact += e, clipped += !e;
        }
    }
    CHECK(exact > 30 && clipped > 30); /* both cases really ran */
}

TEST(vrs_rates_equal_the_big_displays)
{
    display_desc c = crop_display();
    vrs_spec spec;
    char err[128];
    CHECK(vrs_spec_parse("4:1x1,10:2x2,*:4x4", &spec, err, sizeof err) == FS_OK);
    const int t = 16, bx = W0 / t, by = H0 / t, cx = CW / t, cy = CH / t;
    vrs_rate *rb = malloc((size_t)(bx * by)), *rc = malloc((size_t)(cx * cy));
    unsigned s = 3;
    int differ = 0, coarse = 0;
    for (int k = 0; k < 20; k++) {
        float gx, gy;
        crop_gaze(&s, &gx, &gy);
        for (int pass = 0; pass < 2; pass++) {
            const vrs_spec *sp = pass ? &spec : NULL; /* NULL: the auto (acuity) rule */
            vrs_map_fill(&k_big, sp, t, gx, gy, rb);
            vrs_map_fill(&c, sp, t, gx - X0, gy - Y0, rc);
            for (int y = 0; y < cy; y++)
                for (int x = 0; x < cx; x++) {
                    vrs_rate a = rb[(y + Y0 / t) * bx + x + X0 / t], b = rc[y * cx + x];
                    differ += a != b;
                    coarse += b != VRS_1X1;
                }
        }
    }
    CHECK(differ == 0);
    CHECK(coarse > 0);
    free(rb);
    free(rc);
}

TEST(ring_masks_equal_the_big_displays)
{
    display_desc c = crop_display();
    fov_layout l = layout_of("6:1:0,14:1/2:0,30:1/4:0,*:1/8:0");
    unsigned s = 4;
    for (int k = 0; k < 4; k++) {
        float gx, gy;
        crop_gaze(&s, &gx, &gy);
        ring_mask mb, mc;
        CHECK(ring_mask_build(&k_big, &l, gx, gy, &mb) == FS_OK);
        CHECK(ring_mask_build(&c, &l, gx - X0, gy - Y0, &mc) == FS_OK);
        int differ = 0, outer = 0;
        for (int y = 0; y < CH; y++)
            for (int x = 0; x < CW; x++) {
                unsigned char a = mb.ring[(size_t)(y + Y0) * W0 + x + X0], b = mc.ring[(size_t)y * CW + x];
                differ += a != b;
                outer += b > 0;
            }
        CHECK(differ == 0);
        CHECK(outer > 0);
        ring_mask_free(&mb);
        ring_mask_free(&mc);
    }
}

/* A trace whose frame spans +-45 degrees each way (tan_per 2), samples given normalised. */
static void trace_of(gaze_trace *t, const float *xy, int n)
{
    memset(t, 0, sizeof *t);
    snprintf(t->path, sizeof t->path, "synthetic");
    t->format = GAZE_FORMAT_EYELINK;
    t->samples = calloc((size_t)n, sizeof *t->samples);
    t->count = t->valid_count = n;
    for (int i = 0; i < n; i++)
        t->samples[i] = (gaze_sample){i * 0.01, xy[2 * i], xy[2 * i + 1], 1.0f, true};
    t->tan_per_x = t->tan_per_y = 2.0;
}

TEST(gaze_placement_by_angle_equals_the_big_displays)
{
    display_desc c = crop_display();
    display_geom g = display_geom_of(&c);
    /* In the crop's field of view: (x - 0.5) * 2 = tangent; the crop spans tangents
     * [-cx / f, (w - cx) / f] = [-0.7, 0.3] horizontally and [-0.15, 0.55] vertically. */
    const float xy[] = {0.2f, 0.3f, 0.6f, 0.55f, 0.45f, 0.5f, 0.55f, 0.25f, 0.05f, 0.5f, 0.5f, 0.95f};
    const int n = 6;
    gaze_trace tb, tc;
    trace_of(&tb, xy, n);
    trace_of(&tc, xy, n);
    gaze_place_desc pd = {0};
    gaze_place(&tb, &pd, &k_big);
    gaze_place(&tc, &pd, &c);
    for (int i = 0; i < 4; i++) {
        CHECK_NEAR(tc.samples[i].x * CW + X0, tb.samples[i].x * W0, 1e-4);
        CHECK_NEAR(tc.samples[i].y * CH + Y0, tb.samples[i].y * H0, 1e-4);
    }
    /* Past the crop's left edge (tangent -0.9 < -0.7) and bottom edge (-0.9 < -0.15): clamped onto
     * the crop's own edges, not onto a symmetric range. */
    CHECK(-g.cx / g.f > -0.9 && (g.cy - g.h) / g.f > -0.9);
    CHECK_NEAR(tc.samples[4].x, 0.0, 1e-6);
    CHECK_NEAR(tc.samples[5].y, 1.0, 1e-6);
    gaze_free(&tb);
    gaze_free(&tc);
}

/* Clip coordinates of camera-space point (x, y, z, 1) under a column-major projection, in double. */
typedef struct clip4 {
    double x, y, z, w;
} clip4;

static clip4 clip_of(const mat4 *p, double x, double y, double z)
{
    const float *m = p->m;
    return (clip4){m[0] * x + m[4] * y + m[8] * z + m[12], m[1] * x + m[5] * y + m[9] * z + m[13],
                   m[2] * x + m[6] * y + m[10] * z + m[14], m[3] * x + m[7] * y + m[11] * z + m[15]};
}

/* A frame of a default scene whose display is d. */
static frame_record frame_on(const display_desc *d)
{
    scene sc;
    scene_init_defaults(&sc);
    sc.display = *d;
    frame_record fr = frame_record_at(&sc, 0, 0.0f, -1.0f, d->width, d->height);
    scene_free(&sc);
    return fr;
}

TEST(frame_gaze_angles_and_projection_equal_the_big_displays)
{
    display_desc c = crop_display();
    frame_record fb = frame_on(&k_big), fc = frame_on(&c);
    CHECK(fc.display.ppx == c.ppx && fc.display.ppy == c.ppy);
    fov_layout off = fov_layout_off();
    unsigned s = 5;
    for (int k = 0; k < 50; k++) {
        float gx, gy;
        crop_gaze(&s, &gx, &gy);
        frame_record_set_gaze(&fb, &off, &fb.display, gx / W0, gy / H0);
        frame_record_set_gaze(&fc, &off, &fc.display, (gx - X0) / CW, (gy - Y0) / CH);
        CHECK_NEAR(fc.gaze_deg[0], fb.gaze_deg[0], 1e-4);
        CHECK_NEAR(fc.gaze_deg[1], fb.gaze_deg[1], 1e-4);
    }
    /* World points in front of the camera land on the same display pixel (pixels of the crop + its
     * corner), within float matrix rounding. */
    for (int k = 0; k < 200; k++) {
        double x = (rnd(&s) - 0.5) * 4.0, y = (rnd(&s) - 0.5) * 3.0, z = -1.0 - 20.0 * rnd(&s);
        clip4 pb = clip_of(&fb.proj, x, y, z), pc = clip_of(&fc.proj, x, y, z);
        double xb = (pb.x / pb.w + 1.0) * 0.5 * W0, yb = (1.0 - pb.y / pb.w) * 0.5 * H0;
        double xc = (pc.x / pc.w + 1.0) * 0.5 * CW, yc = (1.0 - pc.y / pc.w) * 0.5 * CH;
        CHECK_NEAR(xc + X0, xb, 2e-3);
        CHECK_NEAR(yc + Y0, yb, 2e-3);
    }
}

TEST(centred_projection_is_bit_identical)
{
    mat4 a = m4_perspective_hfov(1.3f, 16.0f / 9.0f, 0.1f, 100.0f);
    mat4 b = m4_perspective_offaxis(1.3f, 16.0f / 9.0f, 0.0f, -0.0f, 0.1f, 100.0f);
    CHECK(memcmp(&a, &b, sizeof a) == 0);
}

/* Quest-Pro-like asymmetric eye: 54 deg out, 40 in, 54 down, 42 up. */
static const display_fov_angles k_eye = {-54.0 * RAD, 40.0 * RAD, -54.0 * RAD, 42.0 * RAD};

TEST(openxr_angles_round_trip)
{
    display_desc d;
    CHECK(display_from_fov_angles(&k_eye, 1800, &d));
    display_fov_angles a = display_fov_angles_of(&d);
    CHECK_NEAR(a.left, k_eye.left, 1e-6);
    CHECK_NEAR(a.right, k_eye.right, 1e-6);
    /* The height is whole pixels: the vertical edges move by at most half a pixel between them. */
    display_geom g = display_geom_of(&d);
    CHECK_NEAR(tan(a.up) - tan(k_eye.up), -(tan(a.down) - tan(k_eye.down)), 1e-6); /* shared equally */
    CHECK(fabs(tan(a.up) - tan(k_eye.up)) <= 0.5 / g.f + 1e-9);
    CHECK(d.ppx > 0.0f && d.ppy < 0.0f); /* the axis right of and above the centre (y down) */
    /* Display -> angles -> display is exact (1e-6 relative). */
    display_desc e;
    CHECK(display_from_fov_angles(&a, d.width, &e));
    CHECK(e.width == d.width && e.height == d.height);
    CHECK_NEAR(e.hfov_deg, d.hfov_deg, 1e-6 * d.hfov_deg);
    CHECK_NEAR(e.ppx, d.ppx, 1e-6 * d.width);
    CHECK_NEAR(e.ppy, d.ppy, 1e-6 * d.width);
    /* A symmetric field of view is a centred display. */
    display_fov_angles sym = {-45.0 * RAD, 45.0 * RAD, -30.0 * RAD, 30.0 * RAD};
    CHECK(display_from_fov_angles(&sym, 1000, &e));
    CHECK_NEAR(e.hfov_deg, 90.0, 1e-5);
    CHECK_NEAR(e.ppx, 0.0, 1e-6);
    CHECK_NEAR(e.ppy, 0.0, 1e-6);
    CHECK(e.height == (int)lround(1000.0 * tan(30.0 * RAD)));
    /* Bad angles. */
    display_fov_angles bad = {0.3, -0.3, -0.2, 0.2};
    CHECK(!display_from_fov_angles(&bad, 100, &e));
    bad = (display_fov_angles){-0.3, 0.3, -0.2, 1.6};
    CHECK(!display_from_fov_angles(&bad, 100, &e));
    CHECK(!display_from_fov_angles(&k_eye, 0, &e));
}

TEST(projection_maps_the_frustum_edges_to_ndc)
{
    display_desc d;
    CHECK(display_from_fov_angles(&k_eye, 1800, &d));
    frame_record fr = frame_on(&d);
    display_fov_angles a = display_fov_angles_of(&d);
    /* Camera-space points on the four edge planes, at several depths and across the other axis. */
    for (int k = 0; k < 3; k++) {
        double z = -0.5 - 3.0 * k, o = 0.1 * (k - 1);
        clip4 pl = clip_of(&fr.proj, tan(a.left) * -z, o * -z, z), pr = clip_of(&fr.proj, tan(a.right) * -z, o * -z, z);
        clip4 pd = clip_of(&fr.proj, o * -z, tan(a.down) * -z, z), pu = clip_of(&fr.proj, o * -z, tan(a.up) * -z, z);
        CHECK_NEAR(pl.x / pl.w, -1.0, 1e-6);
        CHECK_NEAR(pr.x / pr.w, 1.0, 1e-6);
        CHECK_NEAR(pd.y / pd.w, -1.0, 1e-6);
        CHECK_NEAR(pu.y / pu.w, 1.0, 1e-6);
    }
}

int main(void)
{
    RUN(crop_display_is_what_the_test_thinks);
    RUN(eccentricity_equals_the_big_displays);
    RUN(ring_footprints_equal_the_big_displays);
    RUN(vrs_rates_equal_the_big_displays);
    RUN(ring_masks_equal_the_big_displays);
    RUN(gaze_placement_by_angle_equals_the_big_displays);
    RUN(frame_gaze_angles_and_projection_equal_the_big_displays);
    RUN(centred_projection_is_bit_identical);
    RUN(openxr_angles_round_trip);
    RUN(projection_maps_the_frustum_edges_to_ndc);
    return test_summary();
}
