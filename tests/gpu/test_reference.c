/* test_reference.c: the ground truth (src/reference): it converges as 1/sqrt(K), its expectation
 * is order-correct alpha compositing, and its cache is reused, keyed and repaired. */
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "gpu_util.h"
#include "passes/abuffer.h"
#include "passes/plan.h"
#include "passes/renderer.h"
#include "reference/reference.h"

/* Two uniform-alpha cards facing the camera, one in front of the other, each covering the left or
 * the right 3/4 of the view so the middle half sees both: with alpha a (front) and b (back),
 * coverage is a on the left quarter, b on the right quarter and a + (1 - a) b in the middle. */
static void two_cards_scene(scene *sc, float a_front, float a_back)
{
    scene_init_defaults(sc);
    for (int k = 0; k < 2; k++) {
        float al = k == 0 ? a_front : a_back;
        uint8_t *px = malloc(4 * 4 * 4);
        for (int i = 0; i < 16; i++) {
            px[4 * i] = k == 0 ? 255 : 40; /* red front card, blue-ish back card */
            px[4 * i + 1] = 60;
            px[4 * i + 2] = k == 0 ? 40 : 255;
            px[4 * i + 3] = (uint8_t)(al * 255.0f + 0.5f);
        }
        image_rgba8 img = {.width = 4, .height = 4, .rgba = px};
        material m = {.base_color = {1, 1, 1, 1}, .base_color_image = 0, .alpha_kind = ALPHA_KIND_MASK,
                      .alpha_cutoff = 0.5f, .double_sided = true};
        /* The back card at z = -1 projects onto z = 0 scaled by 10/11: [-5.5, 12] -> [-5, 10.9]. */
        float x0 = k == 0 ? -10.0f : -5.5f, x1 = k == 0 ? 5.0f : 12.0f, z = k == 0 ? 0.0f : -1.0f;
        float pos[12] = {x0, -10, z, x1, -10, z, x1, 10, z, x0, 10, z}, uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        asset as = quad_asset(k == 0 ? "front" : "back", pos, uv, m, &img);
        scene_add_asset(sc, &as);
        scene_add_instance(sc, k, m4_identity());
    }
    /* 90 degree horizontal fov from z = 10: the view spans x in [-10, 10] at z = 0. */
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 10), .target = v3(0, 0, 0)};
}

static double column_mean(const exr_image *img, const char *ch, int x0, int x1)
{
    const float *p = exr_image_channel(img, ch);
    double s = 0;
    for (int y = img->height / 4; y < 3 * img->height / 4; y++)
        for (int x = x0; x < x1; x++)
            s += p[(size_t)y * (size_t)img->width + (size_t)x];
    return s / ((double)(x1 - x0) * (img->height / 2));
}

static fs_status ref_frame_desc(const scene *sc, reference_desc rd, exr_image *img, reference_info *info)
{
    fs_status st;
    reference *rf = reference_create(sc, &rd, &st);
    if (!rf)
        return st;
    frame_record fr = frame_record_at(sc, 0, 0.0f, -1.0f, rd.width, rd.height);
    st = reference_frame(rf, &fr, img, info);
    reference_destroy(rf);
    return st;
}

/* The stochastic reference (K tests per sub-sample). */
static fs_status ref_frame(const scene *sc, int w, int h, int ss, int k, const char *cache, exr_image *img,
                           reference_info *info)
{
    return ref_frame_desc(sc, (reference_desc){.width = w, .height = h, .kind = REFERENCE_STOCHASTIC, .supersample = ss,
                                               .samples = k, .cache_dir = cache},
                          img, info);
}

/* The exact reference (K = 4 tests for overflowed pixels, which these tests do not have unless
 * they ask for it). */
static fs_status exact_frame(const scene *sc, int w, int h, int ss, const char *cache, exr_image *img,
                             reference_info *info)
{
    return ref_frame_desc(sc, (reference_desc){.width = w, .height = h, .supersample = ss, .samples = 4,
                                               .cache_dir = cache},
                          img, info);
}

/* >>stacked cards: uniform-alpha cards filling the view, one behind the other, lit so that the
 * shaded colour is the albedo (ambient 1, no direct light). */
typedef struct card {
    float z, alpha, rgb[3];
    alpha_kind kind;
} card;

static void stacked_cards_scene(scene *sc, const card *cards, int n)
{
    scene_init_defaults(sc);
    sc->light.color = v3(0, 0, 0);
    sc->light.ambient = v3(1, 1, 1);
    for (int k = 0; k < n; k++) {
        uint8_t *px = malloc(4 * 4 * 4);
        uint8_t a8 = (uint8_t)(cards[k].alpha * 255.0f + 0.5f);
        for (int i = 0; i < 16; i++) { /* premultiplied white: rgb = alpha */
            px[4 * i] = px[4 * i + 1] = px[4 * i + 2] = 255;
            px[4 * i + 3] = a8;
        }
        image_rgba8 img = {.width = 4, .height = 4, .rgba = px};
        material m = {.base_color = {cards[k].rgb[0], cards[k].rgb[1], cards[k].rgb[2], 1}, .base_color_image = 0,
                      .alpha_kind = cards[k].kind, .alpha_cutoff = 0.5f, .double_sided = true};
        float z = cards[k].z, e = 60.0f; /* wider than the view at every depth used */
        float pos[12] = {-e, -e, z, e, -e, z, e, e, z, -e, e, z}, uv[8] = {0, 1, 1, 1, 1, 0, 0, 0};
        char name[16];
        snprintf(name, sizeof name, "card%d", k);
        asset as = quad_asset(name, pos, uv, m, &img);
        scene_add_asset(sc, &as);
        scene_add_instance(sc, k, m4_identity());
    }
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 10), .target = v3(0, 0, 0)};
}

