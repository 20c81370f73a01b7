/* The alpha-test strategies side by side (seed 000): what each does to coverage with distance,
 * to overlapping layers, and to stability under sub-pixel motion. Tests that can fail: each
 * asserts the ordering the method predicts, with margins. */
#include "stb_png.h"

#include "gpu_util.h"

static void set_cutoff(scene *sc, float cutoff)
{
    for (int a = 0; a < sc->asset_count; a++)
        for (int m = 0; m < sc->assets[a].material_count; m++)
            if (sc->assets[a].materials[m].alpha_kind == ALPHA_KIND_MASK)
                sc->assets[a].materials[m].alpha_cutoff = cutoff;
}

static double render_coverage_p(scene *sc, alpha_mode mode, int w, int h, float t, int frame, alpha_params ap)
{
    exr_image img;
    gpu_fov fv = {.gaze = {0.5f, 0.5f}, .frame = frame, .alpha = ap};
    if (gpu_render_fov(sc, mode, w, h, t, &fv, &img) != FS_OK)
        return NAN;
    double c = plane_mean(&img, "coverage");
    exr_image_free(&img);
    return c;
}

static double render_coverage(scene *sc, alpha_mode mode, int w, int h, float t, int frame)
{
    return render_coverage_p(sc, mode, w, h, t, frame, (alpha_params){0});
}

/* Mean alpha of the fence's wire texture (level 0 = every level, the mips preserve it). */
static double wire_mean_alpha(const scene *sc)
{
    const image_rgba8 *im = &sc->assets[0].images[0];
    double s = 0;
    for (int i = 0; i < im->width * im->height; i++)
        s += im->rgba[4 * i + 3] / 255.0;
    return s / (im->width * im->height);
}

TEST(coverage_with_distance_per_mode)
{
    enum { W = 640, H = 360 };
    scene sc;
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    double mean_alpha = wire_mean_alpha(&sc);
    fprintf(stderr, "fence wire: mean alpha %.3f\n", mean_alpha);
    static const alpha_mode modes[] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED, ALPHA_MODE_STOCHASTIC,
                                       ALPHA_MODE_CASTANO, ALPHA_MODE_MIPSCALE, ALPHA_MODE_A2C, ALPHA_MODE_HASHED_A2C};
    enum { NM = sizeof modes / sizeof modes[0], NT = 5 };
    double kept[NM][NT];
    for (int k = 0; k < NT; k++) {
        float t = sc.duration * (float)k / (NT - 1);
        set_cutoff(&sc, 0.0f);
        double area = render_coverage(&sc, ALPHA_MODE_TRADITIONAL, W, H, t, 0);
        set_cutoff(&sc, 0.5f);
        fprintf(stderr, "t = %.1f s (fence area %.3f):", t, area);
        for (int m = 0; m < NM; m++) {
            kept[m][k] = render_coverage(&sc, modes[m], W, H, t, 0) / area;
            fprintf(stderr, " %s %.3f", alpha_mode_name(modes[m]), kept[m][k]);
        }
        fprintf(stderr, "\n");
    }
    /* Traditional: the wire erodes away with distance. */
    CHECK(kept[0][NT - 1] < 0.2 * kept[0][0]);
    /* Hashed, stochastic and hashed A2C: the wire keeps its mean opacity at every distance (within
     * 35 %: one sample per pixel of a texture whose alpha is mostly 0 or 1). Hashed fades in from the
     * traditional test up close (seed 000 §5.5.1), and for this wire by mip 3, where traditional
     * starts to erode it (renderer_upload.c material_fade): no mid-distance hole. */
    for (int k = 1; k < NT; k++) {
        CHECK(fabs(kept[1][k] - mean_alpha) < 0.35 * mean_alpha);
        CHECK(fabs(kept[2][k] - mean_alpha) < 0.35 * mean_alpha);
        CHECK(fabs(kept[6][k] - mean_alpha) < 0.35 * mean_alpha);
    }
    /* Castano keeps level 0's coverage while the wire's mips still vary (t <= 1 s, mip <= 2);
     * beyond, a tiled symmetric wire cell's coarse mips hold a single alpha value, which no
     * per-level threshold can split: it is all or nothing, and Castano's method (like
     * traditional) loses the fence. Asserted both ways: a known limit of the method. */
    CHECK(fabs(kept[3][1] - kept[3][0]) < 0.6 * kept[3][0]);
    CHECK(kept[3][NT - 1] < 0.01);
    /* And at the far end the hashed family keeps far more than traditional. */
    CHECK(kept[1][NT - 1] > 3.0 * kept[0][NT - 1] + 0.02);
    CHECK(kept[6][NT - 1] > 3.0 * kept[0][NT - 1] + 0.02);
    /* Golus's A2C (seed 002): alpha scaled up by 0.25 per mip level and sharpened with fwidth
     * around the cutoff. The scaling delays the wire's erosion compared with the traditional test;
     * measured and asserted at 3.4 m, where traditional has lost most of it. */
    fprintf(stderr, "a2c sharpened:");
    double sharp[NT];
    for (int k = 0; k < NT; k++) {
        float t = sc.duration * (float)k / (NT - 1);
        set_cutoff(&sc, 0.0f);
        double area = render_coverage(&sc, ALPHA_MODE_TRADITIONAL, W, H, t, 0);
        set_cutoff(&sc, 0.5f);
        sharp[k] = render_coverage_p(&sc, ALPHA_MODE_A2C, W, H, t, 0, (alpha_params){.a2c_sharpen = true}) / area;
        fprintf(stderr, " %.3f", sharp[k]);
    }
    fprintf(stderr, "\n");
    CHECK(sharp[1] > 2.0 * kept[0][1] + 0.02);
    scene_free(&sc);
}

