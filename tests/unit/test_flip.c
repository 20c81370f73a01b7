/* test_flip.c: LDR-FLIP (src/metrics/flip.c) against the official tool's error maps, and small
 * synthetic checks.
 *
 * Fixtures (../shared/fixtures/README.md, section 3): three 256x144 8-bit sRGB PNGs of frame 6
 * (reference, traditional, hashed) and the full-precision float32 error maps that NVlabs/flip v1.6
 * (FLIP.h, CPU) computes for each test image at ppd 2.8444444 (read by the tool as the float
 * 2.84444451) and at its default ppd 67.0206451. The PNGs are loaded as the tool loads them:
 * code / 255, then its sRGB transfer function, both in float (flip_srgb_to_linear).
 */
#include <stdint.h>

#include "metrics/flip.h"
#include "stb_png.h"
#include "test.h"

#define FIX_W 256
#define FIX_H 144

/* The required agreement with the official tool: mean within 1e-3, every pixel within 1e-2. */
#define MEAN_TOL 1e-3
#define PIXEL_TOL 1e-2

typedef struct planes {
    int w, h;
    float *c[3];
} planes;

static void planes_free(planes *p)
{
    for (int c = 0; c < 3; c++)
        free(p->c[c]);
    memset(p, 0, sizeof *p);
}

static int planes_alloc(planes *p, int w, int h)
{
    memset(p, 0, sizeof *p);
    p->w = w;
    p->h = h;
    for (int c = 0; c < 3; c++) {
        p->c[c] = calloc((size_t)w * (size_t)h, sizeof(float));
        if (!p->c[c]) {
            planes_free(p);
            return 0;
        }
    }
    return 1;
}

/* A fixture PNG as linear planes, as the tool loads it. 0 (and a failed CHECK) when missing. */
static int load_srgb_png(const char *rel, planes *out)
{
    const char *path = test_shared_path(rel);
    int w = 0, h = 0, comp = 0;
    uint8_t *px = stbi_load(path, &w, &h, &comp, 3);
    CHECK(px != NULL);
    if (!px) {
        fprintf(stderr, "cannot load %s (set FOVSIM_SHARED)\n", path);
        return 0;
    }
    int ok = planes_alloc(out, w, h);
    CHECK(ok);
    for (size_t i = 0; ok && i < (size_t)w * (size_t)h; i++)
        for (int c = 0; c < 3; c++)
            out->c[c][i] = flip_srgb_to_linear(px[3 * i + (size_t)c]);
    stbi_image_free(px);
    return ok;
}

/* A raw little-endian float32 map of FIX_W x FIX_H (this test runs on little-endian hosts). */
static float *load_f32(const char *rel)
{
    const char *path = test_shared_path(rel);
    const size_t n = (size_t)FIX_W * FIX_H;
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    if (!f) {
        fprintf(stderr, "cannot open %s (set FOVSIM_SHARED)\n", path);
        return NULL;
    }
    float *m = malloc(n * sizeof *m);
    size_t got = m ? fread(m, sizeof *m, n, f) : 0;
    int extra = fgetc(f);
    fclose(f);
    CHECK(got == n && extra == EOF);
    if (got != n || extra != EOF) {
        free(m);
        return NULL;
    }
    return m;
}