/* Front-to-back "over" of the cards, in the order given (front first), over the sky: R, G, B, A,
 * coverage. Alphas as the texture stores them (8 bits). */
static void cards_closed_form(const card *front_first, int n, vec3 sky, double out[5])
{
    double t = 1.0, c[3] = {0, 0, 0}, a = 0.0;
    for (int i = 0; i < n; i++) {
        double al = (double)(uint8_t)(front_first[i].alpha * 255.0f + 0.5f) / 255.0;
        for (int k = 0; k < 3; k++)
            c[k] += t * al * front_first[i].rgb[k];
        a += t * al;
        t *= 1.0 - al;
    }
    out[0] = c[0] + t * sky.x;
    out[1] = c[1] + t * sky.y;
    out[2] = c[2] + t * sky.z;
    out[3] = a;
    out[4] = a;
}

static double image_max_dev(const exr_image *img, const char *ch, double want)
{
    const float *p = exr_image_channel(img, ch);
    double m = 0;
    size_t n = (size_t)img->width * (size_t)img->height;
    for (size_t i = 0; i < n; i++)
        m = fmax(m, fabs(p[i] - want));
    return m;
}

/* Front first (scene order differs): alpha 0.3 red; alpha 0 white (must hide nothing); a BLEND
 * card of alpha 0.5 between MASK cards; two cards at one depth (the first placed is in front, as a
 * depth test with GL_LESS keeps the first drawn); an alpha-1 card that hides the last one. */
static const card k_cards[] = {
    {-5.0f, 0.7f, {1.0f, 1.0f, 1.0f}, ALPHA_KIND_MASK},  /* hidden behind the alpha-1 card */
    {0.0f, 0.3f, {1.0f, 0.1f, 0.1f}, ALPHA_KIND_MASK},
    {-3.0f, 0.5f, {0.2f, 0.9f, 0.9f}, ALPHA_KIND_MASK},  /* equal depth: placed first, in front */
    {-1.0f, 0.5f, {0.1f, 0.1f, 1.0f}, ALPHA_KIND_BLEND},
    {-0.5f, 0.0f, {1.0f, 1.0f, 1.0f}, ALPHA_KIND_MASK},
    {-4.0f, 1.0f, {0.9f, 0.8f, 0.1f}, ALPHA_KIND_MASK},
    {-2.0f, 0.6f, {0.1f, 1.0f, 0.1f}, ALPHA_KIND_MASK},
    {-3.0f, 0.25f, {0.8f, 0.2f, 0.8f}, ALPHA_KIND_MASK}, /* equal depth: placed second, behind */
};
enum { CARD_COUNT = sizeof k_cards / sizeof k_cards[0] };
static const int k_cards_front_first[CARD_COUNT] = {1, 4, 3, 6, 2, 7, 5, 0}; /* depth, then placement */

/* The closed form of k_cards in front-to-back order over the scene's sky. */
static void k_cards_closed_form(const scene *sc, double want[5])
{
    card ftb[CARD_COUNT];
    for (int i = 0; i < CARD_COUNT; i++)
        ftb[i] = k_cards[k_cards_front_first[i]];
    cards_closed_form(ftb, CARD_COUNT, sc->light.sky, want);
}

TEST(exact_stacked_cards_match_the_closed_form)
{
    /* Coverage and colour of every pixel within 1e-3 of the formula (the frame is stored as half
     * floats: about 2.5e-4 of rounding). Back-to-front compositing, or the two equal-depth cards
     * the other way round, would each miss by more than 1e-2: the test can tell. */
    enum { W = 48, H = 32 };
    scene sc;
    stacked_cards_scene(&sc, k_cards, CARD_COUNT);
    card ftb[CARD_COUNT], btf[CARD_COUNT], swapped[CARD_COUNT];
    for (int i = 0; i < CARD_COUNT; i++) {
        ftb[i] = k_cards[k_cards_front_first[i]];
        btf[CARD_COUNT - 1 - i] = ftb[i];
        swapped[i] = ftb[i];
    }
    swapped[4] = ftb[5];
    swapped[5] = ftb[4];
    double want[5], wrong[5], wrong_tie[5];
    cards_closed_form(ftb, CARD_COUNT, sc.light.sky, want);
    cards_closed_form(btf, CARD_COUNT, sc.light.sky, wrong);
    cards_closed_form(swapped, CARD_COUNT, sc.light.sky, wrong_tie);
    exr_image img;
    reference_info info;
    CHECK(exact_frame(&sc, W, H, 1, NULL, &img, &info) == FS_OK);
    CHECK(all_finite(&img));
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    double worst_wrong = 0, worst_tie = 0;
    for (int c = 0; c < 5; c++) {
        double dev = image_max_dev(&img, ch[c], want[c]);
        if (dev > 1e-3)
            fprintf(stderr, "%s: want %.5f, worst deviation %.5f\n", ch[c], want[c], dev);
        CHECK(dev <= 1e-3);
        worst_wrong = fmax(worst_wrong, fabs(wrong[c] - want[c]));
        worst_tie = fmax(worst_tie, fabs(wrong_tie[c] - want[c]));
    }
    CHECK(worst_wrong > 1e-2 && worst_tie > 1e-2);
    CHECK(info.overflow_pixels == 0 && info.long_lists == 0 && info.list_nodes == (uint64_t)W * H * 6);
    /* The alpha-1 card's fragments stop compositing: coverage reaches exactly 1. */
    CHECK_NEAR(want[4], 1.0, 1e-12);
    exr_image_free(&img);
    scene_free(&sc);
}

