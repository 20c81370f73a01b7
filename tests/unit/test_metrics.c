/* test_metrics.c: src/metrics (ring masks, coverage ratio, RMSE/PSNR, change, CSV) on synthetic
 * images with known answers, and the hard cases: NaN/Inf inputs, 1x1 images, rings off screen,
 * gaze outside the display. */
#include <stdbool.h>

#include "core/log.h"
#include "metrics/metrics.h"
#include "test.h"

#define PI_D 3.14159265358979323846

// >>helpers

/* A frame with owned planes, each filled with one value. */
typedef struct frame {
    int w, h;
    float *r, *g, *b, *cov;
    metrics_view v;
} frame;

static void frame_init(frame *f, int w, int h, float r, float g, float b, float cov)
{
    f->w = w;
    f->h = h;
    size_t n = (size_t)w * (size_t)h;
    f->r = malloc(n * sizeof *f->r);
    f->g = malloc(n * sizeof *f->g);
    f->b = malloc(n * sizeof *f->b);
    f->cov = malloc(n * sizeof *f->cov);
    for (size_t i = 0; i < n; i++) {
        f->r[i] = r;
        f->g[i] = g;
        f->b[i] = b;
        f->cov[i] = cov;
    }
    f->v = (metrics_view){w, h, f->r, f->g, f->b, f->cov};
}

static void frame_free(frame *f)
{
    free(f->r);
    free(f->g);
    free(f->b);
    free(f->cov);
    memset(f, 0, sizeof *f);
}

static fov_layout parse_layout(const char *text, const display_desc *d)
{
    fov_layout l;
    char err[200];
    fs_status st = fov_layout_parse(text, d, &l, err, sizeof err);
    if (st != FS_OK)
        fprintf(stderr, "  layout %s: %s\n", text, err);
    CHECK(st == FS_OK);
    return l;
}

static long long count_ring(const ring_mask *m, int ring)
{
    long long n = 0;
    for (size_t i = 0; i < (size_t)m->width * (size_t)m->height; i++)
        n += m->ring[i] == ring;
    return n;
}

/* Every field finite: what CSV and JSON need. */
static bool all_finite(const ring_metrics *m)
{
    return isfinite(m->coverage) && isfinite(m->ref_coverage) && isfinite(m->coverage_ratio) &&
           isfinite(m->rmse) && isfinite(m->psnr) && isfinite(m->change) && isfinite(m->alpha_rmse) &&
           isfinite(m->flip);
}

/* A one-ring mask ("off" layout) of w x h: every pixel in ring 0. */
static ring_mask whole_mask(int w, int h)
{
    display_desc d = {w, h, 90.0f, 0.0f, 0.0f};
    fov_layout off = fov_layout_off();
    ring_mask m;
    CHECK(ring_mask_build(&d, &off, 0.5f * (float)w, 0.5f * (float)h, &m) == FS_OK);
    return m;
}

/* Eccentricity by a route of its own (acos of normalised view rays in double), to check the
 * mask's rings independently of fov_eccentricity_deg. */
static double ecc_ref(const display_desc *d, double gx, double gy, double px, double py)
{
    double f = 0.5 * d->width / tan(0.5 * d->hfov_deg * PI_D / 180.0);
    double a[3] = {gx - 0.5 * d->width, gy - 0.5 * d->height, -f};
    double b[3] = {px - 0.5 * d->width, py - 0.5 * d->height, -f};
    double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double c = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (la * lb);
    return acos(c > 1.0 ? 1.0 : c) * 180.0 / PI_D;
}

// >>ring masks

/* Gaze at the centre of 1280x720 at 90 deg (focal length 640 px), "5:1:0,*:0.5:0": ring 0 holds
 * the pixels whose centre lies within r = 640 tan 5 deg = 55.99 px of the gaze (on the optical
 * axis the 5-degree cone meets the display in a circle). Every pixel with its centre inside lies
 * within the circle of radius r + sqrt(2)/2, and every pixel meeting the circle of radius
 * r - sqrt(2)/2 has its centre inside, so pi (r - 0.71)^2 <= count <= pi (r + 0.71)^2 (+-250
 * around pi r^2 = 9849); the lattice count lands much closer, hence also 1 %. */
