/* Temporal antialiasing per ring: convergence on a static view, NaN/Inf never propagate, camera
 * cuts drop history, saccades take a coarser ring's history (stochastic alpha) or none, hashed
 * alpha + TAA flickers less and covers closer to the reference than hashed alone, swaying foliage
 * is followed by its per-object motion. */
#include "gpu_util.h"

/* A renderer kept across frames (TAA needs consecutive frames). */
typedef struct seq {
    plan pl;
    renderer *r;
} seq;

static taa_controls g_taa_controls; /* zero = defaults; a test may loosen them to show a failure */
static bool g_no_ring_cull;         /* rings draw every instance in their frustum */

static bool seq_begin(seq *q, const scene *sc, alpha_mode mode, int w, int h, const fov_layout *l, bool taa,
                      alpha_params ap)
{
    plan_options po = {.alpha_mode = mode, .width = w, .height = h, .frames = 1000, .taa = taa, .alpha = ap,
                       .taa_controls = g_taa_controls, .no_ring_cull = g_no_ring_cull};
    if (l)
        po.layout = *l;
    fs_status st = plan_build(sc, &po, &q->pl);
    if (st != FS_OK)
        return false;
    q->r = renderer_create(&(renderer_desc){.scene = sc, .plan = &q->pl}, &st);
    return q->r != NULL;
}

/* Draws frame `index` at time t with gaze (gx, gy) and reads it. */
static fs_status seq_frame(seq *q, const scene *sc, int index, float t, float prev_t, float gx, float gy, exr_image *img)
{
    frame_record fr = frame_record_at(sc, index, t, prev_t, q->pl.width, q->pl.height);
    display_desc dd = {q->pl.width, q->pl.height, fr.hfov_deg, 0.0f, 0.0f};
    frame_record_set_gaze(&fr, &q->pl.layout, &dd, gx, gy);
    fs_status st = renderer_draw(q->r, &fr);
    return st == FS_OK && img ? renderer_read(q->r, img) : st;
}

/* RMSE of R, G, B between two images. */
static double rmse_rgb(const exr_image *a, const exr_image *b)
{
    double se = 0;
    long n = 0;
    static const char *const ch[] = {"R", "G", "B"};
    for (int c = 0; c < 3; c++) {
        const float *x = exr_image_channel(a, ch[c]), *y = exr_image_channel(b, ch[c]);
        for (int i = 0; i < a->width * a->height; i++, n++)
            se += (x[i] - y[i]) * (x[i] - y[i]);
    }
    return sqrt(se / (double)n);
}

/* Box-downsamples every channel of `hi` by `k` into `lo` (initialised here). */
static void downsample(const exr_image *hi, int k, exr_image *lo)
{
    exr_image_init(lo, hi->width / k, hi->height / k);
    for (int c = 0; c < hi->channel_count; c++) {
        float *d = exr_image_add_channel(lo, hi->channel_names[c]);
        for (int y = 0; y < lo->height; y++)
            for (int x = 0; x < lo->width; x++) {
                double s = 0;
                for (int j = 0; j < k; j++)
                    for (int i = 0; i < k; i++)
                        s += hi->planes[c][(y * k + j) * hi->width + x * k + i];
                d[y * lo->width + x] = (float)(s / (k * k));
            }
    }
}

static void still_camera(scene *sc, float t)
{
    camera_state cs = camera_path_eval(&sc->camera, t);
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = cs.position, .target = cs.target, .hfov_deg = cs.hfov_deg};
    sc->duration = 0;
}

/* The built-in forest as its camera sees it at time t, held still, and a ring layout for w x h. */
static void still_forest(scene *sc, float t, const char *rings, int w, int h, display_desc *d, fov_layout *l)
{
    CHECK(scene_load_builtin("forest", sc) == FS_OK);
    still_camera(sc, t);
    *d = (display_desc){w, h, sc->display.hfov_deg, 0.0f, 0.0f};
    char err[128];
    CHECK(fov_layout_parse(rings, d, l, err, sizeof err) == FS_OK);
}

