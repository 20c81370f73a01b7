/* Ring LOD on the GPU (docs/ring-lod.md): a field of identical cards keeps its covered
 * area when a ring keeps a fraction u of them; u = 1 draws bit for bit what no simplification
 * draws; a still camera draws the same frame twice; a slowly moving gaze changes coverage no faster
 * with ring LOD than without; the reference and scenes without card aggregates compile nothing. */
#include "gpu_util.h"

#include "scene/cards.h"

static ring_lod_spec lod_of(const char *text)
{
    ring_lod_spec s;
    char err[256];
    if (ring_lod_parse(text, &s, err, sizeof err) != FS_OK) {
        fprintf(stderr, "bad ring LOD %s: %s\n", text, err);
        exit(1);
    }
    return s;
}

/* A field of NX x NY identical square cards (side `side` world units, facing the camera) in one
 * MASK primitive without a texture (alpha 1: a card covers exactly its area), centred, on a grid of
 * pitch `pitch` with a pseudo-random offset of up to a tenth of it each (so pixel-centre sampling
 * estimates every card's area without bias), seen head-on by a 90-degree camera at distance 1
 * (the view spans 2 units across). */
static void card_field(scene *sc, int nx, int ny, float side, float pitch)
{
    scene_init_defaults(sc);
    asset a = {0};
    snprintf(a.name, sizeof a.name, "card_field");
    a.prim_count = a.material_count = 1;
    a.prims = calloc(1, sizeof(prim));
    a.materials = calloc(1, sizeof(material));
    a.materials[0] = (material){.base_color = {0.3f, 0.6f, 0.2f, 1.0f}, .base_color_image = -1,
                                .alpha_kind = ALPHA_KIND_MASK, .alpha_cutoff = 0.5f, .double_sided = true};
    prim *p = &a.prims[0];
    uint32_t n = (uint32_t)(nx * ny);
    p->vertex_count = 4 * n;
    p->index_count = 6 * n;
    p->positions = malloc(sizeof(float) * 12 * n);
    p->normals = calloc(12 * (size_t)n, sizeof(float));
    p->uvs = calloc(8 * (size_t)n, sizeof(float));
    p->colors = malloc(sizeof(float) * 16 * n);
    p->indices = malloc(sizeof(uint32_t) * 6 * n);
    uint32_t seed = 12345u;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            uint32_t c = (uint32_t)(j * nx + i);
            seed = seed * 1664525u + 1013904223u;
            float ox = (float)(seed >> 8) / 16777216.0f * 0.1f * pitch;
            seed = seed * 1664525u + 1013904223u;
            float oy = (float)(seed >> 8) / 16777216.0f * 0.1f * pitch;
            float x0 = -0.5f * (float)nx * pitch + (float)i * pitch + ox, y0 = -0.5f * (float)ny * pitch + (float)j * pitch + oy;
            float q[12] = {x0, y0, 0, x0 + side, y0, 0, x0 + side, y0 + side, 0, x0, y0 + side, 0};
            memcpy(&p->positions[12 * c], q, sizeof q);
            for (int v = 0; v < 4; v++) {
                p->normals[12 * c + 3 * (uint32_t)v + 2] = 1.0f;
                for (int k = 0; k < 4; k++)
                    p->colors[16 * c + 4 * (uint32_t)v + (uint32_t)k] = 1.0f;
            }
            const uint32_t idx[6] = {4 * c, 4 * c + 1, 4 * c + 2, 4 * c, 4 * c + 2, 4 * c + 3};
            memcpy(&p->indices[6 * c], idx, sizeof idx);
        }
    asset_compute_bounds(&a);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    sc->light.direction = v3(0, 0, -1);
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 1), .target = v3(0, 0, 0), .hfov_deg = 90};
    sc->display.hfov_deg = 90;
}

