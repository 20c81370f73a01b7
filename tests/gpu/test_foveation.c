/* Foveation on the GPU: rings composite without seams, the gaze marker lands on the gaze pixel,
 * the GLSL eccentricity/blend agree with their C twins, the full-resolution region follows the gaze,
 * and the periphery loses alpha-tested coverage (the problem fovsim exists to show). */
#include "gpu_util.h"

/* A scene whose image is one constant colour: a huge opaque quad facing the camera, lit head-on. */
static void constant_scene(scene *sc)
{
    scene_init_defaults(sc);
    static const float pos[12] = {-100, -100, 0, 100, -100, 0, 100, 100, 0, -100, 100, 0}, uv[8] = {0};
    material m = {.base_color = {0.5f, 0.3f, 0.2f, 1.0f}, .base_color_image = -1, .alpha_kind = ALPHA_KIND_OPAQUE,
                  .alpha_cutoff = 0.5f};
    asset a = quad_asset("wall", pos, uv, m, NULL);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    sc->light.direction = v3(0, 0, -1);
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 5), .target = v3(0, 0, 0)};
}

static const float k_gazes[][2] = {{0.5f, 0.5f}, {0.0f, 0.0f}, {1.0f, 1.0f}, {0.3f, 0.7f}, {0.93f, 0.08f}, {1.4f, -0.2f}};
enum { NGAZE = sizeof k_gazes / sizeof k_gazes[0] };

TEST(constant_scene_composites_to_that_colour_everywhere)
{
    enum { W = 320, H = 180 };
    scene sc;
    constant_scene(&sc);
    exr_image ref;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0, &ref) == FS_OK);
    const float *rr = exr_image_channel(&ref, "R");
    /* The full-resolution image is constant itself (head-on light, flat quad). */
    for (int i = 1; i < W * H; i++)
        CHECK(rr[i] == rr[0]);
    static const char *const specs[] = {"5:1:0,15:1/2:0,30:1/4:0,*:1/16:0", "auto", "0.01:1:0,*:1/8:1", "20:1/2:0,*:1/4:0"};
    for (int s = 0; s < 4; s++) {
        fov_layout l = gpu_layout(specs[s], W, H);
        for (int g = 0; g < NGAZE; g++) {
            exr_image img;
            gpu_fov fv = {.layout = &l, .gaze = {k_gazes[g][0], k_gazes[g][1]}};
            CHECK(gpu_render_fov(&sc, ALPHA_MODE_DEFAULT, W, H, 0, &fv, &img) == FS_OK);
            int bad = 0;
            for (int c = 0; c < 4; c++) {
                const float *a = img.planes[c], *b = ref.planes[c];
                for (int i = 0; i < W * H; i++)
                    if (fabsf(a[i] - b[i]) > 1e-3f && bad++ < 3)
                        fprintf(stderr, "  %s at (%d, %d): %.4f, full resolution %.4f\n", img.channel_names[c], i % W,
                                i / W, a[i], b[i]);
            }
            if (bad)
                fprintf(stderr, "layout %s gaze (%.2f, %.2f): %d channel values differ\n", specs[s], k_gazes[g][0],
                        k_gazes[g][1], bad);
            CHECK(bad == 0);
            exr_image_free(&img);
        }
    }
    exr_image_free(&ref);
    scene_free(&sc);
}