TEST(static_view_converges_towards_the_supersampled_image)
{
    enum { W = 160, H = 90, K = 4 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    still_camera(&sc, 1.0f);
    exr_image hi, ref;
    CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W * K, H * K, 0, &hi) == FS_OK);
    downsample(&hi, K, &ref);
    exr_image_free(&hi);
    seq q;
    CHECK(seq_begin(&q, &sc, ALPHA_MODE_TRADITIONAL, W, H, NULL, true, (alpha_params){0}));
    double err[3] = {0};
    int at[3] = {1, 16, 64}, k = 0;
    for (int f = 1; f <= 64; f++) {
        exr_image img;
        CHECK(seq_frame(&q, &sc, f - 1, 0, -1, 0.5f, 0.5f, f == at[k] ? &img : NULL) == FS_OK);
        if (f == at[k]) {
            err[k++] = rmse_rgb(&img, &ref);
            exr_image_free(&img);
        }
    }
    exr_image no_taa;
    CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0, &no_taa) == FS_OK);
    double e_plain = rmse_rgb(&no_taa, &ref);
    fprintf(stderr, "RMSE vs 4x4 supersampled: no TAA %.4f; TAA frame 1 %.4f, 16 %.4f, 64 %.4f\n", e_plain, err[0],
            err[1], err[2]);
    CHECK(err[1] < err[0]);
    CHECK(err[2] <= err[1] * 1.02);     /* converged: no worse than at 16 (2 %: rounding of half floats) */
    CHECK(err[2] < 0.75 * e_plain);     /* and clearly closer to the supersampled image than no TAA */
    exr_image_free(&no_taa);
    exr_image_free(&ref);
    renderer_destroy(q.r);
    scene_free(&sc);
}

/* Sets the base colour of the materials named `name` to (v, v, v). */
static void set_colour(scene *sc, const char *name, float v)
{
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++)
            if (!strcmp(sc->assets[a].materials[m].name, name))
                for (int c = 0; c < 3; c++)
                    sc->assets[a].materials[m].base_color[c] = v;
}

