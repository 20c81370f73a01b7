/* abuffer.c: the exact reference's resolve (see abuffer.h). */
#include "passes/abuffer.h"

#include <math.h>
#include <stdlib.h>

#include "core/grow.h"

_Static_assert(sizeof(abuffer_node) == 16 * ABUFFER_NODE_TEXELS, "abuffer_node is the list pass's RGBA32UI texels");

/* Front to back: depth, then draw order, then primitive (a total order on what the list pass can
 * store twice at one pixel, so the result does not depend on the order fragments were appended). */
static int node_before(const abuffer_node *a, const abuffer_node *b)
{
    if (a->depth != b->depth)
        return a->depth < b->depth;
    if (a->order != b->order)
        return a->order < b->order;
    return a->prim < b->prim;
}

static int cmp_node(const void *pa, const void *pb)
{
    const abuffer_node *a = pa, *b = pb;
    return node_before(a, b) ? -1 : node_before(b, a) ? 1 : 0;
}

static void sort_nodes(abuffer_node *f, size_t n)
{
    if (n > 24) {
        qsort(f, n, sizeof *f, cmp_node);
        return;
    }
    for (size_t i = 1; i < n; i++) { /* insertion sort: lists are short */
        abuffer_node x = f[i];
        size_t j = i;
        for (; j > 0 && node_before(&x, &f[j - 1]); j--)
            f[j] = f[j - 1];
        f[j] = x;
    }
}

void abuffer_composite(abuffer_node *frags, size_t n, const float base[ABUFFER_PLANES], float out[ABUFFER_PLANES])
{
    sort_nodes(frags, n);
    double c[3] = {0, 0, 0}, a = 0.0, t = 1.0; /* t: transmittance of what lies in front */
    for (size_t i = 0; i < n && t > 0.0; i++) {
        double al = frags[i].alpha;
        const float *rgb = frags[i].rgb;
        /* Alpha 0 (or NaN) is never kept by a stochastic test, and a non-finite colour must not
         * poison the truth: such a fragment hides nothing. */
        if (!(al > 0.0) || !isfinite(rgb[0]) || !isfinite(rgb[1]) || !isfinite(rgb[2]))
            continue;
        al = al < 1.0 ? al : 1.0;
        for (int k = 0; k < 3; k++)
            c[k] += t * rgb[k];
        a += t * al;
        t *= 1.0 - al;
    }
    for (int k = 0; k < 3; k++)
        out[k] = (float)(c[k] + t * base[k]);
    out[3] = (float)(a + t * base[3]);
    out[4] = (float)(a + t * base[4]); /* every stored fragment is alpha-mapped: it covers by its alpha */
}

int abuffer_resolve_pixel(const abuffer_lists *l, size_t i, const float base[ABUFFER_PLANES],
                          float out[ABUFFER_PLANES], abuffer_scratch *s)
{
    uint64_t stored = l->count < l->capacity ? l->count : l->capacity;
    size_t n = 0;
    int over = 0;
    uint32_t p = l->head[i];
    /* Walk the list; more steps than nodes stored means a cycle (corrupt data): stop. */
    for (uint64_t steps = 0; steps <= stored; steps++) {
        over |= (p & ABUFFER_OVERFLOW_BIT) != 0;
        p &= ~ABUFFER_OVERFLOW_BIT;
        if (p == ABUFFER_END)
            break;
        if (p >= stored) { /* a node that was never written */
            over = 1;
            break;
        }
        if (!FS_GROW(s->items, s->cap, n + 1))
            return -1;
        s->items[n++] = l->nodes[p];
        p = l->nodes[p].next;
    }
    abuffer_composite(s->items, n, base, out);
    return over;
}

long abuffer_resolve(const abuffer_lists *l, const float *const base[ABUFFER_PLANES], float *const out[ABUFFER_PLANES],
                     unsigned char *overflowed, abuffer_scratch *s)
{
    size_t npix = (size_t)l->width * (size_t)l->height;
    long lost = 0;
    for (size_t i = 0; i < npix; i++) {
        float b[ABUFFER_PLANES], o[ABUFFER_PLANES];
        for (int k = 0; k < ABUFFER_PLANES; k++)
            b[k] = base[k][i];
        int over = abuffer_resolve_pixel(l, i, b, o, s);
        if (over < 0)
            return -1;
        for (int k = 0; k < ABUFFER_PLANES; k++)
            out[k][i] = o[k];
        if (overflowed)
            overflowed[i] = (unsigned char)over;
        lost += over;
    }
    return lost;
}

void abuffer_scratch_free(abuffer_scratch *s)
{
    free(s->items);
    s->items = NULL;
    s->cap = 0;
}