TEST(gaze_marker_lands_on_the_gaze_pixel)
{
    enum { W = 256, H = 144 };
    scene sc;
    constant_scene(&sc);
    fov_layout l = gpu_layout("10:1:0,*:1/4:0", W, H);
    const float gz[][2] = {{0.5f, 0.5f}, {0.25f, 0.6f}, {0.9f, 0.1f}, {0.013f, 0.987f}, {0.61f, 0.33f}};
    for (int g = 0; g < 5; g++) {
        exr_image img;
        gpu_fov fv = {.layout = &l, .gaze = {gz[g][0], gz[g][1]}, .overlay = true};
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_DEFAULT, W, H, 0, &fv, &img) == FS_OK);
        const float *r = exr_image_channel(&img, "R"), *gg = exr_image_channel(&img, "G"), *b = exr_image_channel(&img, "B");
        /* The cross's centre is the one magenta pixel with magenta neighbours on all four sides. */
        int cx = -1, cy = -1, centres = 0;
        for (int y = 1; y < H - 1; y++)
            for (int x = 1; x < W - 1; x++) {
#define MAGENTA(i) (r[i] == 1.0f && gg[i] == 0.0f && b[i] == 1.0f)
                int i = y * W + x;
                if (MAGENTA(i) && MAGENTA(i - 1) && MAGENTA(i + 1) && MAGENTA(i - W) && MAGENTA(i + W)) {
                    cx = x;
                    cy = y;
                    centres++;
                }
#undef MAGENTA
            }
        int ex = (int)floorf(gz[g][0] * W), ey = (int)floorf(gz[g][1] * H);
        fprintf(stderr, "gaze (%.3f, %.3f): marker at (%d, %d), gaze pixel (%d, %d)\n", gz[g][0], gz[g][1], cx, cy, ex, ey);
        CHECK(centres == 1 && cx == ex && cy == ey);
        exr_image_free(&img);
    }
    scene_free(&sc);
}

TEST(glsl_eccentricity_and_blend_agree_with_the_c_twins)
{
    enum { W = 320, H = 180 };
    scene sc;
    constant_scene(&sc);
    fov_layout l = gpu_layout("5:1:0,15:1/2:0,30:1/4:0,*:1/16:0", W, H);
    display_desc d = {W, H, 90.0f, 0.0f, 0.0f};
    for (int g = 0; g < NGAZE; g++) {
        exr_image img;
        gpu_fov fv = {.layout = &l, .gaze = {k_gazes[g][0], k_gazes[g][1]}, .debug_channels = true};
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_DEFAULT, W, H, 0, &fv, &img) == FS_OK);
        const float *ecc = exr_image_channel(&img, "eccentricity"), *rid = exr_image_channel(&img, "ring.id");
        CHECK(ecc && rid);
        if (!ecc || !rid)
            continue;
        float gx = fminf(fmaxf(k_gazes[g][0], 0), 1) * W, gy = fminf(fmaxf(k_gazes[g][1], 0), 1) * H;
        double max_e = 0, max_r = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                float e = fov_eccentricity_deg(&d, gx, gy, (float)x + 0.5f, (float)y + 0.5f);
                fov_blend bl = fov_composite_weight(&l, e);
                /* EXR stores half floats: compare within half precision of the value. */
                max_e = fmax(max_e, fabs(ecc[y * W + x] - e) / fmax(1.0, fabs(e)));
                max_r = fmax(max_r, fabs(rid[y * W + x] - ((float)bl.ring + bl.next)));
            }
        fprintf(stderr, "gaze (%.2f, %.2f): max eccentricity error %.2e (relative), max ring.id error %.2e\n",
                k_gazes[g][0], k_gazes[g][1], max_e, max_r);
        CHECK(max_e < 1.5e-3); /* half: 2^-11 relative, plus float atan/cross on the GPU */
        CHECK(max_r < 1e-2);   /* the blend weight's slope (<= 1.5 / band) times the eccentricity error */
        exr_image_free(&img);
    }
    scene_free(&sc);
}

/* The tiled composite (tiles inside one ring fetch it without searching) gives exactly the image of
 * the per-pixel search, every channel, for gazes on, at the corners of and outside the display and
 * for layouts with and without blend bands; the tiles really are used (most of the display). */
