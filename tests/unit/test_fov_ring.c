/* fov_ring: acuity layouts, eccentricity, footprints, crop frusta, composite weights, parsing.
 * Every expectation is recomputed here independently (closed forms, brute force over pixels). */
#include "fov/fov_ring.h"

#include "core/log.h"
#include "test.h"

#define PI_D 3.14159265358979323846

static display_desc disp(int w, int h, float hfov)
{
    return (display_desc){.width = w, .height = h, .hfov_deg = hfov};
}

static double focal(const display_desc *d)
{
    return 0.5 * d->width / tan(0.5 * d->hfov_deg * PI_D / 180.0);
}

/* Degrees per pixel at eccentricity e (from the centre, horizontally): d/dx atan(x / f). */
static double pitch_deg(double f, double e_deg)
{
    double c = cos(e_deg * PI_D / 180.0);
    return 180.0 / PI_D * c * c / f;
}

static double mar_deg(double e_deg)
{
    return FOV_ACUITY_SLOPE_DEFAULT * e_deg + FOV_ACUITY_OMEGA0_DEFAULT;
}

static double corner_deg(const display_desc *d)
{
    return atan(hypot(0.5 * d->width, 0.5 * d->height) / focal(d)) * 180.0 / PI_D;
}

/* Independent eccentricity: 2 asin(|a^ - b^| / 2), accurate at all angles. */
static double ecc_ref(const display_desc *d, double gx, double gy, double px, double py)
{
    double f = focal(d);
    double a[3] = {gx - 0.5 * d->width, -(gy - 0.5 * d->height), -f};
    double b[3] = {px - 0.5 * d->width, -(py - 0.5 * d->height), -f};
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double dx = a[0] / la - b[0] / lb, dy = a[1] / la - b[1] / lb, dz = a[2] / la - b[2] / lb;
    return 2.0 * asin(0.5 * sqrt(dx * dx + dy * dy + dz * dz)) * 180.0 / PI_D;
}

static unsigned rng_state = 12345u;
static double rnd(void) /* [0, 1) */
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return (double)(rng_state >> 8) / 16777216.0;
}

static fov_layout parse_ok(const char *text, const display_desc *d)
{
    fov_layout l = fov_layout_off();
    char err[256];
    fs_status s = fov_layout_parse(text, d, &l, err, sizeof err);
    if (s != FS_OK)
        fprintf(stderr, "unexpected parse error for '%s': %s\n", text, err);
    CHECK(s == FS_OK);
    return l;
}

static void print_layout(const char *name, const display_desc *d, const fov_layout *l)
{
    char buf[512];
    fov_layout_format(l, buf, sizeof buf);
    printf("layout %-16s %4dx%-4d @%5.1f deg (corner %.2f deg): %s\n", name, d->width, d->height,
           (double)d->hfov_deg, corner_deg(d), buf);
}

// >>layouts

/* The auto layout satisfies its defining equation at every ring border (the largest block on the
 * display, 2^k pixels at the principal point, equals MAR there: any gaze may put the principal
 * point on the border) and stops where it should. */
static void check_auto(const display_desc *d)
{
    fov_layout l = fov_layout_auto(d, 0, 0);
    print_layout("auto", d, &l);
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK);
    CHECK(l.kind == FOV_LAYOUT_AUTO);
    CHECK(l.blend_deg == FOV_BLEND_DEG_DEFAULT);
    double f = focal(d), emax = corner_deg(d);
    CHECK_NEAR(fov_focal_px(d), f, 1e-3 * f);
    CHECK_NEAR(fov_pixels_per_degree(d), 1.0 / pitch_deg(f, 0), 1e-3);
    /* These displays are coarser than acuity at the centre: full resolution there, then one scale
     * step per ring. */
    CHECK(2.0 * pitch_deg(f, 0) > FOV_ACUITY_OMEGA0_DEFAULT);
    for (int i = 0; i < l.count; i++) {
        CHECK(l.rings[i].scale_log2 == i);
        CHECK(l.rings[i].mip_bias == 0.0f);
    }
    for (int i = 0; i + 1 < l.count; i++) {
        double e = l.rings[i].outer_deg;
        double block = (double)(1 << (i + 1));
        CHECK_NEAR(block * pitch_deg(f, 0), mar_deg(e), 1e-4);
        CHECK(mar_deg(e) >= block * pitch_deg(f, 0) * (1.0 - 1e-6)); /* rounded outwards */
        CHECK(e < emax);
    }
    int last = l.rings[l.count - 1].scale_log2;
    CHECK(isinf(l.rings[l.count - 1].outer_deg));
    /* The next scale would only pay off beyond the corner (or there is none). */
    CHECK(last == MAX_FOV_SCALE_LOG2 || (double)(1 << (last + 1)) * pitch_deg(f, 0) >= mar_deg(emax));
}

TEST(auto_layout_follows_the_acuity_model)
{
    display_desc ds[] = {disp(1280, 720, 90), disp(1920, 1080, 90), disp(1920, 1080, 60), disp(4096, 2160, 110)};
    for (int k = 0; k < 4; k++)
        check_auto(&ds[k]);

    /* Regression values (the comment above fov_layout_auto), computed apart in Python as
     * e_k = (2^k (180/pi) / f - 1/48) / 0.0275: at 1280x720 the 1/16 ring would start at 51.33
     * deg, beyond the corner (48.93 deg), so there are 4 rings. */
    display_desc a = disp(1280, 720, 90), b = disp(1920, 1080, 90);
    fov_layout la = fov_layout_auto(&a, 0, 0), lb = fov_layout_auto(&b, 0, 0);
    const double ea[] = {5.753308, 12.264192, 25.285960}, eb[] = {3.583014, 7.923603, 16.604782, 33.967139};
    CHECK(la.count == 4 && lb.count == 5);
    for (int i = 0; i < 3; i++)
        CHECK_NEAR(la.rings[i].outer_deg, ea[i], 1e-4);
    for (int i = 0; i < 4; i++)
        CHECK_NEAR(lb.rings[i].outer_deg, eb[i], 1e-4);
    CHECK(la.rings[3].scale_log2 == 3 && lb.rings[4].scale_log2 == 4);
    /* Explicit model parameters: a steeper slope moves every border inwards. */
    fov_layout steep = fov_layout_auto(&a, 0.05f, 1.0f / 48.0f);
    CHECK(steep.count >= 2 && steep.rings[0].outer_deg < la.rings[0].outer_deg);
    /* Non-positive or NaN parameters mean the defaults. */
    fov_layout def = fov_layout_auto(&a, -1.0f, NAN);
    CHECK(def.count == la.count && def.rings[1].outer_deg == la.rings[1].outer_deg);
}