TEST(exact_overflow_falls_back_to_stochastic_for_the_lost_pixels)
{
    /* 48 x 32 pixels with 6 stored fragments each (the alpha-0 card stores none, the solid pass
     * hides the card behind the alpha-1 one) need 9216 nodes; a budget of 8216 loses the
     * last-drawn (BLEND) card's fragments at about 1000 pixels per pass. They
     * are counted, and take the stochastic estimate (K = 256 tests): each within 6 sigma of the
     * closed form (sigma <= 0.5 / sqrt(K) for a mean of samples in [0, 1]), their mean within
     * 5 sigma / sqrt(their count); every other pixel is exact (1e-3). */
    enum { W = 48, H = 32, K = 256, NEEDED = W * H * 6 };
    scene sc;
    stacked_cards_scene(&sc, k_cards, CARD_COUNT);
    double want[5];
    k_cards_closed_form(&sc, want);
    exr_image img;
    reference_info info;
    CHECK(ref_frame_desc(&sc, (reference_desc){.width = W, .height = H, .supersample = 1, .samples = K,
                                               .list_nodes = NEEDED - 1000},
                         &img, &info) == FS_OK);
    /* Summed over the frame's passes: the 1 x 1 grid and the 2 x 2 one of the error estimate. */
    fprintf(stderr, "overflowed pixels: %ld in 5 passes of %d, nodes asked for %llu\n", info.overflow_pixels, W * H,
            (unsigned long long)info.list_nodes);
    CHECK(info.list_nodes == NEEDED);
    CHECK(info.overflow_pixels >= 5 * 900 && info.overflow_pixels <= 5 * 1000);
    CHECK(all_finite(&img));
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    size_t n = (size_t)W * H;
    double sigma = 0.5 / sqrt((double)K);
    for (int c = 0; c < 5; c++) {
        const float *p = exr_image_channel(&img, ch[c]);
        size_t inexact = 0, far = 0;
        double sum = 0;
        for (size_t i = 0; i < n; i++) {
            double d = p[i] - want[c];
            if (fabs(d) > 1e-3) {
                inexact++;
                sum += d;
            }
            far += fabs(d) > 6.0 * sigma;
        }
        fprintf(stderr, "%s: %zu pixels not exact, their mean difference %+.5f\n", ch[c], inexact,
                inexact ? sum / (double)inexact : 0.0);
        CHECK(far == 0);
        CHECK(inexact <= 1000);
        if (inexact > 0)
            CHECK(fabs(sum / (double)inexact) <= 5.0 * sigma / sqrt((double)inexact) + 1e-3);
    }
    exr_image_free(&img);
    scene_free(&sc);
}

/* Per-pixel agreement of the exact reference with a K-test stochastic one at S = 1 and the same
 * LOD: every channel of every pixel within 5 sigma + 2e-3, sigma = sqrt((M - mu) mu / K) the
 * largest standard deviation a mean of K samples in [0, M] with mean mu can have (Bhatia-Davis;
 * binomial for coverage, whose samples are 0 or 1). mu is the exact value; M = 1 for A and
 * coverage, and for colour the larger of 1 and the channel's largest value in either image (a
 * sample is one fragment's shaded colour, which these scenes keep below 1). And the frame's mean
 * within 1e-3. */
static void exact_matches_stochastic(const char *builtin, int w, int h, int k)
{
    scene sc;
    CHECK(scene_load_builtin(builtin, &sc) == FS_OK);
    exr_image ex, st;
    reference_info ie, is;
    CHECK(exact_frame(&sc, w, h, 1, NULL, &ex, &ie) == FS_OK);
    CHECK(ref_frame(&sc, w, h, 1, k, NULL, &st, &is) == FS_OK);
    CHECK(ie.overflow_pixels == 0);
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    size_t n = (size_t)w * (size_t)h, partial = 0;
    for (int c = 0; c < 5; c++) {
        const float *a = exr_image_channel(&ex, ch[c]), *b = exr_image_channel(&st, ch[c]);
        double m = 1.0, worst = 0, mean = 0;
        for (size_t i = 0; c < 3 && i < n; i++)
            m = fmax(m, fmax(a[i], b[i]));
        size_t bad = 0;
        for (size_t i = 0; i < n; i++) {
            double mu = a[i], sigma = sqrt(fmax((m - mu) * mu, 0.0) / k), d = fabs((double)b[i] - mu);
            bad += d > 5.0 * sigma + 2e-3;
            if (d > 5.0 * sigma + 2e-3 && bad < 6)
                fprintf(stderr, "  pixel (%zu, %zu): %s exact %.4f, stochastic %.4f\n", i % (size_t)w, i / (size_t)w,
                        ch[c], a[i], b[i]);
            worst = fmax(worst, d / (5.0 * sigma + 2e-3));
            mean += (double)b[i] - mu;
            partial += c == 4 && mu > 0.01 && mu < 0.99;
        }
        mean /= (double)n;
        fprintf(stderr, "%s %s: mean difference %+.5f, worst pixel at %.2f of its bound, %zu out of it\n", builtin, ch[c],
                mean, worst, bad);
        CHECK(bad == 0);
        CHECK(fabs(mean) < 1e-3);
    }
    CHECK(partial > n / 20); /* the scene has partial coverage for the bound to test */
    exr_image_free(&ex);
    exr_image_free(&st);
    scene_free(&sc);
}

