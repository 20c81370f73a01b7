/* The stochastic test's salt and the exact reference's list order key fragments by their triangle
 * within its primitive (what gl_PrimitiveID counts), read from the flat ATTR_TRIANGLE instead
 * (common/draw_order.glsl). Two coplanar half-transparent quads in one primitive that follows
 * another primitive's triangles: their triangles must get their own salts (stochastic coverage
 * 3/4, not 1/2 as with one shared salt), the same salts as without the leading primitive (the
 * index restarts per primitive), and the exact reference must put the first drawn in front, as
 * when the quads are drawn by two draws. */
#include "gpu_util.h"
#include "reference/reference.h"

enum { LEAD_TRIS = 5, W = 64, H = 48 };

/* Appends quad q (4 vertices from vertex v0, 2 triangles (0, 1, 2) and (3, 0, 2), both ending on
 * vertex 2: the upload duplicates it) to p: 40 x 40 at z = 0 facing +Z, vertex colour rgb, alpha
 * 0.5. */
static void add_quad(prim *p, uint32_t v0, const float rgb[3])
{
    static const float corner[4][2] = {{-20, -20}, {20, -20}, {20, 20}, {-20, 20}};
    static const uint32_t tri[6] = {0, 1, 2, 3, 0, 2};
    for (uint32_t k = 0; k < 4; k++) {
        uint32_t v = v0 + k;
        p->positions[3 * v] = corner[k][0];
        p->positions[3 * v + 1] = corner[k][1];
        p->normals[3 * v + 2] = 1.0f;
        memcpy(&p->colors[4 * v], rgb, 3 * sizeof(float));
        p->colors[4 * v + 3] = 0.5f;
    }
    for (int k = 0; k < 6; k++)
        p->indices[p->index_count++] = v0 + tri[k];
}

/* A primitive of material `mat`: `count` coplanar quads, coloured red, blue from colour `first`. */
static prim quads_prim(int first, int count, int mat)
{
    static const float rgb[2][3] = {{1, 0, 0}, {0, 0, 1}};
    prim p = {.material = mat, .vertex_count = 4u * (uint32_t)count};
    p.positions = calloc(3 * (size_t)p.vertex_count, sizeof(float));
    p.normals = calloc(3 * (size_t)p.vertex_count, sizeof(float));
    p.uvs = calloc(2 * (size_t)p.vertex_count, sizeof(float));
    p.colors = calloc(4 * (size_t)p.vertex_count, sizeof(float));
    p.indices = calloc(6 * (size_t)count, sizeof(uint32_t));
    for (int q = 0; q < count; q++)
        add_quad(&p, 4u * (uint32_t)q, rgb[first + q]);
    return p;
}

/* LEAD_TRIS triangles of an opaque material that cover nothing (all corners at one point). */
static prim lead_prim(void)
{
    prim p = {.material = 0, .vertex_count = 3, .index_count = 3 * LEAD_TRIS};
    p.positions = calloc(9, sizeof(float));
    p.normals = calloc(9, sizeof(float));
    p.uvs = calloc(6, sizeof(float));
    p.colors = calloc(12, sizeof(float));
    p.indices = calloc(3 * LEAD_TRIS, sizeof(uint32_t));
    for (int i = 0; i < 3 * LEAD_TRIS; i++)
        p.indices[i] = (uint32_t)i % 3u;
    return p;
}

typedef enum { ONE_PRIM, LEAD_THEN_ONE_PRIM, TWO_PRIMS } layout_kind;

/* The quads filling the view from z = 5, lit so that the shaded colour is the albedo: in one
 * primitive, after a leading one, or one primitive per quad (two draws). */