/* One 16 m card tiled 8 x 8 with MegaKit Leaves.png (cutoff 0.2, mean alpha 0.44), facing the
 * camera, which recedes from 2.5 m to 80 m: at 640 px for 90 degrees the lookups go from about
 * mip 1 to mip 8, and the card still covers ~60 x 60 pixels at the far end. */
static bool leaves_card_scene(scene *sc)
{
    int w, h, n;
    unsigned char *px = stbi_load(test_shared_path("assets/quaternius_megakit_set_a/Leaves.png"), &w, &h, &n, 4);
    if (!px)
        return false;
    scene_init_defaults(sc);
    image_rgba8 img = {.width = w, .height = h, .rgba = px};
    material m = {.base_color = {1, 1, 1, 1}, .base_color_image = 0, .alpha_kind = ALPHA_KIND_MASK,
                  .alpha_cutoff = 0.2f, .double_sided = true};
    float pos[12] = {-8, -8, 0, 8, -8, 0, 8, 8, 0, -8, 8, 0}, uv[8] = {0, 8, 8, 8, 8, 0, 0, 0};
    asset a = quad_asset("leaves_card", pos, uv, m, &img);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    float d[] = {2.5f, 6, 14, 34, 80};
    sc->camera.count = 5;
    for (int k = 0; k < 5; k++)
        sc->camera.keys[k] = (camera_key){.time = (float)k, .position = v3(0, 0, d[k]), .target = v3(0, 0, 0)};
    sc->duration = 4;
    return true;
}