TEST(ring_mask_centre_circle)
{
    display_desc d = {1280, 720, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("5:1:0,*:0.5:0", &d);
    ring_mask m;
    CHECK(ring_mask_build(&d, &l, 640.0f, 360.0f, &m) == FS_OK);
    CHECK(m.width == 1280 && m.height == 720 && m.ring_count == 2);
    double r = 640.0 * tan(5.0 * PI_D / 180.0);
    double h = sqrt(0.5);
    long long n0 = count_ring(&m, 0), n1 = count_ring(&m, 1);
    CHECK(n0 + n1 == 1280LL * 720LL);
    CHECK(n0 >= PI_D * (r - h) * (r - h) && n0 <= PI_D * (r + h) * (r + h));
    CHECK_NEAR((double)n0, PI_D * r * r, 0.01 * PI_D * r * r);
    /* Symmetric about the gaze (a pixel corner): mirrored pixels share a ring. */
    int asym = 0;
    for (int y = 0; y < 720; y++)
        for (int x = 0; x < 1280; x++)
            asym += m.ring[y * 1280 + x] != m.ring[y * 1280 + (1279 - x)] ||
                    m.ring[y * 1280 + x] != m.ring[(719 - y) * 1280 + x];
    CHECK(asym == 0);
    ring_mask_free(&m);
    ring_mask_free(&m); /* no-op on a freed mask */
    ring_mask_free(NULL);
}

/* Gaze on a corner: off-axis the cone meets the display in an ellipse, so count against an
 * independent eccentricity instead of a formula; only pixels within float rounding of the
 * border (1e-3 deg) may disagree. */
TEST(ring_mask_corner_matches_independent_eccentricity)
{
    display_desc d = {320, 180, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("10:1:0,25:0.5:0,*:0.25:0", &d);
    static const float gazes[][2] = {{0.0f, 0.0f}, {320.0f, 180.0f}, {0.0f, 180.0f}, {100.5f, 3.25f}};
    for (size_t k = 0; k < sizeof gazes / sizeof gazes[0]; k++) {
        ring_mask m;
        CHECK(ring_mask_build(&d, &l, gazes[k][0], gazes[k][1], &m) == FS_OK);
        int wrong = 0, borderline = 0;
        for (int y = 0; y < d.height; y++) {
            for (int x = 0; x < d.width; x++) {
                double e = ecc_ref(&d, gazes[k][0], gazes[k][1], x + 0.5, y + 0.5);
                int want = e < 10.0 ? 0 : e < 25.0 ? 1 : 2;
                if (m.ring[y * d.width + x] != want) {
                    if (fabs(e - 10.0) < 1e-3 || fabs(e - 25.0) < 1e-3)
                        borderline++;
                    else
                        wrong++;
                }
            }
        }
        CHECK(wrong == 0);
        CHECK(borderline <= 2);
        CHECK(count_ring(&m, 0) > 0 && count_ring(&m, 1) > 0 && count_ring(&m, 2) > 0);
        ring_mask_free(&m);
    }
}

/* Gaze outside the display is clamped first (the composite's gaze); a NaN gaze is the centre. */
TEST(ring_mask_gaze_outside_clamps)
{
    display_desc d = {160, 90, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("10:1:0,*:0.5:0", &d);
    ring_mask out, edge, nan_gaze, centre;
    CHECK(ring_mask_build(&d, &l, -500.0f, 2000.0f, &out) == FS_OK);
    CHECK(ring_mask_build(&d, &l, 0.0f, 90.0f, &edge) == FS_OK);
    CHECK(ring_mask_build(&d, &l, NAN, 10.0f, &nan_gaze) == FS_OK);
    CHECK(ring_mask_build(&d, &l, 80.0f, 45.0f, &centre) == FS_OK);
    CHECK(memcmp(out.ring, edge.ring, 160 * 90) == 0);
    CHECK(memcmp(nan_gaze.ring, centre.ring, 160 * 90) == 0);
    CHECK(out.ring[(90 - 1) * 160] == 0); /* the bottom-left pixel is the gaze's */
    CHECK(out.ring[159] == 1);
    ring_mask_free(&out);
    ring_mask_free(&edge);
    ring_mask_free(&nan_gaze);
    ring_mask_free(&centre);
}

TEST(ring_mask_bad_input)
{
    display_desc d = {0, 90, 90.0f, 0.0f, 0.0f};
    fov_layout l = fov_layout_off();
    ring_mask m;
    CHECK(ring_mask_build(&d, &l, 0.0f, 0.0f, &m) == FS_ERR_USAGE);
    CHECK(m.ring == NULL);
    d.width = MAX_DISPLAY_SIZE + 1;
    CHECK(ring_mask_build(&d, &l, 0.0f, 0.0f, &m) == FS_ERR_USAGE);
    d.width = 16;
    l.count = 0;
    CHECK(ring_mask_build(&d, &l, 0.0f, 0.0f, &m) == FS_ERR_USAGE);
}

// >>error

TEST(rmse_psnr_known_values)
{
    ring_mask m = whole_mask(7, 5);
    ring_metrics o[2];
    frame img, ref;
    /* A constant offset of 0.125 in every channel: RMSE 0.125, PSNR 10 log10(64) = 18.06 dB.
     * (0.375 - 0.25 is exact in float.) */
    frame_init(&img, 7, 5, 0.375f, 0.625f, 1.125f, 1.0f);
    frame_init(&ref, 7, 5, 0.25f, 0.5f, 1.0f, 1.0f);
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].pixels == 35 && o[1].pixels == 35);
    CHECK_NEAR(o[0].rmse, 0.125, 1e-15);
    CHECK_NEAR(o[0].psnr, 10.0 * log10(64.0), 1e-12);
    CHECK_NEAR(o[1].rmse, 0.125, 1e-15);

    /* A known MSE: R off by 0.5 in every pixel, G and B exact -> MSE = 0.25 / 3. */
    for (int i = 0; i < 35; i++) {
        img.r[i] = ref.r[i] + 0.5f;
        img.g[i] = ref.g[i];
        img.b[i] = ref.b[i];
    }
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK_NEAR(o[0].rmse, sqrt(0.25 / 3.0), 1e-15);
    CHECK_NEAR(o[0].psnr, 10.0 * log10(3.0 / 0.25), 1e-12);

    /* Identical images: RMSE 0, PSNR at the cap (not Inf). */
    CHECK(metrics_compute(&ref.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].rmse == 0.0);
    CHECK(o[0].psnr == METRICS_PSNR_CAP_DB);
    /* Just above the cap's MSE (1e-10) the formula takes over, continuous with the cap. */
    for (int i = 0; i < 35; i++)
        img.r[i] = ref.r[i];
    img.r[0] = ref.r[0] + 0.001f; /* MSE = 1e-6 / 105 ~ 9.5e-9: 80.2 dB */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    double d0 = (double)(ref.r[0] + 0.001f) - (double)ref.r[0];
    CHECK_NEAR(o[0].psnr, -10.0 * log10(d0 * d0 / 105.0), 1e-9);
    CHECK(o[0].psnr < METRICS_PSNR_CAP_DB);
    frame_free(&img);
    frame_free(&ref);
    ring_mask_free(&m);
}

/* Error only inside ring 0: ring 1 is exact, and the whole display is the pixel-weighted mean
 * of the rings' MSE. */
TEST(error_per_ring)
{
    display_desc d = {64, 36, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("10:1:0,*:0.5:0", &d);
    ring_mask m;
    CHECK(ring_mask_build(&d, &l, 32.0f, 18.0f, &m) == FS_OK);
    frame img, ref;
    frame_init(&img, 64, 36, 0.5f, 0.5f, 0.5f, 0.0f);
    frame_init(&ref, 64, 36, 0.5f, 0.5f, 0.5f, 0.0f);
    for (int i = 0; i < 64 * 36; i++)
        if (m.ring[i] == 0)
            img.g[i] = 0.75f;
    ring_metrics o[3];
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    long long n0 = count_ring(&m, 0);
    CHECK(n0 > 0 && o[0].pixels == n0 && o[1].pixels == 64 * 36 - n0 && o[2].pixels == 64 * 36);
    CHECK_NEAR(o[0].rmse, sqrt(0.0625 / 3.0), 1e-15);
    CHECK(o[1].rmse == 0.0 && o[1].psnr == METRICS_PSNR_CAP_DB);
    CHECK_NEAR(o[2].rmse * o[2].rmse * 64 * 36, o[0].rmse * o[0].rmse * (double)n0, 1e-12);
    frame_free(&img);
    frame_free(&ref);
    ring_mask_free(&m);
}

// >>coverage

TEST(coverage_ratio)
{
    ring_mask m = whole_mask(8, 4);
    ring_metrics o[2];
    frame img, ref;
    frame_init(&img, 8, 4, 0.1f, 0.2f, 0.3f, 0.5f);
    frame_init(&ref, 8, 4, 0.1f, 0.2f, 0.3f, 1.0f);
    /* Half the reference's coverage (erosion). */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].coverage == 0.5 && o[0].ref_coverage == 1.0);
    CHECK(o[0].coverage_ratio == 0.5);
    /* Twice the reference's coverage (bloat): the other direction. */
    CHECK(metrics_compute(&ref.v, &img.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].coverage_ratio == 2.0);
    /* Both empty: nothing to preserve, nothing added -> 1. */
    for (int i = 0; i < 32; i++)
        img.cov[i] = ref.cov[i] = 0.0f;
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].coverage_ratio == 1.0);
    /* Empty reference, covered method: num / METRICS_EPS, large and finite. */
    img.cov[0] = 1.0f; /* mean 1/32 */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK_NEAR(o[0].coverage_ratio, (1.0 / 32.0) / METRICS_EPS, 1e-6);
    /* A tiny but real reference stays a plain ratio. */
    ref.cov[1] = 3.2e-4f; /* mean 1e-5 */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK_NEAR(o[0].coverage_ratio, (1.0 / 32.0) / ((double)3.2e-4f / 32.0), 1e-6);
    frame_free(&img);
    frame_free(&ref);
    ring_mask_free(&m);
}

