/* hash.c: FNV-1a 64 (see hash.h). */
#include "core/hash.h"

#include <math.h>
#include <string.h>

uint64_t hash_bytes(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

uint64_t hash_str(uint64_t h, const char *s)
{
    return hash_bytes(h, s, strlen(s) + 1);
}

uint64_t hash_u64(uint64_t h, uint64_t v)
{
    unsigned char b[8];
    for (int i = 0; i < 8; i++)
        b[i] = (unsigned char)(v >> (8 * i)); /* little-endian whatever the host */
    return hash_bytes(h, b, sizeof b);
}

uint64_t hash_floats(uint64_t h, const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        float f = v[i] == 0.0f ? 0.0f : isnan(v[i]) ? NAN : v[i];
        uint32_t u;
        memcpy(&u, &f, sizeof u);
        h = hash_u64(h, u);
    }
    return h;
}
