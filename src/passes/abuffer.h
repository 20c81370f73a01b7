/* abuffer.h: the exact reference's resolve (docs/reference.md, "Exact"): every pixel's list of
 * semi-transparent fragments, sorted front to back and composited over the opaque colour.
 *
 * The list pass (shaders/common/abuffer.glsl) stores, for every MASK or BLEND fragment of opacity
 * alpha > 0 in front of the nearest opaque surface, its depth, its draw order, its premultiplied
 * colour and alpha. The expectation of a stochastic alpha test with depth testing is exactly
 * front-to-back "over" compositing of those fragments (Enderton et al. 2010):
 *   colour   = sum_i c_i a_i T_i + T_n base,   T_i = prod_{j<i} (1 - a_j)
 *   A        = sum_i a_i T_i + T_n base.A
 *   coverage = sum_i a_i T_i + T_n base.coverage   (a MASK fragment that passes covers the pixel)
 * Equal depths are ordered by draw order (the order a depth test with GL_LESS would keep them in),
 * then primitive: the result does not depend on the order the GPU appended the fragments in.
 *
 * Pure C, no GL: the twin of shaders/list_resolve.frag, which resolves every list of up to
 * ABUFFER_RESOLVE_MAX nodes on the GPU; the reference resolves the longer ones here (the renderer
 * reads the lists back, renderer_read_lists). Unit-tested on hand-built lists; test_reference
 * checks that the two resolves agree.
 */
#ifndef FOVSIM_ABUFFER_H
#define FOVSIM_ABUFFER_H

#include <stddef.h>
#include <stdint.h>

#include "common/shared_defs.h"

/* One stored fragment: ABUFFER_NODE_TEXELS RGBA32UI texels, in this order. */
typedef struct abuffer_node {
    uint32_t next;   /* index of the next node, ABUFFER_END; may carry ABUFFER_OVERFLOW_BIT */
    float depth;     /* window-space depth in [0, 1] */
    uint32_t order;  /* draw order of the fragment's instance (draw call base + instance) */
    uint32_t prim;   /* primitive within the draw */
    float rgb[3];    /* premultiplied: shaded colour * alpha */
    float alpha;     /* in (0, 1] */
} abuffer_node;

/* A pass's lists as read back: `head` has width * height entries (rows top first, as the images
 * fovsim writes), `nodes` the first min(count, capacity) nodes. */
typedef struct abuffer_lists {
    int width, height;
    const uint32_t *head;
    const abuffer_node *nodes;
    uint64_t count;    /* nodes the pass asked for (more than capacity: some were lost) */
    uint64_t capacity; /* nodes the store holds */
} abuffer_lists;

/* Per-pixel scratch that grows to the longest list; zero-initialise, free with abuffer_scratch_free. */
typedef struct abuffer_scratch {
    abuffer_node *items;
    size_t cap;
} abuffer_scratch;

enum { ABUFFER_PLANES = 5 }; /* R, G, B, A, coverage */

/* Composites every pixel's list over `base` (ABUFFER_PLANES planes of width * height: the opaque
 * pass's premultiplied colour, A and coverage) into `out` (the same layout; may not alias base).
 * A pixel whose list lost fragments (any pointer with ABUFFER_OVERFLOW_BIT, or a node index past
 * what was stored) gets overflowed[i] = 1 (when `overflowed` is not NULL) and is composited from
 * what was stored. Returns the number of such pixels, or -1 when the scratch cannot grow. */
long abuffer_resolve(const abuffer_lists *l, const float *const base[ABUFFER_PLANES], float *const out[ABUFFER_PLANES],
                     unsigned char *overflowed, abuffer_scratch *s);

/* One pixel (index i, rows top first) of abuffer_resolve: returns 1 when its list lost fragments,
 * 0 when not, -1 when the scratch cannot grow. */
int abuffer_resolve_pixel(const abuffer_lists *l, size_t i, const float base[ABUFFER_PLANES],
                          float out[ABUFFER_PLANES], abuffer_scratch *s);

/* Composites one pixel's fragments (any order; sorted here in place) over base[ABUFFER_PLANES]. */
void abuffer_composite(abuffer_node *frags, size_t n, const float base[ABUFFER_PLANES], float out[ABUFFER_PLANES]);

void abuffer_scratch_free(abuffer_scratch *s);

#endif