TEST(a_field_of_cards_keeps_its_covered_area)
{
    /* 96 x 54 cards of 4 x 4 pixels on a 12.8-pixel pitch (96 % of the view's width) at
     * 1280 x 720: at u = 1/8 a kept card is sqrt(8) = 2.8 times wider (11.3 px), still apart from
     * its neighbours (offsets of at most 1.3 px) and inside the view, so the image's mean coverage
     * is the sum of the cards' areas.
     *
     * The tolerance. With independent random ranks the kept count would be Binomial(N, u), and the
     * total area's relative standard deviation sqrt((1 - u) / (N u)): 1.4 %, 2.4 % and 3.7 % for
     * u = 1/2, 1/4, 1/8 with N = 5184 (4 sigma: 5.6 %, 9.6 %, 14.7 %). The ranks are stratified
     * (docs/ring-lod.md "Ranks"): the kept count is exact to one card, 1 / (N u) = 0.04 %, 0.08 %,
     * 0.15 % of the area; the cards in the transition band are deterministic. What remains is
     * pixel-centre sampling of ~5200 / 1300 / 650 squares at random offsets: a square of side s
     * pixels covers s^2 +- about sqrt(s) pixels, 0.1 % of the total or less. 1 % is that bound
     * with a wide margin and still a tenth of the binomial spread at u = 1/8; a law without the
     * area gain would give u, a gain off by the band's share (1 - B/2 = 0.875) 12.5 % too much. */
    enum { W = 1280, H = 720, NX = 96, NY = 54 };
    scene sc;
    card_field(&sc, NX, NY, 2.0f * 4.0f / W, 2.0f * 12.8f / W);
    fov_layout one = gpu_layout("*:1:0", W, H);
    gpu_fov fv = {.layout = &one, .gaze = {0.5f, 0.5f}};
    exr_image base;
    CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &fv, &base) == FS_OK);
    double c0 = plane_mean(&base, "coverage");
    double expect = (double)NX * NY * 16.0 / ((double)W * H); /* 4 x 4 pixels a card */
    fprintf(stderr, "u = 1: mean coverage %.5f (the cards' area: %.5f)\n", c0, expect);
    CHECK(fabs(c0 / expect - 1.0) < 0.01);
    /* The field fits in 2.8-fold enlarged cards' reach: nothing covered at the image's border. */
    const float *bc = exr_image_channel(&base, "coverage");
    for (int x = 0; x < W; x++)
        CHECK(bc[x] == 0.0f && bc[(size_t)(H - 1) * W + (size_t)x] == 0.0f);
    CHECK(fabs(c0 / expect - 1.0) < 0.01);
    static const char *const specs[] = {"simplify:1/2", "simplify:1/4", "simplify:1/8"};
    for (int s = 0; s < 3; s++) {
        fv.ring_lod = lod_of(specs[s]);
        exr_image img;
        CHECK(gpu_render_fov(&sc, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &fv, &img) == FS_OK);
        double c = plane_mean(&img, "coverage");
        long long lit = 0;
        const float *cov = exr_image_channel(&img, "coverage");
        for (int i = 0; i < W * H; i++)
            lit += cov[i] > 0.5f;
        fprintf(stderr, "%s: mean coverage %.5f, %+.2f %% of u = 1's (%lld pixels covered)\n", specs[s], c,
                100.0 * (c / c0 - 1.0), lit);
        CHECK(fabs(c / c0 - 1.0) < 0.01);
        exr_image_free(&img);
    }
    exr_image_free(&base);
    scene_free(&sc);
}

