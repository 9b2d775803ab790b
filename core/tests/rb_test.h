/* Minimal test harness for the C core: CHECK macros and a closing line
 * "N passed, N failed" that CI recognises. */
#ifndef RB_TEST_H
#define RB_TEST_H

#include <math.h>
#include <stdio.h>
#include <string.h>

static int rb_test_passed = 0;
static int rb_test_failed = 0;

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (cond) {                                                                 \
            rb_test_passed++;                                                       \
        } else {                                                                    \
            rb_test_failed++;                                                       \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
        }                                                                           \
    } while (0)

/* |actual - expected| <= rel * |expected| + abs_tol */
#define CHECK_CLOSE(actual, expected, rel, abs_tol)                                          \
    do {                                                                                     \
        double a_ = (actual), e_ = (expected);                                               \
        if (fabs(a_ - e_) <= (rel) * fabs(e_) + (abs_tol)) {                                 \
            rb_test_passed++;                                                                \
        } else {                                                                             \
            rb_test_failed++;                                                                \
            fprintf(stderr, "%s:%d: CHECK_CLOSE failed: %s = %.12g, expected %.12g\n",       \
                    __FILE__, __LINE__, #actual, a_, e_);                                    \
        }                                                                                    \
    } while (0)

static int rb_test_summary(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, rb_test_passed, rb_test_failed);
    return rb_test_failed ? 1 : 0;
}

#endif