// >>change

TEST(change_and_no_previous)
{
    /* The method's mean frame-to-frame change (not motion-compensated): the static-view flicker
     * on frames with a still camera. The flicker ratio it once fed (change over the reference's
     * change) is gone: it scored a frozen image best. */
    ring_mask m = whole_mask(6, 6);
    ring_metrics o[2];
    frame img, ref, prev;
    frame_init(&img, 6, 6, 0.5f, 0.5f, 0.5f, 1.0f);
    frame_init(&ref, 6, 6, 0.5f, 0.5f, 0.5f, 1.0f);
    frame_init(&prev, 6, 6, 0.375f, 0.5f, 0.5f, 1.0f); /* R changed by 0.125 */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, &prev.v, &m, o) == FS_OK);
    CHECK(o[0].has_prev == 1);
    CHECK_NEAR(o[0].change, 0.125 / 3.0, 1e-15);
    /* No previous frame (first frame, after a cut). */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].has_prev == 0 && o[0].change == 0.0);
    /* Unchanged: 0. */
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, &img.v, &m, o) == FS_OK);
    CHECK(o[0].has_prev == 1 && o[0].change == 0.0);
    frame_free(&img);
    frame_free(&ref);
    frame_free(&prev);
    ring_mask_free(&m);
}

// >>hard cases

