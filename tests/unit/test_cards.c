/* Unit tests of foliage cards (src/scene/cards.c): components through shared indices and shared
 * positions, centres and areas, degenerate input (no indices, zero-area triangles, unused vertices,
 * bad indices), stratified and stable ranks, the vertex attribute, and the generated foliage. */
#include <stdint.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"
#include "fov/ring_lod.h"
#include "scene/cards.h"
#include "scene/generators.h"
#include "test.h"

/* >>helpers: a prim built from quads */

typedef struct quads {
    float pos[3 * 64];
    uint32_t idx[6 * 32 + 12];
    float nrm[3 * 64], uv[2 * 64], col[4 * 64];
    prim p;
} quads;

static void quads_init(quads *q)
{
    memset(q, 0, sizeof *q);
    q->p.positions = q->pos;
    q->p.normals = q->nrm;
    q->p.uvs = q->uv;
    q->p.colors = q->col;
    q->p.indices = q->idx;
}

static uint32_t add_vertex(quads *q, float x, float y, float z)
{
    uint32_t v = q->p.vertex_count++;
    q->pos[3 * v] = x, q->pos[3 * v + 1] = y, q->pos[3 * v + 2] = z;
    return v;
}

static void add_tri(quads *q, uint32_t a, uint32_t b, uint32_t c)
{
    q->idx[q->p.index_count++] = a;
    q->idx[q->p.index_count++] = b;
    q->idx[q->p.index_count++] = c;
}

/* An axis-aligned w x h quad in the z = z0 plane with its lower-left corner at (x, y). */
static void add_quad(quads *q, float x, float y, float w, float h, float z0)
{
    uint32_t a = add_vertex(q, x, y, z0), b = add_vertex(q, x + w, y, z0), c = add_vertex(q, x + w, y + h, z0),
             d = add_vertex(q, x, y + h, z0);
    add_tri(q, a, b, c);
    add_tri(q, a, c, d);
}

/* >>components */

TEST(separate_quads_are_separate_cards)
{
    quads q;
    quads_init(&q);
    for (int i = 0; i < 5; i++)
        add_quad(&q, 3.0f * (float)i, 1.0f, 1.0f + (float)i, 2.0f, 0.5f * (float)i);
    prim_cards c;
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 5);
    for (uint32_t i = 0; i < c.card_count && i < 5; i++) {
        float w = 1.0f + (float)i;
        CHECK_NEAR(c.area[i], 2.0 * w, 1e-5);
        CHECK_NEAR(c.centre[3 * i], 3.0 * i + 0.5 * w, 1e-5);
        CHECK_NEAR(c.centre[3 * i + 1], 2.0, 1e-6);
        CHECK_NEAR(c.centre[3 * i + 2], 0.5 * i, 1e-6);
        CHECK(c.triangles[i] == 2);
        double half_diag = 0.5 * sqrt((double)w * w + 4.0);
        CHECK(c.radius[i] >= half_diag && c.radius[i] <= half_diag * (1.0 + 1e-6));
        for (int k = 0; k < 4; k++) /* numbered in the order of their first triangle */
            CHECK(c.vertex_card[4 * i + (uint32_t)k] == i);
        CHECK(c.rank[i] >= 0.0f && c.rank[i] < 1.0f);
    }
    CHECK(!c.simplified); /* prim_cards_build leaves it to asset_cards_build */
    prim_cards_free(&c);
    CHECK(c.card_count == 0 && c.rank == NULL);
}

