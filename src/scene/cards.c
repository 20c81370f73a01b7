/* cards.c: connected components of foliage primitives and their stratified ranks (cards.h).
 *
 * Steps, each O(indices + vertices):
 *   1. mark the vertices some triangle uses (and check the indices);
 *   2. union-find over vertex indices (union by size, path halving): the three vertices of every
 *      triangle, and every used vertex with the first used vertex of bit-identical position (an
 *      open-addressing hash table of positions; -0 is taken as +0);
 *   3. card ids in the order of each component's first triangle, so the numbering depends only on
 *      the index buffer;
 *   4. one pass over the triangles for areas, area-weighted centroids (double sums) and counts;
 *   5. stratified ranks (cards_stratified_ranks).
 */
#include "scene/cards.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/shared_defs.h"
#include "core/log.h"

/* >>ranks */

static uint64_t splitmix64(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [0, bound), bound <= 2^32 (Lemire's multiply-shift; bias below 2^-32 per draw). */
static uint32_t below(uint64_t *s, uint64_t bound)
{
    return (uint32_t)(((splitmix64(s) >> 32) * bound) >> 32);
}

/* perm (n entries) is scratch. */
static void stratified_ranks(uint32_t n, int prim_index, uint32_t *perm, float *rank)
{
    uint64_t s = 0x6a09e667f3bcc909ull ^ ((uint64_t)(uint32_t)prim_index * 0x9e3779b97f4a7c15ull);
    for (uint32_t i = 0; i < n; i++)
        perm[i] = i;
    for (uint32_t i = n; i > 1; i--) { /* Fisher-Yates */
        uint32_t j = below(&s, i), t = perm[i - 1];
        perm[i - 1] = perm[j];
        perm[j] = t;
    }
    const uint64_t one = (uint64_t)1 << RING_LOD_RANK_BITS;
    for (uint32_t i = 0; i < n; i++) {
        /* floor((perm + jitter) / n * 2^24), jitter in [0, 1): inside stratum perm, below 2^24. */
        uint64_t k = ((uint64_t)perm[i] * one + below(&s, one)) / n;
        rank[i] = (float)k * (float)(1.0 / RING_LOD_RANK_ONE);
    }
}

fs_status cards_stratified_ranks(uint32_t n, int prim_index, float *rank)
{
    if (n == 0)
        return FS_OK;
    uint32_t *perm = malloc(sizeof *perm * (size_t)n);
    if (!perm)
        return FS_ERR_NOMEM;
    stratified_ranks(n, prim_index, perm, rank);
    free(perm);
    return FS_OK;
}

/* >>components */

static uint32_t uf_find(uint32_t *parent, uint32_t v)
{
    while (parent[v] != v) {
        parent[v] = parent[parent[v]]; /* path halving */
        v = parent[v];
    }
    return v;
}

static void uf_union(uint32_t *parent, uint32_t *size, uint32_t a, uint32_t b)
{
    a = uf_find(parent, a);
    b = uf_find(parent, b);
    if (a == b)
        return;
    if (size[a] < size[b]) {
        uint32_t t = a;
        a = b;
        b = t;
    }
    parent[b] = a;
    size[a] += size[b];
}

static uint32_t pos_bits(float x)
{
    if (x == 0.0f)
        x = 0.0f; /* -0 -> +0 */
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* The position's slot: murmur3's fmix64 over the three words, top bits (a table of 2^bits). */
static uint32_t pos_slot(const uint32_t b[3], int bits)
{
    uint64_t h = ((uint64_t)b[0] << 32 | b[1]) ^ ((uint64_t)b[2] * 0x9e3779b97f4a7c15ull);
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return (uint32_t)(h >> (64 - bits));
}

/* Unions every used vertex with the first used vertex at the same position. table: cap = 2^bits
 * entries (more than twice the vertices), UINT32_MAX = empty. */
static void weld_positions(const prim *p, const uint8_t *used, uint32_t *table, int bits, uint32_t *parent,
                           uint32_t *size)
{
    const uint32_t cap = (uint32_t)1 << bits;
    for (uint32_t i = 0; i < cap; i++)
        table[i] = UINT32_MAX;
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        if (!used[v])
            continue;
        const float *q = &p->positions[3 * (size_t)v];
        uint32_t b[3] = {pos_bits(q[0]), pos_bits(q[1]), pos_bits(q[2])};
        for (uint32_t h = pos_slot(b, bits);; h = (h + 1) & (cap - 1)) {
            uint32_t w = table[h];
            if (w == UINT32_MAX) {
                table[h] = v;
                break;
            }
            const float *r = &p->positions[3 * (size_t)w];
            if (pos_bits(r[0]) == b[0] && pos_bits(r[1]) == b[1] && pos_bits(r[2]) == b[2]) {
                uf_union(parent, size, v, w);
                break;
            }
        }
    }
}

/* >>build */

void prim_cards_free(prim_cards *c)
{
    if (!c)
        return;
    free(c->vertex_card);
    free(c->triangles);
    free(c->centre);
    free(c->area);
    free(c->radius);
    free(c->rank);
    memset(c, 0, sizeof *c);
}

fs_status prim_cards_build(const prim *p, int prim_index, prim_cards *out)
{
    memset(out, 0, sizeof *out);
    if (p->index_count % 3 != 0) {
        log_error("cards: primitive %d has %u indices, not a multiple of 3", prim_index, p->index_count);
        return FS_ERR_SCENE;
    }
    uint32_t nv = p->vertex_count, nt = p->index_count / 3;
    for (uint32_t i = 0; i < p->index_count; i++)
        if (p->indices[i] >= nv) {
            log_error("cards: primitive %d: index %u of %u is %u, beyond its %u vertices", prim_index, i,
                      p->index_count, p->indices[i], nv);
            return FS_ERR_SCENE;
        }
    out->vertex_count = nv;
    if (nv == 0)
        return FS_OK;
    if (nv > (1u << 30)) { /* the position table would not fit in 2^31 slots at most half full */
        log_error("cards: primitive %d has %u vertices, more than 2^30", prim_index, nv);
        return FS_ERR_NOMEM;
    }

    int bits = 1;
    while (bits < 31 && ((uint64_t)1 << bits) < 2 * (uint64_t)nv)
        bits++;
    uint32_t cap = (uint32_t)1 << bits;
    uint32_t *parent = malloc(sizeof *parent * (size_t)nv), *size = malloc(sizeof *size * (size_t)nv);
    uint32_t *table = malloc(sizeof *table * (size_t)cap);
    uint8_t *used = calloc(nv, 1);
    out->vertex_card = malloc(sizeof *out->vertex_card * (size_t)nv);
    fs_status st = FS_ERR_NOMEM;
    if (!parent || !size || !table || !used || !out->vertex_card)
        goto done;

    for (uint32_t v = 0; v < nv; v++) {
        parent[v] = v;
        size[v] = 1;
    }
    for (uint32_t i = 0; i < p->index_count; i++)
        used[p->indices[i]] = 1;
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *ix = &p->indices[3 * (size_t)t];
        uf_union(parent, size, ix[0], ix[1]);
        uf_union(parent, size, ix[0], ix[2]);
    }
    weld_positions(p, used, table, bits, parent, size);

    /* Card ids in the order of first triangles; `size` now maps a root to its card. */
    uint32_t cards = 0;
    for (uint32_t v = 0; v < nv; v++)
        size[v] = CARD_NONE;
    for (uint32_t t = 0; t < nt; t++) {
        uint32_t r = uf_find(parent, p->indices[3 * (size_t)t]);
        if (size[r] == CARD_NONE)
            size[r] = cards++;
    }
    for (uint32_t v = 0; v < nv; v++)
        out->vertex_card[v] = used[v] ? size[uf_find(parent, v)] : CARD_NONE;
    out->card_count = cards;
    if (cards == 0) {
        st = FS_OK;
        goto done;
    }

    out->triangles = calloc(cards, sizeof *out->triangles);
    out->centre = malloc(sizeof *out->centre * 3 * (size_t)cards);
    out->area = malloc(sizeof *out->area * (size_t)cards);
    out->radius = calloc(cards, sizeof *out->radius);
    out->rank = malloc(sizeof *out->rank * (size_t)cards);
    double *acc = calloc((size_t)cards * 7, sizeof *acc); /* area, area * centroid (3), centroid sum (3) */
    if (!out->triangles || !out->centre || !out->area || !out->radius || !out->rank || !acc) {
        free(acc);
        goto done;
    }
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *ix = &p->indices[3 * (size_t)t];
        const float *a = &p->positions[3 * (size_t)ix[0]], *b = &p->positions[3 * (size_t)ix[1]],
                    *c = &p->positions[3 * (size_t)ix[2]];
        double e1[3], e2[3], m[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)b[k] - (double)a[k];
            e2[k] = (double)c[k] - (double)a[k];
            m[k] = ((double)a[k] + (double)b[k] + (double)c[k]) / 3.0;
        }
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        uint32_t id = out->vertex_card[ix[0]];
        double *s = &acc[7 * (size_t)id];
        s[0] += area;
        for (int k = 0; k < 3; k++) {
            s[1 + k] += area * m[k];
            s[4 + k] += m[k];
        }
        out->triangles[id]++;
    }
    for (uint32_t i = 0; i < cards; i++) {
        const double *s = &acc[7 * (size_t)i];
        for (int k = 0; k < 3; k++)
            out->centre[3 * (size_t)i + k] =
                (float)(s[0] > 0.0 ? s[1 + k] / s[0] : s[4 + k] / (double)out->triangles[i]);
        out->area[i] = (float)s[0];
    }
    free(acc);
    for (uint32_t v = 0; v < nv; v++) {
        uint32_t id = out->vertex_card[v];
        if (id == CARD_NONE)
            continue;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) {
            double d = (double)p->positions[3 * (size_t)v + k] - (double)out->centre[3 * (size_t)id + k];
            d2 += d * d;
        }
        float r = (float)sqrt(d2);
        r = nextafterf(r, INFINITY); /* an upper bound despite the rounding of sqrt and float */
        if (r > out->radius[id])
            out->radius[id] = r;
    }
    stratified_ranks(cards, prim_index, parent, out->rank); /* parent: scratch, cards <= nv */
    st = FS_OK;