/* NaN counts as 0 and +-Inf as +-65504 (as the EXR file stores them): every output finite, and
 * the values follow from that rule. */
TEST(non_finite_inputs)
{
    ring_mask m = whole_mask(1, 1);
    ring_metrics o[2];
    frame img, ref, prev;
    frame_init(&img, 1, 1, NAN, 0.5f, 0.5f, NAN);
    frame_init(&ref, 1, 1, 0.5f, 0.5f, 0.5f, 1.0f);
    frame_init(&prev, 1, 1, 0.5f, INFINITY, 0.5f, 1.0f);
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, &prev.v, &m, o) == FS_OK);
    for (int k = 0; k < 2; k++)
        CHECK(all_finite(&o[k]));
    CHECK_NEAR(o[0].rmse, sqrt(0.25 / 3.0), 1e-15);  /* NaN R -> 0 against 0.5 */
    CHECK(o[0].coverage == 0.0 && o[0].coverage_ratio == 0.0);
    CHECK_NEAR(o[0].change, (0.5 + (65504.0 - 0.5) + 0.0) / 3.0, 1e-9);

    /* Everything broken at once, in a larger frame with rings. */
    display_desc d = {16, 9, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("20:1:0,*:0.5:0", &d);
    ring_mask rm;
    CHECK(ring_mask_build(&d, &l, 8.0f, 4.5f, &rm) == FS_OK);
    frame a, b;
    frame_init(&a, 16, 9, INFINITY, -INFINITY, NAN, INFINITY);
    frame_init(&b, 16, 9, NAN, NAN, 1e30f, -1e30f);
    ring_metrics r[3];
    CHECK(metrics_compute(&a.v, &b.v, NULL, NULL, &b.v, &rm, r) == FS_OK);
    for (int k = 0; k < 3; k++)
        CHECK(all_finite(&r[k]));
    frame_free(&a);
    frame_free(&b);
    ring_mask_free(&rm);
    frame_free(&img);
    frame_free(&ref);
    frame_free(&prev);
    ring_mask_free(&m);
}