TEST(receding_leaf_card_per_mode)
{
    /* The other direction of the coverage error (docs/design.md "Ground truth and metrics"): Leaves.png has mean alpha 0.44 above its
     * 0.2 cutoff, so box-filtered mips bloat the traditional test towards full cover. Castano and
     * the hashed family keep the card's coverage. */
    enum { W = 640, H = 360 };
    scene sc;
    CHECK(leaves_card_scene(&sc));
    const image_rgba8 *im = &sc.assets[0].images[0];
    double mean = 0, pass0 = 0;
    for (int i = 0; i < im->width * im->height; i++) {
        mean += im->rgba[4 * i + 3] / 255.0;
        pass0 += im->rgba[4 * i + 3] >= 51; /* 51/255 = 0.2 */
    }
    mean /= im->width * im->height;
    pass0 /= im->width * im->height;
    fprintf(stderr, "Leaves.png: mean alpha %.3f, texels passing 0.2: %.3f\n", mean, pass0);
    static const alpha_mode modes[] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED, ALPHA_MODE_STOCHASTIC,
                                       ALPHA_MODE_CASTANO};
    enum { NM = 4, NT = 5 };
    double kept[NM][NT];
    for (int k = 0; k < NT; k++) {
        set_cutoff(&sc, 0.0f);
        double area = render_coverage(&sc, ALPHA_MODE_TRADITIONAL, W, H, (float)k, 0);
        set_cutoff(&sc, 0.2f);
        fprintf(stderr, "distance step %d (card area %.5f):", k, area);
        for (int m = 0; m < NM; m++) {
            kept[m][k] = render_coverage(&sc, modes[m], W, H, (float)k, 0) / area;
            fprintf(stderr, " %s %.3f", alpha_mode_name(modes[m]), kept[m][k]);
        }
        fprintf(stderr, "\n");
    }
    CHECK(kept[0][NT - 1] > 1.5 * pass0);            /* traditional bloats towards full cover */
    for (int k = 0; k < NT; k++) {
        CHECK(fabs(kept[3][k] - pass0) < 0.2 * pass0); /* castano keeps level 0's coverage */
        CHECK(fabs(kept[2][k] - mean) < 0.2 * mean);   /* stochastic: the mean alpha */
    }
    for (int k = 2; k < NT; k++)                       /* hashed, once faded in */
        CHECK(fabs(kept[1][k] - mean) < 0.2 * mean);
    scene_free(&sc);
}

/* n parallel quads stacked in depth in ONE asset (so their object-space z differs), constant
 * alpha 0.4, facing the camera. */
static void stack_scene(scene *sc, int n)
{
    scene_init_defaults(sc);
    asset a = {0};
    snprintf(a.name, sizeof a.name, "stack");
    a.prim_count = a.material_count = 1;
    a.prims = calloc(1, sizeof(prim));
    a.materials = calloc(1, sizeof(material));
    a.materials[0] = (material){.base_color = {0.3f, 0.6f, 0.2f, 0.4f}, .base_color_image = -1,
                                .alpha_kind = ALPHA_KIND_MASK, .alpha_cutoff = 0.5f, .double_sided = true};
    prim *p = &a.prims[0];
    p->vertex_count = 4 * (uint32_t)n;
    p->index_count = 6 * (uint32_t)n;
    p->positions = malloc(sizeof(float) * 3 * p->vertex_count);
    p->normals = calloc(3 * p->vertex_count, sizeof(float));
    p->uvs = calloc(2 * p->vertex_count, sizeof(float));
    p->colors = malloc(sizeof(float) * 4 * p->vertex_count);
    p->indices = malloc(sizeof(uint32_t) * p->index_count);
    for (int q = 0; q < n; q++) {
        float z = -0.37f * (float)q;
        float v[12] = {-3, -3, z, 3, -3, z, 3, 3, z, -3, 3, z};
        memcpy(&p->positions[12 * q], v, sizeof v);
        for (int k = 0; k < 4; k++)
            p->normals[12 * q + 3 * k + 2] = 1.0f;
        uint32_t b = 4 * (uint32_t)q, idx[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(&p->indices[6 * q], idx, sizeof idx);
    }
    for (uint32_t i = 0; i < 4 * p->vertex_count; i++)
        p->colors[i] = 1.0f;
    asset_compute_bounds(&a);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 2.0f), .target = v3(0, 0, -1), .hfov_deg = 60};
}