TEST(auto_layout_on_degenerate_displays)
{
    /* 1x1 at 90 deg: one pixel is 114 deg wide; no coarser scale ever pays off. */
    display_desc one = disp(1, 1, 90);
    fov_layout l = fov_layout_auto(&one, 0, 0);
    print_layout("auto", &one, &l);
    CHECK(l.count == 1 && l.rings[0].scale_log2 == 0 && isinf(l.rings[0].outer_deg));

    /* hfov 1 deg: pixels far finer than acuity, so even 1/16 resolves everywhere; the empty rings
     * [0, 0) are skipped, leaving one 1/16 ring. */
    display_desc narrow = disp(1280, 720, 1);
    l = fov_layout_auto(&narrow, 0, 0);
    print_layout("auto", &narrow, &l);
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK);
    CHECK(l.count == 1 && l.rings[0].scale_log2 == MAX_FOV_SCALE_LOG2);

    /* hfov 179 deg: a pixel at the centre spans 10 deg, so 2-pixel blocks only meet MAR at 745
     * deg: one full-resolution ring, whatever the gaze. */
    display_desc wide = disp(1280, 720, 179);
    l = fov_layout_auto(&wide, 0, 0);
    print_layout("auto", &wide, &l);
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK);
    CHECK(l.count == 1 && l.rings[0].scale_log2 == 0);
    /* hfov 150 deg on a wide display: still a valid layout with borders on the defining equation. */
    display_desc w150 = disp(7680, 2160, 150);
    l = fov_layout_auto(&w150, 0, 0);
    print_layout("auto", &w150, &l);
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK && l.count >= 2);
    for (int i = 0; i + 1 < l.count; i++) {
        double e = l.rings[i].outer_deg;
        CHECK_NEAR((double)(1 << l.rings[i + 1].scale_log2) * pitch_deg(focal(&w150), 0), mar_deg(e), 1e-4);
    }

    /* A display in between: 2x blocks resolve the acuity at the centre, 4x do not -> e_1 = 0, the
     * full-resolution ring [0, 0) is skipped and the innermost ring is 1/2. */
    double f2 = 2.0 * 180.0 / PI_D / FOV_ACUITY_OMEGA0_DEFAULT * 1.2; /* 2 pitch(0) < omega0 < 4 pitch(0) */
    int w = (int)(2.0 * f2 * tan(20.0 * PI_D / 180.0));
    display_desc fine = disp(w, w / 2, 40);
    l = fov_layout_auto(&fine, 0, 0);
    print_layout("auto", &fine, &l);
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK);
    CHECK(l.count >= 2 && l.rings[0].scale_log2 == 1 && l.rings[1].scale_log2 == 2);
    CHECK_NEAR(4.0 * pitch_deg(focal(&fine), 0), mar_deg(l.rings[0].outer_deg), 1e-4);
}

/* Unit vector of the view ray through display point (x, y), pixels from the top-left corner
 * (the camera of fov_ring.h, rebuilt here). */
static void ray_unit(const display_desc *d, double x, double y, double u[3])
{
    double f = focal(d);
    u[0] = x - 0.5 * d->width, u[1] = -(y - 0.5 * d->height), u[2] = -f;
    double n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    u[0] /= n, u[1] /= n, u[2] /= n;
}

/* Angle in degrees between the view rays through two display points: 2 asin(chord / 2). */
static double span_deg(const display_desc *d, double ax, double ay, double bx, double by)
{
    double a[3], b[3];
    ray_unit(d, ax, ay, a);
    ray_unit(d, bx, by, b);
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return 2.0 * asin(0.5 * sqrt(dx * dx + dy * dy + dz * dz)) * 180.0 / PI_D;
}

/* The largest angle a block of b x b display pixels with top-left corner (x0, y0) spans, from
 * first principles: its four sides, and the segments of length b through its centre pointing away
 * from the display centre (the radial pitch) and across (the tangential pitch), each measured as
 * the angle between the view rays through its end points. */
static double block_span_deg(const display_desc *d, double x0, double y0, int b)
{
    double x1 = x0 + b, y1 = y0 + b;
    double s = fmax(fmax(span_deg(d, x0, y0, x1, y0), span_deg(d, x0, y1, x1, y1)),
                    fmax(span_deg(d, x0, y0, x0, y1), span_deg(d, x1, y0, x1, y1)));
    double cx = x0 + 0.5 * b, cy = y0 + 0.5 * b, rx = cx - 0.5 * d->width, ry = cy - 0.5 * d->height;
    double r = hypot(rx, ry);
    if (r > 0.0)
        rx /= r, ry /= r;
    else
        rx = 1.0, ry = 0.0;
    double h = 0.5 * b;
    s = fmax(s, span_deg(d, cx - h * rx, cy - h * ry, cx + h * rx, cy + h * ry));
    s = fmax(s, span_deg(d, cx + h * ry, cy - h * rx, cx - h * ry, cy + h * rx));
    return s;
}

/* For gazes on a 5 x 5 grid over the display (its centre, the midpoints of its edges, its corners
 * and points between), the largest block-span / MAR(inner edge) of ring i of l over every block
 * of the ring's pixel grid that reaches into the ring: one of its corners at an eccentricity >= the
 * inner edge (a square's farthest point from a ray is a corner), i.e. a view ray through a corner
 * whose dot product with the gaze ray is <= cos(inner edge). Blocks are where the renderer puts
 * them, on multiples of the block size. Also reports the gaze that gives the worst. */
static double worst_block_over_mar(const display_desc *d, const fov_layout *l, int i, double *worst_gx,
                                   double *worst_gy)
{
    int b = 1 << l->rings[i].scale_log2;
    double inner = i > 0 ? l->rings[i - 1].outer_deg : 0.0, mar = mar_deg(inner);
    double cos_inner = cos(inner * PI_D / 180.0);
    int nx = (d->width + b - 1) / b, ny = (d->height + b - 1) / b, lx = nx + 1;
    double *span = malloc(sizeof(double) * (size_t)nx * ny);
    double *ray = malloc(3 * sizeof(double) * (size_t)lx * (ny + 1));
    bool *out = malloc(sizeof(bool) * (size_t)lx * (ny + 1));
    CHECK(span && ray && out);
    if (!span || !ray || !out) {
        free(span), free(ray), free(out);
        return INFINITY;
    }
    for (int by = 0; by < ny; by++)
        for (int bx = 0; bx < nx; bx++)
            span[by * nx + bx] = block_span_deg(d, bx * b, by * b, b);
    for (int y = 0; y <= ny; y++)
        for (int x = 0; x <= nx; x++)
            ray_unit(d, x * b, y * b, &ray[3 * (y * lx + x)]);
    double worst = 0.0;
    for (int gy = 0; gy <= 4; gy++)
        for (int gx = 0; gx <= 4; gx++) {
            double px = 0.25 * gx * d->width, py = 0.25 * gy * d->height, g[3];
            ray_unit(d, px, py, g);
            for (int k = 0; k < lx * (ny + 1); k++)
                out[k] = ray[3 * k] * g[0] + ray[3 * k + 1] * g[1] + ray[3 * k + 2] * g[2] <= cos_inner;
            for (int by = 0; by < ny; by++)
                for (int bx = 0; bx < nx; bx++) {
                    const bool *o = &out[by * lx + bx];
                    if (!(o[0] || o[1] || o[lx] || o[lx + 1]))
                        continue;
                    double r = span[by * nx + bx] / mar;
                    if (r > worst)
                        worst = r, *worst_gx = px, *worst_gy = py;
                }
        }
    free(span);
    free(ray);
    free(out);
    return worst;
}

/* docs/foveation.md "Layouts": no ring's block is coarser than the MAR at the ring's inner edge, for the larger
 * of the two pixel pitches (radial cos^2 e / f, tangential cos e / f) and for any gaze on the
 * display. Checked by brute force over gazes and blocks, and fov_ring_block_mar_ratio bounds what
 * the brute force finds, closely where some gaze puts the display centre in the ring. */
TEST(auto_layout_blocks_resolve_the_acuity_for_any_gaze)
{
    display_desc ds[] = {disp(1280, 720, 90), disp(1920, 1080, 90), disp(1920, 1080, 60), disp(800, 800, 110)};
    for (int k = 0; k < 4; k++) {
        const display_desc *d = &ds[k];
        fov_layout l = fov_layout_auto(d, 0, 0);
        print_layout("auto", d, &l);
        CHECK(l.count >= 3);
        double margin = fov_layout_acuity_margin(d, &l, 0, 0, NULL);
        CHECK(margin >= 1.0);
        for (int i = 1; i < l.count; i++) {
            double gx = 0, gy = 0, inner = l.rings[i - 1].outer_deg;
            double worst = worst_block_over_mar(d, &l, i, &gx, &gy);
            double bound = fov_ring_block_mar_ratio(d, &l, i, 0, 0);
            printf("acuity   %4dx%-4d @%5.1f ring %d (1/%-2d from %6.3f deg): worst block / MAR(inner) %.6f "
                   "(gaze %.0f, %.0f), bound %.6f\n", d->width, d->height, (double)d->hfov_deg, i,
                   1 << l.rings[i].scale_log2, inner, worst, gx, gy, bound);
            CHECK(worst <= 1.0 + 1e-9);
            CHECK(worst <= bound * (1.0 + 1e-9));
            CHECK(worst >= 0.98 * bound); /* the corner gazes put the display centre in the ring */
        }
    }
}

