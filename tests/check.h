/* Minimal assertions for the C tests: report and count, never abort early
 * without saying what failed. */
#ifndef MPS2P_TEST_CHECK_H
#define MPS2P_TEST_CHECK_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int check_failures = 0;

#define CHECK(condition, ...)                                                  \
    do {                                                                       \
        if (!(condition)) {                                                    \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #condition); \
            fprintf(stderr, __VA_ARGS__);                                      \
            fprintf(stderr, "\n");                                             \
            check_failures++;                                                  \
        }                                                                      \
    } while (0)

/* A call that must succeed; stops the test when it does not. */
#define MUST(call)                                                             \
    do {                                                                       \
        int must_status_ = (call);                                             \
        if (must_status_ < 0) {                                                \
            fprintf(stderr, "FAIL %s:%d: %s returned %s: %s\n", __FILE__,      \
                    __LINE__, #call, mps2p_status_string(must_status_),       \
                    mps2p_last_error());                                      \
            exit(1);                                                           \
        }                                                                      \
    } while (0)

#define CHECK_CLOSE(actual, expected, tolerance, what)                          \
    CHECK(fabs((actual) - (expected)) <= (tolerance),                           \
          "%s: got %.10g, expected %.10g (tolerance %g)", what, (double)(actual),  \
          (double)(expected), (double)(tolerance))

static inline int check_summary(const char *name)
{
    if (check_failures)
        fprintf(stderr, "%s: %d check(s) failed\n", name, check_failures);
    else
        printf("%s: all checks passed\n", name);
    return check_failures ? 1 : 0;
}

#endif
