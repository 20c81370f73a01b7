/* test_reference.c: the ground truth (src/reference): it converges as 1/sqrt(K), its expectation
 * is order-correct alpha compositing, and its cache is reused, keyed and repaired. */
#include <sys/stat.h>
#include <unistd.h>

#include "core/file_read.h"
#include "core/log.h"
#include "gpu_util.h"
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

static fs_status ref_frame(const scene *sc, int w, int h, int ss, int k, const char *cache, exr_image *img,
                           reference_info *info)
{
    fs_status st;
    reference *rf = reference_create(sc, &(reference_desc){.width = w, .height = h, .supersample = ss,
                                                           .samples = k, .cache_dir = cache}, &st);
    if (!rf)
        return st;
    frame_record fr = frame_record_at(sc, 0, 0.0f, -1.0f, w, h);
    st = reference_frame(rf, &fr, img, info);
    reference_destroy(rf);
    return st;
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
    exr_image_free(&first);
    scene_free(&sc);
}

TEST(reference_ignores_mode_overrides)
{
    /* A material's own alpha mode does not change the reference (it is always stochastic), so
     * the key and the image stay. */
    enum { W = 64, H = 40 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    exr_image a, b;
    reference_info ia, ib;
    CHECK(ref_frame(&sc, W, H, 1, 2, NULL, &a, &ia) == FS_OK);
    for (int m = 0; m < sc.assets[0].material_count; m++)
        sc.assets[0].materials[m].alpha_mode = ALPHA_MODE_TRADITIONAL;
    CHECK(ref_frame(&sc, W, H, 1, 2, NULL, &b, &ib) == FS_OK);
    CHECK(ia.key == ib.key);
    CHECK(files_equal(&a, &b));
    exr_image_free(&a);
    exr_image_free(&b);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(expectation_is_order_correct_compositing);
    RUN(error_shrinks_as_one_over_sqrt_k);
    RUN(cache_reused_keyed_and_repaired);
    RUN(reference_ignores_mode_overrides);
    return test_summary();
}