/* The margin of explicit layouts, from the closed form (block / f radians against MAR at the inner
 * edge), checked by the same brute force where it falls short. */
TEST(acuity_margin_of_explicit_layouts)
{
    display_desc d = disp(1280, 720, 90);
    /* The auto layout of before 2026-12-01 (radial pitch, centred gaze): the 1/16 ring from
     * 34.56 deg has 1.432 deg blocks at the principal point against MAR = 0.971 deg. */
    fov_layout old = parse_ok("5.689322:1:0,11.726324:1/2:0,21.719414:1/4:0,34.564426:1/8:0,*:1/16:0", &d);
    int worst = -2;
    double margin = fov_layout_acuity_margin(&d, &old, 0, 0, &worst);
    double expect = mar_deg(34.564426) / (16.0 / 640.0 * 180.0 / PI_D);
    CHECK(worst == 4);
    CHECK_NEAR(margin, expect, 1e-6);
    CHECK_NEAR(margin, 0.678134, 1e-5);
    for (int i = 1; i < old.count; i++) {
        double ratio = fov_ring_block_mar_ratio(&d, &old, i, 0, 0);
        CHECK_NEAR(ratio, (1 << i) / 640.0 * 180.0 / PI_D / mar_deg(old.rings[i - 1].outer_deg), 1e-6);
    }
    double gx = 0, gy = 0;
    double found = worst_block_over_mar(&d, &old, 4, &gx, &gy);
    printf("acuity   old auto layout, ring 4: worst block / MAR(inner) %.6f (gaze %.0f, %.0f), margin %.6f\n", found, gx,
           gy, margin);
    CHECK(found > 1.4 && found <= 1.0 / margin * (1.0 + 1e-9));

    /* A coarse ring 0 is checked against MAR(0). */
    fov_layout coarse = parse_ok("*:1/2:0", &d);
    CHECK_NEAR(fov_layout_acuity_margin(&d, &coarse, 0, 0, &worst), FOV_ACUITY_OMEGA0_DEFAULT / (2.0 / 640.0 * 180.0 / PI_D),
               1e-6);
    CHECK(worst == 0);
    /* Full resolution everywhere, or a coarse ring no gaze on the display reaches (corner to corner
     * is 97.85 deg): nothing to check. */
    fov_layout off = fov_layout_off(), far = parse_ok("98:1:0,*:1/16:0", &d), near = parse_ok("97:1:0,*:1/16:0", &d);
    CHECK(isinf(fov_layout_acuity_margin(&d, &off, 0, 0, &worst)) && worst == -1);
    CHECK(isinf(fov_layout_acuity_margin(&d, &far, 0, 0, &worst)) && worst == -1);
    CHECK(fov_layout_acuity_margin(&d, &near, 0, 0, &worst) > 1.0 && worst == 1);
    /* The model's parameters: twice the slope, about twice the margin far out. */
    double m2 = fov_layout_acuity_margin(&d, &old, 2.0f * FOV_ACUITY_SLOPE_DEFAULT, 0, NULL);
    CHECK_NEAR(m2, (2.0 * FOV_ACUITY_SLOPE_DEFAULT * 34.564426 + FOV_ACUITY_OMEGA0_DEFAULT) / (16.0 / 640.0 * 180.0 / PI_D),
               1e-6);
}

TEST(off_layout)
{
    fov_layout l = fov_layout_off();
    CHECK(l.kind == FOV_LAYOUT_OFF && l.count == 1 && l.rings[0].scale_log2 == 0 && isinf(l.rings[0].outer_deg));
    CHECK(fov_layout_check(&l, NULL, 0) == FS_OK);
    char buf[64];
    fov_layout_format(&l, buf, sizeof buf);
    CHECK(strcmp(buf, "*:1:0") == 0);
}

static bool same_layout(const fov_layout *a, const fov_layout *b)
{
    if (a->count != b->count)
        return false;
    for (int i = 0; i < a->count; i++)
        if (a->rings[i].outer_deg != b->rings[i].outer_deg || a->rings[i].scale_log2 != b->rings[i].scale_log2 ||
            a->rings[i].mip_bias != b->rings[i].mip_bias)
            return false;
    return true;
}

TEST(parse_good_layouts)
{
    display_desc d = disp(1280, 720, 90);
    fov_layout l = parse_ok("10:1:0,25:0.5:0,*:0.25:0.5", &d);
    CHECK(l.kind == FOV_LAYOUT_EXPLICIT && l.count == 3);
    CHECK(l.rings[0].outer_deg == 10.0f && l.rings[0].scale_log2 == 0 && l.rings[0].mip_bias == 0.0f);
    CHECK(l.rings[1].outer_deg == 25.0f && l.rings[1].scale_log2 == 1);
    CHECK(isinf(l.rings[2].outer_deg) && l.rings[2].scale_log2 == 2 && l.rings[2].mip_bias == 0.5f);
    CHECK(l.blend_deg == FOV_BLEND_DEG_DEFAULT);

    fov_layout m = parse_ok("  10 : 1 : 0 ,\t25:1/2:0 , * : 1 / 4 : 0.5 ", &d);
    CHECK(same_layout(&l, &m));

    l = parse_ok("*:1/16:-1.5", &d);
    CHECK(l.count == 1 && l.rings[0].scale_log2 == 4 && l.rings[0].mip_bias == -1.5f);
    l = parse_ok("*:0.0625:0", &d);
    CHECK(l.count == 1 && l.rings[0].scale_log2 == 4);
    l = parse_ok("0.001:1:0,2.5:1:0,*:1:0", &d); /* equal scales are fine */
    CHECK(l.count == 3 && l.rings[0].outer_deg == 0.001f);
    l = parse_ok("1:1:0,2:1:0,3:1/2:0,4:1/2:0,5:1/4:0,6:1/8:0,7:1/16:0,*:1/16:2", &d); /* MAX_FOV_RINGS */
    CHECK(l.count == MAX_FOV_RINGS);
    l = parse_ok("100:1:0,*:1:0", &d); /* larger than the display: allowed */
    CHECK(l.count == 2);

    l = parse_ok("auto", &d);
    fov_layout a = fov_layout_auto(&d, 0, 0);
    CHECK(l.kind == FOV_LAYOUT_AUTO && same_layout(&l, &a));
    l = parse_ok(" off\n", NULL);
    CHECK(l.kind == FOV_LAYOUT_OFF && l.count == 1);
    /* aggressive: auto's construction with twice the slope (so its borders come nearer the gaze),
     * the same ring scales, and +0.5 bias exactly on the reduced rings. */
    l = parse_ok("aggressive", &d);
    fov_layout steep = fov_layout_auto(&d, 2.0f * FOV_ACUITY_SLOPE_DEFAULT, FOV_ACUITY_OMEGA0_DEFAULT);
    CHECK(l.kind == FOV_LAYOUT_AGGRESSIVE && l.count == steep.count && l.count > 1);
    for (int i = 0; i < l.count; i++) {
        CHECK(l.rings[i].scale_log2 == steep.rings[i].scale_log2 && l.rings[i].outer_deg == steep.rings[i].outer_deg);
        CHECK(l.rings[i].mip_bias == (l.rings[i].scale_log2 > 0 ? 0.5f : 0.0f));
        if (i < l.count - 1 && i < a.count - 1)
            CHECK(l.rings[i].outer_deg < a.rings[i].outer_deg);
    }
    CHECK(strcmp(fov_layout_kind_name(l.kind), "aggressive") == 0);
    char agg_err[256];
    CHECK(fov_layout_parse("aggressive", NULL, &l, agg_err, sizeof agg_err) == FS_ERR_USAGE &&
          strstr(agg_err, "needs the display"));

    /* Format -> parse round trip, including auto radii with many digits. */
    const char *texts[] = {"10:1:0,25:1/2:0,*:1/4:0.5", "0.001:1:-0.25,*:1/16:0", "auto", "off"};
    for (int k = 0; k < 4; k++) {
        fov_layout x = parse_ok(texts[k], &d), y;
        char buf[512], err[256];
        fov_layout_format(&x, buf, sizeof buf);
        CHECK(fov_layout_parse(buf, NULL, &y, err, sizeof err) == FS_OK);
        CHECK(same_layout(&x, &y));
        if (k == 0)
            CHECK(strcmp(buf, texts[0]) == 0);
    }
    /* A too-small buffer truncates without overflow. */
    char tiny[8];
    fov_layout_format(&a, tiny, sizeof tiny);
    CHECK(strlen(tiny) == 7);
}

