/* The C tests' checks (strict C99, header-only): CHECK counts every check and reports a failed
 * one with its file, line, condition and pyramid_last_error(); check_summary prints the counts
 * and gives the program's exit status. One translation unit a program: the counters are its own. */
#ifndef PYRAMID_TESTS_SUPPORT_C_CHECK_H
#define PYRAMID_TESTS_SUPPORT_C_CHECK_H

#include <stddef.h>
#include <stdio.h>

#include "libpyramid/capi/pyramid.h"

static int checks = 0;
static int failures = 0;

#define CHECK(cond)                                                                  \
    do {                                                                             \
        ++checks;                                                                    \
        if (!(cond)) {                                                               \
            fprintf(stderr, "%s:%d: CHECK failed: %s (%s)\n", __FILE__, __LINE__, #cond, \
                    pyramid_last_error());                                           \
            ++failures;                                                              \
        }                                                                            \
    } while (0)

/* dir/name into out (of size bytes). */
static inline void path_of(char* out, size_t size, const char* dir, const char* name) {
    snprintf(out, size, "%s/%s", dir, name);
}

/* Prints "N passed, M failed"; the exit status: 1 when a check failed, else 0. */
static inline int check_summary(void) {
    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures ? 1 : 0;
}

#endif
