/* Golden-image regression: fixed scenes, fixed times, small sizes, compared with
 * tests/golden/refs/<name>.exr under per-case RMSE and max-error tolerances.
 *
 * On failure the render and a diff image (|render - ref| per channel) are written to
 * $FOVSIM_TEST_OUT/golden/ for inspection. Regenerate the references after an intended change:
 *   FOVSIM_UPDATE_GOLDEN=1 ./build/test_golden      (then look at them and commit)
 *
 * Tolerances: llvmpipe renders these bit-identically run to run (measured: RMSE 0, max 0), so the
 * budget covers half-float storage of the references (relative 2^-11) and rasteriser differences
 * between llvmpipe builds/CPUs: a handful of alpha-tested edge pixels may flip between leaf and
 * background (error up to 1 in one channel of one pixel), hence a max error on 2x2-averaged pixels
 * (a flipped pixel counts 1/4) and a small RMSE. A real GPU rasterises and filters differently and
 * is expected to exceed them; the golden test is a regression test of one renderer.
 *
 * Why not `fovsim check` (docs/check.md) itself: these cases are single frames of the renderer alone
 * (no reference, no metrics) at fixed times and gazes, drawn in one GL context; a check baseline
 * is a whole compare run (its frames carry every mode and the supersampled reference), so running
 * them through check would add baselines and minutes, not remove code. They share check's
 * comparison instead (image_diff_add). */
#include <sys/stat.h>

#include "gpu_util.h"
#include "metrics/image_diff.h"

typedef struct golden_case {
    const char *name;   /* refs/<name>.exr */
    const char *scene;  /* builtin name or shared asset */
    bool builtin;
    float time;
    int w, h;
    double max_rmse;    /* over R, G, B, A, coverage */
    double max_err_2x2; /* max abs error of 2x2-averaged pixels */
    const char *rings;  /* foveation layout, NULL = full resolution */
    float gaze[2];
} golden_case;

static const golden_case k_cases[] = {
    {"forest_t1", "forest", true, 1.0f, 192, 108, 0.01, 0.3, NULL, {0, 0}},
    {"fence_t0", "fence", true, 0.0f, 192, 108, 0.01, 0.3, NULL, {0, 0}},
    {"bush_common", "assets/quaternius_megakit_set_a/Bush_Common.gltf", false, 0.0f, 128, 96, 0.01, 0.3, NULL, {0, 0}},
    /* Foveated: four rings down to 1/16 around an off-centre gaze, composited with blend bands. */
    {"forest_fov", "forest", true, 2.0f, 320, 180, 0.01, 0.3, "6:1:0,14:1/2:0,30:1/4:0.5,*:1/16:0", {0.3f, 0.6f}},
};

static void write_diff(const golden_case *gc, const exr_image *img, const exr_image *ref)
{
    char dir[1100], path[1200];
    snprintf(dir, sizeof dir, "%s/golden", test_out_dir());
    mkdir(dir, 0777);
    snprintf(path, sizeof path, "%s/%s.render.exr", dir, gc->name);
    exr_write_file(path, img, EXR_COMPRESS_ZIP);
    exr_image diff;
    if (!exr_image_init(&diff, img->width, img->height))
        return;
    for (int c = 0; c < img->channel_count; c++) {
        const float *r = exr_image_channel(ref, img->channel_names[c]);
        float *d = exr_image_add_channel(&diff, img->channel_names[c]);
        for (int i = 0; r && d && i < img->width * img->height; i++)
            d[i] = fabsf(img->planes[c][i] - r[i]);
    }
    snprintf(path, sizeof path, "%s/%s.diff.exr", dir, gc->name);
    exr_write_file(path, &diff, EXR_COMPRESS_ZIP);
    fprintf(stderr, "golden %s: wrote %s and the render beside it\n", gc->name, path);
    exr_image_free(&diff);
}