TEST(parse_bad_layouts)
{
    display_desc d = disp(1280, 720, 90);
    const char *bad[] = {
        "",                                                       /* empty */
        "   ",                                                    /* blank */
        "10:0.3:0,*:0.25:0",                                      /* not a power of two */
        "10:3/8:0,*:1/4:0",                                       /* fraction, not a power of two */
        "10:2:0,*:1:0",                                           /* coarser than... finer than full */
        "10:1/32:0,*:1/32:0",                                     /* beyond 1/16 */
        "10:1/0:0,*:1:0",                                         /* division by zero */
        "20:1:0,10:0.5:0,*:0.25:0",                               /* radii decreasing */
        "10:1:0,10:0.5:0,*:0.25:0",                               /* radii equal */
        "10:1:0,20:0.5:0",                                        /* last is not '*' */
        "*:1:0,10:0.5:0,*:0.5:0",                                 /* '*' not last */
        "1:1:0,2:1:0,3:1:0,4:1:0,5:1:0,6:1:0,7:1:0,8:1:0,*:1:0",  /* 9 rings */
        "10:0.5:0,*:1:0",                                         /* finer than the previous ring */
        "10:1:0,*:0.25:0 x",                                      /* trailing garbage */
        "10:1:0,*:0.25:0,",                                       /* trailing comma */
        "10x:1:0,*:1:0",                                          /* garbage in a number */
        "10:1,*:0.25:0",                                          /* two fields */
        "10:1:0:0,*:1:0",                                         /* four fields */
        "10::0,*:1:0",                                            /* empty field */
        "-5:1:0,*:1:0",                                           /* negative radius */
        "0:1:0,*:1:0",                                            /* zero radius */
        "nan:1:0,*:1:0",                                          /* NaN radius */
        "inf:1:0,*:1:0",                                          /* inf spelled out is not '*' */
        "1e40:1:0,*:1:0",                                         /* overflows float */
        "10:1:nan,*:1:0",                                         /* NaN bias */
        "10:1:0;*:1:0",                                           /* wrong separator */
        "Auto",                                                   /* keywords are lower case */
        "auto x",                                                 /* trailing garbage after keyword */
        "aggresive",                                              /* misspelt name */
    };
    int n = (int)(sizeof bad / sizeof bad[0]);
    for (int k = 0; k < n; k++) {
        fov_layout l = fov_layout_off();
        l.count = 77; /* sentinel: untouched on error */
        char err[256] = "";
        fs_status s = fov_layout_parse(bad[k], &d, &l, err, sizeof err);
        if (s != FS_ERR_USAGE)
            fprintf(stderr, "accepted bad layout '%s'\n", bad[k]);
        CHECK(s == FS_ERR_USAGE);
        CHECK(l.count == 77);
        CHECK(err[0] != '\0' && strchr(err, '\n') == NULL); /* one line, some text */
        printf("  bad layout %-58s -> %s\n", bad[k], err);
    }
    char err[256];
    CHECK(fov_layout_parse("aggresive", &d, NULL, err, sizeof err) == FS_ERR_USAGE &&
          strstr(err, "'aggresive' is not a ring layout (expected auto, aggressive, off"));
    /* "auto" needs the display. */
    fov_layout l;
    CHECK(fov_layout_parse("auto", NULL, &l, NULL, 0) == FS_ERR_USAGE);
    CHECK(fov_layout_parse(NULL, &d, &l, NULL, 0) == FS_ERR_USAGE);
    /* Tiny error buffers are fine. */
    char e1[1];
    CHECK(fov_layout_parse("x", &d, &l, e1, 1) == FS_ERR_USAGE && e1[0] == '\0');
}

TEST(check_rejects_bad_structs)
{
    fov_layout good = fov_layout_off();
    good.count = 3;
    good.kind = FOV_LAYOUT_EXPLICIT;
    good.rings[0] = (fov_ring){5, 0, 0};
    good.rings[1] = (fov_ring){15, 1, 0};
    good.rings[2] = (fov_ring){INFINITY, 3, 0};
    CHECK(fov_layout_check(&good, NULL, 0) == FS_OK);

    fov_layout b;
    char err[256];
#define EXPECT_BAD(mutation)                                          \
    do {                                                              \
        b = good;                                                     \
        mutation;                                                     \
        CHECK(fov_layout_check(&b, err, sizeof err) == FS_ERR_USAGE); \
    } while (0)
    EXPECT_BAD(b.count = 0);
    EXPECT_BAD(b.count = MAX_FOV_RINGS + 1);
    EXPECT_BAD(b.rings[0].scale_log2 = -1);
    EXPECT_BAD(b.rings[2].scale_log2 = MAX_FOV_SCALE_LOG2 + 1);
    EXPECT_BAD(b.rings[1].scale_log2 = 4);         /* ring 3 finer than ring 2 */
    EXPECT_BAD(b.rings[1].mip_bias = NAN);
    EXPECT_BAD(b.rings[2].mip_bias = INFINITY);
    EXPECT_BAD(b.rings[2].outer_deg = 40);         /* last not '*' */
    EXPECT_BAD(b.rings[0].outer_deg = INFINITY);   /* '*' not last */
    EXPECT_BAD(b.rings[0].outer_deg = NAN);
    EXPECT_BAD(b.rings[0].outer_deg = -1);
    EXPECT_BAD(b.rings[1].outer_deg = 5);          /* not increasing */
    EXPECT_BAD(b.blend_deg = -1);
    EXPECT_BAD(b.blend_deg = NAN);
#undef EXPECT_BAD
    CHECK(fov_layout_check(NULL, err, sizeof err) == FS_ERR_USAGE);
}

// >>angles

TEST(eccentricity_is_zero_at_gaze_symmetric_and_accurate)
{
    display_desc ds[] = {disp(1280, 720, 90), disp(1920, 1080, 60), disp(1, 1, 90), disp(1280, 720, 1),
                         disp(1280, 720, 179)};
    for (int k = 0; k < 5; k++) {
        const display_desc *d = &ds[k];
        for (int t = 0; t < 2000; t++) {
            /* Points on and far off the display. */
            double s = t % 5 == 0 ? 1e6 : 2.0;
            float gx = (float)((rnd() * s - 0.5 * (s - 1)) * d->width);
            float gy = (float)((rnd() * s - 0.5 * (s - 1)) * d->height);
            float px = (float)((rnd() * s - 0.5 * (s - 1)) * d->width);
            float py = (float)((rnd() * s - 0.5 * (s - 1)) * d->height);
            CHECK(fov_eccentricity_deg(d, gx, gy, gx, gy) == 0.0f);
            float e1 = fov_eccentricity_deg(d, gx, gy, px, py), e2 = fov_eccentricity_deg(d, px, py, gx, gy);
            CHECK(e1 == e2);
            CHECK(e1 >= 0.0f && e1 <= 180.0f);
            CHECK_NEAR(e1, ecc_ref(d, gx, gy, px, py), 1e-4);
            /* Tiny separations stay accurate (relative). */
            float qx = gx + 0.01f * (float)(rnd() - 0.5), qy = gy + 0.01f * (float)(rnd() - 0.5);
            double r = ecc_ref(d, gx, gy, qx, qy);
            CHECK_NEAR(fov_eccentricity_deg(d, gx, gy, qx, qy), r, 1e-4 * r + 1e-12);
        }
    }
    /* Known values: the display edge at 90 deg hfov is 45 deg from the centre. */
    display_desc d = disp(1280, 720, 90);
    CHECK_NEAR(fov_eccentricity_deg(&d, 640, 360, 1280, 360), 45.0, 1e-5);
    CHECK_NEAR(fov_eccentricity_deg(&d, 0, 360, 1280, 360), 90.0, 1e-5);
    /* NaN/Inf gaze -> the display centre. */
    CHECK(fov_eccentricity_deg(&d, NAN, 3, 640, 360) == 0.0f);
    CHECK(fov_eccentricity_deg(&d, INFINITY, -INFINITY, 1280, 360) == fov_eccentricity_deg(&d, 640, 360, 1280, 360));
}