static void quads_scene(scene *sc, layout_kind kind)
{
    scene_init_defaults(sc);
    sc->light.color = v3(0, 0, 0);
    sc->light.ambient = v3(1, 1, 1);
    asset a = {0};
    snprintf(a.name, sizeof a.name, "quads");
    a.material_count = 2;
    a.materials = calloc(2, sizeof(material));
    a.materials[0] = (material){.base_color = {1, 1, 1, 1}, .base_color_image = -1};
    a.materials[1] = (material){.base_color = {1, 1, 1, 1}, .base_color_image = -1,
                                .alpha_kind = ALPHA_KIND_MASK, .alpha_cutoff = 0.5f, .double_sided = true};
    a.prims = calloc(3, sizeof(prim));
    if (kind == LEAD_THEN_ONE_PRIM)
        a.prims[a.prim_count++] = lead_prim();
    if (kind == TWO_PRIMS) {
        a.prims[a.prim_count++] = quads_prim(0, 1, 1);
        a.prims[a.prim_count++] = quads_prim(1, 1, 1);
    } else {
        a.prims[a.prim_count++] = quads_prim(0, 2, 1);
    }
    asset_compute_bounds(&a);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 5), .target = v3(0, 0, 0)};
}

static double channel_mean(const exr_image *img, const char *ch)
{
    const float *p = exr_image_channel(img, ch);
    double m = 0;
    for (int i = 0; p && i < W * H; i++)
        m += p[i];
    return m / (W * H);
}

static int values_differing(const exr_image *a, const exr_image *b)
{
    int differ = 0;
    for (int c = 0; c < a->channel_count; c++)
        for (int i = 0; i < W * H; i++)
            differ += memcmp(&a->planes[c][i], &b->planes[c][i], sizeof(float)) != 0;
    return differ;
}

TEST(stochastic_salts_are_the_primitives_own_triangles)
{
    exr_image img[2];
    for (int k = 0; k < 2; k++) {
        scene sc;
        quads_scene(&sc, k == 0 ? ONE_PRIM : LEAD_THEN_ONE_PRIM);
        CHECK(gpu_render(&sc, ALPHA_MODE_STOCHASTIC, W, H, 0.0f, &img[k]) == FS_OK);
        scene_free(&sc);
    }
    /* Independent tests of two alpha-0.5 layers keep 3/4 of the pixels (one salt: 1/2); 3072
     * pixels give a standard error of 0.008. */
    double cov = channel_mean(&img[0], "A");
    int differ = values_differing(&img[0], &img[1]);
    fprintf(stderr, "stochastic: coverage %.4f; %d values differ after a leading primitive\n", cov, differ);
    CHECK(cov > 0.70 && cov < 0.80);
    CHECK(differ == 0);
    exr_image_free(&img[0]);
    exr_image_free(&img[1]);
}

TEST(exact_orders_coplanar_triangles_of_one_primitive_as_drawn)
{
    exr_image img[2];
    for (int k = 0; k < 2; k++) {
        scene sc;
        quads_scene(&sc, k == 0 ? LEAD_THEN_ONE_PRIM : TWO_PRIMS);
        reference_desc rd = {.width = W, .height = H, .supersample = 1, .samples = 4};
        fs_status st;
        reference *rf = reference_create(&sc, &rd, &st);
        CHECK(rf != NULL);
        frame_record fr = frame_record_at(&sc, 0, 0.0f, -1.0f, W, H);
        reference_info info;
        CHECK(rf && reference_frame(rf, &fr, &img[k], &info) == FS_OK);
        reference_destroy(rf);
        scene_free(&sc);
    }
    /* Red (drawn first) in front: R = 0.5 + 0.25 sky.r, B = 0.25 + 0.25 sky.b. */
    double r = channel_mean(&img[0], "R"), b = channel_mean(&img[0], "B");
    int differ = values_differing(&img[0], &img[1]);
    fprintf(stderr, "exact: R %.4f, B %.4f; %d values differ from two draws\n", r, b, differ);
    CHECK(r > b);
    CHECK(differ == 0);
    exr_image_free(&img[0]);
    exr_image_free(&img[1]);
}

int main(void)
{
    gpu_begin();
    RUN(stochastic_salts_are_the_primitives_own_triangles);
    RUN(exact_orders_coplanar_triangles_of_one_primitive_as_drawn);
    gl_device_destroy();
    return test_summary();
}