/* A 1x1 display with rings: its one pixel is the gaze's, so ring 0; the outer ring is off screen
 * and reports pixels 0 with the neutral values. */
TEST(one_pixel_and_empty_ring)
{
    display_desc d = {1, 1, 90.0f, 0.0f, 0.0f};
    fov_layout l = parse_layout("5:1:0,*:0.5:0", &d);
    ring_mask m;
    CHECK(ring_mask_build(&d, &l, 0.5f, 0.5f, &m) == FS_OK);
    CHECK(m.ring[0] == 0);
    frame img, ref;
    frame_init(&img, 1, 1, 0.25f, 0.25f, 0.25f, 0.25f);
    frame_init(&ref, 1, 1, 0.5f, 0.5f, 0.5f, 1.0f);
    ring_metrics o[3];
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[0].pixels == 1 && o[1].pixels == 0 && o[2].pixels == 1);
    CHECK_NEAR(o[0].rmse, 0.25, 1e-15);
    CHECK(o[0].coverage_ratio == 0.25);
    CHECK(o[1].coverage == 0.0 && o[1].coverage_ratio == 1.0 && o[1].rmse == 0.0 &&
          o[1].psnr == METRICS_PSNR_CAP_DB && o[1].change == 0.0);
    CHECK(o[2].rmse == o[0].rmse && o[2].coverage_ratio == o[0].coverage_ratio);
    for (int k = 0; k < 3; k++)
        CHECK(all_finite(&o[k]));
    ring_mask_free(&m);

    /* A ring too small to hold any pixel centre: gaze on a pixel corner, radius 0.01 deg. */
    display_desc d2 = {64, 36, 90.0f, 0.0f, 0.0f};
    fov_layout tiny = parse_layout("0.01:1:0,*:0.5:0", &d2);
    CHECK(ring_mask_build(&d2, &tiny, 0.0f, 0.0f, &m) == FS_OK);
    CHECK(count_ring(&m, 0) == 0 && count_ring(&m, 1) == 64 * 36);
    ring_mask_free(&m);
    frame_free(&img);
    frame_free(&ref);
}

TEST(size_mismatch_refused)
{
    ring_mask m = whole_mask(4, 4);
    frame img, ref;
    frame_init(&img, 4, 4, 0, 0, 0, 0);
    frame_init(&ref, 4, 3, 0, 0, 0, 0);
    ring_metrics o[2];
    log_set_quiet_errors(true);
    CHECK(metrics_compute(&img.v, &ref.v, NULL, NULL, NULL, &m, o) == FS_ERR_INTERNAL);
    CHECK(metrics_compute(&img.v, &img.v, NULL, NULL, &ref.v, &m, o) == FS_ERR_INTERNAL);
    metrics_view no_cov = img.v;
    no_cov.coverage = NULL;
    CHECK(metrics_compute(&no_cov, &img.v, NULL, NULL, NULL, &m, o) == FS_ERR_INTERNAL);
    log_set_quiet_errors(false);
    CHECK(o[0].pixels == 0 && o[1].pixels == 0);
    frame_free(&img);
    frame_free(&ref);
    ring_mask_free(&m);
}

// >>band-limited reference

/* A display, a three-ring layout (full, 1/2, 1/4) and its footprints for a gaze. */
typedef struct band_setup {
    display_desc d;
    fov_layout l;
    fov_ring_rect rects[MAX_FOV_RINGS];
    float gx, gy;
} band_setup;

