/* cards.h: the cards of an asset's foliage, for per-ring stochastic simplification (docs/ring-lod.md; Cook,
 * Halstead, Planck & Ryu 2007, "Stochastic Simplification of Aggregate Detail"; the per-ring law is
 * src/fov/ring_lod.h).
 *
 * A card is a connected component of one primitive's triangles: two triangles belong to the same
 * card when they share a vertex index or a vertex position (bit-identical x, y, z after -0 -> +0),
 * so a leaf whose vertices were split for flat shading or UV seams (unwelded glTF, non-indexed
 * meshes) stays one card. Simplification keeps or drops whole cards, never part of one. Because a
 * card is a union of whole connected components, no vertex can belong to two cards: every vertex a
 * triangle uses gets exactly one card id. A vertex no triangle uses gets CARD_NONE.
 *
 * Per card: its centre (the area-weighted centroid of its triangles, asset space; the mean of its
 * triangles' centroids when every triangle has zero area), its area (sum of triangle areas) and its
 * rank in [0, 1). The ranks of a primitive's N cards are stratified: card i gets a rank in the stratum
 * [pi(i) / N, (pi(i) + 1) / N) of a random permutation pi, at a random place in it, both drawn from
 * a generator seeded by the primitive's index in its asset. So the ranks are stable (the same
 * primitive gives the same ranks in every build, frame, ring and run), carry no structure of the
 * index order (neighbouring cards in the file are not thinned in a pattern), and exactly one card
 * falls in each stratum: a threshold c keeps N c cards to within one, not N c +- sqrt(N c (1 - c))
 * as independent hashes would (tests/unit/test_ring_lod.c checks the consequence for coverage).
 * Ranks are multiples of 2^-RING_LOD_RANK_BITS, exact in a float, so the GLSL can rotate them per
 * instance in integers (ring_lod_rank).
 *
 * Which primitives take part: those of MASK materials (BLEND and OPAQUE never) with at least
 * RING_LOD_MIN_CARDS cards. Fewer cards is not an aggregate: a whole mesh that is one connected
 * component (the generated fence's single wire quad, a glTF bush modelled as one mesh) would be
 * all-or-nothing and enlarged by 1/sqrt(u) about its centre, so such a primitive keeps rank
 * RING_LOD_RANK_KEEP (never simplified, never scaled) and its cards are still listed.
 *
 * Cost: O(indices + vertices) time and memory (union-find with path halving over vertex indices, a
 * hash table of vertex positions, one pass over the triangles); no quadratic step.
 *
 * Usage (the renderer, per asset):
 *   asset_cards ac;
 *   if (asset_cards_build(a, &ac) == FS_OK) {
 *       for (int p = 0; p < a->prim_count; p++)
 *           if (ac.prims[p].simplified) {           // only these need the LOD shader variant
 *               float *v = malloc(sizeof(float) * 4 * a->prims[p].vertex_count);
 *               prim_cards_vertex_attrib(&ac.prims[p], &a->prims[p], v); // -> ATTR_CARD, vec4
 *               ...
 *           }
 *       asset_cards_free(&ac);
 *   }
 */
#ifndef FOVSIM_CARDS_H
#define FOVSIM_CARDS_H

#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "scene/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

#define CARD_NONE UINT32_MAX

typedef struct prim_cards {
    uint32_t vertex_count; /* the primitive's */
    uint32_t card_count;   /* 0 for a primitive without triangles */
    uint32_t *vertex_card; /* vertex_count: each vertex's card, CARD_NONE when no triangle uses it */
    uint32_t *triangles;   /* card_count: triangles of each card (zero-area ones included) */
    float *centre;         /* 3 per card: area-weighted centroid of its triangles, asset space */
    float *area;           /* card_count: sum of its triangles' areas, asset units^2 */
    float *radius;         /* card_count: farthest vertex of the card from its centre, asset units */
    float *rank;           /* card_count: stratified rank in [0, 1), a multiple of 2^-24 */
    bool simplified;       /* MASK material and card_count >= RING_LOD_MIN_CARDS: the ring LOD
                              applies; false: draw it as it is (its vertex attribute says KEEP) */
} prim_cards;

/* Cards of one primitive; prim_index (its index in the asset) seeds the ranks. `simplified` is left
 * false: asset_cards_build sets it from the material. FS_ERR_SCENE (message printed) for an index
 * out of range or an index count that is not a multiple of 3; FS_ERR_NOMEM. *out is zeroed first
 * and on failure. A primitive with index_count 0 gives 0 cards and every vertex CARD_NONE. */
fs_status prim_cards_build(const prim *p, int prim_index, prim_cards *out);
void prim_cards_free(prim_cards *c);

/* The vertex attribute the ring-LOD vertex shader reads at ATTR_CARD: 4 floats per vertex into
 * out4 (p->vertex_count * 4): the centre of the vertex's card and its rank; rank
 * RING_LOD_RANK_KEEP (-1, never scaled) for every vertex of a primitive that is not simplified and
 * for a vertex of no card (centre = its own position). Safe for any primitive: a zeroed prim_cards
 * (asset_cards' entry for a primitive that is not MASK) gives KEEP everywhere. */
void prim_cards_vertex_attrib(const prim_cards *c, const prim *p, float *out4);
/* The second attribute, at ATTR_CARD_SIDE: 1 float per vertex into out1 (p->vertex_count), the
 * side of the vertex's card, sqrt(area) in asset units (what the per-card schedule measures in
 * ring pixels); 0 for a vertex no triangle uses. */
void prim_cards_vertex_side(const prim_cards *c, const prim *p, float *out1);

/* The ranks of a primitive of n cards (prim_cards_build's, alone): rank[i] for card i. Exposed for
 * tests and for fields of identical cards built without geometry. FS_ERR_NOMEM (rank untouched). */
fs_status cards_stratified_ranks(uint32_t n, int prim_index, float *rank);

typedef struct asset_cards {
    prim_cards *prims;      /* prim_count; all-zero for primitives whose material is not MASK */
    int prim_count;
    uint32_t card_count;    /* cards of MASK primitives */
    uint32_t simplified_cards; /* cards of the primitives that are simplified */
    int simplified_prims;   /* primitives with simplified = true */
} asset_cards;

/* True when primitive `p` of the asset has a MASK material (the candidates for simplification). */
bool cards_prim_is_candidate(const asset *a, int p);
/* Cards of every MASK primitive of the asset. FS_ERR_NOMEM / FS_ERR_SCENE as prim_cards_build. */
fs_status asset_cards_build(const asset *a, asset_cards *out);
void asset_cards_free(asset_cards *c);

/* Asset-space bounds of the asset when its simplified cards are drawn up to `scale` times their size
 * about their centres (ring_lod_max_scale of the ring's law): the asset's own bounds grown to hold
 * every such card's centre +- radius * scale. A ring that simplifies must cull instances with
 * these, not asset.bounds_*, or an enlarged card near a frustum edge would vanish with its
 * instance. scale <= 1 gives the asset's bounds. */
void asset_cards_bounds(const asset *a, const asset_cards *c, float scale, vec3 *lo, vec3 *hi);

/* For `fovsim plan`: how many primitives of the scene's instanced assets would be simplified (per
 * asset), and their cards in the scene (each asset's times its instances). 0 = nothing to simplify, compile nothing new. Builds
 * and frees the cards; FS_ERR_NOMEM / FS_ERR_SCENE as above. */
fs_status scene_cards_count(const scene *sc, int *simplified_prims, uint64_t *simplified_cards);

#ifdef __cplusplus
}
#endif

#endif