TEST(overlapping_layers_decorrelate)
{
    enum { W = 256, H = 256, N = 4 };
    scene sc;
    stack_scene(&sc, N);
    double expect = 1.0 - pow(1.0 - 0.4, N); /* independent layers of alpha 0.4 */
    double trad = render_coverage(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0, 0);
    double a2c = render_coverage(&sc, ALPHA_MODE_A2C, W, H, 0, 0);
    double ha2c = render_coverage(&sc, ALPHA_MODE_HASHED_A2C, W, H, 0, 0);
    double hashed = render_coverage(&sc, ALPHA_MODE_HASHED, W, H, 0, 0);
    double stoch = render_coverage(&sc, ALPHA_MODE_STOCHASTIC, W, H, 0, 0);
    fprintf(stderr, "%d layers of alpha 0.4: independent %.3f; traditional %.3f, a2c %.3f, hashed_a2c %.3f, "
                    "hashed %.3f, stochastic %.3f\n", N, expect, trad, a2c, ha2c, hashed, stoch);
    CHECK(trad < 0.01);                    /* 0.4 < cutoff 0.5: nothing */
    CHECK(a2c < 0.6);                      /* the same dither pattern in every layer: ~ one layer's worth */
    CHECK(fabs(ha2c - expect) < 0.06);     /* decorrelated per-sample thresholds */
    CHECK(fabs(hashed - expect) < 0.06);
    CHECK(fabs(stoch - expect) < 0.06);
    CHECK(ha2c > a2c + 0.2);
    scene_free(&sc);
}

/* Fraction of pixels whose colour changes between two renders. */
static double changed_fraction(const exr_image *a, const exr_image *b)
{
    long n = 0;
    const float *ra = exr_image_channel(a, "G"), *rb = exr_image_channel(b, "G");
    for (int i = 0; i < a->width * a->height; i++)
        n += fabsf(ra[i] - rb[i]) > 0.02f;
    return (double)n / (a->width * a->height);
}

TEST(stability_under_subpixel_motion)
{
    /* Seed 000 Figure 9: a camera moving by a fraction of a pixel. Hashed noise is anchored to
     * the object at pixel scale, so it changes about as little as traditional testing; stochastic
     * draws new thresholds every frame. */
    enum { W = 320, H = 180 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    static const alpha_mode modes[] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED, ALPHA_MODE_STOCHASTIC};
    double changed[3];
    for (int m = 0; m < 3; m++) {
        exr_image a, b;
        gpu_fov f0 = {.gaze = {0.5f, 0.5f}, .frame = 0}, f1 = {.gaze = {0.5f, 0.5f}, .frame = 1};
        /* The dolly moves ~2.7 m/s: 1 ms is ~3 mm, well under a pixel at these distances. */
        CHECK(gpu_render_fov(&sc, modes[m], W, H, 1.0f, &f0, &a) == FS_OK);
        CHECK(gpu_render_fov(&sc, modes[m], W, H, 1.001f, &f1, &b) == FS_OK);
        changed[m] = changed_fraction(&a, &b);
        fprintf(stderr, "%s: %.4f of pixels change\n", alpha_mode_name(modes[m]), changed[m]);
        exr_image_free(&a);
        exr_image_free(&b);
    }
    CHECK(changed[1] < 3.0 * changed[0] + 0.01); /* hashed: the same order as traditional */
    CHECK(changed[2] > 5.0 * changed[1] + 0.02); /* stochastic: an order of magnitude more */
    scene_free(&sc);
}

int main(void)
{
    gpu_begin();
    RUN(coverage_with_distance_per_mode);
    RUN(receding_leaf_card_per_mode);
    RUN(overlapping_layers_decorrelate);
    RUN(stability_under_subpixel_motion);
    gl_device_destroy();
    return test_summary();
}