static band_setup band_setup_make(int w, int h, float gx, float gy)
{
    band_setup b = {.d = {w, h, 90.0f, 0.0f, 0.0f}, .gx = gx, .gy = gy};
    char err[160];
    CHECK(fov_layout_parse("8:1:0,20:1/2:0,*:1/4:0", &b.d, &b.l, err, sizeof err) == FS_OK);
    for (int i = 0; i < b.l.count; i++)
        b.rects[i] = fov_ring_footprint(&b.d, &b.l, i, gx, gy, FOV_MARGIN_BLOCKS);
    return b;
}

TEST(band_limit_keeps_what_the_rings_can_show)
{
    /* A constant image stays constant; an image linear in x and y is reproduced by box filter +
     * bilinear reconstruction wherever the taps are not clamped (away from a footprint's edge):
     * checked over the pixels whose ring footprint holds them with a margin of two ring pixels. */
    enum { W = 160, H = 96 };
    band_setup b = band_setup_make(W, H, 60.0f, 40.0f);
    frame ref, out;
    frame_init(&ref, W, H, 0.3f, 0.5f, 0.7f, 0.25f);
    frame_init(&out, W, H, 0, 0, 0, 0);
    float *planes[4] = {out.r, out.g, out.b, out.cov};
    metrics_view band;
    CHECK(metrics_band_limit(&ref.v, &b.d, &b.l, b.rects, b.gx, b.gy, planes, &band) == FS_OK);
    double worst = 0;
    for (int i = 0; i < W * H; i++)
        worst = fmax(worst, fmax(fabs(out.r[i] - 0.3f), fabs(out.cov[i] - 0.25f)));
    CHECK(worst < 1e-6);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            ref.r[y * W + x] = 0.01f * (float)x + 0.02f * (float)y;
    CHECK(metrics_band_limit(&ref.v, &b.d, &b.l, b.rects, b.gx, b.gy, planes, &band) == FS_OK);
    worst = 0;
    long checked = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool inside = true;
            for (int k = 0; k < b.l.count; k++) {
                const fov_ring_rect *r = &b.rects[k];
                int m = 2 * r->block;
                inside = inside && x >= r->x0 + m && x < r->x1 - m && y >= r->y0 + m && y < r->y1 - m &&
                         r->x1 <= W && r->y1 <= H;
            }
            if (!inside)
                continue;
            checked++;
            worst = fmax(worst, fabs(out.r[y * W + x] - ref.r[y * W + x]));
        }
    CHECK(checked > 100);
    CHECK(worst < 1e-4);
    frame_free(&ref);
    frame_free(&out);
}