TEST(exact_matches_stochastic_k1024_on_the_fence_and_the_forest)
{
    exact_matches_stochastic("fence", 64, 40, 1024);
    exact_matches_stochastic("forest", 64, 36, 1024);
}

TEST(exact_error_shrinks_with_s)
{
    /* The exact kind's error estimate is RMS(ref_S - ref_S/2): spatial only. For even S the S/2
     * estimates are the four sub-grids of every other sub-sample (no extra pass); S = 1 draws a
     * 2 x 2 grid to compare with. On the fence it halves from S = 2 to S = 4 (edges converge as
     * 1/S: 0.5 +- 0.15 catches no convergence and 1/S^2), and it is not zero. */
    enum { W = 64, H = 40 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    exr_image a, b;
    reference_info i2, i4;
    CHECK(exact_frame(&sc, W, H, 2, NULL, &a, &i2) == FS_OK);
    CHECK(exact_frame(&sc, W, H, 4, NULL, &b, &i4) == FS_OK);
    fprintf(stderr, "exact error: S=2 %.5f (vs 1x1), S=4 %.5f (vs 2x2)\n", i2.error, i4.error);
    CHECK(i2.passes == 4 && i4.passes == 16);
    CHECK(i4.error > 0.0);
    CHECK_NEAR(i4.error / i2.error, 0.5, 0.15);
    exr_image c;
    reference_info i1;
    CHECK(exact_frame(&sc, W, H, 1, NULL, &c, &i1) == FS_OK);
    CHECK(i1.passes == 1 + 4 && i1.error > 0.0);
    exr_image_free(&c);
    exr_image_free(&a);
    exr_image_free(&b);
    scene_free(&sc);
}

TEST(expectation_is_order_correct_compositing)
{
    /* Front alpha 0.4 over back alpha 0.5: 0.4, 0.5 and 0.4 + 0.6 * 0.5 = 0.7 in the middle. The
     * estimate of each region's mean over ~1000 pixels x 16 tests is within 0.01 (3 sigma is
     * about 0.004); a method that composited in the wrong order, or added alphas, would give
     * 0.5 + 0.5 * 0.4 = 0.7 (same: commutative for coverage) but a different colour, so check
     * colour too: the middle's red is 0.4 * front red + 0.6 * 0.5 * back red. */
    enum { W = 96, H = 64 };
    scene sc;
    two_cards_scene(&sc, 0.4f, 0.5f);
    exr_image img;
    reference_info info;
    CHECK(ref_frame(&sc, W, H, 2, 16, NULL, &img, &info) == FS_OK);
    CHECK(all_finite(&img));
    CHECK_NEAR(column_mean(&img, "coverage", 2, W / 4 - 2), 0.4, 0.01);
    CHECK_NEAR(column_mean(&img, "coverage", 3 * W / 4 + 2, W - 2), 0.5, 0.01);
    CHECK_NEAR(column_mean(&img, "coverage", W / 4 + 2, 3 * W / 4 - 2), 0.7, 0.01);
    CHECK_NEAR(column_mean(&img, "A", W / 4 + 2, 3 * W / 4 - 2), 0.7, 0.01);
    /* Colour: the same two cards drawn alone, fully opaque, give each card's own shaded colour. */
    scene solo;
    two_cards_scene(&solo, 1.0f, 1.0f);
    exr_image opaque;
    CHECK(ref_frame(&solo, W, H, 1, 2, NULL, &opaque, &info) == FS_OK);
    double front_r = column_mean(&opaque, "R", 2, W / 4 - 2), back_r = column_mean(&opaque, "R", 3 * W / 4 + 2, W - 2);
    double sky_r = sc.light.sky.x;
    double want = 0.4 * front_r + 0.6 * (0.5 * back_r + 0.5 * sky_r);
    CHECK_NEAR(column_mean(&img, "R", W / 4 + 2, 3 * W / 4 - 2), want, 0.01);
    double wrong = 0.5 * back_r + 0.5 * (0.4 * front_r + 0.6 * sky_r); /* back over front */
    CHECK(fabs(wrong - want) > 0.03);                                   /* the check can tell */
    exr_image_free(&opaque);
    exr_image_free(&img);
    scene_free(&solo);
    scene_free(&sc);
}

TEST(error_shrinks_as_one_over_sqrt_k)
{
    /* The estimate RMS((A - B) / 2) for K = 4, 16, 64 on the fence: each 4x more tests halve it.
     * Per pixel the estimate is a mean of ~6000 squared differences, so the ratio's own noise is
     * a few per cent; +-20 % catches a wrong power (1/K would give 4, no convergence 1). */
    enum { W = 128, H = 80 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    double e[3];
    int ks[3] = {4, 16, 64};
    for (int i = 0; i < 3; i++) {
        exr_image img;
        reference_info info;
        CHECK(ref_frame(&sc, W, H, 1, ks[i], NULL, &img, &info) == FS_OK);
        e[i] = info.error;
        CHECK(info.passes == ks[i]);
        exr_image_free(&img);
    }
    fprintf(stderr, "errors: K=4 %.5f, K=16 %.5f, K=64 %.5f\n", e[0], e[1], e[2]);
    CHECK(e[2] > 0.0);
    CHECK_NEAR(e[0] / e[1], 2.0, 0.4);
    CHECK_NEAR(e[1] / e[2], 2.0, 0.4);
    scene_free(&sc);
}

static bool files_equal(const exr_image *a, const exr_image *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    for (int c = 0; c < a->channel_count; c++) {
        const float *q = exr_image_channel(b, a->channel_names[c]);
        if (!q || memcmp(a->planes[c], q, n * sizeof(float)))
            return false;
    }
    return a->width == b->width && a->height == b->height;
}

/* Equal within half-float rounding (a drawn frame is float, a cached one was stored as half). */
static bool images_close(const exr_image *a, const exr_image *b)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    for (int c = 0; c < a->channel_count; c++) {
        const float *q = exr_image_channel(b, a->channel_names[c]);
        for (size_t i = 0; q && i < n; i++)
            if (fabsf(a->planes[c][i] - q[i]) > 1e-3f * fabsf(a->planes[c][i]) + 1e-6f)
                return false;
        if (!q)
            return false;
    }
    return a->width == b->width && a->height == b->height;
}

TEST(cache_reused_keyed_and_repaired)
{
    enum { W = 64, H = 40 };
    char dir[512];
    snprintf(dir, sizeof dir, "%s/reference_cache", getenv("FOVSIM_TEST_OUT") ? getenv("FOVSIM_TEST_OUT") : "/tmp");
    char cmd[2200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    exr_image first, again, moved;
    reference_info i1, i2, i3;
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &first, &i1) == FS_OK);
    CHECK(!i1.cached && i1.passes == 16);
    struct stat sb;
    CHECK(stat(i1.path, &sb) == 0);
    /* Same key: read back, bit for bit what was written (half floats both times). */
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &again, &i2) == FS_OK);
    CHECK(i2.cached && i2.passes == 0 && i2.key == i1.key && !strcmp(i2.path, i1.path));
    CHECK_NEAR(i2.error, i1.error, 1e-3 * i1.error + 1e-9);
    exr_image disk;
    CHECK(exr_read_file(i1.path, &disk) == FS_OK);
    CHECK(files_equal(&disk, &again));
    exr_image_free(&disk);
    exr_image_free(&again);
    /* Other sample counts, size or a changed scene: other keys, drawn anew. */
    CHECK(ref_frame(&sc, W, H, 2, 6, dir, &again, &i2) == FS_OK);
    CHECK(!i2.cached && i2.key != i1.key);
    exr_image_free(&again);
    float sky = sc.light.sky.x;
    sc.light.sky.x += 0.1f;
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &moved, &i3) == FS_OK);
    CHECK(!i3.cached && i3.key != i1.key);
    exr_image_free(&moved);
    sc.light.sky.x = sky; /* restored exactly: += then -= 0.1 need not */
    /* A truncated file under the right name: detected, drawn again, and the same frame results
     * (the passes' seeds are fixed). */
    CHECK(truncate(i1.path, sb.st_size / 2) == 0);
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &again, &i2) == FS_OK);
    CHECK(!i2.cached && i2.rebuilt && i2.key == i1.key);
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &moved, &i3) == FS_OK);
    CHECK(i3.cached);
    CHECK(images_close(&again, &moved));
    exr_image_free(&moved);
    exr_image_free(&again);
    /* A stale file (another key inside, e.g. copied over): redrawn. */
    snprintf(cmd, sizeof cmd, "cp '%s' '%s.bak'", i1.path, i1.path);
    CHECK(system(cmd) == 0);
    exr_image_set_string(&first, "fovsim:ref_key", "0123456789abcdef");
    CHECK(exr_write_file(i1.path, &first, EXR_COMPRESS_ZIP) == FS_OK);
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &again, &i2) == FS_OK);
    CHECK(!i2.cached && i2.rebuilt);
    exr_image_free(&again);
    /* Exact and stochastic frames of the same scene, size, S and K never collide: the exact one
     * gets its own key and file, and each kind then reads back its own. */
    exr_image ex, ex2, st2;
    reference_info ie, ie2, is2;
    CHECK(ref_frame_desc(&sc, (reference_desc){.width = W, .height = H, .supersample = 2, .samples = 4,
                                               .cache_dir = dir},
                         &ex, &ie) == FS_OK);
    CHECK(!ie.cached && ie.key != i1.key && strcmp(ie.path, i1.path));
    const exr_attr *kind = exr_image_attr(&ex, "fovsim:ref_kind");
    CHECK(kind && kind->type == FS_EXR_ATTR_STRING && !strcmp(kind->s, "exact"));
    CHECK(ref_frame_desc(&sc, (reference_desc){.width = W, .height = H, .supersample = 2, .samples = 4,
                                               .cache_dir = dir},
                         &ex2, &ie2) == FS_OK);
    CHECK(ie2.cached && ie2.key == ie.key && files_equal(&ex, &ex2));
    CHECK(ref_frame(&sc, W, H, 2, 4, dir, &st2, &is2) == FS_OK);
    CHECK(is2.cached && is2.key == i1.key);
    kind = exr_image_attr(&st2, "fovsim:ref_kind");
    CHECK(kind && kind->type == FS_EXR_ATTR_STRING && !strcmp(kind->s, "stochastic"));
    exr_image_free(&ex);
    exr_image_free(&ex2);
    exr_image_free(&st2);
    exr_image_free(&first);
    scene_free(&sc);
}