/* Our map of fixture test image `name` at ppd against the official one: mean and every pixel. */
static void check_against_official(const char *name, double ppd, const char *ppd_dir,
                                   const char *ppd_tag, double official_mean)
{
    char rel[256];
    planes ref, test;
    if (!load_srgb_png("fixtures/flip/inputs/reference.0006.srgb8.png", &ref))
        return;
    snprintf(rel, sizeof rel, "fixtures/flip/inputs/%s.0006.srgb8.png", name);
    if (!load_srgb_png(rel, &test)) {
        planes_free(&ref);
        return;
    }
    snprintf(rel, sizeof rel, "fixtures/flip/%s/%s.%s.f32", ppd_dir, name, ppd_tag);
    float *official = load_f32(rel);
    CHECK(ref.w == FIX_W && ref.h == FIX_H && test.w == FIX_W && test.h == FIX_H);
    float *err = malloc((size_t)FIX_W * FIX_H * sizeof *err);
    CHECK(err != NULL);
    if (official && err && ref.w == FIX_W && ref.h == FIX_H && test.w == FIX_W &&
        test.h == FIX_H) {
        CHECK(flip_ldr((const float *const *)ref.c, (const float *const *)test.c, FIX_W, FIX_H,
                       ppd, err) == FS_OK);
        double worst = 0.0, sum_abs = 0.0;
        int wx = 0, wy = 0, differing = 0;
        for (int i = 0; i < FIX_W * FIX_H; i++) {
            double d = fabs((double)err[i] - (double)official[i]);
            sum_abs += d;
            differing += err[i] != official[i];
            if (d > worst) {
                worst = d;
                wx = i % FIX_W;
                wy = i / FIX_W;
            }
        }
        double mean = flip_mean(err, FIX_W, FIX_H);
        double official_map_mean = flip_mean(official, FIX_W, FIX_H);
        fprintf(stderr,
                "  %s ppd %.9g: mean %.9f, official map's mean %.9f (diff %.3g), worst pixel "
                "|diff| %.3g at (%d, %d) (ours %.9g, official %.9g), mean |diff| %.3g, %d of %d "
                "pixels not bit-identical\n",
                name, ppd, mean, official_map_mean, mean - official_map_mean, worst, wx, wy,
                (double)err[wy * FIX_W + wx], (double)official[wy * FIX_W + wx],
                sum_abs / (FIX_W * FIX_H), differing, FIX_W * FIX_H);
        /* The map file and the README's number are the same thing; a mismatch is a bad fixture. */
        CHECK_NEAR(official_map_mean, official_mean, 1e-8);
        CHECK_NEAR(mean, official_mean, MEAN_TOL);
        CHECK_NEAR(mean, official_map_mean, MEAN_TOL);
        CHECK(worst <= PIXEL_TOL);
    }
    free(err);
    free(official);
    planes_free(&ref);
    planes_free(&test);
}

/* 2.8444444 = 256 px / 90 degrees, as the fixtures were made (the tool reads it with std::stof;
 * flip_ldr converts ppd to float the same way). */
static const double PPD_LOW = 2.8444444;

TEST(official_traditional_ppd_low)
{
    check_against_official("traditional", PPD_LOW, "ppd_2.8444444", "ppd2.8444444", 0.243835299);
}

TEST(official_hashed_ppd_low)
{
    check_against_official("hashed", PPD_LOW, "ppd_2.8444444", "ppd2.8444444", 0.226346385);
}

TEST(official_traditional_ppd_default)
{
    check_against_official("traditional", flip_ppd(0.7, 3840, 0.7), "ppd_default", "ppddefault",
                           0.193204096);
}

TEST(official_hashed_ppd_default)
{
    check_against_official("hashed", flip_ppd(0.7, 3840, 0.7), "ppd_default", "ppddefault",
                           0.150190988);
}

TEST(default_ppd_value)
{
    /* FLIP::calculatePPD(0.7, 3840, 0.7) in float, printed by the tool as 67.0206451. */
    CHECK_NEAR(flip_ppd(0.7, 3840, 0.7), 67.0206451, 1e-6);
}

TEST(srgb_decode)
{
    CHECK(flip_srgb_to_linear(0) == 0.0f);
    CHECK_NEAR(flip_srgb_to_linear(255), 1.0, 1e-6);
    CHECK_NEAR(flip_srgb_to_linear(10), 10.0 / 255.0 / 12.92, 1e-9);  /* linear segment */
    CHECK_NEAR(flip_srgb_to_linear(128), 0.2158605, 1e-6);             /* sRGB 0.50196 */
}