TEST(quads_sharing_an_edge_are_one_card)
{
    /* Shared indices: 6 vertices, two unit-height quads of widths 1 and 3 side by side. */
    quads q;
    quads_init(&q);
    uint32_t v[6];
    const float xs[3] = {0.0f, 1.0f, 4.0f};
    for (int i = 0; i < 3; i++) {
        v[i] = add_vertex(&q, xs[i], 0.0f, 0.0f);
        v[3 + i] = add_vertex(&q, xs[i], 1.0f, 0.0f);
    }
    add_tri(&q, v[0], v[1], v[4]);
    add_tri(&q, v[0], v[4], v[3]);
    add_tri(&q, v[1], v[2], v[5]);
    add_tri(&q, v[1], v[5], v[4]);
    prim_cards c;
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 1);
    CHECK_NEAR(c.area[0], 4.0, 1e-6);
    CHECK_NEAR(c.centre[0], (1.0 * 0.5 + 3.0 * 2.5) / 4.0, 1e-6); /* area-weighted, not the vertex mean */
    CHECK_NEAR(c.centre[1], 0.5, 1e-6);
    CHECK(c.triangles[0] == 4);
    prim_cards_free(&c);

    /* The same two quads unwelded (each with its own 4 vertices, the shared edge duplicated), and
     * flat-shaded triangles with 3 vertices each: still one card (shared positions). */
    quads_init(&q);
    add_quad(&q, 0.0f, 0.0f, 1.0f, 1.0f, 0.0f);
    add_quad(&q, 1.0f, 0.0f, 3.0f, 1.0f, 0.0f);
    add_quad(&q, 10.0f, 0.0f, 1.0f, 1.0f, 0.0f); /* and a separate one */
    uint32_t a = add_vertex(&q, 20, 0, 0), b = add_vertex(&q, 21, 0, 0), d = add_vertex(&q, 21, 1, 0);
    uint32_t e = add_vertex(&q, 20, 0, 0), f = add_vertex(&q, 21, 1, -0.0f), g = add_vertex(&q, 20, 1, 0);
    (void)b;
    add_tri(&q, a, b, d);
    add_tri(&q, e, f, g); /* -0 and +0 are the same position */
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 3);
    CHECK_NEAR(c.area[0], 4.0, 1e-6);
    CHECK_NEAR(c.area[1], 1.0, 1e-6);
    CHECK_NEAR(c.area[2], 1.0, 1e-6);
    CHECK_NEAR(c.centre[6], 20.5, 1e-6);
    CHECK(c.vertex_card[a] == 2 && c.vertex_card[g] == 2);
    prim_cards_free(&c);
}

TEST(a_connected_mesh_is_one_card)
{
    /* A 4 x 4 grid of quads sharing vertices: all-or-nothing (one card). */
    quads q;
    quads_init(&q);
    for (int y = 0; y <= 4; y++)
        for (int x = 0; x <= 4; x++)
            add_vertex(&q, (float)x, (float)y, 0.0f);
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            uint32_t v = (uint32_t)(5 * y + x);
            add_tri(&q, v, v + 1, v + 6);
            add_tri(&q, v, v + 6, v + 5);
        }
    prim_cards c;
    CHECK(prim_cards_build(&q.p, 3, &c) == FS_OK);
    CHECK(c.card_count == 1);
    CHECK_NEAR(c.area[0], 16.0, 1e-5);
    CHECK_NEAR(c.centre[0], 2.0, 1e-6);
    CHECK_NEAR(c.centre[1], 2.0, 1e-6);
    prim_cards_free(&c);
}

/* >>degenerate input */

