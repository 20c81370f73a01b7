/* The problem fovsim exists to show: traditional alpha testing erodes thin foliage with distance.
 *
 * The built-in fence scene dollies straight back from a chain-link fence (mean alpha of the wire
 * texture well below the 0.5 cutoff). Coverage is measured relative to the fence's own screen
 * area, obtained by rendering the same frame with the wire's cutoff set to 0 (every texel passes),
 * so the shrinking projection does not enter the ratio:
 *   kept(t) = coverage(cutoff 0.5) / coverage(cutoff 0).
 * Near the fence kept ≈ the fraction of wire texels with alpha >= 0.5; far away the box-filtered
 * mips drop below the cutoff and kept falls towards 0. */
#include "gpu_util.h"

enum { W = 1280, H = 720 }; /* the scene's display: the mip levels the user sees */

static double coverage_at(scene *sc, float t, float cutoff)
{
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++)
            if (sc->assets[a].materials[m].alpha_kind == ALPHA_KIND_MASK)
                sc->assets[a].materials[m].alpha_cutoff = cutoff;
    exr_image img;
    if (gpu_render(sc, ALPHA_MODE_TRADITIONAL, W, H, t, &img) != FS_OK)
        return NAN;
    double c = plane_mean(&img, "coverage");
    exr_image_free(&img);
    return c;
}

TEST(traditional_alpha_test_erodes_the_fence_with_distance)
{
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    float cutoff = 0.5f;
    for (int m = 0; m < sc.assets[0].material_count; m++)
        if (sc.assets[0].materials[m].alpha_kind == ALPHA_KIND_MASK)
            cutoff = sc.assets[0].materials[m].alpha_cutoff;
    const int steps = 9;
    double kept[9];
    for (int i = 0; i < steps; i++) {
        float t = sc.duration * (float)i / (float)(steps - 1);
        double area = coverage_at(&sc, t, 0.0f);
        double cov = coverage_at(&sc, t, cutoff);
        kept[i] = cov / area;
        fprintf(stderr, "t = %.2f s: fence area %.3f of the frame, coverage %.4f, kept %.3f\n", t, area, cov, kept[i]);
        CHECK(area > 0.02); /* the fence stays in view (> 18k pixels): the ratio means something */
    }
    /* Near: a real fraction of the wire survives. Far: well below the near value. */
    CHECK(kept[0] > 0.1);
    CHECK(kept[steps - 1] < 0.25 * kept[0]);
    /* And coverage only ever goes down as the fence recedes (0.01: rasterisation noise). */
    for (int i = 1; i < steps; i++)
        CHECK(kept[i] <= kept[i - 1] + 0.01);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(traditional_alpha_test_erodes_the_fence_with_distance);
    gl_device_destroy();
    return test_summary();
}
