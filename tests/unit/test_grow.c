/* test_grow.c: the growable-array helper (src/core/grow.c): doubling, sizes that overflow, and a
 * failure that leaves the old block and capacity as they were. */
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/grow.h"
#include "test.h"

TEST(grow_starts_at_the_first_capacity_and_doubles)
{
    int *a = NULL;
    size_t cap = 0;
    CHECK(FS_GROW(a, cap, 1));
    CHECK(a != NULL);
    CHECK(cap == FS_GROW_FIRST);
    for (int i = 0; i < FS_GROW_FIRST; i++)
        a[i] = i;
    CHECK(FS_GROW(a, cap, FS_GROW_FIRST)); /* room already: nothing changes */
    CHECK(cap == FS_GROW_FIRST);
    CHECK(FS_GROW(a, cap, FS_GROW_FIRST + 1));
    CHECK(cap == 2 * FS_GROW_FIRST);
    CHECK(FS_GROW(a, cap, 5 * FS_GROW_FIRST)); /* doubles until it holds need */
    CHECK(cap == 8 * FS_GROW_FIRST);
    for (int i = 0; i < FS_GROW_FIRST; i++) /* the contents moved with the block */
        CHECK(a[i] == i);
    free(a);
}

TEST(grow_int_counts_in_int)
{
    double *a = NULL;
    int cap = 0;
    for (int n = 0; n < 1000; n++) {
        if (n == cap)
            CHECK(FS_GROW_INT(a, cap, n + 1));
        a[n] = n;
    }
    CHECK(cap == 1024);
    CHECK(a[999] == 999.0);
    free(a);
}

TEST(grow_refuses_a_size_that_overflows_and_keeps_the_old_block)
{
    char *a = NULL;
    size_t cap = 0;
    CHECK(FS_GROW(a, cap, 100));
    CHECK(cap == 128);
    memcpy(a, "kept", 5);
    char *old = a;
    /* need * elem does not fit size_t: refused before any allocation */
    CHECK(!fs_grow((void **)&a, &cap, SIZE_MAX / 8 + 1, 8));
    CHECK(a == old && cap == 128 && !strcmp(a, "kept"));
    /* an int capacity: a need past INT_MAX cannot be asked for; elem * need overflowing is refused */
    int icap = 16;
    void *p = a;
    CHECK(!fs_grow_int(&p, &icap, INT_MAX / 2 + 2, SIZE_MAX / 4));
    CHECK(p == old && icap == 16 && !strcmp(a, "kept"));
    free(a);
}

/* A request the allocator refuses (glibc: more than PTRDIFF_MAX bytes). Not under AddressSanitizer,
 * which stops the process on such a request instead of returning NULL. */
#if defined(__SANITIZE_ADDRESS__)
#define GROW_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define GROW_ASAN 1
#endif
#endif
TEST(grow_failure_leaves_the_old_block)
{
#ifndef GROW_ASAN
    long *a = NULL;
    size_t cap = 0;
    CHECK(FS_GROW(a, cap, 3));
    a[0] = 42;
    long *old = a;
    CHECK(!FS_GROW(a, cap, SIZE_MAX / sizeof *a / 2));
    CHECK(a == old && cap == FS_GROW_FIRST && a[0] == 42);
    free(a);
#endif
}

int main(void)
{
    RUN(grow_starts_at_the_first_capacity_and_doubles);
    RUN(grow_int_counts_in_int);
    RUN(grow_refuses_a_size_that_overflows_and_keeps_the_old_block);
    RUN(grow_failure_leaves_the_old_block);
    return test_summary();
}