TEST(degenerate_input_is_handled)
{
    quads q;
    quads_init(&q);
    prim_cards c;
    /* No vertices, no indices. */
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 0 && c.vertex_count == 0);
    prim_cards_free(&c);

    /* Vertices but index_count 0: no cards, every vertex CARD_NONE, the attribute says KEEP. */
    add_vertex(&q, 1, 2, 3);
    add_vertex(&q, 4, 5, 6);
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 0 && c.vertex_card[0] == CARD_NONE && c.vertex_card[1] == CARD_NONE);
    float attr[4 * 64];
    prim_cards_vertex_attrib(&c, &q.p, attr);
    CHECK(attr[0] == 1.0f && attr[1] == 2.0f && attr[2] == 3.0f && attr[3] == (float)RING_LOD_RANK_KEEP);
    CHECK(attr[7] == (float)RING_LOD_RANK_KEEP);
    prim_cards_free(&c);

    /* Zero-area triangles: a card of area 0 whose centre is the mean of its triangles' centroids;
     * a quad with a repeated index; an unused vertex in between. */
    quads_init(&q);
    uint32_t a = add_vertex(&q, 0, 0, 0), b = add_vertex(&q, 3, 0, 0), c3 = add_vertex(&q, 6, 0, 0);
    add_vertex(&q, 100, 100, 100); /* unused */
    add_tri(&q, a, b, c3);         /* collinear */
    add_tri(&q, a, a, b);          /* repeated vertex */
    add_quad(&q, 10, 0, 2, 2, 0);
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_OK);
    CHECK(c.card_count == 2);
    CHECK(c.area[0] == 0.0f);
    CHECK_NEAR(c.centre[0], (3.0 + 1.0) / 2.0, 1e-6); /* centroids 3 and 1 */
    CHECK(c.centre[1] == 0.0f && c.centre[2] == 0.0f);
    CHECK(c.triangles[0] == 2);
    CHECK(c.vertex_card[3] == CARD_NONE);
    CHECK_NEAR(c.area[1], 4.0, 1e-6);
    CHECK_NEAR(c.centre[3], 11.0, 1e-6);
    prim_cards_free(&c);

    /* Bad input: an index out of range, an index count that is not a multiple of 3. */
    log_set_quiet_errors(true);
    quads_init(&q);
    add_quad(&q, 0, 0, 1, 1, 0);
    q.idx[4] = 4;
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_ERR_SCENE);
    CHECK(c.card_count == 0 && c.vertex_card == NULL);
    q.idx[4] = 2;
    q.p.index_count = 5;
    CHECK(prim_cards_build(&q.p, 0, &c) == FS_ERR_SCENE);
    log_set_quiet_errors(false);
    prim_cards_free(&c); /* zeroed: a no-op */
}

/* >>ranks */

TEST(ranks_are_stratified_stable_and_exact)
{
    enum { N = 1000 };
    static float r1[N], r2[N], r3[N];
    CHECK(cards_stratified_ranks(N, 2, r1) == FS_OK);
    CHECK(cards_stratified_ranks(N, 2, r2) == FS_OK);
    CHECK(cards_stratified_ranks(N, 3, r3) == FS_OK);
    CHECK(memcmp(r1, r2, sizeof r1) == 0); /* the same primitive: the same ranks */
    static int stratum[N];
    memset(stratum, 0, sizeof stratum);
    int same = 0;
    for (int i = 0; i < N; i++) {
        CHECK(r1[i] >= 0.0f && r1[i] < 1.0f);
        double k = (double)r1[i] * RING_LOD_RANK_ONE; /* a multiple of 2^-24 */
        CHECK(k == (double)(uint32_t)k);
        int s = (int)((double)r1[i] * N);
        if (s >= 0 && s < N)
            stratum[s]++;
        same += r1[i] == r3[i];
    }
    for (int s = 0; s < N; s++) /* exactly one card per stratum [s/N, (s+1)/N) */
        CHECK(stratum[s] == 1);
    CHECK(same < 10); /* another primitive, other ranks */
    /* No index-order structure: the ranks of consecutive cards are not correlated (|rho| below 4
     * standard errors of 1/sqrt(N)). */
    double sxy = 0.0;
    for (int i = 0; i + 1 < N; i++)
        sxy += ((double)r1[i] - 0.5) * ((double)r1[i + 1] - 0.5);
    double rho = sxy / (N - 1) / (1.0 / 12.0);
    CHECK(fabs(rho) < 4.0 / sqrt((double)N));
}