TEST(nan_and_inf_never_enter_history)
{
    /* The bark shades to NaN (then Inf): TAA sanitises the current sample (NaN -> 0, Inf -> 65504)
     * before it can reach the neighbourhood or the history. With NaN bark the sequence must equal
     * the one with black bark exactly, and stay finite everywhere with Inf bark. */
    enum { W = 160, H = 90, N = 6 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    display_desc d = {W, H, sc.display.hfov_deg, 0.0f, 0.0f};
    fov_layout l;
    char err[128];
    CHECK(fov_layout_parse("10:1:0,*:1/4:0", &d, &l, err, sizeof err) == FS_OK);
    exr_image out[3][N];
    const float bark[3] = {NAN, 0.0f, INFINITY};
    for (int v = 0; v < 3; v++) {
        set_colour(&sc, "bark", bark[v]);
        seq q;
        CHECK(seq_begin(&q, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
        for (int f = 0; f < N; f++)
            CHECK(seq_frame(&q, &sc, f, 0.5f + f / 24.0f, f ? 0.5f + (f - 1) / 24.0f : -1, 0.4f, 0.5f, &out[v][f]) == FS_OK);
        renderer_destroy(q.r);
    }
    int nonfinite = 0, differ = 0;
    for (int f = 0; f < N; f++) {
        for (int v = 0; v < 3; v++)
            nonfinite += !all_finite(&out[v][f]);
        for (int c = 0; c < out[0][f].channel_count; c++)
            for (int i = 0; i < W * H; i++)
                differ += out[0][f].planes[c][i] != out[1][f].planes[c][i];
    }
    fprintf(stderr, "non-finite frames: %d; values differing between NaN and black bark: %d\n", nonfinite, differ);
    CHECK(nonfinite == 0);
    CHECK(differ == 0);
    for (int f = 0; f < N; f++)
        for (int v = 0; v < 3; v++)
            exr_image_free(&out[v][f]);
    scene_free(&sc);
}

/* New-fovea G RMSE between a and b where the eccentricity from gaze (gx, gy) is below the inner
 * ring's blend band. */
static double fovea_rmse(const exr_image *a, const exr_image *b, const display_desc *d, const fov_layout *l,
                         float gx, float gy)
{
    const float *ag = exr_image_channel(a, "G"), *bg = exr_image_channel(b, "G");
    double se = 0;
    long n = 0;
    for (int py = 0; py < a->height; py++)
        for (int px = 0; px < a->width; px++)
            if (fov_eccentricity_deg(d, gx, gy, px + 0.5f, py + 0.5f) < l->rings[0].outer_deg - 2.0f) {
                double e = ag[py * a->width + px] - bg[py * a->width + px];
                se += e * e;
                n++;
            }
    return n ? sqrt(se / n) : INFINITY;
}

TEST(camera_cut_and_saccade_history)
{
    enum { W = 192, H = 108 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    display_desc d = {W, H, sc.display.hfov_deg, 0.0f, 0.0f};
    fov_layout l;
    char err[128];
    CHECK(fov_layout_parse("8:1:0,20:1/2:0,*:1/4:0", &d, &l, err, sizeof err) == FS_OK);
    /* A cut at frame 8: the camera jumps to another key. The output of the cut frame must equal
     * that of a renderer that never saw the earlier frames (same frame index, so same jitter). */
    sc.camera.count = 3;
    sc.camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 1.6f, 0.5f), .target = v3(0, 2.2f, -14)};
    sc.camera.keys[1] = (camera_key){.time = 0.2f, .position = v3(0.2f, 1.6f, 1.0f), .target = v3(0, 2.2f, -14)};
    sc.camera.keys[2] = (camera_key){.time = 8.0f / 24.0f, .position = v3(6, 2, 4), .target = v3(-2, 1.5f, -10),
                                     .cut = true};
    seq a, b;
    CHECK(seq_begin(&a, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    CHECK(seq_begin(&b, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    exr_image x, y;
    for (int f = 0; f < 8; f++)
        CHECK(seq_frame(&a, &sc, f, f / 24.0f, f ? (f - 1) / 24.0f : -1, 0.5f, 0.5f, NULL) == FS_OK);
    CHECK(seq_frame(&a, &sc, 8, 8 / 24.0f, 7 / 24.0f, 0.5f, 0.5f, &x) == FS_OK);
    CHECK(seq_frame(&b, &sc, 8, 8 / 24.0f, -1, 0.5f, 0.5f, &y) == FS_OK);
    double e = rmse_rgb(&x, &y);
    fprintf(stderr, "camera cut: RMSE to a fresh history %.6f\n", e);
    CHECK(e == 0.0);
    exr_image_free(&x);
    exr_image_free(&y);
    renderer_destroy(a.r);
    renderer_destroy(b.r);

    /* A saccade across the display (still camera): inside the new fovea, where the eccentricity
     * is below the inner ring's blend band, the output equals a fresh history's: no colour from
     * where the gaze used to be. */
    still_camera(&sc, 0.0f);
    CHECK(seq_begin(&a, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    CHECK(seq_begin(&b, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    for (int f = 0; f < 8; f++)
        CHECK(seq_frame(&a, &sc, f, 0, -1, 0.05f, 0.05f, NULL) == FS_OK);
    CHECK(seq_frame(&a, &sc, 8, 0, -1, 0.95f, 0.95f, &x) == FS_OK);
    CHECK(seq_frame(&b, &sc, 8, 0, -1, 0.95f, 0.95f, &y) == FS_OK);
    float gx = 0.95f * W, gy = 0.95f * H;
    long inside = 0, differ = 0;
    const float *xr = exr_image_channel(&x, "G"), *yr = exr_image_channel(&y, "G");
    for (int py = 0; py < H; py++)
        for (int px = 0; px < W; px++)
            if (fov_eccentricity_deg(&d, gx, gy, px + 0.5f, py + 0.5f) < l.rings[0].outer_deg - 2.0f) {
                inside++;
                differ += xr[py * W + px] != yr[py * W + px];
            }
    fprintf(stderr, "saccade: %ld new-fovea pixels, %ld differ from a fresh history\n", inside, differ);
    CHECK(inside > 100 && differ == 0);
    exr_image_free(&x);
    exr_image_free(&y);
    /* The new fovea converges again: 16 frames after the saccade it matches (RMSE < 0.005 in the
     * new fovea) a history that has looked at the new gaze point from the start. */
    for (int f = 9; f <= 24; f++) {
        CHECK(seq_frame(&a, &sc, f, 0, -1, 0.95f, 0.95f, f == 24 ? &x : NULL) == FS_OK);
        CHECK(seq_frame(&b, &sc, f, 0, -1, 0.95f, 0.95f, f == 24 ? &y : NULL) == FS_OK);
    }
    seq c;
    CHECK(seq_begin(&c, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    exr_image z;
    for (int f = 0; f <= 24; f++)
        CHECK(seq_frame(&c, &sc, f, 0, -1, 0.95f, 0.95f, f == 24 ? &z : NULL) == FS_OK);
    double e16 = fovea_rmse(&x, &z, &d, &l, gx, gy);
    fprintf(stderr, "saccade: 16 frames later, new-fovea RMSE to a settled history %.5f\n", e16);
    CHECK(e16 < 0.005);
    exr_image_free(&x);
    exr_image_free(&y);
    exr_image_free(&z);
    renderer_destroy(a.r);
    renderer_destroy(b.r);
    renderer_destroy(c.r);

    /* With stochastic (here hashed) alpha tests the current sample is noise, so a pixel that the
     * saccade moved out of its ring's footprint takes the innermost coarser ring's history at the
     * same display point (TAA_COARSE_HISTORY). Right after the saccade the new fovea is closer to
     * a history that looked there all along than the fresh current sample is; colour from where
     * the gaze used to be would make it farther. */
    seq fresh, settled;
    CHECK(seq_begin(&a, &sc, ALPHA_MODE_HASHED, W, H, &l, true, (alpha_params){0}));
    CHECK(seq_begin(&fresh, &sc, ALPHA_MODE_HASHED, W, H, &l, true, (alpha_params){0}));
    CHECK(seq_begin(&settled, &sc, ALPHA_MODE_HASHED, W, H, &l, true, (alpha_params){0}));
    CHECK(a.pl.taa_coarse_history);
    for (int f = 0; f < 8; f++)
        CHECK(seq_frame(&a, &sc, f, 0, -1, 0.05f, 0.05f, NULL) == FS_OK);
    for (int f = 0; f <= 8; f++)
        CHECK(seq_frame(&settled, &sc, f, 0, -1, 0.95f, 0.95f, f == 8 ? &z : NULL) == FS_OK);
    CHECK(seq_frame(&a, &sc, 8, 0, -1, 0.95f, 0.95f, &x) == FS_OK);
    CHECK(seq_frame(&fresh, &sc, 8, 0, -1, 0.95f, 0.95f, &y) == FS_OK);
    double ea = fovea_rmse(&x, &z, &d, &l, gx, gy), eb = fovea_rmse(&y, &z, &d, &l, gx, gy);
    fprintf(stderr, "saccade, hashed: new-fovea RMSE to a settled history %.4f from the coarser ring's history, "
                    "%.4f from the current sample\n", ea, eb);
    CHECK(ea < 0.8 * eb);
    exr_image_free(&x);
    exr_image_free(&y);
    exr_image_free(&z);
    renderer_destroy(a.r);
    renderer_destroy(fresh.r);
    renderer_destroy(settled.r);
    scene_free(&sc);
}

/* Seed 000 and the TAA issue: with TAA, hashed alpha's thresholds change every frame (a golden-ratio
 * offset) and the history averages them: coverage moves towards the converged reference and
 * flickers less under slow camera motion than hashed without TAA. */
/* A ring skips instances that lie wholly in its hole (where the finer ring is shown alone), so its
 * history there lacks them. After a saccade away from that hole, the pixels there take the ring and
 * must not take that history: each equals a fresh history's, bit for bit; and the ring did skip
 * instances (else the test shows nothing). Traditional (no coarser-ring fallback) and hashed
 * (TAA_COARSE_HISTORY). */
TEST(saccade_into_a_culled_region_takes_a_fresh_history)
{
    enum { W = 320, H = 180 };
    scene sc;
    display_desc d;
    fov_layout l;
    still_forest(&sc, 3.0f, "24:1:0,*:1/2:0", W, H, &d, &l);
    /* The hole less the two ring-1 pixels the composite's bilinear tap may reach across. */
    float hole = fov_ring_hole_deg(&l, 1) - 2.0f * 2.0f / fov_focal_px(&d) * (float)(180.0 / FS_PI);
    static const alpha_mode modes[] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED};
    for (int m = 0; m < 2; m++) {
        seq a, b, c;
        CHECK(seq_begin(&a, &sc, modes[m], W, H, &l, true, (alpha_params){0}));
        CHECK(seq_begin(&b, &sc, modes[m], W, H, &l, true, (alpha_params){0}));
        g_no_ring_cull = true;
        CHECK(seq_begin(&c, &sc, modes[m], W, H, &l, true, (alpha_params){0}));
        g_no_ring_cull = false;
        for (int f = 0; f < 8; f++)
            CHECK(seq_frame(&a, &sc, f, 0, -1, 0.5f, 0.5f, NULL) == FS_OK);
        CHECK(seq_frame(&c, &sc, 7, 0, -1, 0.5f, 0.5f, NULL) == FS_OK);
        int culled = renderer_last_stats(c.r).ring_instances[1] - renderer_last_stats(a.r).ring_instances[1];
        exr_image x, y;
        CHECK(seq_frame(&a, &sc, 8, 0, -1, 0.02f, 0.03f, &x) == FS_OK);
        CHECK(seq_frame(&b, &sc, 8, 0, -1, 0.02f, 0.03f, &y) == FS_OK);
        long inside = 0, differ = 0;
        for (int py = 0; py < H; py++)
            for (int px = 0; px < W; px++)
                if (fov_eccentricity_deg(&d, 0.5f * W, 0.5f * H, px + 0.5f, py + 0.5f) < hole) {
                    inside++;
                    for (int ch = 0; ch < 5; ch++)
                        differ += x.planes[ch][py * W + px] != y.planes[ch][py * W + px];
                }
        fprintf(stderr, "%s: ring 1 skipped %d instances; %ld pixels of its old hole, %ld values differ from a "
                "fresh history\n", alpha_mode_name(modes[m]), culled, inside, differ);
        CHECK(culled > 0);
        CHECK(inside > 1000 && differ == 0);
        exr_image_free(&x);
        exr_image_free(&y);
        renderer_destroy(a.r);
        renderer_destroy(b.r);
        renderer_destroy(c.r);
    }
    scene_free(&sc);
}

TEST(hashed_with_taa_flickers_less_and_covers_closer)
{
    enum { W = 320, H = 180, N = 24 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    scene moving = sc; /* shares assets; only the camera differs and only sc is freed */
    still_camera(&sc, 2.0f); /* 7.75 m: the traditional test has lost the wire */
    exr_image hi;
    /* Reference coverage: a 4x4 supersampled stochastic test averaged over 8 frames. */
    exr_image ref;
    exr_image_init(&ref, W, H);
    float *rc = exr_image_add_channel(&ref, "coverage");
    for (int f = 0; f < 8; f++) {
        gpu_fov fv = {.gaze = {0.5f, 0.5f}, .frame = f};
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_STOCHASTIC, W * 4, H * 4, 0, &fv, &hi) == FS_OK);
        exr_image lo;
        downsample(&hi, 4, &lo);
        const float *c = exr_image_channel(&lo, "coverage");
        for (int i = 0; i < W * H; i++)
            rc[i] += c[i] / 8.0f;
        exr_image_free(&lo);
        exr_image_free(&hi);
    }
    double flicker[2], err[2];
    for (int taa = 0; taa < 2; taa++) {
        /* Coverage error: still camera, the last 8 of 24 frames. */
        seq q;
        CHECK(seq_begin(&q, &sc, ALPHA_MODE_HASHED, W, H, NULL, taa, (alpha_params){0}));
        double e = 0;
        for (int f = 0; f < N; f++) {
            exr_image cur;
            CHECK(seq_frame(&q, &sc, f, 0, -1, 0.5f, 0.5f, &cur) == FS_OK);
            const float *c = exr_image_channel(&cur, "coverage");
            for (int i = 0; f >= N - 8 && i < W * H; i++)
                e += (c[i] - rc[i]) * (c[i] - rc[i]);
            exr_image_free(&cur);
        }
        err[taa] = sqrt(e / (8.0 * W * H));
        renderer_destroy(q.r);
        /* Flicker: the fence's own dolly at 0.01 s per frame (about 10 cm, ~2 pixels at 7.75 m),
         * mean |coverage change| between consecutive frames over the last 8. (For sub-pixel steps
         * hashed alone is already stable: measured 0.0050 without TAA, 0.0058 with, at 1 ms.) */
        CHECK(seq_begin(&q, &moving, ALPHA_MODE_HASHED, W, H, NULL, taa, (alpha_params){0}));
        exr_image prev = {0};
        double fl = 0;
        for (int f = 0; f < N; f++) {
            exr_image cur;
            float t = 2.0f + f * 0.01f;
            CHECK(seq_frame(&q, &moving, f, t, f ? t - 0.01f : -1, 0.5f, 0.5f, &cur) == FS_OK);
            if (f >= N - 8) {
                const float *c = exr_image_channel(&cur, "coverage"), *p = exr_image_channel(&prev, "coverage");
                for (int i = 0; i < W * H; i++)
                    fl += fabsf(c[i] - p[i]);
            }
            exr_image_free(&prev);
            prev = cur;
        }
        exr_image_free(&prev);
        flicker[taa] = fl / (8.0 * W * H);
        renderer_destroy(q.r);
    }
    fprintf(stderr, "hashed: coverage RMSE vs reference %.4f without TAA, %.4f with; flicker under ~2 px/frame "
                    "motion %.4f without, %.4f with\n", err[0], err[1], flicker[0], flicker[1]);
    CHECK(err[1] < 0.8 * err[0]);
    CHECK(flicker[1] < 0.5 * flicker[0]);
    exr_image_free(&ref);
    scene_free(&sc);
}

/* Mean |Laplacian| of luminance in a window (high-frequency energy). */
static double hf(const exr_image *img, int cx, int cy, int half)
{
    const float *g = exr_image_channel(img, "G");
    int W = img->width, H = img->height;
    double e = 0;
    int n = 0;
    for (int y = cy - half; y <= cy + half; y++)
        for (int x = cx - half; x <= cx + half; x++)
            if (x > 0 && y > 0 && x < W - 1 && y < H - 1) {
                e += fabs(4 * g[y * W + x] - g[y * W + x - 1] - g[y * W + x + 1] - g[(y - 1) * W + x] - g[(y + 1) * W + x]);
                n++;
            }
    return n ? e / n : 0;
}

TEST(fovea_stays_sharp_in_pursuit_and_motion_leaves_no_ghosts)
{
    enum { W = 320, H = 180, N = 24 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    display_desc d = {W, H, sc.display.hfov_deg, 0.0f, 0.0f};
    fov_layout l;
    char err[128];
    CHECK(fov_layout_parse("10:1:0,25:1/2:0,*:1/4:0", &d, &l, err, sizeof err) == FS_OK);
    /* Pursuit: the gaze slides 2 display pixels per frame (still camera); at the end the window
     * around it is as sharp as after the same number of frames with the gaze fixed there. */
    scene still = sc;
    still_camera(&still, 1.0f);
    seq a, b;
    CHECK(seq_begin(&a, &still, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    CHECK(seq_begin(&b, &still, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    exr_image x, y;
    float gy = 0.45f, gx_end = 0.6f;
    for (int f = 0; f < N; f++) {
        float gx = gx_end - (float)(N - 1 - f) * 2.0f / W;
        CHECK(seq_frame(&a, &still, f, 0, -1, gx, gy, f == N - 1 ? &x : NULL) == FS_OK);
        CHECK(seq_frame(&b, &still, f, 0, -1, gx_end, gy, f == N - 1 ? &y : NULL) == FS_OK);
    }
    double ex = hf(&x, (int)(gx_end * W), (int)(gy * H), 10), ey = hf(&y, (int)(gx_end * W), (int)(gy * H), 10);
    fprintf(stderr, "pursuit: HF energy at the gaze %.4f moving, %.4f fixed (ratio %.2f)\n", ex, ey, ex / ey);
    CHECK(ex > 0.85 * ey);
    exr_image_free(&x);
    exr_image_free(&y);
    renderer_destroy(a.r);
    renderer_destroy(b.r);
    /* Camera dolly at the scene's own speed (24 fps), compared with the same frame drawn without
     * TAA: antialiasing itself changes alpha-tested edges strongly, so the share of strongly
     * differing pixels is compared with the same share for a still camera (no motion, no
     * trails). Trails behind moving edges would add to it; the variance clip keeps it close. */
    /* The same for hashed (reported, for docs/taa.md): its samples are noise in time, so the
     * sparse-coverage rule keeps more of their history, and run 3 shows what the disocclusion test
     * removes. */
    static const alpha_mode modes[2] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED};
    double strong[2][4] = {{0}};
    float *dolly_g = calloc((size_t)W * H, sizeof *dolly_g);
    long sparse_differs = -1;
    for (int mi = 0; mi < 2; mi++)
        for (int moving = 0; moving < 4; moving++) {
            /* Run 2: the dolly again with clipping effectively off (gamma 100), for comparison
             * (traditional only); run 3: without the disocclusion test. */
            if (mi == 1 && moving == 2)
                continue;
            g_taa_controls = moving == 2   ? (taa_controls){.gamma = 100.0f}
                             : moving == 3 ? (taa_controls){.no_disocclusion = true}
                                           : (taa_controls){0};
            const scene *s2 = moving ? &sc : &still;
            seq c;
            CHECK(seq_begin(&c, s2, modes[mi], W, H, &l, true, (alpha_params){0}));
            for (int f = 0; f < N; f++) {
                float t = moving ? 1.0f + f / 24.0f : 0.0f;
                CHECK(seq_frame(&c, s2, f, t, f && moving ? t - 1 / 24.0f : -1, 0.5f, 0.5f, f == N - 1 ? &x : NULL) == FS_OK);
            }
            gpu_fov fv = {.layout = &l, .gaze = {0.5f, 0.5f}, .frame = N - 1};
            CHECK(gpu_render_fov(s2, modes[mi], W, H, moving ? 1.0f + (N - 1) / 24.0f : 0.0f, &fv, &y) == FS_OK);
            const float *xg = exr_image_channel(&x, "G"), *yg = exr_image_channel(&y, "G");
            long n = 0;
            for (int i = 0; i < W * H; i++)
                n += fabsf(xg[i] - yg[i]) > 0.15f;
            strong[mi][moving] = (double)n / (W * H);
            /* The disocclusion test is compiled in only where pixels move: it changes the dolly. */
            if (mi == 0 && moving == 1)
                memcpy(dolly_g, xg, (size_t)W * H * sizeof *dolly_g);
            if (mi == 0 && moving == 3) {
                sparse_differs = 0;
                for (int i = 0; i < W * H; i++)
                    sparse_differs += memcmp(&dolly_g[i], &xg[i], sizeof *xg) != 0;
            }
            exr_image_free(&x);
            exr_image_free(&y);
            renderer_destroy(c.r);
        }
    g_taa_controls = (taa_controls){0};
    free(dolly_g);
    fprintf(stderr, "pixels differing by > 0.15 from the frame without TAA, traditional: %.4f still, %.4f in the dolly, "
                    "%.4f in the dolly without clipping, %.4f without the disocclusion test (%ld pixels differ "
                    "from the dolly's)\n",
            strong[0][0], strong[0][1], strong[0][2], strong[0][3], sparse_differs);
    fprintf(stderr, "  hashed: %.4f still, %.4f in the dolly, %.4f without the disocclusion test\n", strong[1][0],
            strong[1][1], strong[1][3]);
    CHECK(sparse_differs > 0);
    /* Reported, not asserted: with exact reprojection of static geometry, trails can only come from
     * disocclusions, which are a small area per frame; clipping trims them (0.038 -> 0.035). A
     * wrong reprojection (the previous ring frustum ignored) would smear every moving edge and
     * break the bound above. */
    /* Measured 0.036 (still camera 0.019); with the previous ring frustum ignored
     * in the reprojection it is 0.044, so 0.040 separates the two. */
    CHECK(strong[0][1] < 0.040);
    scene_free(&sc);
}

TEST(jitter_does_not_leak_into_the_image)
{
    /* Still camera and gaze: consecutive converged TAA frames barely change (no shake), and the
     * TAA image lines up with the unjittered image: of the shifts by -1, 0, +1 pixel in x and y,
     * the unshifted one matches best. */
    enum { W = 192, H = 108, N = 40 };
    scene sc;
    display_desc d;
    fov_layout l;
    still_forest(&sc, 1.0f, "10:1:0,*:1/2:0", W, H, &d, &l);
    seq q;
    CHECK(seq_begin(&q, &sc, ALPHA_MODE_TRADITIONAL, W, H, &l, true, (alpha_params){0}));
    exr_image a = {0}, b = {0};
    for (int f = 0; f < N; f++)
        CHECK(seq_frame(&q, &sc, f, 0, -1, 0.5f, 0.5f, f == N - 2 ? &a : f == N - 1 ? &b : NULL) == FS_OK);
    double shake = 0;
    const float *ga = exr_image_channel(&a, "G"), *gb = exr_image_channel(&b, "G");
    for (int i = 0; i < W * H; i++)
        shake += fabsf(ga[i] - gb[i]);
    shake /= W * H;
    exr_image plain;
    gpu_fov fv = {.layout = &l, .gaze = {0.5f, 0.5f}};
    CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0, &fv, &plain) == FS_OK);
    const float *gp = exr_image_channel(&plain, "G");
    double best = INFINITY, at0 = 0;
    int bx = 9, by = 9;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            double e = 0;
            for (int y = 2; y < H - 2; y++)
                for (int x = 2; x < W - 2; x++) {
                    double v = gb[y * W + x] - gp[(y + dy) * W + x + dx];
                    e += v * v;
                }
            if (dx == 0 && dy == 0)
                at0 = e;
            if (e < best) {
                best = e;
                bx = dx;
                by = dy;
            }
        }
    fprintf(stderr, "converged TAA: mean |frame change| %.5f; best alignment with the unjittered image at (%d, %d)\n",
            shake, bx, by);
    CHECK(shake < 0.005);
    CHECK(bx == 0 && by == 0 && best == at0);
    exr_image_free(&a);
    exr_image_free(&b);
    exr_image_free(&plain);
    renderer_destroy(q.r);
    scene_free(&sc);
}

/* Swaying foliage under a still camera: TAA that follows each fragment's own motion (the plan's
 * velocity path) ends closer to the supersampled image than TAA that reprojects the leaves as if
 * they stood still (--object-motion off), which smears them along their path. */
TEST(swaying_foliage_follows_its_own_motion)
{
    enum { W = 160, H = 90, K = 4, N = 24 };
    scene sc;
    CHECK(scene_load_builtin("wind", &sc) == FS_OK);
    CHECK(scene_sway_count(&sc) == sc.instance_count);
    /* A gale: 3x the trees' sway and twice as fast, about 1-2 display pixels per frame here. */
    for (int i = 0; i < sc.instance_count; i++) {
        sc.instances[i].sway.offset = v3_scale(sc.instances[i].sway.offset, 3.0f);
        sc.instances[i].sway.frequency *= 2.0f;
    }
    double err[2] = {0}, plain = 0;
    int measured = 0;
    for (int om = 0; om < 2; om++) {
        g_taa_controls.no_object_motion = om == 1;
        seq q;
        CHECK(seq_begin(&q, &sc, ALPHA_MODE_TRADITIONAL, W, H, NULL, true, (alpha_params){0}));
        CHECK(q.pl.sway && q.pl.velocity == (om == 0));
        for (int f = 0; f < N; f++) {
            float t = (float)f / 24.0f;
            bool at = f >= N - 8 && f % 2 == 1; /* 4 frames after 15 of accumulation */
            exr_image img;
            CHECK(seq_frame(&q, &sc, f, t, f ? t - 1.0f / 24.0f : -1, 0.5f, 0.5f, at ? &img : NULL) == FS_OK);
            if (!at)
                continue;
            exr_image hi, ref;
            CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W * K, H * K, t, &hi) == FS_OK);
            downsample(&hi, K, &ref);
            err[om] += rmse_rgb(&img, &ref) / 4.0;
            if (om == 0) {
                exr_image no_taa;
                CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W, H, t, &no_taa) == FS_OK);
                plain += rmse_rgb(&no_taa, &ref) / 4.0;
                measured++;
                exr_image_free(&no_taa);
            }
            exr_image_free(&hi);
            exr_image_free(&ref);
            exr_image_free(&img);
        }
        renderer_destroy(q.r);
    }
    g_taa_controls = (taa_controls){0};
    fprintf(stderr, "swaying trees, RMSE vs 4x4 supersampled (mean of %d frames): no TAA %.4f; TAA with per-object "
                    "motion %.4f, without %.4f\n", measured, plain, err[0], err[1]);
    CHECK(measured == 4);
    CHECK(err[0] < 0.92 * err[1]); /* following the leaves beats reprojecting them as still */
    CHECK(err[0] < plain);         /* and TAA still beats no TAA */
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(static_view_converges_towards_the_supersampled_image);
    RUN(nan_and_inf_never_enter_history);
    RUN(camera_cut_and_saccade_history);
    RUN(saccade_into_a_culled_region_takes_a_fresh_history);
    RUN(hashed_with_taa_flickers_less_and_covers_closer);
    RUN(fovea_stays_sharp_in_pursuit_and_motion_leaves_no_ghosts);
    RUN(jitter_does_not_leak_into_the_image);
    RUN(swaying_foliage_follows_its_own_motion);
    gl_device_destroy();
    return test_summary();
}
