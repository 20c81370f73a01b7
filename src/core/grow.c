/* grow.c: growing an array in place (grow.h). */
#include "core/grow.h"

#include <limits.h>
#include <stdint.h>
#include <stdlib.h>

/* fs_grow with the capacity bounded by max_cap elements: doubling stops there. */
static bool grow(void **p, size_t *cap, size_t need, size_t elem, size_t max_cap)
{
    if (need <= *cap)
        return true;
    if (elem == 0 || need > max_cap || need > SIZE_MAX / elem)
        return false;
    size_t ncap = *cap ? *cap : FS_GROW_FIRST;
    while (ncap < need)
        ncap = ncap > max_cap / 2 ? max_cap : ncap * 2;
    if (ncap > max_cap)
        ncap = max_cap;
    if (ncap > SIZE_MAX / elem) /* doubling overshot: exactly what is needed still fits */
        ncap = need;
    void *grown = realloc(*p, ncap * elem);
    if (!grown)
        return false;
    *p = grown;
    *cap = ncap;
    return true;
}

bool fs_grow(void **p, size_t *cap, size_t need, size_t elem)
{
    return grow(p, cap, need, elem, SIZE_MAX);
}

bool fs_grow_int(void **p, int *cap, int need, size_t elem)
{
    if (need <= *cap)
        return true;
    if (*cap < 0)
        return false;
    size_t c = (size_t)*cap;
    if (!grow(p, &c, (size_t)need, elem, INT_MAX))
        return false;
    *cap = (int)c;
    return true;
}
