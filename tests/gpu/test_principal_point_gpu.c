/* test_principal_point_gpu.c: a frame drawn on a display with an off-centre principal point
 * (core/display.h) equals the same sub-rectangle of the frame drawn on a larger centred display
 * with the same camera and focal length: the off-axis projection (frame.c) casts the same rays.
 * Foveation off, the traditional alpha test (no screen-position noise), so the two renders differ
 * only where rasterisation of the same rays rounds differently at a few edges. A negative control
 * (the crop drawn as a centred display) shows the check can fail. */
#include "gpu_util.h"

/* The big display and the crop [X0, X0 + CW) x [Y0, Y0 + CH) of it. */
enum { W0 = 384, H0 = 216, X0 = 64, Y0 = 32, CW = 224, CH = 144 };

typedef struct diff_stats {
    double mean, max;  /* absolute difference over R, G, B, A */
    double share_off;  /* share of pixels whose largest channel difference exceeds 0.05 */
} diff_stats;

static diff_stats crop_diff(const exr_image *big, const exr_image *crop)
{
    static const char *const ch[4] = {"R", "G", "B", "A"};
    diff_stats d = {0, 0, 0};
    long off = 0;
    for (int y = 0; y < CH; y++)
        for (int x = 0; x < CW; x++) {
            double worst = 0.0;
            for (int c = 0; c < 4; c++) {
                double a = exr_image_channel(big, ch[c])[(size_t)(y + Y0) * W0 + x + X0];
                double b = exr_image_channel(crop, ch[c])[(size_t)y * CW + x];
                double e = fabs(a - b);
                d.mean += e;
                worst = e > worst ? e : worst;
            }
            d.max = worst > d.max ? worst : d.max;
            off += worst > 0.05;
        }
    d.mean /= 4.0 * CW * CH;
    d.share_off = (double)off / (CW * CH);
    return d;
}

static bool render_on(scene *sc, display_desc disp, exr_image *img)
{
    sc->display = disp;
    return gpu_render(sc, ALPHA_MODE_TRADITIONAL, disp.width, disp.height, 1.0f, img) == FS_OK;
}

TEST(offcentre_frame_is_the_crop_of_the_centred_frame)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    for (int k = 0; k < sc.camera.count; k++)
        sc.camera.keys[k].hfov_deg = 0.0f; /* the display's field of view, so the focal lengths match */
    display_desc big = {W0, H0, 90.0f, 0.0f, 0.0f};
    display_geom g = display_geom_of(&big);
    display_desc crop = {CW, CH, (float)(2.0 * atan(0.5 * CW / g.f) * 180.0 / FS_PI), (float)(g.cx - X0 - 0.5 * CW),
                         (float)(g.cy - Y0 - 0.5 * CH)};
    display_desc centred = crop;
    centred.ppx = centred.ppy = 0.0f;
    exr_image ib, ic, iw;
    CHECK(render_on(&sc, big, &ib));
    CHECK(render_on(&sc, crop, &ic));
    CHECK(render_on(&sc, centred, &iw));
    diff_stats d = crop_diff(&ib, &ic), w = crop_diff(&ib, &iw);
    fprintf(stderr, "crop vs big: mean %.3g, max %.3g, pixels off by > 0.05: %.4f\n", d.mean, d.max, d.share_off);
    fprintf(stderr, "centred crop (control): mean %.3g, max %.3g, pixels off: %.4f\n", w.mean, w.max, w.share_off);
    /* Measured on llvmpipe (LLVM 15.0.6): mean 4.5e-6, 3 pixels of 32256 off by > 0.05 (max 0.125,
     * alpha-tested leaf edges); the control: mean 0.13, half the pixels off. */
    CHECK(d.mean < 1e-4);
    CHECK(d.share_off < 0.001);
    CHECK(w.mean > 10.0 * d.mean && w.share_off > 0.05);
    exr_image_free(&ib);
    exr_image_free(&ic);
    exr_image_free(&iw);
    scene_free(&sc);
}

/* The composite's eccentricity (GLSL, u_principal_px) on the off-centre display agrees with the C
 * twin (fov_eccentricity_deg on the same display), and differs from the centred display's. */
TEST(glsl_eccentricity_uses_the_principal_point)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    display_desc d = {CW, CH, 70.0f, 40.0f, -25.0f}, centred = {CW, CH, 70.0f, 0.0f, 0.0f};
    sc.display = d;
    fov_layout l = gpu_layout("5:1:0,15:1/2:0,30:1/4:0,*:1/16:0", CW, CH);
    const float gaze[2] = {0.3f, 0.6f};
    gpu_fov fv = {.layout = &l, .gaze = {gaze[0], gaze[1]}, .debug_channels = true};
    exr_image img;
    CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, CW, CH, 1.0f, &fv, &img) == FS_OK);
    const float *ecc = exr_image_channel(&img, "eccentricity"), *rid = exr_image_channel(&img, "ring.id");
    CHECK(ecc && rid);
    float gx = gaze[0] * CW, gy = gaze[1] * CH;
    double max_e = 0, max_r = 0, max_centred = 0;
    for (int y = 0; ecc && rid && y < CH; y++)
        for (int x = 0; x < CW; x++) {
            float e = fov_eccentricity_deg(&d, gx, gy, (float)x + 0.5f, (float)y + 0.5f);
            float ec = fov_eccentricity_deg(&centred, gx, gy, (float)x + 0.5f, (float)y + 0.5f);
            fov_blend bl = fov_composite_weight(&l, e);
            max_e = fmax(max_e, fabs(ecc[y * CW + x] - e) / fmax(1.0, fabs(e)));
            max_centred = fmax(max_centred, fabs(ecc[y * CW + x] - ec) / fmax(1.0, fabs(ec)));
            max_r = fmax(max_r, fabs(rid[y * CW + x] - ((float)bl.ring + bl.next)));
        }
    fprintf(stderr, "off-centre eccentricity: max error %.2e (relative), ring.id %.2e; against the centred twin %.2e\n",
            max_e, max_r, max_centred);
    CHECK(max_e < 1.5e-3); /* test_foveation's bound: half storage and float math on the GPU */
    CHECK(max_r < 1e-2);
    CHECK(max_centred > 1e-2);
    exr_image_free(&img);
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(offcentre_frame_is_the_crop_of_the_centred_frame);
    RUN(glsl_eccentricity_uses_the_principal_point);
    return test_summary();
}
