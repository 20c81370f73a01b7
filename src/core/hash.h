/* hash.h: FNV-1a 64-bit, for content keys (the reference cache). Not cryptographic: a key names
 * the inputs of a computation, and a collision would need two different scenes to meet by chance
 * (2^-64 per pair). Incremental: start with HASH_FNV_INIT and feed bytes, strings, numbers. */
#ifndef FOVSIM_HASH_H
#define FOVSIM_HASH_H

#include <stddef.h>
#include <stdint.h>

#define HASH_FNV_INIT 0xcbf29ce484222325ull

uint64_t hash_bytes(uint64_t h, const void *data, size_t n);
uint64_t hash_str(uint64_t h, const char *s); /* includes the terminating NUL, so "a","b" != "ab" */
uint64_t hash_u64(uint64_t h, uint64_t v);
/* Floats by value: -0 and +0 hash alike, every NaN hashes alike. */
uint64_t hash_floats(uint64_t h, const float *v, size_t n);

#endif