TEST(tiled_composite_equals_the_per_pixel_search_bit_for_bit)
{
    enum { W = 320, H = 180 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    static const char *const specs[] = {"auto", "5:1:0,15:1/2:0,30:1/4:0,*:1/16:0", "20:1/2:0,*:1/4:0"};
    display_desc d = {W, H, 90.0f, 0.0f, 0.0f};
    for (int s = 0; s < 3; s++) {
        fov_layout l = gpu_layout(specs[s], W, H);
        if (s == 2)
            l.blend_deg = 0.0f; /* hard ring edges */
        for (int g = 0; g < NGAZE; g++) {
            exr_image a, b;
            gpu_fov fa = {.layout = &l, .gaze = {k_gazes[g][0], k_gazes[g][1]}, .debug_channels = true};
            gpu_fov fb = fa;
            fb.per_pixel = true;
            CHECK(gpu_render_fov(&sc, ALPHA_MODE_HASHED, W, H, 1.0f, &fa, &a) == FS_OK);
            CHECK(gpu_render_fov(&sc, ALPHA_MODE_HASHED, W, H, 1.0f, &fb, &b) == FS_OK);
            int differ = 0;
            for (int c = 0; c < a.channel_count; c++)
                for (int i = 0; i < W * H; i++)
                    differ += memcmp(&a.planes[c][i], &b.planes[c][i], sizeof(float)) != 0;
            /* The share of the display the tiles of one ring cover (what the search no longer pays). */
            fov_tile tiles[512];
            float gx = k_gazes[g][0] * W, gy = k_gazes[g][1] * H;
            int n = fov_composite_tiles(&d, &l, gx, gy, tiles, 512);
            long long pure = 0;
            for (int i = 0; i < n; i++)
                pure += tiles[i].ring >= 0 ? (long long)(tiles[i].x1 - tiles[i].x0) * (tiles[i].y1 - tiles[i].y0) : 0;
            fprintf(stderr, "layout %s gaze (%.2f, %.2f): %d values differ; tiles of one ring cover %.0f %%\n",
                    specs[s], k_gazes[g][0], k_gazes[g][1], differ, 100.0 * (double)pure / (W * H));
            CHECK(differ == 0);
            CHECK(pure > W * H / 4); /* 33-94 % here (16-pixel tiles are coarse at 320x180) */
            exr_image_free(&a);
            exr_image_free(&b);
        }
    }
    scene_free(&sc);
}

/* Mean |Laplacian| of luminance in a window: high-frequency energy. */
static double hf_energy(const exr_image *img, int cx, int cy, int half)
{
    const float *r = exr_image_channel(img, "R"), *g = exr_image_channel(img, "G"), *b = exr_image_channel(img, "B");
    int W = img->width, H = img->height;
    double s = 0;
    int n = 0;
#define LUM(x, y) (0.2126f * r[(y) * W + (x)] + 0.7152f * g[(y) * W + (x)] + 0.0722f * b[(y) * W + (x)])
    for (int y = cy - half; y <= cy + half; y++)
        for (int x = cx - half; x <= cx + half; x++) {
            if (x < 1 || y < 1 || x >= W - 1 || y >= H - 1)
                continue;
            s += fabs(4 * LUM(x, y) - LUM(x - 1, y) - LUM(x + 1, y) - LUM(x, y - 1) - LUM(x, y + 1));
            n++;
        }
#undef LUM
    return n ? s / n : 0;
}

TEST(full_resolution_region_follows_the_gaze)
{
    enum { W = 480, H = 270 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    fov_layout l = gpu_layout("8:1:0,16:1/4:0,*:1/8:0", W, H);
    exr_image full;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.5f, &full) == FS_OK);
    /* A pursuit: the gaze slides across the frame; the window around it stays sharp, the window at
     * the mirrored position (far from the gaze) is blurred. Energies are relative to the full-res
     * image's own energy in the same window, so scene content cancels. */
    const float path[][2] = {{0.3f, 0.45f}, {0.4f, 0.4f}, {0.6f, 0.5f}, {0.7f, 0.55f}};
    for (int k = 0; k < 4; k++) {
        exr_image img;
        gpu_fov fv = {.layout = &l, .gaze = {path[k][0], path[k][1]}};
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_DEFAULT, W, H, 0.5f, &fv, &img) == FS_OK);
        int gx = (int)(path[k][0] * W), gy = (int)(path[k][1] * H);
        int fx = W - 1 - gx, fy = H - 1 - gy;
        double at_gaze = hf_energy(&img, gx, gy, 12) / hf_energy(&full, gx, gy, 12);
        double far = hf_energy(&img, fx, fy, 12) / hf_energy(&full, fx, fy, 12);
        fprintf(stderr, "gaze (%.2f, %.2f): HF energy vs full resolution: %.3f at the gaze, %.3f far from it\n",
                path[k][0], path[k][1], at_gaze, far);
        CHECK(at_gaze > 0.9 && at_gaze < 1.1); /* identical pixels up to the blend band */
        CHECK(far < 0.6);
        exr_image_free(&img);
    }
    exr_image_free(&full);
    scene_free(&sc);
}