TEST(ranks_of_the_same_prim_match_across_builds)
{
    gen_tree_desc d = {.seed = 5};
    asset a1, a2;
    CHECK(gen_tree(&d, &a1) == FS_OK);
    CHECK(gen_tree(&d, &a2) == FS_OK);
    asset_cards c1, c2;
    CHECK(asset_cards_build(&a1, &c1) == FS_OK);
    CHECK(asset_cards_build(&a2, &c2) == FS_OK);
    CHECK(c1.card_count == c2.card_count && c1.card_count > 0);
    if (c1.card_count == c2.card_count && c1.card_count > 0) {
        CHECK(memcmp(c1.prims[0].rank, c2.prims[0].rank, sizeof(float) * c1.prims[0].card_count) == 0);
        CHECK(memcmp(c1.prims[0].centre, c2.prims[0].centre, sizeof(float) * 3 * c1.prims[0].card_count) == 0);
    }
    asset_cards_free(&c1);
    asset_cards_free(&c2);
    asset_free(&a1);
    asset_free(&a2);
}

/* >>assets */

/* Every triangle's vertices share a card and the attribute carries that card's centre and rank. */
static void check_attrib(const asset *a, const asset_cards *ac)
{
    for (int p = 0; p < a->prim_count; p++) {
        const prim *pr = &a->prims[p];
        const prim_cards *c = &ac->prims[p];
        if (!cards_prim_is_candidate(a, p)) {
            CHECK(c->card_count == 0 && c->vertex_card == NULL && !c->simplified);
            continue;
        }
        float *attr = malloc(sizeof(float) * 4 * pr->vertex_count);
        CHECK(attr != NULL);
        if (!attr)
            return;
        prim_cards_vertex_attrib(c, pr, attr);
        int bad = 0;
        for (uint32_t t = 0; t < pr->index_count; t += 3) {
            uint32_t id = c->vertex_card[pr->indices[t]];
            bad += id >= c->card_count || c->vertex_card[pr->indices[t + 1]] != id ||
                   c->vertex_card[pr->indices[t + 2]] != id;
            for (int k = 0; k < 3 && id < c->card_count; k++) {
                const float *v = &attr[4 * (size_t)pr->indices[t + (uint32_t)k]];
                bad += memcmp(v, &c->centre[3 * (size_t)id], sizeof(float) * 3) != 0;
                bad += v[3] != (c->simplified ? c->rank[id] : (float)RING_LOD_RANK_KEEP);
            }
        }
        CHECK(bad == 0);
        free(attr);
    }
}

TEST(generated_foliage_cards)
{
    asset a;
    asset_cards ac;
    /* Tree: every leaf quad is a card (2 or 3 crossed quads per cluster, each its own); the
     * trunk is opaque, not a candidate. */
    gen_tree_desc td = {.seed = 3, .card_count = 90};
    CHECK(gen_tree(&td, &a) == FS_OK);
    CHECK(asset_cards_build(&a, &ac) == FS_OK);
    CHECK(ac.prims[0].card_count == a.prims[0].index_count / 6);
    CHECK(ac.prims[0].card_count >= 180 && ac.prims[0].card_count <= 270);
    CHECK(ac.prims[0].simplified && ac.simplified_prims == 1 && ac.prims[1].card_count == 0);
    for (uint32_t i = 0; i < ac.prims[0].card_count; i++)
        CHECK(ac.prims[0].area[i] >= 1.0403f && ac.prims[0].area[i] <= 1.9045f); /* (1.2 * [0.85, 1.15])^2 */
    check_attrib(&a, &ac);
    asset_cards_free(&ac);
    asset_free(&a);

    /* Grass: 2 crossed quads per tuft. */
    gen_grass_desc gd = {.card_count = 143};
    CHECK(gen_grass(&gd, &a) == FS_OK);
    CHECK(asset_cards_build(&a, &ac) == FS_OK);
    CHECK(ac.prims[0].card_count == 286 && ac.prims[0].simplified);
    check_attrib(&a, &ac);
    asset_cards_free(&ac);
    asset_free(&a);

    /* Fence: its wire is one quad, one card: kept whole, never simplified. */
    CHECK(gen_fence(&(gen_fence_desc){0}, &a) == FS_OK);
    CHECK(asset_cards_build(&a, &ac) == FS_OK);
    CHECK(ac.prims[0].card_count == 1 && !ac.prims[0].simplified && ac.simplified_prims == 0);
    CHECK(ac.card_count == 1 && ac.simplified_cards == 0);
    check_attrib(&a, &ac);
    asset_cards_free(&ac);
    asset_free(&a);

    /* Fern: 8 fronds, each an arched strip (one card): fewer than RING_LOD_MIN_CARDS. */
    CHECK(gen_fern(&(gen_fern_desc){0}, &a) == FS_OK);
    CHECK(asset_cards_build(&a, &ac) == FS_OK);
    CHECK(ac.prims[0].card_count == 8 && !ac.prims[0].simplified);
    check_attrib(&a, &ac);
    asset_cards_free(&ac);
    asset_free(&a);
}

