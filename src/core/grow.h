/* grow.h: growing an array in place (realloc by doubling), the one pattern of every growable array
 * (sample buffers, event lists, task lists, mesh builders).
 *
 * fs_grow makes room for `need` elements of `elem` bytes in *p, whose capacity is *cap elements:
 * nothing happens when *cap >= need; otherwise the capacity doubles (from FS_GROW_FIRST when it is
 * 0) until it holds `need`. On success *p and *cap are the new block and capacity. On failure
 * (out of memory, or a size that does not fit size_t) it returns false and leaves *p and *cap as
 * they were: the old block is still valid and still the caller's to free. *p may be NULL (and *cap
 * 0) for an array not allocated yet.
 *
 * fs_grow_int is the same for the arrays that count in int (capacity at most INT_MAX). The
 * FS_GROW / FS_GROW_INT macros pass the array's address and element size for it.
 */
#ifndef FOVSIM_GROW_H
#define FOVSIM_GROW_H

#include <stdbool.h>
#include <stddef.h>

#define FS_GROW_FIRST 16 /* the capacity of an array's first block */

bool fs_grow(void **p, size_t *cap, size_t need, size_t elem);
bool fs_grow_int(void **p, int *cap, int need, size_t elem);

#define FS_GROW(arr, cap, need) fs_grow((void **)&(arr), &(cap), (need), sizeof *(arr))
#define FS_GROW_INT(arr, cap, need) fs_grow_int((void **)&(arr), &(cap), (need), sizeof *(arr))

#endif