TEST(u_one_draws_what_no_simplification_draws_bit_for_bit)
{
    enum { W = 320, H = 180 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    fov_layout l = gpu_layout("8:1:0,20:1/2:0,*:1/8:0", W, H);
    static const alpha_mode modes[] = {ALPHA_MODE_TRADITIONAL, ALPHA_MODE_HASHED, ALPHA_MODE_A2C};
    for (int m = 0; m < 3; m++) {
        gpu_fov off = {.layout = &l, .gaze = {0.4f, 0.55f}}, ones = off;
        ones.ring_lod = lod_of("simplify:1,1,1");
        plan pl;
        plan_options po = {.alpha_mode = modes[m], .width = W, .height = H, .frames = 1, .layout = l,
                           .ring_lod = ones.ring_lod};
        CHECK(plan_build(&sc, &po, &pl) == FS_OK);
        CHECK(pl.ring_lod); /* the RING_LOD variant runs, with the identity law in every ring */
        exr_image a, b;
        CHECK(gpu_render_fov(&sc, modes[m], W, H, 2.0f, &off, &a) == FS_OK);
        CHECK(gpu_render_fov(&sc, modes[m], W, H, 2.0f, &ones, &b) == FS_OK);
        int differ = 0;
        for (int c = 0; c < a.channel_count; c++)
            differ += memcmp(a.planes[c], b.planes[c], sizeof(float) * W * H) != 0;
        fprintf(stderr, "%s: %d of %d planes differ\n", alpha_mode_name(modes[m]), differ, a.channel_count);
        CHECK(differ == 0);
        exr_image_free(&a);
        exr_image_free(&b);
    }
    scene_free(&sc);
}

/* Pixels whose coverage differs between a and b, in rings <= `inner` (by ring.id) and beyond. */
static void diff_by_ring(const exr_image *a, const exr_image *b, int inner, int *in, int *out)
{
    const float *ring = exr_image_channel(a, "ring.id"), *ca = exr_image_channel(a, "coverage"),
                *cb = exr_image_channel(b, "coverage");
    *in = *out = 0;
    for (int i = 0; i < a->width * a->height; i++) {
        bool d = ca[i] != cb[i];
        if (ring[i] < (float)inner + 0.5f)
            *in += d;
        else
            *out += d;
    }
}

TEST(simplification_thins_the_periphery_only_and_a_still_camera_repeats_its_frame)
{
    enum { W = 320, H = 180 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    fov_layout l = gpu_layout("8:1:0,20:1/2:0,*:1/8:0", W, H);
    l.blend_deg = 0.0f; /* hard ring edges: a pixel shows one ring's image */
    for (int m = 0; m < 2; m++) {
        alpha_mode mode = m ? ALPHA_MODE_HASHED : ALPHA_MODE_TRADITIONAL;
        gpu_fov plain = {.layout = &l, .gaze = {0.5f, 0.5f}, .debug_channels = true};
        exr_image p;
        CHECK(gpu_render_fov(&sc, mode, W, H, 1.0f, &plain, &p) == FS_OK);
        /* Explicit keep fractions 1, 1, 1/16: only ring 2 differs from no ring LOD. The default
         * (per card): the full-resolution ring 0 never differs; a still view repeats its frame. */
        static const char *const specs[] = {"simplify:1,1,1/16", "simplify"};
        for (int k = 0; k < 2; k++) {
            gpu_fov fv = plain;
            fv.ring_lod = lod_of(specs[k]);
            exr_image a, b;
            CHECK(gpu_render_fov(&sc, mode, W, H, 1.0f, &fv, &a) == FS_OK);
            fv.frame = 1; /* another frame of the same still view */
            CHECK(gpu_render_fov(&sc, mode, W, H, 1.0f, &fv, &b) == FS_OK);
            int differ = 0;
            for (int c = 0; c < a.channel_count; c++)
                differ += memcmp(a.planes[c], b.planes[c], sizeof(float) * W * H) != 0;
            CHECK(differ == 0);
            int inner, outer;
            diff_by_ring(&a, &p, k == 0 ? 1 : 0, &inner, &outer);
            fprintf(stderr, "%s, %s: still frames equal; pixels that differ from no ring LOD: %d in rings 0-%d, %d "
                            "beyond\n", alpha_mode_name(mode), specs[k], inner, k == 0 ? 1 : 0, outer);
            CHECK(inner == 0);
            /* Under the default, traditional's thinned cards (those below a ring pixel) mostly fail
             * its test before and after, so only hashed is sure to show them. */
            if (k == 0 || mode == ALPHA_MODE_HASHED)
                CHECK(outer > 0);
            exr_image_free(&a);
            exr_image_free(&b);
        }
        exr_image_free(&p);
    }
    scene_free(&sc);
}

TEST(the_default_keeps_cards_of_a_ring_pixel_and_thins_smaller_ones_keeping_their_area)
{
    /* One ring at quarter scale over the whole display (ring pixels of 4 x 4 display pixels).
     * Cards of 8 x 8 display pixels span 2 ring pixels: kept as they are, bit for bit. Cards of
     * 2 x 2 display pixels span half a ring pixel: u = 1/4 at the view's centre, less towards its
     * corners (they are farther from the eye), at least 1/16; kept cards grow to about a ring
     * pixel. Their mean coverage stays within 5 % of the cards' area: ~5200 cards at u >= 0.14
     * keep ~730 or more, each 2 ring pixels wide at most, sampled at ring pixel centres with a
     * relative spread of about 1 / sqrt(730 * 4) = 1.9 % (the stratified count adds 0.2 %). */
    enum { W = 1280, H = 720, NX = 96, NY = 54 };
    fov_layout quarter = gpu_layout("*:1/4:0", W, H);
    gpu_fov plain = {.layout = &quarter, .gaze = {0.5f, 0.5f}}, lod = plain;
    lod.ring_lod = lod_of("simplify");
    scene big, small;
    card_field(&big, 40, 22, 2.0f * 8.0f / W, 2.0f * 30.0f / W);
    exr_image a, b;
    CHECK(gpu_render_fov(&big, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &plain, &a) == FS_OK);
    CHECK(gpu_render_fov(&big, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &lod, &b) == FS_OK);
    int differ = 0;
    for (int c = 0; c < a.channel_count; c++)
        differ += memcmp(a.planes[c], b.planes[c], sizeof(float) * W * H) != 0;
    fprintf(stderr, "cards of 2 ring pixels: %d of %d planes differ from no ring LOD\n", differ, a.channel_count);
    CHECK(differ == 0);
    exr_image_free(&a);
    exr_image_free(&b);
    scene_free(&big);
    card_field(&small, NX, NY, 2.0f * 2.0f / W, 2.0f * 12.8f / W);
    CHECK(gpu_render_fov(&small, ALPHA_MODE_TRADITIONAL, W, H, 0.0f, &lod, &b) == FS_OK);
    double c = plane_mean(&b, "coverage"), expect = (double)NX * NY * 4.0 / ((double)W * H);
    fprintf(stderr, "cards of half a ring pixel: mean coverage %.5f, the cards' area %.5f (%+.2f %%)\n", c, expect,
            100.0 * (c / expect - 1.0));
    CHECK(fabs(c / expect - 1.0) < 0.05);
    exr_image_free(&b);
    scene_free(&small);
}

/* Mean and largest |coverage change| between consecutive frames of a gaze moving `step` pixels a
 * frame, for `frames` frames. */
static void gaze_sweep(const scene *sc, const fov_layout *l, const ring_lod_spec *lod, int w, int h, float step,
                       int frames, double *mean, double *max)
{
    exr_image prev = {0};
    *mean = *max = 0.0;
    for (int f = 0; f < frames; f++) {
        gpu_fov fv = {.layout = l, .gaze = {0.35f + (float)f * step / (float)w, 0.5f}, .ring_lod = *lod};
        exr_image img;
        CHECK(gpu_render_fov(sc, ALPHA_MODE_TRADITIONAL, w, h, 1.0f, &fv, &img) == FS_OK);
        if (f > 0) {
            const float *c = exr_image_channel(&img, "coverage"), *q = exr_image_channel(&prev, "coverage");
            for (int i = 0; i < w * h; i++) {
                double d = fabs((double)c[i] - (double)q[i]);
                *mean += d / ((double)w * h * (frames - 1));
                *max = d > *max ? d : *max;
            }
            exr_image_free(&prev);
        }
        prev = img;
    }
    exr_image_free(&prev);
}

TEST(a_slowly_moving_gaze_changes_coverage_no_faster_than_without_ring_lod)
{
    /* u is the ring's, and a card's rank never changes, so as the gaze moves a card can only pass
     * from one ring's image to the next through the composite's blend band, at the band's rate.
     * The rings' own images shift with the gaze too (their pixels are coarse), without ring LOD as
     * with it: the test holds ring LOD to that, where a card popping in or out would add whole
     * card-sized steps of coverage. */
    enum { W = 320, H = 180, FRAMES = 8 };
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    fov_layout l = gpu_layout("8:1:0,20:1/2:0,*:1/8:0", W, H);
    ring_lod_spec off = {0}, on = lod_of("simplify");
    double m0, x0, m1, x1;
    gaze_sweep(&sc, &l, &off, W, H, 0.5f, FRAMES, &m0, &x0);
    gaze_sweep(&sc, &l, &on, W, H, 0.5f, FRAMES, &m1, &x1);
    fprintf(stderr, "gaze moving 0.5 px a frame: mean |coverage change| %.5f without ring LOD, %.5f with; "
                    "largest %.3f / %.3f\n", m0, m1, x0, x1);
    CHECK(m1 <= 1.5 * m0 + 1e-4);
    scene_free(&sc);
}

TEST(only_scenes_with_card_aggregates_compile_it_and_never_the_reference)
{
    static const char *const builtins[] = {"forest", "fence", "grass"};
    for (int b = 0; b < 3; b++) {
        scene sc;
        CHECK(scene_load_builtin(builtins[b], &sc) == FS_OK);
        int prims = 0;
        uint64_t cards = 0;
        CHECK(scene_cards_count(&sc, &prims, &cards) == FS_OK);
        fov_layout l = gpu_layout("8:1:0,20:1/2:0,*:1/8:0", 320, 180);
        plan_options po = {.alpha_mode = ALPHA_MODE_HASHED, .width = 320, .height = 180, .frames = 1, .layout = l,
                           .ring_lod = lod_of("simplify")};
        plan pl, ref;
        CHECK(plan_build(&sc, &po, &pl) == FS_OK);
        po.reference = true;
        CHECK(plan_build(&sc, &po, &ref) == FS_OK);
        int variants = 0, ref_variants = 0;
        for (int i = 0; i < pl.pass_count; i++)
            for (int d = 0; d < pl.passes[i].define_count; d++)
                variants += !strncmp(pl.passes[i].defines[d], "RING_LOD", 8);
        for (int i = 0; i < ref.pass_count; i++)
            for (int d = 0; d < ref.passes[i].define_count; d++)
                ref_variants += !strncmp(ref.passes[i].defines[d], "RING_LOD", 8);
        fprintf(stderr, "%s: %d simplified primitives, %llu cards; RING_LOD in %d passes (reference: %d)\n",
                builtins[b], prims, (unsigned long long)cards, variants, ref_variants);
        CHECK(pl.ring_lod == (prims > 0));
        CHECK(variants == (prims > 0 ? 1 : 0));
        CHECK(!ref.ring_lod && ref_variants == 0);
        scene_free(&sc);
    }
}

int main(void)
{
    gpu_begin();
    RUN(a_field_of_cards_keeps_its_covered_area);
    RUN(u_one_draws_what_no_simplification_draws_bit_for_bit);
    RUN(simplification_thins_the_periphery_only_and_a_still_camera_repeats_its_frame);
    RUN(the_default_keeps_cards_of_a_ring_pixel_and_thins_smaller_ones_keeping_their_area);
    RUN(a_slowly_moving_gaze_changes_coverage_no_faster_than_without_ring_lod);
    RUN(only_scenes_with_card_aggregates_compile_it_and_never_the_reference);
    return test_summary();
}
