// ring_lod.glsl: per-ring stochastic simplification of foliage cards (docs/ring-lod.md; Cook et al. 2007).
// C twin: src/fov/ring_lod.c (declared in src/fov/ring_lod.h, which documents the law); both
// evaluate the same float operations in the same order. The law's (a, k, gain) is computed per ring
// on the CPU (ring_lod_law_for) and comes in as one vec3; cards and ranks: src/scene/cards.h.
// tests/gpu/test_ring_lod_twin.c compares the twins.
//
// Use in a vertex shader (before anything reads the position):
//   layout(location = ATTR_CARD) in vec4 a_card;   // card centre (asset space), rank
//   uniform vec3 u_ring_lod;                       // ring_lod_law of the ring drawn
//   uniform uint u_ring_lod_instance;              // the draw's first instance slot in the scene
//   vec3 p = ring_lod_apply(a_position, vec4(a_card.xyz,
//                           ring_lod_rank(a_card.w, u_ring_lod_instance + uint(gl_InstanceID))), u_ring_lod);
#ifndef FOVSIM_RING_LOD_GLSL
#define FOVSIM_RING_LOD_GLSL

#include "common/shared_defs.h"

// C twin: ring_lod_instance_offset. lowbias32 of the key, top 24 bits.
uint ring_lod_instance_offset(uint key)
{
    uint x = key ^ RING_LOD_INSTANCE_SEED;
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x >> (32 - RING_LOD_RANK_BITS);
}

// C twin: ring_lod_rank. The card's rank rotated per instance, mod 1 in 24-bit integers (exact);
// a value outside [0, 1) (RING_LOD_RANK_KEEP) is returned unchanged.
float ring_lod_rank(float card_rank, uint instance_key)
{
    if (!(card_rank >= 0.0 && card_rank < 1.0))
        return card_rank;
    uint k = uint(card_rank * float(RING_LOD_RANK_ONE)) + ring_lod_instance_offset(instance_key);
    return float(k & RING_LOD_RANK_MASK) * float(1.0 / RING_LOD_RANK_ONE);
}

// C twin: ring_lod_weight. g = clamp(1 - k (rank - a), 0, 1); 1 for a rank below 0.
// The law (a, k, gain) of keep fraction u (ring_lod_law_for): the identity for u >= 1; E[g] = u
// by construction, so gain = 1 / u.
vec3 ring_lod_law_for(float u)
{
    if (!(u > 0.0) || u >= 1.0)
        return vec3(1.0, 0.0, 1.0);
    const float B = float(RING_LOD_BAND), us = 1.0 / (1.0 + 0.5 * float(RING_LOD_BAND));
    float uu = max(u, float(RING_LOD_U_FLOOR));
    precise float a, k;
    if (uu <= us) {
        a = uu * (1.0 - 0.5 * B);
        k = 1.0 / (B * uu);
    } else {
        a = 1.0 - B * us;
        precise float w = 1.0 - a;
        k = 2.0 * (1.0 - uu) / (w * w);
    }
    return vec3(a, k, 1.0 / uu);
}

// The default schedule's keep fraction of a card whose side spans `side_px` ring pixels.
float ring_lod_card_u(float side_px)
{
    precise float area = side_px * side_px;
    return clamp(area / float(RING_LOD_AREA_REF), float(RING_LOD_U_MIN), 1.0);
}

float ring_lod_weight(float rank, vec3 law)
{
    if (rank < 0.0)
        return 1.0;
    precise float t = rank - law.x;
    t = law.y * t;
    precise float g = 1.0 - t;
    return clamp(g, 0.0, 1.0);
}

// C twin: ring_lod_scale. The card's linear scale about its centre, sqrt(g gain).
float ring_lod_scale(float rank, vec3 law)
{
    if (rank < 0.0)
        return 1.0;
    precise float a = ring_lod_weight(rank, law) * law.z;
    return sqrt(a);
}

// C twin: ring_lod_apply. The vertex p of a card (centre card.xyz, rank card.w): p itself when the
// scale is 1, else centre + (p - centre) * scale (scale 0: every vertex on the centre, a card with
// zero area that rasterises nothing).
vec3 ring_lod_apply(vec3 p, vec4 card, vec3 law)
{
    float s = ring_lod_scale(card.w, law);
    if (s == 1.0)
        return p;
    precise vec3 d = p - card.xyz;
    d = d * s;
    precise vec3 q = card.xyz + d;
    return q;
}

#endif