TEST(eccentricity_grows_along_lines_from_the_gaze)
{
    display_desc d = disp(1280, 720, 90);
    const float gaze[][2] = {{640, 360}, {0, 0}, {1280, 720}, {100, 600}, {-500, 2000}};
    for (int g = 0; g < 5; g++) {
        for (int dir = 0; dir < 16; dir++) {
            double a = dir * 2.0 * PI_D / 16.0 + 0.1;
            float prev = -1.0f;
            for (int s = 0; s <= 4000; s++) {
                double t = s * s * 0.01; /* up to 160000 px */
                float e = fov_eccentricity_deg(&d, gaze[g][0], gaze[g][1], (float)(gaze[g][0] + t * cos(a)),
                                               (float)(gaze[g][1] + t * sin(a)));
                CHECK(e >= prev - 1e-5f);
                prev = e;
            }
        }
    }
}

// >>footprints

static void clamp_gaze_ref(const display_desc *d, float gx, float gy, double *x, double *y)
{
    if (!isfinite(gx) || !isfinite(gy)) {
        *x = 0.5 * d->width, *y = 0.5 * d->height;
        return;
    }
    *x = gx < 0 ? 0 : gx > d->width ? d->width : gx;
    *y = gy < 0 ? 0 : gy > d->height ? d->height : gy;
}

static int snap_down(int v, int b)
{
    return (int)floor((double)v / b) * b;
}

/* Brute force over every pixel centre: conservative, tight-ish, aligned, clamped, nested. */
static void check_footprints(const display_desc *d, const fov_layout *l, float gx, float gy, int margin)
{
    double cx, cy;
    clamp_gaze_ref(d, gx, gy, &cx, &cy);
    float kx = gx, ky = gy;
    fov_gaze_clamp(d, &kx, &ky);
    CHECK(kx == (float)cx && ky == (float)cy);
    int gpx = (int)floor(cx) < d->width ? (int)floor(cx) : d->width - 1;
    int gpy = (int)floor(cy) < d->height ? (int)floor(cy) : d->height - 1;
    double f = focal(d);
    double gaze_angle = atan(hypot(cx - 0.5 * d->width, cy - 0.5 * d->height) / f) * 180.0 / PI_D;
    fov_ring_rect prev = {0, 0, 0, 0, 0, 0, 1};
    for (int i = 0; i < l->count; i++) {
        fov_ring_rect r = fov_ring_footprint(d, l, i, gx, gy, margin);
        int b = 1 << l->rings[i].scale_log2;
        int gw = (d->width + b - 1) / b * b, gh = (d->height + b - 1) / b * b;
        CHECK(r.block == b);
        CHECK(r.x0 % b == 0 && r.y0 % b == 0 && (r.x1 - r.x0) % b == 0 && (r.y1 - r.y0) % b == 0);
        CHECK(r.width == (r.x1 - r.x0) / b && r.height == (r.y1 - r.y0) / b);
        CHECK(r.width >= 1 && r.height >= 1);
        CHECK(r.x0 >= 0 && r.y0 >= 0 && r.x1 <= gw && r.y1 <= gh);
        CHECK(r.x0 <= gpx && gpx < r.x1 && r.y0 <= gpy && gpy < r.y1); /* holds the gaze pixel */
        if (i > 0)
            CHECK(r.x0 <= prev.x0 && r.y0 <= prev.y0 && r.x1 >= prev.x1 && r.y1 >= prev.y1);
        if (i == l->count - 1)
            CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 == gw && r.y1 == gh);
        prev = r;
        if (i == l->count - 1)
            continue;
        float outer = l->rings[i].outer_deg;
        int mx0 = 1 << 30, my0 = 1 << 30, mx1 = -1, my1 = -1, misses = 0;
        for (int y = 0; y < d->height; y++)
            for (int x = 0; x < d->width; x++) {
                float e = fov_eccentricity_deg(d, (float)cx, (float)cy, x + 0.5f, y + 0.5f);
                if (e <= outer) {
                    if (!(x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1))
                        misses++;
                    mx0 = x < mx0 ? x : mx0, my0 = y < my0 ? y : my0;
                    mx1 = x + 1 > mx1 ? x + 1 : mx1, my1 = y + 1 > my1 ? y + 1 : my1;
                }
            }
        if (misses)
            fprintf(stderr, "ring %d outer %g gaze (%g, %g): %d pixels outside [%d,%d)x[%d,%d)\n", i, (double)outer,
                    (double)gx, (double)gy, misses, r.x0, r.x1, r.y0, r.y1);
        CHECK(misses == 0);
        /* Not wastefully large: within a few pixels (plus the margin, snapped) of the brute-force
         * box, when the cone section is bounded and holds pixel centres. */
        if (margin == 0 && mx1 > 0 && gaze_angle + outer < 85.0) {
            bool tight = r.x0 >= snap_down(mx0 - 4, b) && r.y0 >= snap_down(my0 - 4, b) &&
                         r.x1 <= snap_down(mx1 + 4 + b - 1, b) && r.y1 <= snap_down(my1 + 4 + b - 1, b);
            if (!tight)
                fprintf(stderr, "ring %d outer %g gaze (%g, %g) b %d: rect [%d,%d)x[%d,%d) vs pixels [%d,%d)x[%d,%d)\n", i,
                        (double)outer, (double)gx, (double)gy, b, r.x0, r.x1, r.y0, r.y1, mx0, mx1, my0, my1);
            CHECK(tight);
        }
    }
}

TEST(footprints_are_conservative_nested_and_aligned)
{
    display_desc d = disp(320, 180, 90);
    fov_layout layouts[4];
    layouts[0] = fov_layout_auto(&d, 0, 0);
    layouts[1] = parse_ok("0.01:1:0,3:1:0,10:1/2:0,30:1/4:0,60:1/8:0,*:1/16:0", &d);
    layouts[2] = parse_ok("0.3:1/16:0,45:1/16:0,*:1/16:0", &d);
    layouts[3] = parse_ok("20:1/2:0,89.5:1/2:0,100:1/4:0,*:1/4:0", &d);
    print_layout("auto", &d, &layouts[0]);
    const float gazes[][2] = {{160, 90}, {0, 0}, {320, 0}, {0, 180}, {320, 180}, {159.5f, 89.5f}, {-40, 90},
                              {500, -300}, {1e9f, 1e9f}, {NAN, 20}, {INFINITY, 0}, {0.25f, 179.75f}, {37.3f, 121.9f}};
    int ng = (int)(sizeof gazes / sizeof gazes[0]);
    for (int k = 0; k < 4; k++)
        for (int g = 0; g < ng; g++) {
            check_footprints(&d, &layouts[k], gazes[g][0], gazes[g][1], 0);
            if (g % 3 == 0)
                check_footprints(&d, &layouts[k], gazes[g][0], gazes[g][1], 2);
        }
    for (int t = 0; t < 10; t++)
        check_footprints(&d, &layouts[1], (float)(rnd() * 320), (float)(rnd() * 180), t % 2);

    /* A wide display, where cones reach 90 degrees from off-centre gazes, and a narrow one. */
    display_desc wide = disp(160, 90, 150), narrow = disp(96, 54, 1);
    fov_layout lw = parse_ok("5:1:0,20:1/2:0,40:1/4:0,70:1/8:0,*:1/16:0", &wide);
    fov_layout ln = parse_ok("0.001:1:0,0.01:1/2:0,0.3:1/4:0,*:1/16:0", &narrow);
    for (int g = 0; g < ng; g++) {
        check_footprints(&wide, &lw, gazes[g][0] * 0.5f, gazes[g][1] * 0.5f, 0);
        check_footprints(&narrow, &ln, gazes[g][0] * 0.3f, gazes[g][1] * 0.3f, 1);
    }
    display_desc w179 = disp(64, 36, 179);
    fov_layout l179 = fov_layout_auto(&w179, 0, 0);
    fov_layout l179b = parse_ok("1:1:0,30:1/2:0,60:1/4:0,89:1/8:0,*:1/8:0", &w179);
    for (int g = 0; g < ng; g++) {
        check_footprints(&w179, &l179, gazes[g][0] * 0.2f, gazes[g][1] * 0.2f, 0);
        check_footprints(&w179, &l179b, gazes[g][0] * 0.2f, gazes[g][1] * 0.2f, 0);
    }
}

