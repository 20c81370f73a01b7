/* Every row of the alpha-mode table (FS_ALPHA_MODES, common/shared_defs.h) compiles and draws: the
 * fence, MASK throughout, in each mode the table lists, so a new mode is compiled and drawn here
 * without a new test. Its plan has one MASK pass of that mode, MSAA targets exactly when the row
 * asks for them, and at 320x180 from 1.5 m the wire covers some of the image in every mode. */
#include "gpu_util.h"

TEST(every_mode_compiles_and_draws)
{
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    enum { W = 320, H = 180 };
    for (int m = ALPHA_MODE_TRADITIONAL; m < ALPHA_MODE_COUNT; m++) {
        plan pl;
        CHECK(plan_build(&sc, &(plan_options){.alpha_mode = (alpha_mode)m, .width = W, .height = H, .frames = 1},
                         &pl) == FS_OK);
        CHECK(plan_find(&pl, PLAN_PASS_FORWARD_MASK, (alpha_mode)m) != NULL);
        CHECK(pl.msaa == alpha_mode_has((alpha_mode)m, ALPHA_TRAIT_MSAA));
        exr_image img;
        fs_status st = gpu_render(&sc, (alpha_mode)m, W, H, 0.0f, &img);
        CHECK(st == FS_OK);
        if (st != FS_OK)
            continue;
        double c = plane_mean(&img, "coverage");
        fprintf(stderr, "%-12s coverage %.4f\n", alpha_mode_name((alpha_mode)m), c);
        CHECK(c > 0.0);
        exr_image_free(&img);
    }
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(every_mode_compiles_and_draws);
    gl_device_destroy();
    return test_summary();
}