TEST(reference_ignores_mode_overrides)
{
    /* A material's own alpha mode does not change the reference (it is the expectation of a
     * stochastic test, whatever the mode), so the key and the image stay, for both kinds. */
    enum { W = 64, H = 40 };
    for (int kind = 0; kind < 2; kind++) {
        scene sc;
        CHECK(scene_load_builtin("fence", &sc) == FS_OK);
        reference_desc rd = {.width = W, .height = H, .kind = (reference_kind)kind, .supersample = 1, .samples = 2};
        exr_image a, b;
        reference_info ia, ib;
        CHECK(ref_frame_desc(&sc, rd, &a, &ia) == FS_OK);
        for (int m = 0; m < sc.assets[0].material_count; m++)
            sc.assets[0].materials[m].alpha_mode = ALPHA_MODE_TRADITIONAL;
        CHECK(ref_frame_desc(&sc, rd, &b, &ib) == FS_OK);
        CHECK(ia.key == ib.key);
        CHECK(files_equal(&a, &b));
        exr_image_free(&a);
        exr_image_free(&b);
        scene_free(&sc);
    }
}

TEST(exact_long_lists_are_resolved_by_the_c_twin)
{
    /* 30 cards of alpha 0.1: every list is longer than the GPU resolve sorts
     * (ABUFFER_RESOLVE_MAX), so every pixel is resolved by abuffer_resolve_pixel on the CPU, and
     * still matches the closed form within 1e-3. */
    enum { W = 32, H = 20, N = 30 };
    card cards[N];
    for (int i = 0; i < N; i++) /* placed back to front: the list pass appends them in that order */
        cards[i] = (card){-0.25f * (float)(N - 1 - i), 0.1f, {(float)(i % 3 == 0), (float)(i % 3 == 1), (float)(i % 3 == 2)},
                          ALPHA_KIND_MASK};
    card ftb[N];
    for (int i = 0; i < N; i++)
        ftb[i] = cards[N - 1 - i];
    scene sc;
    stacked_cards_scene(&sc, cards, N);
    double want[5];
    cards_closed_form(ftb, N, sc.light.sky, want);
    exr_image img;
    reference_info info;
    CHECK(exact_frame(&sc, W, H, 1, NULL, &img, &info) == FS_OK);
    CHECK(N > ABUFFER_RESOLVE_MAX);
    CHECK(info.long_lists == 5L * W * H); /* every pixel of the 1 x 1 and the 2 x 2 grid */
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    for (int c = 0; c < 5; c++)
        CHECK(image_max_dev(&img, ch[c], want[c]) <= 1e-3);
    exr_image_free(&img);
    scene_free(&sc);
}