TEST(bounds_hold_the_enlarged_cards)
{
    gen_tree_desc td = {.seed = 9, .card_count = 40};
    asset a;
    asset_cards ac;
    CHECK(gen_tree(&td, &a) == FS_OK);
    CHECK(asset_cards_build(&a, &ac) == FS_OK);
    vec3 lo, hi;
    asset_cards_bounds(&a, &ac, 1.0f, &lo, &hi); /* scale 1: the asset's own */
    CHECK(memcmp(&lo, &a.bounds_min, sizeof lo) == 0 && memcmp(&hi, &a.bounds_max, sizeof hi) == 0);
    const float us[3] = {0.25f, 1.0f / 16.0f, (float)RING_LOD_U_FLOOR};
    for (int i = 0; i < 3; i++) {
        ring_lod_law l = ring_lod_law_for(us[i]);
        asset_cards_bounds(&a, &ac, ring_lod_max_scale(&l), &lo, &hi);
        CHECK(hi.y - lo.y > a.bounds_max.y - a.bounds_min.y); /* enlarged leaves stick out */
        const prim *p = &a.prims[0];
        float *attr = malloc(sizeof(float) * 4 * p->vertex_count);
        if (!attr)
            break;
        prim_cards_vertex_attrib(&ac.prims[0], p, attr);
        int outside = 0;
        for (uint32_t v = 0; v < p->vertex_count; v++)
            for (uint32_t key = 0; key < 8; key++) { /* every instance rotation: the kept cards differ */
                float card[4] = {attr[4 * v], attr[4 * v + 1], attr[4 * v + 2], ring_lod_rank(attr[4 * v + 3], key)};
                vec3 q = ring_lod_apply(&l, v3(p->positions[3 * v], p->positions[3 * v + 1], p->positions[3 * v + 2]),
                                        card);
                outside += q.x < lo.x || q.y < lo.y || q.z < lo.z || q.x > hi.x || q.y > hi.y || q.z > hi.z;
            }
        CHECK(outside == 0);
        free(attr);
    }
    asset_cards_free(&ac);
    asset_free(&a);
}

TEST(scene_counts_for_the_plan)
{
    scene sc;
    CHECK(scene_load_builtin("forest", &sc) == FS_OK);
    int prims = -1;
    uint64_t cards = 0;
    CHECK(scene_cards_count(&sc, &prims, &cards) == FS_OK);
    CHECK(prims == 2);                /* the trees' leaves and the grass blades */
    CHECK(cards == 226 * 17 + 286 * 49); /* each asset's cards times its instances (17 trees, 49 tufts) */
    scene_free(&sc);
    CHECK(scene_load_builtin("fence", &sc) == FS_OK);
    CHECK(scene_cards_count(&sc, &prims, &cards) == FS_OK);
    CHECK(prims == 0 && cards == 0); /* nothing to simplify: the plan compiles nothing new */
    scene_free(&sc);
}

int main(void)
{
    RUN(separate_quads_are_separate_cards);
    RUN(quads_sharing_an_edge_are_one_card);
    RUN(a_connected_mesh_is_one_card);
    RUN(degenerate_input_is_handled);
    RUN(ranks_are_stratified_stable_and_exact);
    RUN(ranks_of_the_same_prim_match_across_builds);
    RUN(generated_foliage_cards);
    RUN(bounds_hold_the_enlarged_cards);
    RUN(scene_counts_for_the_plan);
    return test_summary();
}