done:
    free(parent);
    free(size);
    free(table);
    free(used);
    if (st != FS_OK) {
        if (st == FS_ERR_NOMEM)
            log_error("cards: out of memory for primitive %d (%u vertices)", prim_index, nv);
        prim_cards_free(out);
    }
    return st;
}

void prim_cards_vertex_attrib(const prim_cards *c, const prim *p, float *out4)
{
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        float *o = &out4[4 * (size_t)v];
        uint32_t id = v < c->vertex_count ? c->vertex_card[v] : CARD_NONE;
        if (id == CARD_NONE) {
            memcpy(o, &p->positions[3 * (size_t)v], sizeof(float) * 3);
            o[3] = (float)RING_LOD_RANK_KEEP;
        } else {
            memcpy(o, &c->centre[3 * (size_t)id], sizeof(float) * 3);
            o[3] = c->simplified ? c->rank[id] : (float)RING_LOD_RANK_KEEP;
        }
    }
}

void prim_cards_vertex_side(const prim_cards *c, const prim *p, float *out1)
{
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        uint32_t id = v < c->vertex_count ? c->vertex_card[v] : CARD_NONE;
        out1[v] = id == CARD_NONE ? 0.0f : sqrtf(c->area[id]);
    }
}

/* >>assets */

bool cards_prim_is_candidate(const asset *a, int p)
{
    if (!a || p < 0 || p >= a->prim_count)
        return false;
    int m = a->prims[p].material;
    return m >= 0 && m < a->material_count && a->materials[m].alpha_kind == ALPHA_KIND_MASK;
}