TEST(gpu_and_c_resolves_agree_on_the_forest)
{
    /* The twin check: the same lists resolved by shaders/list_resolve.frag and by abuffer_resolve
     * agree at every pixel the GPU resolved (float vs double: 1e-5), and the GPU flags none of
     * the forest's lists as overflowed. */
    enum { W = 96, H = 54 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    plan pl;
    plan_options po = {.width = W, .height = H, .frames = 1, .reference = true, .reference_lists = true};
    CHECK(plan_build(&sc, &po, &pl) == FS_OK);
    CHECK(pl.list_resolve);
    fs_status st;
    renderer *r = renderer_create(&(renderer_desc){.scene = &sc, .plan = &pl, .list_nodes = 64 * W * H}, &st);
    CHECK(r != NULL);
    frame_record fr = frame_record_at(&sc, 0, 0.0f, -1.0f, W, H);
    CHECK(renderer_draw(r, &fr) == FS_OK);
    exr_image gpu, base;
    abuffer_lists l;
    CHECK(renderer_read(r, &gpu) == FS_OK);
    CHECK(renderer_read_opaque(r, &base) == FS_OK);
    CHECK(renderer_read_lists(r, &l, true) == FS_OK);
    CHECK(l.count > 0 && l.count <= l.capacity);
    size_t n = (size_t)W * H;
    float *cpu = malloc(sizeof(float) * 5 * n);
    unsigned char *over = malloc(n);
    const float *bp[5];
    float *op[5];
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    for (int c = 0; c < 5; c++) {
        bp[c] = exr_image_channel(&base, ch[c]);
        op[c] = cpu + (size_t)c * n;
    }
    abuffer_scratch scr = {0};
    CHECK(abuffer_resolve(&l, bp, op, over, &scr) == 0);
    const float *flag = exr_image_channel(&gpu, RENDERER_LIST_FLAG_CHANNEL);
    size_t resolved = 0, with_lists = 0;
    double worst = 0;
    for (size_t i = 0; i < n; i++) {
        CHECK(flag[i] != (float)ABUFFER_FLAG_OVERFLOW);
        if (flag[i] != (float)ABUFFER_FLAG_DONE)
            continue;
        resolved++;
        with_lists += l.head[i] != ABUFFER_END;
        for (int c = 0; c < 5; c++)
            worst = fmax(worst, fabs(exr_image_channel(&gpu, ch[c])[i] - op[c][i]) / fmax(1.0, fabs(op[c][i])));
    }
    fprintf(stderr, "twin: %zu of %zu pixels resolved on the GPU (%zu with lists), worst difference %.2g\n", resolved,
            n, with_lists, worst);
    CHECK(resolved > n * 3 / 4 && with_lists > n / 4);
    CHECK(worst <= 1e-5);
    abuffer_scratch_free(&scr);
    free(cpu);
    free(over);
    exr_image_free(&gpu);
    exr_image_free(&base);
    renderer_destroy(r);
    scene_free(&sc);
}

TEST(exact_opaque_only_scene_is_the_opaque_pass)
{
    /* No MASK or BLEND material: no list pass, and the exact frame is the opaque card's colour,
     * coverage 0, A 1, the same as the stochastic kind (which has nothing to test either). */
    enum { W = 32, H = 20 };
    static const card opaque[1] = {{-1.0f, 1.0f, {0.2f, 0.5f, 0.7f}, ALPHA_KIND_OPAQUE}};
    scene sc;
    stacked_cards_scene(&sc, opaque, 1);
    exr_image ex, st;
    reference_info ie, is;
    CHECK(exact_frame(&sc, W, H, 2, NULL, &ex, &ie) == FS_OK);
    CHECK(ref_frame(&sc, W, H, 2, 2, NULL, &st, &is) == FS_OK);
    CHECK(ie.list_nodes == 0 && ie.overflow_pixels == 0);
    CHECK(files_equal(&ex, &st));
    CHECK(image_max_dev(&ex, "G", 0.5) <= 1e-3 && image_max_dev(&ex, "coverage", 0.0) == 0.0 &&
          image_max_dev(&ex, "A", 1.0) == 0.0);
    exr_image_free(&ex);
    exr_image_free(&st);
    scene_free(&sc);
}

TEST(exact_works_on_every_builtin_scene)
{
    /* Every built-in scene (the swaying one at t = 0.5 s): the exact frame is finite, A and
     * coverage lie in [0, 1], nothing overflows, and each channel's frame mean agrees with a
     * K = 64 stochastic frame within 5 sigma of the mean (sigma <= 0.5 / sqrt(K * pixels)) + 1e-3. */
    enum { W = 48, H = 28, K = 64 };
    static const char *const names[] = {"fence", "forest", "grass", "tree", "wind"};
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    for (size_t s = 0; s < sizeof names / sizeof names[0]; s++) {
        scene sc;
        CHECK(scene_load_builtin(names[s], &sc) == FS_OK);
        frame_record fr = frame_record_at(&sc, 12, 0.5f, 0.5f - 1.0f / 24.0f, W, H);
        exr_image ex, st;
        reference_info ie, is;
        fs_status rc;
        reference *re = reference_create(&sc, &(reference_desc){.width = W, .height = H, .supersample = 2}, &rc);
        reference *rs = reference_create(&sc, &(reference_desc){.width = W, .height = H, .supersample = 2,
                                                                .kind = REFERENCE_STOCHASTIC, .samples = K},
                                         &rc);
        CHECK(re && rs);
        CHECK(reference_frame(re, &fr, &ex, &ie) == FS_OK);
        CHECK(reference_frame(rs, &fr, &st, &is) == FS_OK);
        CHECK(all_finite(&ex) && ie.overflow_pixels == 0);
        for (int c = 0; c < 5; c++) {
            const float *p = exr_image_channel(&ex, ch[c]), *q = exr_image_channel(&st, ch[c]);
            double me = 0, ms = 0;
            for (int i = 0; i < W * H; i++) {
                me += p[i];
                ms += q[i];
                if (c >= 3)
                    CHECK(p[i] >= 0.0f && p[i] <= 1.0f + 1e-3f);
            }
            me /= W * H;
            ms /= W * H;
            if (fabs(me - ms) > 5.0 * 0.5 / sqrt((double)K * 4 * W * H) + 1e-3)
                fprintf(stderr, "%s %s: exact mean %.5f, stochastic %.5f\n", names[s], ch[c], me, ms);
            CHECK_NEAR(me, ms, 5.0 * 0.5 / sqrt((double)K * 4 * W * H) + 1e-3);
        }
        exr_image_free(&ex);
        exr_image_free(&st);
        reference_destroy(re);
        reference_destroy(rs);
        scene_free(&sc);
    }
}

TEST(stochastic_coplanar_cards_are_tested_independently)
{
    /* The stochastic reference (K = 512) of the stacked cards: each channel's mean over the frame
     * within 5 standard errors of the closed form (per pixel sigma <= 0.5 / sqrt(K), 1536 pixels).
     * The two coplanar cards share their primitive index and depth: before their thresholds were
     * salted with the draw order, they passed and failed together, and the magenta card behind
     * never showed (green +0.010, blue -0.013). */
    enum { W = 48, H = 32, K = 512 };
    scene sc;
    stacked_cards_scene(&sc, k_cards, CARD_COUNT);
    double want[5];
    k_cards_closed_form(&sc, want);
    exr_image img;
    reference_info info;
    CHECK(ref_frame(&sc, W, H, 1, K, NULL, &img, &info) == FS_OK);
    static const char *const ch[5] = {"R", "G", "B", "A", "coverage"};
    for (int c = 0; c < 5; c++) {
        const float *p = exr_image_channel(&img, ch[c]);
        double m = 0;
        for (int i = 0; i < W * H; i++)
            m += p[i];
        m /= W * H;
        fprintf(stderr, "stochastic %s: mean %.5f, closed form %.5f\n", ch[c], m, want[c]);
        CHECK_NEAR(m, want[c], 5.0 * 0.5 / sqrt((double)K * W * H) + 1e-3);
    }
    exr_image_free(&img);
    scene_free(&sc);
}

/* The cache once trusted any readable EXR with the right key. A tampered entry
 * (pixels rewritten, header kept) gave silently wrong metrics; a FIFO at the entry's path hung
 * the run (the open waited for a writer); a directory there failed the whole run (the rename of
 * the redrawn frame). Now every entry carries a checksum of its pixels, verified on read, and
 * anything that is not a regular file is a miss. The alarm turns a hang into a failure. */
static void on_hang_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "test_reference: cache_tampered_fifo_directory: hung on the cache entry\n";
    if (write(2, msg, sizeof msg - 1) < 0) { /* nothing else to do */ }
    _exit(1);
}