/* Mean coverage over the pixels of the outermost ring (eccentricity beyond the previous ring). */
static void outer_ring_coverage(const char *builtin, float t)
{
    enum { W = 1280, H = 720 }; /* the scenes' display: the mip levels a user sees */
    scene sc;
    CHECK(scene_load_builtin(builtin, &sc) == FS_OK);
    display_desc d = {W, H, sc.display.hfov_deg, 0.0f, 0.0f};
    fov_layout l = fov_layout_auto(&d, 0, 0);
    exr_image full, fov;
    gpu_fov fv = {.layout = &l, .gaze = {0.5f, 0.5f}, .debug_channels = true};
    CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, W, H, t, &full) == FS_OK);
    CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, W, H, t, &fv, &fov) == FS_OK);
    const float *ecc = exr_image_channel(&fov, "eccentricity");
    const float *cf = exr_image_channel(&full, "coverage"), *cv = exr_image_channel(&fov, "coverage");
    float inner = l.rings[l.count - 2].outer_deg;
    double sf = 0, sv = 0;
    long n = 0;
    for (int i = 0; i < W * H; i++)
        if (ecc[i] > inner) {
            sf += cf[i];
            sv += cv[i];
            n++;
        }
    fprintf(stderr, "%s t=%.1f: outer ring (beyond %.1f deg, 1/%d res, %ld px): coverage %.4f full res, %.4f foveated\n",
            builtin, t, inner, 1 << l.rings[l.count - 1].scale_log2, n, sf / n, sv / n);
    CHECK(n > W * H / 20);
    CHECK(sf / n > 0.05);           /* there is foliage out there at full resolution */
    CHECK(sv / n < 0.75 * (sf / n)); /* and the low-resolution ring loses a clear share of it */
    exr_image_free(&full);
    exr_image_free(&fov);
    scene_free(&sc);
}

TEST(the_periphery_loses_alpha_tested_coverage)
{
    outer_ring_coverage("fence", 0.0f);
    outer_ring_coverage("forest", 0.0f);
}

TEST(ring_mip_bias_reaches_the_alpha_lookup)
{
    /* One full-resolution ring with an extra mip bias: coarser mips of the fence wire have lower
     * alpha (box-filtered towards the texture's mean of ~0.13), so the traditional test keeps less
     * of the fence as the bias grows — the bias reaches the alpha lookup, on top of the LOD the
     * resolution gives. */
    enum { W = 1280, H = 720 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    double prev = 2.0;
    static const char *const specs[] = {"*:1:0", "*:1:1", "*:1:2", "*:1:3"};
    for (int i = 0; i < 4; i++) {
        fov_layout l = gpu_layout(specs[i], W, H);
        exr_image img;
        gpu_fov fv = {.layout = &l, .gaze = {0.5f, 0.5f}};
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &fv, &img) == FS_OK);
        double c = plane_mean(&img, "coverage");
        fprintf(stderr, "fence, mip bias %s: coverage %.4f\n", specs[i] + 4, c);
        CHECK(c < prev);
        prev = c;
        exr_image_free(&img);
    }
    CHECK(prev < 0.01); /* three levels coarser and the wire is gone */
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(constant_scene_composites_to_that_colour_everywhere);
    RUN(tiled_composite_equals_the_per_pixel_search_bit_for_bit);
    RUN(gaze_marker_lands_on_the_gaze_pixel);
    RUN(glsl_eccentricity_and_blend_agree_with_the_c_twins);
    RUN(full_resolution_region_follows_the_gaze);
    RUN(the_periphery_loses_alpha_tested_coverage);
    RUN(ring_mip_bias_reaches_the_alpha_lookup);
    gl_device_destroy();
    return test_summary();
}