void asset_cards_free(asset_cards *c)
{
    if (!c)
        return;
    for (int i = 0; i < c->prim_count && c->prims; i++)
        prim_cards_free(&c->prims[i]);
    free(c->prims);
    memset(c, 0, sizeof *c);
}

fs_status asset_cards_build(const asset *a, asset_cards *out)
{
    memset(out, 0, sizeof *out);
    if (a->prim_count <= 0)
        return FS_OK;
    out->prims = calloc((size_t)a->prim_count, sizeof *out->prims);
    if (!out->prims) {
        log_error("cards: out of memory for asset %s", a->name);
        return FS_ERR_NOMEM;
    }
    out->prim_count = a->prim_count;
    for (int p = 0; p < a->prim_count; p++) {
        if (!cards_prim_is_candidate(a, p))
            continue;
        prim_cards *c = &out->prims[p];
        fs_status s = prim_cards_build(&a->prims[p], p, c);
        if (s != FS_OK) {
            asset_cards_free(out);
            return s;
        }
        c->simplified = c->card_count >= RING_LOD_MIN_CARDS;
        out->card_count += c->card_count;
        if (c->simplified) {
            out->simplified_cards += c->card_count;
            out->simplified_prims++;
        }
    }
    return FS_OK;
}

void asset_cards_bounds(const asset *a, const asset_cards *c, float scale, vec3 *lo, vec3 *hi)
{
    vec3 l = a->bounds_min, h = a->bounds_max;
    for (int p = 0; scale > 1.0f && c && p < c->prim_count && p < a->prim_count; p++) {
        const prim_cards *pc = &c->prims[p];
        if (!pc->simplified)
            continue;
        for (uint32_t i = 0; i < pc->card_count; i++) {
            const float *m = &pc->centre[3 * (size_t)i];
            float r = pc->radius[i] * scale;
            l = v3(fminf(l.x, m[0] - r), fminf(l.y, m[1] - r), fminf(l.z, m[2] - r));
            h = v3(fmaxf(h.x, m[0] + r), fmaxf(h.y, m[1] + r), fmaxf(h.z, m[2] + r));
        }
    }
    *lo = l;
    *hi = h;
}

fs_status scene_cards_count(const scene *sc, int *simplified_prims, uint64_t *simplified_cards)
{
    int prims = 0;
    uint64_t cards = 0;
    int *instanced = sc->asset_count > 0 ? calloc((size_t)sc->asset_count, sizeof *instanced) : NULL;
    if (sc->asset_count > 0 && !instanced) {
        log_error("cards: out of memory");
        return FS_ERR_NOMEM;
    }
    for (int i = 0; i < sc->instance_count; i++)
        if (sc->instances[i].asset >= 0 && sc->instances[i].asset < sc->asset_count)
            instanced[sc->instances[i].asset]++;
    for (int a = 0; a < sc->asset_count; a++) {
        if (!instanced[a])
            continue;
        asset_cards ac;
        fs_status s = asset_cards_build(&sc->assets[a], &ac);
        if (s != FS_OK) {
            free(instanced);
            return s;
        }
        prims += ac.simplified_prims;
        cards += (uint64_t)ac.simplified_cards * (uint64_t)instanced[a];
        asset_cards_free(&ac);
    }
    free(instanced);
    if (simplified_prims)
        *simplified_prims = prims;
    if (simplified_cards)
        *simplified_cards = cards;
    return FS_OK;
}
