/* Headless rendering on llvmpipe (or a GPU): built-in scenes and real glTF assets produce
 * plausible images, coverage behaves as docs/design.md "Coverage" defines it. */
#include "gpu_util.h"

enum { W = 160, H = 90 };

TEST(builtin_forest_renders_foliage)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    exr_image img;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.0f, &img) == FS_OK);
    CHECK(all_finite(&img));
    double cov = plane_mean(&img, "coverage"), a = plane_mean(&img, "A");
    fprintf(stderr, "forest: coverage %.3f, geometry %.3f\n", cov, a);
    CHECK(cov > 0.15 && cov < 0.9); /* foliage covers a good share of the view, not all of it */
    CHECK(a > cov);                 /* trunks, posts and ground are geometry without coverage */
    CHECK(a > 0.5 && a < 1.0);      /* some sky is visible */
    /* Coverage only where there is geometry; values in [0, 1]. */
    const float *cv = exr_image_channel(&img, "coverage"), *al = exr_image_channel(&img, "A");
    for (int i = 0; i < W * H; i++) {
        CHECK(cv[i] >= 0.0f && cv[i] <= 1.0f);
        if (al[i] == 0.0f)
            CHECK(cv[i] == 0.0f);
    }
    /* Foliage is green-dominant: mean G > mean B over covered pixels. */
    const float *g = exr_image_channel(&img, "G"), *b = exr_image_channel(&img, "B");
    double sg = 0, sb = 0;
    for (int i = 0; i < W * H; i++)
        if (cv[i] > 0.5f) {
            sg += g[i];
            sb += b[i];
        }
    CHECK(sg > 1.2 * sb);
    exr_image_free(&img);
    scene_free(&sc);
}

TEST(opaque_gltf_has_no_coverage)
{
    scene sc;
    CHECK(scene_load_file(test_shared_path("assets/quaternius_megakit_set_a/Grass_Wispy_Tall.gltf"), &sc) == FS_OK);
    exr_image img;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.0f, &img) == FS_OK);
    double a = plane_mean(&img, "A");
    fprintf(stderr, "Grass_Wispy_Tall: geometry %.3f\n", a);
    CHECK(a > 0.02);                                 /* the camera fitted to the asset sees it */
    CHECK(plane_mean(&img, "coverage") == 0.0);      /* opaque: no alpha-mapped coverage */
    exr_image_free(&img);
    scene_free(&sc);
}

TEST(masked_gltf_assets_render)
{
    static const char *const files[] = {
        "assets/quaternius_megakit_set_a/Bush_Common.gltf",
        "assets/quaternius_megakit_set_a/Flower_4_Single.gltf", /* NPOT texture, UVs outside [0,1] */
        "assets/quaternius_megakit_set_a/Plant_1_Big.gltf",
    };
    for (int i = 0; i < 3; i++) {
        scene sc;
        CHECK(scene_load_file(test_shared_path(files[i]), &sc) == FS_OK);
        exr_image img;
        CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.0f, &img) == FS_OK);
        double cov = plane_mean(&img, "coverage"), a = plane_mean(&img, "A");
        fprintf(stderr, "%s: coverage %.3f, geometry %.3f\n", files[i], cov, a);
        CHECK(cov > 0.03);      /* leaves are visible */
        CHECK(cov <= a + 1e-6); /* coverage never exceeds geometry */
        CHECK(all_finite(&img));
        exr_image_free(&img);
        scene_free(&sc);
    }
}

TEST(mask_without_alpha_source_renders_solid_cards)
{
    /* fern_02.glb: MASK material whose base colour is an RGB JPEG, so nothing is discarded
     * (SOURCES.md A2). It must load and render as solid cards, not crash. */
    scene sc;
    CHECK(scene_load_file(test_shared_path("assets/polyhaven_fern_02_glb/fern_02.glb"), &sc) == FS_OK);
    exr_image img;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.0f, &img) == FS_OK);
    const float *cv = exr_image_channel(&img, "coverage"), *al = exr_image_channel(&img, "A");
    int geo = 0, covered = 0;
    for (int i = 0; i < W * H; i++) {
        geo += al[i] > 0.0f;
        covered += cv[i] == 1.0f;
    }
    fprintf(stderr, "fern_02: %d geometry pixels, %d fully covered\n", geo, covered);
    CHECK(geo > 100);
    CHECK(covered == geo); /* every fern pixel is an alpha-mapped surface that passed */
    exr_image_free(&img);
    scene_free(&sc);
}

TEST(blend_gltf_gives_fractional_coverage)
{
    scene sc;
    CHECK(scene_load_file(test_shared_path("assets/polypizza_flower_bushes_glb/flower_bushes.glb"), &sc) == FS_OK);
    exr_image img;
    CHECK(gpu_render(&sc, ALPHA_MODE_DEFAULT, W, H, 0.0f, &img) == FS_OK);
    const float *cv = exr_image_channel(&img, "coverage"), *al = exr_image_channel(&img, "A");
    int any = 0, bad = 0;
    for (int i = 0; i < W * H; i++) {
        any += cv[i] > 0.01f;
        bad += fabsf(cv[i] - al[i]) > 2e-3f; /* only blended geometry: opacity == coverage */
    }
    fprintf(stderr, "flower_bushes: %d covered pixels, %d where A != coverage\n", any, bad);
    CHECK(any > 50);
    CHECK(bad == 0);
    exr_image_free(&img);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(builtin_forest_renders_foliage);
    RUN(opaque_gltf_has_no_coverage);
    RUN(masked_gltf_assets_render);
    RUN(mask_without_alpha_source_renders_solid_cards);
    RUN(blend_gltf_gives_fractional_coverage);
    gl_device_destroy();
    return test_summary();
}