static void run_case(const golden_case *gc)
{
    scene sc;
    fs_status st = gc->builtin ? scene_load_builtin(gc->scene, &sc) : scene_load_file(test_shared_path(gc->scene), &sc);
    CHECK(st == FS_OK);
    if (st != FS_OK)
        return;
    exr_image img;
    fov_layout l = fov_layout_off();
    if (gc->rings) {
        char err[256];
        display_desc d = {gc->w, gc->h, sc.display.hfov_deg, 0.0f, 0.0f};
        CHECK(fov_layout_parse(gc->rings, &d, &l, err, sizeof err) == FS_OK);
    }
    gpu_fov fv = {.layout = &l, .gaze = {gc->gaze[0], gc->gaze[1]}};
    if (!gc->rings)
        fv.gaze[0] = fv.gaze[1] = 0.5f;
    CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, gc->w, gc->h, gc->time, &fv, &img) == FS_OK);
    scene_free(&sc);
    char ref_path[1100];
    snprintf(ref_path, sizeof ref_path, "%s", test_source_path("tests/golden/refs/"));
    snprintf(ref_path + strlen(ref_path), sizeof ref_path - strlen(ref_path), "%s.exr", gc->name);
    if (getenv("FOVSIM_UPDATE_GOLDEN")) {
        exr_image_set_string(&img, "fovsim:renderer", gl_device_renderer());
        CHECK(exr_write_file(ref_path, &img, EXR_COMPRESS_ZIP) == FS_OK);
        fprintf(stderr, "golden %s: reference updated (%s)\n", gc->name, ref_path);
        exr_image_free(&img);
        return;
    }
    exr_image ref;
    CHECK(exr_read_file(ref_path, &ref) == FS_OK);
    CHECK(ref.width == img.width && ref.height == img.height);
    /* The comparison is fovsim check's (metrics/image_diff.h): RMSE over every channel, and the
     * largest difference of 2x2 block means. */
    image_diff diff = {0};
    for (int c = 0; c < img.channel_count && ref.width == img.width && ref.height == img.height; c++) {
        const float *r = exr_image_channel(&ref, img.channel_names[c]);
        CHECK(r != NULL);
        if (r)
            image_diff_add(&diff, img.planes[c], r, img.width, img.height, 2, NULL, 0);
    }
    double rmse = diff.count ? image_diff_rmse(&diff) : INFINITY, max2 = diff.max_block;
    fprintf(stderr, "golden %s: RMSE %.5f (limit %.3f), max 2x2 error %.4f (limit %.2f)\n", gc->name, rmse,
            gc->max_rmse, max2, gc->max_err_2x2);
    bool ok = rmse <= gc->max_rmse && max2 <= gc->max_err_2x2;
    CHECK(rmse <= gc->max_rmse);
    CHECK(max2 <= gc->max_err_2x2);
    if (!ok)
        write_diff(gc, &img, &ref);
    exr_image_free(&ref);
    exr_image_free(&img);
}

TEST(golden_images)
{
    for (size_t i = 0; i < sizeof k_cases / sizeof k_cases[0]; i++)
        run_case(&k_cases[i]);
}

TEST(a_changed_render_fails_the_comparison)
{
    /* The comparison can fail: the fence drawn with a different cutoff is not the fence golden. */
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    for (int m = 0; m < sc.assets[0].material_count; m++)
        if (sc.assets[0].materials[m].alpha_kind == ALPHA_KIND_MASK)
            sc.assets[0].materials[m].alpha_cutoff = 0.05f;
    exr_image img, ref;
    CHECK(gpu_render(&sc, ALPHA_MODE_TRADITIONAL, 192, 108, 0.0f, &img) == FS_OK);
    CHECK(exr_read_file(test_source_path("tests/golden/refs/fence_t0.exr"), &ref) == FS_OK);
    const float *a = exr_image_channel(&img, "coverage"), *b = exr_image_channel(&ref, "coverage");
    CHECK(a && b);
    image_diff diff = {0};
    if (a && b)
        image_diff_add(&diff, a, b, 192, 108, 2, NULL, 0);
    CHECK(image_diff_rmse(&diff) > 0.01);
    exr_image_free(&img);
    exr_image_free(&ref);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(golden_images);
    if (!getenv("FOVSIM_UPDATE_GOLDEN"))
        RUN(a_changed_render_fails_the_comparison);
    gl_device_destroy();
    return test_summary();
}