TEST(footprint_hard_cases)
{
    display_desc d = disp(1920, 1080, 90);
    /* Radius below one pixel: one ring pixel block around the gaze pixel. */
    fov_layout l = parse_ok("0.0001:1:0,0.0002:1/16:0,*:1/16:0", &d);
    fov_ring_rect r = fov_ring_footprint(&d, &l, 0, 700.5f, 300.5f, 0);
    CHECK(r.x0 <= 700 && r.x1 > 700 && r.y0 <= 300 && r.y1 > 300);
    CHECK(r.width <= 3 && r.height <= 3);
    r = fov_ring_footprint(&d, &l, 1, 700.5f, 300.5f, 0);
    CHECK(r.block == 16 && r.width == 1 && r.height == 1 && r.x0 == 688 && r.y0 == 288);
    /* ... also at the bottom-right corner, where the gaze pixel is (1919, 1079). */
    r = fov_ring_footprint(&d, &l, 1, 1920, 1080, 0);
    CHECK(r.x0 <= 1919 && r.x1 > 1919 && r.y0 <= 1079 && r.y1 > 1079 && r.width >= 1 && r.height >= 1);
    /* 1/16 of 1080 rows: the grid is 1088 tall (one block past the display, by less than a block). */
    r = fov_ring_footprint(&d, &l, 2, 960, 540, 0);
    CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 == 1920 && r.y1 == 1088 && r.width == 120 && r.height == 68);
    /* Radius beyond the display: the whole display. */
    fov_layout big = parse_ok("60:1:0,100:1/2:0,*:1/4:0", &d);
    r = fov_ring_footprint(&d, &big, 0, 960, 540, 0);
    CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 == 1920 && r.y1 == 1080);
    r = fov_ring_footprint(&d, &big, 1, 0, 0, 0);
    CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 == 1920 && r.y1 == 1080 && r.width == 960);
    /* Huge margins clamp to the display. */
    r = fov_ring_footprint(&d, &big, 0, 10, 10, 1 << 30);
    CHECK(r.x0 == 0 && r.y0 == 0 && r.x1 == 1920 && r.y1 == 1080);
    /* Degenerate 1x1 display: every ring is one ring pixel. */
    display_desc one = disp(1, 1, 90);
    fov_layout lo = parse_ok("1:1:0,10:1/4:0,*:1/16:0", &one);
    for (int i = 0; i < 3; i++) {
        r = fov_ring_footprint(&one, &lo, i, 0.5f, 0.5f, 3);
        CHECK(r.x0 == 0 && r.y0 == 0 && r.width == 1 && r.height == 1 && r.x1 == r.block && r.y1 == r.block);
    }
}

// >>crop

static void clip_of(mat4 m, const double p[3], double c[4])
{
    for (int r = 0; r < 4; r++)
        c[r] = m.m[r] * p[0] + m.m[4 + r] * p[1] + m.m[8 + r] * p[2] + m.m[12 + r];
}

static void check_crop(const display_desc *d, const fov_ring_rect *r, int npts)
{
    double f = focal(d);
    mat4 proj = m4_perspective_hfov(d->hfov_deg * (float)PI_D / 180.0f, (float)d->width / (float)d->height, 0.1f, 100.0f);
    mat4 c = fov_ring_crop(d, r);
    mat4 rp = m4_mul(c, proj);
    int b = r->block;
    /* The rectangle's corners land on ring NDC -1 / +1 (up to float rounding of the matrix, whose
     * entries grow with the zoom). */
    double X0 = 2.0 * r->x0 / d->width - 1, X1 = 2.0 * r->x1 / d->width - 1;
    double Y0 = 1 - 2.0 * r->y1 / d->height, Y1 = 1 - 2.0 * r->y0 / d->height;
    double ex = 1e-6 * (fabs(c.m[0]) + fabs(c.m[12]) + 1), ey = 1e-6 * (fabs(c.m[5]) + fabs(c.m[13]) + 1);
    CHECK_NEAR(c.m[0] * X0 + c.m[12], -1.0, ex);
    CHECK_NEAR(c.m[0] * X1 + c.m[12], 1.0, ex);
    CHECK_NEAR(c.m[5] * Y0 + c.m[13], -1.0, ey);
    CHECK_NEAR(c.m[5] * Y1 + c.m[13], 1.0, ey);
    CHECK(c.m[10] == 1.0f && c.m[15] == 1.0f && c.m[14] == 0.0f && c.m[3] == 0.0f && c.m[7] == 0.0f);
    int bad = 0;
    for (int k = 0; k < npts; k++) {
        /* A world point (camera at the origin, identity view) inside display pixel (px, py). */
        int px = r->x0 + (int)(rnd() * (r->x1 - r->x0)), py = r->y0 + (int)(rnd() * (r->y1 - r->y0));
        double u = 0.02 + 0.96 * rnd(), v = 0.02 + 0.96 * rnd(), z = -(0.2 + 90.0 * rnd());
        double p[3] = {(px + u - 0.5 * d->width) * -z / f, -(py + v - 0.5 * d->height) * -z / f, z};
        double cd[4], cr[4];
        clip_of(proj, p, cd);
        clip_of(rp, p, cr);
        int dx = (int)floor((cd[0] / cd[3] + 1) * 0.5 * d->width);
        int dy = (int)floor((1 - cd[1] / cd[3]) * 0.5 * d->height);
        int rx = (int)floor((cr[0] / cr[3] + 1) * 0.5 * r->width);
        int ry = (int)floor((1 - cr[1] / cr[3]) * 0.5 * r->height);
        bool ok = dx == px && dy == py && rx >= 0 && rx < r->width && ry >= 0 && ry < r->height &&
                  r->x0 + rx * b <= dx && dx < r->x0 + (rx + 1) * b && r->y0 + ry * b <= dy && dy < r->y0 + (ry + 1) * b;
        if (!ok && bad++ < 3)
            fprintf(stderr, "crop: rect [%d,%d)x[%d,%d) b %d: pixel (%d,%d) -> display (%d,%d) ring (%d,%d)\n",
                    r->x0, r->x1, r->y0, r->y1, b, px, py, dx, dy, rx, ry);
    }
    CHECK(bad == 0);
}