TEST(band_limited_reference_scores_zero_alpha_error)
{
    /* A mode that renders the band-limited reference exactly: alpha_rmse 0 in every ring, while its
     * rmse against the full reference (a high-frequency checkerboard the coarse rings cannot hold)
     * is large outside the full-resolution ring. A wrong band limit would leave alpha_rmse > 0. */
    enum { W = 160, H = 96 };
    band_setup b = band_setup_make(W, H, 80.0f, 48.0f);
    frame ref, out;
    frame_init(&ref, W, H, 0, 0, 0, 0.5f);
    frame_init(&out, W, H, 0, 0, 0, 0);
    for (int i = 0; i < W * H; i++)
        ref.r[i] = ref.g[i] = ref.b[i] = (float)(((i % W) + (i / W)) % 2);
    float *planes[4] = {out.r, out.g, out.b, out.cov};
    metrics_view band;
    CHECK(metrics_band_limit(&ref.v, &b.d, &b.l, b.rects, b.gx, b.gy, planes, &band) == FS_OK);
    ring_mask m;
    CHECK(ring_mask_build(&b.d, &b.l, b.gx, b.gy, &m) == FS_OK);
    ring_metrics o[MAX_FOV_RINGS + 1];
    CHECK(metrics_compute(&band, &ref.v, &band, NULL, NULL, &m, o) == FS_OK);
    for (int k = 0; k <= b.l.count; k++)
        CHECK(o[k].pixels == 0 || o[k].alpha_rmse < 1e-9);
    CHECK(o[2].pixels > 0 && o[2].rmse > 0.3);
    /* Without a band-limited reference, alpha_rmse is rmse. */
    CHECK(metrics_compute(&band, &ref.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[2].alpha_rmse == o[2].rmse);
    /* One full-resolution ring: the band-limited reference is the reference. */
    fov_layout off = fov_layout_off();
    fov_ring_rect full = fov_ring_footprint(&b.d, &off, 0, b.gx, b.gy, 0);
    CHECK(metrics_band_limit(&ref.v, &b.d, &off, &full, b.gx, b.gy, planes, &band) == FS_OK);
    CHECK(memcmp(out.r, ref.r, sizeof(float) * W * H) == 0);
    ring_mask_free(&m);
    frame_free(&ref);
    frame_free(&out);
}

TEST(flip_map_is_averaged_per_ring)
{
    /* A FLIP map holding each pixel's ring index: every ring's flip is its index, the whole
     * display's the pixel-weighted mean of them. */
    enum { W = 160, H = 96 };
    band_setup b = band_setup_make(W, H, 80.0f, 48.0f);
    frame img;
    frame_init(&img, W, H, 0.5f, 0.5f, 0.5f, 0.5f);
    ring_mask m;
    CHECK(ring_mask_build(&b.d, &b.l, b.gx, b.gy, &m) == FS_OK);
    float *map = malloc(sizeof(float) * W * H);
    double sum = 0;
    for (int i = 0; i < W * H; i++)
        sum += map[i] = (float)m.ring[i];
    ring_metrics o[MAX_FOV_RINGS + 1];
    CHECK(metrics_compute(&img.v, &img.v, NULL, map, NULL, &m, o) == FS_OK);
    for (int k = 0; k < b.l.count; k++)
        CHECK(o[k].pixels == 0 || o[k].flip == (double)k);
    CHECK_NEAR(o[b.l.count].flip, sum / (W * H), 1e-12);
    CHECK(metrics_compute(&img.v, &img.v, NULL, NULL, NULL, &m, o) == FS_OK);
    CHECK(o[b.l.count].flip == 0.0);
    free(map);
    ring_mask_free(&m);
    frame_free(&img);
}

// >>csv

TEST(csv_rows)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    CHECK(f != NULL);
    if (!f)
        return;
    ring_metrics m = {.pixels = 9849, .coverage = 0.25, .ref_coverage = 0.5,
                      .coverage_ratio = 0.5, .rmse = 0.125, .alpha_rmse = 0.0625, .flip = 0.25, .psnr = 18.0617997,
                      .temporal_error = 0.03125, .disoccluded = 0.125,
                      .change = 0.01, .has_prev = 1};
    CHECK(metrics_csv_header(f));
    CHECK(metrics_csv_row(f, 3, 0.125f, "hashed", 0, &m, true, 12.5, "fixation"));   /* still camera: change */
    CHECK(metrics_csv_row(f, 4, NAN, "a,\"b\"", -1, &m, false, NAN, "saccade")); /* moving: -1 */
    fclose(f);
    const char *want =
        "frame,time,mode,ring,pixels,coverage,ref_coverage,coverage_ratio,rmse,alpha_rmse,flip,psnr,"
        "temporal_error,disoccluded,static_flicker,gaze_event,frame_ms\n"
        "3,0.125,hashed,0,9849,0.25,0.5,0.5,0.125,0.0625,0.25,18.0617997,0.03125,0.125,0.01,fixation,12.500\n"
        "4,0,\"a,\"\"b\"\"\",-1,9849,0.25,0.5,0.5,0.125,0.0625,0.25,18.0617997,0.03125,0.125,-1,saccade,-1.000\n";
    CHECK(buf && strcmp(buf, want) == 0);
    if (buf && strcmp(buf, want) != 0)
        fprintf(stderr, "  got:\n%s", buf);
    free(buf);
}

int main(void)
{
    RUN(ring_mask_centre_circle);
    RUN(ring_mask_corner_matches_independent_eccentricity);
    RUN(ring_mask_gaze_outside_clamps);
    RUN(ring_mask_bad_input);
    RUN(rmse_psnr_known_values);
    RUN(error_per_ring);
    RUN(coverage_ratio);
    RUN(change_and_no_previous);
    RUN(non_finite_inputs);
    RUN(one_pixel_and_empty_ring);
    RUN(size_mismatch_refused);
    RUN(band_limit_keeps_what_the_rings_can_show);
    RUN(band_limited_reference_scores_zero_alpha_error);
    RUN(flip_map_is_averaged_per_ring);
    RUN(csv_rows);
    return test_summary();
}
