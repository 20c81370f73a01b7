/* test.h: the minimal test harness of fovsim's C tests (header only).
 *
 * Usage:
 *   TEST(parses_numbers) { CHECK(x == 1); CHECK_NEAR(y, 0.5, 1e-6); }
 *   int main(void) { RUN(parses_numbers); return test_summary(); }
 * A failed CHECK prints file:line and the expression and marks the current test failed (the test
 * goes on). test_summary prints "N passed, N failed" and returns the exit status for ctest.
 * test_shared_path("assets/x.gltf") resolves a file of ../shared (FOVSIM_SHARED from CMake).
 */
#ifndef FOVSIM_TEST_H
#define FOVSIM_TEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int test_passed_, test_failed_, test_cur_failed_;
static const char *test_cur_name_;

#define TEST(name) static void name(void)

#define CHECK(c)                                                                          \
    do {                                                                                  \
        if (!(c)) {                                                                       \
            fprintf(stderr, "%s:%d: %s: CHECK failed: %s\n", __FILE__, __LINE__,          \
                    test_cur_name_, #c);                                                  \
            test_cur_failed_ = 1;                                                         \
        }                                                                                 \
    } while (0)

#define CHECK_NEAR(a, b, eps)                                                             \
    do {                                                                                  \
        double a_ = (double)(a), b_ = (double)(b);                                        \
        if (!(fabs(a_ - b_) <= (double)(eps))) {                                          \
            fprintf(stderr, "%s:%d: %s: CHECK_NEAR failed: %s = %.9g, %s = %.9g, eps %g\n",  \
                    __FILE__, __LINE__, test_cur_name_, #a, a_, #b, b_, (double)(eps));   \
            test_cur_failed_ = 1;                                                         \
        }                                                                                 \
    } while (0)

#define RUN(name)                                                                         \
    do {                                                                                  \
        test_cur_name_ = #name;                                                           \
        test_cur_failed_ = 0;                                                             \
        name();                                                                           \
        if (test_cur_failed_) {                                                           \
            test_failed_++;                                                               \
            fprintf(stderr, "FAIL %s\n", #name);                                          \
        } else {                                                                          \
            test_passed_++;                                                               \
            fprintf(stderr, "ok   %s\n", #name);                                          \
        }                                                                                 \
    } while (0)

static inline int test_summary(void)
{
    printf("%d passed, %d failed\n", test_passed_, test_failed_);
    return test_failed_ ? 1 : 0;
}

/* Path of a file under ../shared (env FOVSIM_SHARED, set by CMake). Static buffer, rotating. */
static inline const char *test_shared_path(const char *rel)
{
    static char buf[4][1024];
    static int k;
    const char *root = getenv("FOVSIM_SHARED");
    k = (k + 1) & 3;
    snprintf(buf[k], sizeof buf[k], "%s/%s", root ? root : "../shared", rel);
    return buf[k];
}

/* Path of a file under the source tree (env FOVSIM_SOURCE). */
static inline const char *test_source_path(const char *rel)
{
    static char buf[4][1024];
    static int k;
    const char *root = getenv("FOVSIM_SOURCE");
    k = (k + 1) & 3;
    snprintf(buf[k], sizeof buf[k], "%s/%s", root ? root : ".", rel);
    return buf[k];
}

/* A scratch directory for test output (env FOVSIM_TEST_OUT), created on demand. */
static inline const char *test_out_dir(void)
{
    static char buf[1024];
    const char *root = getenv("FOVSIM_TEST_OUT");
    snprintf(buf, sizeof buf, "%s", root ? root : "test_out");
    char cmd[1100];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", buf);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot create %s\n", buf);
    return buf;
}

#endif