TEST(crop_aligns_ring_pixels_with_display_pixels)
{
    display_desc ds[] = {disp(1280, 720, 90), disp(1917, 1079, 73)};
    const int blocks[] = {1, 2, 4, 16};
    for (int k = 0; k < 2; k++) {
        const display_desc *d = &ds[k];
        for (int bi = 0; bi < 4; bi++) {
            int b = blocks[bi];
            /* Odd block offsets and sizes, including a rectangle past the display's right/bottom
             * edge by less than a block. */
            int gw = (d->width + b - 1) / b * b, gh = (d->height + b - 1) / b * b;
            fov_ring_rect rs[3] = {
                {3 * b, 5 * b, 3 * b + 37 * b, 5 * b + 23 * b, 37, 23, b},
                {0, 0, gw, gh, gw / b, gh / b, b},
                {gw - 7 * b, gh - 3 * b, gw, gh, 7, 3, b},
            };
            for (int j = 0; j < 3; j++)
                check_crop(d, &rs[j], 3000);
        }
        /* Real footprints. */
        fov_layout l = fov_layout_auto(d, 0, 0);
        for (int i = 0; i < l.count; i++) {
            fov_ring_rect r = fov_ring_footprint(d, &l, i, 211.3f, 97.8f, 1);
            check_crop(d, &r, 2000);
        }
    }
}

// >>composite

static void check_continuity(const fov_layout *l)
{
    float emax = 0;
    float min_band = 1e9f;
    for (int i = 0; i + 1 < l->count; i++) {
        emax = l->rings[i].outer_deg;
        float band = fminf(l->blend_deg, 0.5f * (l->rings[i].outer_deg - (i ? l->rings[i - 1].outer_deg : 0)));
        min_band = fminf(min_band, band);
    }
    const double step = 1e-4;
    double prev = 0;
    int jumps = 0, backs = 0;
    for (long s = 0; s * step <= emax + 5.0; s++) {
        float e = (float)(s * step);
        fov_blend w = fov_composite_weight(l, e);
        CHECK(w.ring >= 0 && w.ring < l->count && w.next >= 0.0f && w.next <= 1.0f);
        CHECK(e < l->rings[w.ring].outer_deg && (w.ring == 0 || e >= l->rings[w.ring - 1].outer_deg));
        double m = w.ring + w.next;
        if (s > 0) {
            if (m < prev - 1e-6)
                backs++;
            if (m - prev > 1.5 * step / min_band + 1e-4)
                jumps++;
        }
        prev = m;
    }
    CHECK(backs == 0);
    CHECK(jumps == 0);
    /* At the borders themselves. */
    for (int i = 0; i + 1 < l->count; i++) {
        float o = l->rings[i].outer_deg;
        fov_blend at = fov_composite_weight(l, o), below = fov_composite_weight(l, nextafterf(o, 0));
        CHECK(at.ring == i + 1 && at.next == 0.0f);
        CHECK(below.ring == i && below.next > 0.999f);
    }
}

TEST(composite_weights_are_continuous_and_monotone)
{
    display_desc d = disp(1280, 720, 90);
    fov_layout a = fov_layout_auto(&d, 0, 0);
    check_continuity(&a);
    fov_layout narrow = parse_ok("1:1:0,1.5:1/2:0,30:1/4:0,*:1/8:0", &d);
    check_continuity(&narrow);
    /* Band = min(blend, half the ring's width). */
    fov_blend w = fov_composite_weight(&narrow, 0.75f); /* ring 0's band is [0.5, 1) */
    CHECK(w.ring == 0 && w.next == 0.5f);
    w = fov_composite_weight(&narrow, 1.25f); /* ring 1's band is [1.25, 1.5) */
    CHECK(w.ring == 1 && w.next == 0.0f);
    w = fov_composite_weight(&narrow, 29.0f); /* ring 2's band is [28, 30) */
    CHECK(w.ring == 2 && w.next == 0.5f);
    /* Odd inputs. */
    w = fov_composite_weight(&narrow, -3.0f);
    CHECK(w.ring == 0 && w.next == 0.0f);
    w = fov_composite_weight(&narrow, NAN);
    CHECK(w.ring == 3 && w.next == 0.0f);
    w = fov_composite_weight(&narrow, INFINITY);
    CHECK(w.ring == 3 && w.next == 0.0f);
    fov_layout off = fov_layout_off();
    w = fov_composite_weight(&off, 12.0f);
    CHECK(w.ring == 0 && w.next == 0.0f);
    /* Blend 0: hard edges. */
    narrow.blend_deg = 0;
    w = fov_composite_weight(&narrow, 0.999f);
    CHECK(w.ring == 0 && w.next == 0.0f);
}

// >>cost

TEST(shaded_pixels_of_the_auto_layout)
{
    const display_desc ds[] = {disp(1280, 720, 90), disp(1920, 1080, 90), disp(1920, 1080, 60), disp(4096, 2160, 110)};
    for (int k = 0; k < 4; k++) {
        const display_desc *d = &ds[k];
        fov_layout l = fov_layout_auto(d, 0, 0);
        double total = (double)d->width * d->height;
        long long per[MAX_FOV_RINGS];
        long long n = fov_shaded_pixels(d, &l, 0.5f * d->width, 0.5f * d->height, 0, per);
        long long n2 = fov_shaded_pixels(d, &l, 0.5f * d->width, 0.5f * d->height, 2, NULL);
        long long nc = fov_shaded_pixels(d, &l, 0, 0, 0, NULL);
        long long sum = 0;
        for (int i = 0; i < l.count; i++) {
            fov_ring_rect r = fov_ring_footprint(d, &l, i, 0.5f * d->width, 0.5f * d->height, 0);
            CHECK(per[i] == (long long)r.width * r.height);
            sum += per[i];
        }
        for (int i = l.count; i < MAX_FOV_RINGS; i++)
            CHECK(per[i] == 0);
        CHECK(sum == n);
        CHECK(n2 >= n);
        /* Independent estimate at central gaze: each inner ring is a square of side 2 f tan(outer)
         * (clipped to the display) at 1/b^2; the last ring is the whole display. */
        double f = focal(d), est = 0;
        for (int i = 0; i < l.count; i++) {
            double b = 1 << l.rings[i].scale_log2, s = i + 1 < l.count ? 2 * f * tan(l.rings[i].outer_deg * PI_D / 180) : 1e9;
            est += fmin(s, d->width) * fmin(s, d->height) / (b * b);
        }
        CHECK(fabs(n - est) < 0.1 * est);
        printf("shaded   %4dx%-4d @%5.1f: %d rings, centre gaze %lld px = %.1f %% of the display "
               "(margin 2: %.1f %%, corner gaze: %.1f %%); per ring:",
               d->width, d->height, (double)d->hfov_deg, l.count, n, 100.0 * n / total, 100.0 * n2 / total,
               100.0 * nc / total);
        for (int i = 0; i < l.count; i++)
            printf(" %lld", per[i]);
        printf("\n");
        if (k == 0)
            CHECK(n > 0.03 * total && n < 0.35 * total);
    }
    fov_layout off = fov_layout_off();
    display_desc d = disp(1280, 720, 90);
    CHECK(fov_shaded_pixels(&d, &off, 3, 4, 0, NULL) == 1280LL * 720);
}

/* The composite's tiles: they partition the display; every pixel centre of a tile of one ring takes
 * that ring with no blend, even with the eccentricity off by the GPU's error (checked at e +- half
 * the slack); most of the display is in such tiles; hard cases fall back to the search. */