/* A w x h image, every pixel (r, g, b). */
static int flat_image(planes *p, int w, int h, float r, float g, float b)
{
    if (!planes_alloc(p, w, h))
        return 0;
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
        p->c[0][i] = r;
        p->c[1][i] = g;
        p->c[2][i] = b;
    }
    return 1;
}

/* Textured image: a smooth colour pattern with a few hard edges, so both pipelines have work. */
static int pattern_image(planes *p, int w, int h)
{
    if (!planes_alloc(p, w, h))
        return 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * (size_t)w + (size_t)x;
            p->c[0][i] = 0.5f + 0.5f * sinf(0.3f * (float)x);
            p->c[1][i] = (float)y / (float)(h - 1);
            p->c[2][i] = ((x / 5 + y / 7) & 1) ? 0.9f : 0.1f;
        }
    return 1;
}

static double map_max(const float *m, size_t n)
{
    double mx = 0.0;
    for (size_t i = 0; i < n; i++)
        mx = (double)m[i] > mx ? (double)m[i] : mx;
    return mx;
}

TEST(identical_images_give_zero)
{
    const int w = 40, h = 30;
    planes a;
    CHECK(pattern_image(&a, w, h));
    float *err = malloc((size_t)w * h * sizeof *err);
    CHECK(err != NULL);
    if (err && a.c[0]) {
        for (int k = 0; k < 2; k++) {
            double ppd = k == 0 ? PPD_LOW : flip_ppd(0.7, 3840, 0.7);
            CHECK(flip_ldr((const float *const *)a.c, (const float *const *)a.c, w, h, ppd,
                           err) == FS_OK);
            CHECK(map_max(err, (size_t)w * h) == 0.0);
        }
    }
    free(err);
    planes_free(&a);
}

TEST(map_in_unit_range)
{
    const int w = 48, h = 32;
    planes a, b;
    CHECK(pattern_image(&a, w, h));
    /* The test is out of range on purpose (negative, above 1, NaN): it is clamped like the tool
     * clamps, and the map must stay in [0, 1] and finite. */
    CHECK(flat_image(&b, w, h, 0.0f, 1.0f, 0.0f));
    float *err = malloc((size_t)w * h * sizeof *err);
    CHECK(err != NULL);
    if (err && a.c[0] && b.c[0]) {
        b.c[0][5] = -3.0f;
        b.c[1][6] = 7.0f;
        b.c[2][7] = NAN;
        for (int k = 0; k < 2; k++) {
            double ppd = k == 0 ? PPD_LOW : flip_ppd(0.7, 3840, 0.7);
            CHECK(flip_ldr((const float *const *)a.c, (const float *const *)b.c, w, h, ppd, err) ==
                  FS_OK);
            int ok = 1;
            for (int i = 0; i < w * h; i++)
                ok &= err[i] >= 0.0f && err[i] <= 1.0f;
            CHECK(ok);
            CHECK(map_max(err, (size_t)w * h) > 0.5);
        }
    }
    free(err);
    planes_free(&a);
    planes_free(&b);
}