TEST(cache_tampered_fifo_directory)
{
    enum { W = 32, H = 20 };
    char dir[512], cmd[2200];
    snprintf(dir, sizeof dir, "%s/reference_cache_tamper", getenv("FOVSIM_TEST_OUT") ? getenv("FOVSIM_TEST_OUT") : "/tmp");
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    CHECK(system(cmd) == 0);
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    exr_image first, got;
    reference_info i1, i2, i3;
    CHECK(ref_frame(&sc, W, H, 1, 2, dir, &first, &i1) == FS_OK);
    CHECK(!i1.cached);

    /* Tampered: one pixel of the stored entry changed, every attribute (the key too) kept. */
    exr_image disk;
    CHECK(exr_read_file(i1.path, &disk) == FS_OK);
    float *r = exr_image_channel(&disk, "R");
    CHECK(r != NULL);
    if (r)
        r[W * (H / 2) + W / 2] += 0.5f;
    CHECK(exr_write_file(i1.path, &disk, EXR_COMPRESS_ZIP) == FS_OK);
    exr_image_free(&disk);
    CHECK(ref_frame(&sc, W, H, 1, 2, dir, &got, &i2) == FS_OK);
    CHECK(!i2.cached && i2.rebuilt);
    CHECK(files_equal(&first, &got)); /* the true frame, not the tampered one */
    exr_image_free(&got);
    /* ... and the entry was rewritten: read back, equal to the first. */
    CHECK(ref_frame(&sc, W, H, 1, 2, dir, &got, &i3) == FS_OK);
    CHECK(i3.cached && files_equal(&first, &got));
    exr_image_free(&got);

    void (*old_alarm)(int) = signal(SIGALRM, on_hang_alarm);
    alarm(60);
    /* A FIFO at the entry's path: a miss, drawn, no hang; the FIFO is replaced by the entry. */
    CHECK(unlink(i1.path) == 0);
    CHECK(mkfifo(i1.path, 0644) == 0);
    CHECK(ref_frame(&sc, W, H, 1, 2, dir, &got, &i2) == FS_OK);
    CHECK(!i2.cached && files_equal(&first, &got));
    exr_image_free(&got);
    struct stat sb;
    CHECK(stat(i1.path, &sb) == 0 && S_ISREG(sb.st_mode));
    /* A directory there: the cache cannot hold the entry, so the run stops with one line (docs/reference.md "Cache":
     * one rule with a cache folder that cannot be written; it used to be bypassed), no hang, and
     * the directory is left alone (it may hold someone's files). */
    CHECK(unlink(i1.path) == 0);
    CHECK(mkdir(i1.path, 0755) == 0);
    log_set_quiet_errors(true);
    CHECK(ref_frame(&sc, W, H, 1, 2, dir, &got, &i2) == FS_ERR_IO);
    log_set_quiet_errors(false);
    CHECK(stat(i1.path, &sb) == 0 && S_ISDIR(sb.st_mode));
    alarm(0);
    signal(SIGALRM, old_alarm);
    exr_image_free(&first);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(expectation_is_order_correct_compositing);
    RUN(error_shrinks_as_one_over_sqrt_k);
    RUN(cache_reused_keyed_and_repaired);
    RUN(cache_tampered_fifo_directory);
    RUN(reference_ignores_mode_overrides);
    RUN(exact_stacked_cards_match_the_closed_form);
    RUN(exact_overflow_falls_back_to_stochastic_for_the_lost_pixels);
    RUN(exact_matches_stochastic_k1024_on_the_fence_and_the_forest);
    RUN(exact_error_shrinks_with_s);
    RUN(exact_long_lists_are_resolved_by_the_c_twin);
    RUN(gpu_and_c_resolves_agree_on_the_forest);
    RUN(exact_opaque_only_scene_is_the_opaque_pass);
    RUN(exact_works_on_every_builtin_scene);
    RUN(stochastic_coplanar_cards_are_tested_independently);
    return test_summary();
}
