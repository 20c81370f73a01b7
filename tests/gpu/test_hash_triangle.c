/* Hashed alpha's per-triangle layer key (common/draw_order.glsl): the forward pass reads each
 * triangle's index from its provoking vertex (ATTR_TRIANGLE) instead of gl_PrimitiveID, and the
 * upload duplicates a vertex that two triangles end on. A mesh whose two triangles per quad both
 * end on one vertex must hash exactly as the same triangles with vertices of their own. */
#include "gpu_util.h"

enum { QUADS = 8 };

/* QUADS unit quads side by side in a row (x from -4 to 4, y from -1 to 1), facing +Z, alpha 0.5
 * untextured (the hashed noise alone decides each pixel). shared: 4 vertices per quad, triangles
 * (0, 1, 2) and (3, 0, 2), both ending on vertex 2; split: the same triangles in the same order,
 * 3 vertices each. */
static asset quads_asset(bool shared)
{
    asset a = {0};
    snprintf(a.name, sizeof a.name, "quads");
    a.prim_count = a.material_count = 1;
    a.prims = calloc(1, sizeof(prim));
    a.materials = calloc(1, sizeof(material));
    a.materials[0] = (material){.base_color = {0.8f, 0.6f, 0.2f, 0.5f}, .base_color_image = -1,
                                .alpha_kind = ALPHA_KIND_MASK, .alpha_cutoff = 0.5f, .double_sided = true};
    prim *p = &a.prims[0];
    p->index_count = 6 * QUADS;
    p->vertex_count = shared ? 4 * QUADS : 6 * QUADS;
    p->positions = calloc(3 * (size_t)p->vertex_count, sizeof(float));
    p->normals = calloc(3 * (size_t)p->vertex_count, sizeof(float));
    p->uvs = calloc(2 * (size_t)p->vertex_count, sizeof(float));
    p->colors = malloc(4 * sizeof(float) * (size_t)p->vertex_count);
    p->indices = malloc(sizeof(uint32_t) * (size_t)p->index_count);
    static const uint32_t tri[6] = {0, 1, 2, 3, 0, 2};
    for (int q = 0; q < QUADS; q++) {
        float x0 = -4.0f + (float)q, x1 = x0 + 1.0f;
        const float corner[4][2] = {{x0, -1.0f}, {x1, -1.0f}, {x1, 1.0f}, {x0, 1.0f}};
        for (int k = 0; k < 6; k++) {
            uint32_t v = shared ? 4u * (uint32_t)q + tri[k] : 6u * (uint32_t)q + (uint32_t)k;
            p->indices[6 * q + k] = v;
            p->positions[3 * v] = corner[tri[k]][0];
            p->positions[3 * v + 1] = corner[tri[k]][1];
        }
    }
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        p->normals[3 * v + 2] = 1.0f;
        for (int c = 0; c < 4; c++)
            p->colors[4 * v + c] = 1.0f;
    }
    asset_compute_bounds(&a);
    return a;
}

static void quads_scene(scene *sc, bool shared)
{
    scene_init_defaults(sc);
    asset a = quads_asset(shared);
    scene_add_asset(sc, &a);
    scene_add_instance(sc, 0, m4_identity());
    sc->light.direction = v3(0, 0, -1);
    sc->camera.count = 1;
    sc->camera.keys[0] = (camera_key){.time = 0, .position = v3(0, 0, 5), .target = v3(0, 0, 0)};
}

TEST(triangles_ending_on_one_vertex_hash_as_with_vertices_of_their_own)
{
    enum { W = 240, H = 136 };
    const alpha_mode modes[2] = {ALPHA_MODE_HASHED, ALPHA_MODE_HASHED_A2C};
    for (int m = 0; m < 2; m++) {
        exr_image img[2];
        for (int s = 0; s < 2; s++) {
            scene sc;
            quads_scene(&sc, s == 0);
            CHECK(gpu_render(&sc, modes[m], W, H, 0.0f, &img[s]) == FS_OK);
            scene_free(&sc);
        }
        int differ = 0, covered = 0;
        for (int c = 0; c < img[0].channel_count; c++)
            for (int i = 0; i < W * H; i++)
                differ += memcmp(&img[0].planes[c][i], &img[1].planes[c][i], sizeof(float)) != 0;
        /* The noise really decides: the quads cover 28 % of the display, hashed keeps about half of
         * it (hashed_a2c keeps part of the samples of every pixel). */
        const float *a = exr_image_channel(&img[0], "A");
        for (int i = 0; a && i < W * H; i++)
            covered += a[i] > 0.0f;
        fprintf(stderr, "%s: %d values differ; %d of %d pixels covered\n", alpha_mode_name(modes[m]), differ,
                covered, W * H);
        CHECK(differ == 0);
        if (modes[m] == ALPHA_MODE_HASHED)
            CHECK(covered > W * H / 20 && covered < W * H / 4);
        exr_image_free(&img[0]);
        exr_image_free(&img[1]);
    }
}

int main(void)
{
    gpu_begin();
    RUN(triangles_ending_on_one_vertex_hash_as_with_vertices_of_their_own);
    gl_device_destroy();
    return test_summary();
}
