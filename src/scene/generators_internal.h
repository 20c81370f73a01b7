/* generators_internal.h: what the generator files share (internal to src/scene/; the public
 * contract is generators.h).
 *
 * generators.c builds each asset (geometry, materials, checks of the desc); gen_textures.c paints
 * its textures. Both draw from the PCG32 streams below.
 */
#ifndef FOVSIM_GENERATORS_INTERNAL_H
#define FOVSIM_GENERATORS_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "scene/scene.h"

/* >>rng */

/* PCG32 (O'Neill 2014, pcg32_random_r). */
typedef struct gen_rng {
    uint64_t state, inc;
} gen_rng;

static inline uint32_t rng_u32(gen_rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ULL + r->inc;
    uint32_t xs = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xs >> rot) | (xs << ((32u - rot) & 31u));
}

static inline gen_rng rng_make(uint32_t seed, uint64_t stream)
{
    gen_rng r = {0u, (stream << 1u) | 1u};
    rng_u32(&r);
    r.state += seed;
    rng_u32(&r);
    return r;
}

/* Uniform in [0, 1). */
static inline float rng_float(gen_rng *r) { return (float)(rng_u32(r) >> 8) * (1.0f / 16777216.0f); }
static inline float rng_range(gen_rng *r, float lo, float hi) { return lo + (hi - lo) * rng_float(r); }
static inline int rng_int(gen_rng *r, int lo, int hi) { return lo + (int)(rng_u32(r) % (uint32_t)(hi - lo + 1)); }

/* Streams: one per generator and purpose. */
enum { STREAM_TEXTURE = 1, STREAM_GEOMETRY = 2, STREAM_BARK = 3 };

/* >>textures (gen_textures.c) */

/* Each paints an RGBA8 texture `n` texels square into *img (named); false when out of memory. */
bool gen_tex_leaves(uint32_t seed, int n, image_rgba8 *img);
bool gen_tex_blades(uint32_t seed, int n, image_rgba8 *img);
bool gen_tex_wire(int n, int wire, image_rgba8 *img);
bool gen_tex_fern(uint32_t seed, int n, image_rgba8 *img);
/* 64 texels square, opaque. */
bool gen_tex_bark(uint32_t seed, image_rgba8 *img);

#endif