TEST(larger_difference_scores_higher)
{
    const int w = 32, h = 32;
    const double ppd = flip_ppd(0.7, 3840, 0.7);
    planes grey, tiny, red, green, blue;
    CHECK(flat_image(&grey, w, h, 0.5f, 0.5f, 0.5f));
    CHECK(flat_image(&tiny, w, h, 0.51f, 0.5f, 0.5f));
    CHECK(flat_image(&red, w, h, 1.0f, 0.0f, 0.0f));
    CHECK(flat_image(&green, w, h, 0.0f, 1.0f, 0.0f));
    CHECK(flat_image(&blue, w, h, 0.0f, 0.0f, 1.0f));
    float *e = malloc((size_t)w * h * sizeof *e);
    CHECK(e != NULL);
    if (e && grey.c[0] && tiny.c[0] && red.c[0] && green.c[0] && blue.c[0]) {
        CHECK(flip_ldr((const float *const *)grey.c, (const float *const *)tiny.c, w, h, ppd, e) ==
              FS_OK);
        double m_tiny = flip_mean(e, w, h);
        CHECK(flip_ldr((const float *const *)grey.c, (const float *const *)red.c, w, h, ppd, e) ==
              FS_OK);
        double m_red = flip_mean(e, w, h);
        fprintf(stderr, "  grey vs grey+0.01 R: %.4f, grey vs pure red: %.4f\n", m_tiny, m_red);
        CHECK(m_tiny > 0.0);
        CHECK(m_tiny < 0.2);
        CHECK(m_red > 0.5);
        CHECK(m_red > 3.0 * m_tiny);
        /* Green against blue is cmax, the largest colour difference: error 1 everywhere. */
        CHECK(flip_ldr((const float *const *)green.c, (const float *const *)blue.c, w, h, ppd,
                       e) == FS_OK);
        CHECK_NEAR(flip_mean(e, w, h), 1.0, 1e-5);
    }
    free(e);
    planes_free(&grey);
    planes_free(&tiny);
    planes_free(&red);
    planes_free(&green);
    planes_free(&blue);
}

/* A one-pixel line present in the test only is found where it is, and nowhere beyond the
 * filters' reach (spatial radius 10 px, feature radius 9 px at the default ppd). */
TEST(line_is_local)
{
    const int w = 64, h = 64;
    const double ppd = flip_ppd(0.7, 3840, 0.7);
    planes a, b;
    CHECK(flat_image(&a, w, h, 0.3f, 0.3f, 0.3f));
    CHECK(flat_image(&b, w, h, 0.3f, 0.3f, 0.3f));
    float *e = malloc((size_t)w * h * sizeof *e);
    CHECK(e != NULL);
    if (e && a.c[0] && b.c[0]) {
        for (int y = 0; y < h; y++)
            for (int c = 0; c < 3; c++)
                b.c[c][(size_t)y * w + 32] = 0.6f;
        CHECK(flip_ldr((const float *const *)a.c, (const float *const *)b.c, w, h, ppd, e) ==
              FS_OK);
        float on = e[32 * w + 32], off = e[32 * w + 10];
        fprintf(stderr, "  line: error on the line %.4f, far from it %.4f\n", (double)on,
                (double)off);
        CHECK(on > 0.2f);
        CHECK(off == 0.0f);
    }
    free(e);
    planes_free(&a);
    planes_free(&b);
}

TEST(rejects_bad_arguments)
{
    float one = 0.5f, out = -1.0f;
    const float *p[3] = {&one, &one, &one};
    CHECK(flip_ldr(p, p, 1, 1, 67.0, &out) == FS_OK);
    CHECK(out == 0.0f);
    CHECK(flip_ldr(p, p, 0, 1, 67.0, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, -1, 67.0, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, 1, 0.0, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, 1, -2.0, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, 1, NAN, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, 1, FLIP_MAX_PPD * 2.0, &out) == FS_ERR_USAGE);
    CHECK(flip_ldr(p, p, 1, 1, 67.0, NULL) == FS_ERR_USAGE);
    const float *bad[3] = {&one, NULL, &one};
    CHECK(flip_ldr(p, bad, 1, 1, 67.0, &out) == FS_ERR_USAGE);
}

int main(void)
{
    RUN(default_ppd_value);
    RUN(srgb_decode);
    RUN(official_traditional_ppd_low);
    RUN(official_hashed_ppd_low);
    RUN(official_traditional_ppd_default);
    RUN(official_hashed_ppd_default);
    RUN(identical_images_give_zero);
    RUN(map_in_unit_range);
    RUN(larger_difference_scores_higher);
    RUN(line_is_local);
    RUN(rejects_bad_arguments);
    return test_summary();
}