TEST(composite_tiles_are_exact_partitions_and_conservative)
{
    static const int sizes[][2] = {{1280, 720}, {320, 180}, {333, 77}, {17, 5}};
    static const char *const specs[] = {"auto", "5:1:0,15:1/2:0,30:1/4:0,*:1/16:0", "0.01:1:0,*:1/8:1", "*:1/2:0"};
    int checked = 0;
    for (int si = 0; si < 4; si++)
        for (int li = 0; li < 4; li++)
            for (int g = 0; g < 6; g++) {
                display_desc d = disp(sizes[si][0], sizes[si][1], si == 3 ? 150.0f : 90.0f);
                fov_layout l = parse_ok(specs[li], &d);
                float gx = g == 0 ? 0.5f * d.width : (float)(rnd() * 1.6 - 0.3) * d.width;
                float gy = g == 0 ? 0.5f * d.height : (float)(rnd() * 1.6 - 0.3) * d.height;
                int max = fov_tile_max(&d);
                fov_tile *t = malloc(sizeof *t * (size_t)max);
                unsigned char *hit = calloc((size_t)d.width * (size_t)d.height, 1);
                int n = fov_composite_tiles(&d, &l, gx, gy, t, max);
                CHECK(n >= 1 && n <= max);
                float cgx = gx, cgy = gy;
                fov_gaze_clamp(&d, &cgx, &cgy);
                long long pure = 0;
                int bad = 0;
                for (int i = 0; i < n; i++) {
                    CHECK(t[i].x0 >= 0 && t[i].y0 >= 0 && t[i].x1 <= d.width && t[i].y1 <= d.height);
                    CHECK(t[i].ring >= -1 && t[i].ring < l.count);
                    for (int y = t[i].y0; y < t[i].y1; y++)
                        for (int x = t[i].x0; x < t[i].x1; x++) {
                            hit[(size_t)y * (size_t)d.width + (size_t)x]++;
                            if (t[i].ring < 0)
                                continue;
                            float e = fov_eccentricity_deg(&d, cgx, cgy, x + 0.5f, y + 0.5f);
                            for (int k = -1; k <= 1; k++) {
                                fov_blend b = fov_composite_weight(&l, e + k * 0.5f * FOV_TILE_SLACK_DEG);
                                bad += b.ring != t[i].ring || b.next != 0.0f;
                            }
                            checked++;
                        }
                    if (t[i].ring >= 0)
                        pure += (long long)(t[i].x1 - t[i].x0) * (t[i].y1 - t[i].y0);
                }
                int holes = 0;
                for (size_t i = 0; i < (size_t)d.width * (size_t)d.height; i++)
                    holes += hit[i] != 1;
                CHECK(bad == 0);
                CHECK(holes == 0);
                /* One ring (no blending anywhere): the whole display is one ring's tiles. */
                if (l.count == 1)
                    CHECK(pure == (long long)d.width * d.height);
                /* The auto layout at 1280x720: the bands are thin next to the rings. */
                if (si == 0 && li == 0)
                    CHECK(pure > 0.6 * d.width * d.height);
                free(t);
                free(hit);
            }
    CHECK(checked > 1000000);
    /* Hard cases: NaN gaze is the centre, as in the footprints; an empty rectangle searches. */
    display_desc d = disp(640, 360, 90.0f);
    fov_layout l = parse_ok("10:1:0,*:1/4:0", &d);
    CHECK(fov_tile_ring(&d, &l, NAN, NAN, 312, 172, 328, 188) == fov_tile_ring(&d, &l, 320, 180, 312, 172, 328, 188));
    CHECK(fov_tile_ring(&d, &l, 320, 180, 312, 172, 328, 188) == 0);
    CHECK(fov_tile_ring(&d, &l, 320, 180, 10, 10, 10, 20) == -1);
    CHECK(fov_tile_ring(&d, &l, INFINITY, 1e30f, 0, 0, 16, 16) == 1); /* the centre gaze: a corner is ring 1 */
    CHECK(fov_tile_ring(&d, NULL, 320, 180, 0, 0, 16, 16) == -1);
}

/* Ring culling: the hole is where the finer ring is shown alone (no pixel there takes ring i, even
 * blended); the culled radius keeps a margin of 3 ring pixels; a rectangle whose corners are
 * within a radius is wholly within it (the region is convex). */
TEST(ring_holes_and_culling_are_conservative)
{
    display_desc d = disp(1280, 720, 90);
    fov_layout l = parse_ok("10:1:0,20:1/2:0,30:1/4:0,*:1/16:0", &d);
    CHECK(fov_ring_hole_deg(&l, 0) == 0.0f);
    CHECK_NEAR(fov_ring_hole_deg(&l, 1), 8.0, 1e-6);  /* 10 less the 2-degree band */
    CHECK_NEAR(fov_ring_hole_deg(&l, 2), 18.0, 1e-6);
    CHECK_NEAR(fov_ring_hole_deg(&l, 3), 28.0, 1e-6);
    CHECK(fov_ring_hole_deg(&l, 4) == 0.0f && fov_ring_hole_deg(&l, -1) == 0.0f && fov_ring_hole_deg(NULL, 1) == 0.0f);
    /* Margin: 3 ring pixels at the largest angular pixel size (1 / focal length, radians). */
    double f = focal(&d);
    CHECK_NEAR(fov_ring_cull_deg(&d, &l, 3), 28.0 - 3 * 16 / f * 180 / PI_D, 1e-4);
    CHECK(fov_ring_cull_deg(&d, &l, 0) == 0.0f);
    fov_layout tiny = parse_ok("0.5:1:0,*:1/16:0", &d); /* hole smaller than the margin: nothing culled */
    CHECK(fov_ring_cull_deg(&d, &tiny, 1) == 0.0f);
    fov_layout wide = parse_ok("100:1:0,*:1/2:0", &d); /* the hole's cone is no longer convex in the plane */
    CHECK(fov_ring_cull_deg(&d, &wide, 1) == 0.0f);
    /* No eccentricity below ring i's hole takes ring i, with or without blending. */
    for (int k = 0; k < 20000; k++) {
        float e = (float)(rnd() * 40.0);
        fov_blend b = fov_composite_weight(&l, e);
        for (int i = 1; i < l.count; i++)
            if (e < fov_ring_hole_deg(&l, i))
                CHECK(b.ring < i && !(b.ring == i - 1 && b.next > 0.0f));
    }
    /* Rectangles within a radius: every point inside is within it too. */
    int within = 0;
    for (int k = 0; k < 3000; k++) {
        float gx = (float)(rnd() * 1280), gy = (float)(rnd() * 720), deg = (float)(rnd() * 40 + 1);
        float x0 = (float)(rnd() * 1400 - 60), y0 = (float)(rnd() * 800 - 40);
        float rect[4] = {x0, y0, x0 + (float)(rnd() * 300), y0 + (float)(rnd() * 300)};
        if (!fov_rect_within_deg(&d, gx, gy, rect, deg))
            continue;
        within++;
        for (int s = 0; s < 64; s++) {
            float px = rect[0] + (rect[2] - rect[0]) * (float)(s % 8) / 7, py = rect[1] + (rect[3] - rect[1]) * (float)(s / 8) / 7;
            CHECK(fov_eccentricity_deg(&d, gx, gy, px, py) < deg + 1e-4f);
        }
    }
    CHECK(within > 200);
    const float r[4] = {600, 300, 700, 400};
    CHECK(fov_rect_within_deg(&d, 640, 360, r, 10.0f));
    CHECK(!fov_rect_within_deg(&d, 640, 360, r, 1.0f));
    CHECK(!fov_rect_within_deg(&d, 640, 360, r, 95.0f));   /* not convex: refused */
    CHECK(!fov_rect_within_deg(&d, 640, 360, r, NAN));
}

int main(void)
{
    log_set_quiet_errors(true);
    RUN(auto_layout_follows_the_acuity_model);
    RUN(auto_layout_on_degenerate_displays);
    RUN(auto_layout_blocks_resolve_the_acuity_for_any_gaze);
    RUN(acuity_margin_of_explicit_layouts);
    RUN(off_layout);
    RUN(parse_good_layouts);
    RUN(parse_bad_layouts);
    RUN(check_rejects_bad_structs);
    RUN(eccentricity_is_zero_at_gaze_symmetric_and_accurate);
    RUN(eccentricity_grows_along_lines_from_the_gaze);
    RUN(footprints_are_conservative_nested_and_aligned);
    RUN(footprint_hard_cases);
    RUN(crop_aligns_ring_pixels_with_display_pixels);
    RUN(composite_weights_are_continuous_and_monotone);
    RUN(shaded_pixels_of_the_auto_layout);
    RUN(composite_tiles_are_exact_partitions_and_conservative);
    RUN(ring_holes_and_culling_are_conservative);
    return test_summary();
}
