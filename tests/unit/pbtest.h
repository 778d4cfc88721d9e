/* A minimal test harness: CHECK records a failure and goes on; the closing
 * line "N passed, N failed" is what ctest's log and CI read. */
#ifndef PB_TEST_H
#define PB_TEST_H

#include <math.h>
#include <stdio.h>

static int pbt_pass, pbt_fail;

#define CHECK(cond)                                                            \
  do {                                                                         \
    if (cond) {                                                                \
      pbt_pass++;                                                              \
    } else {                                                                   \
      pbt_fail++;                                                              \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
    }                                                                          \
  } while (0)

#define CHECK_EQ_INT(a, b)                                                     \
  do {                                                                         \
    long long pbt_a = (long long)(a), pbt_b = (long long)(b);                  \
    if (pbt_a == pbt_b) {                                                      \
      pbt_pass++;                                                              \
    } else {                                                                   \
      pbt_fail++;                                                              \
      fprintf(stderr, "%s:%d: CHECK_EQ_INT failed: %s = %lld, %s = %lld\n",     \
              __FILE__, __LINE__, #a, pbt_a, #b, pbt_b);                       \
    }                                                                          \
  } while (0)

/* |a - b| <= tol */
#define CHECK_NEAR(a, b, tol)                                                  \
  do {                                                                         \
    double pbt_a = (double)(a), pbt_b = (double)(b), pbt_t = (double)(tol);    \
    if (fabs(pbt_a - pbt_b) <= pbt_t) {                                        \
      pbt_pass++;                                                              \
    } else {                                                                   \
      pbt_fail++;                                                              \
      fprintf(stderr, "%s:%d: CHECK_NEAR failed: %s = %.9g, %s = %.9g, tol %g\n", \
              __FILE__, __LINE__, #a, pbt_a, #b, pbt_b, pbt_t);                \
    }                                                                          \
  } while (0)

static inline int pbt_done(void) {
  printf("%d passed, %d failed\n", pbt_pass, pbt_fail);
  return pbt_fail ? 1 : (pbt_pass ? 0 : 1); /* a test that checked nothing fails */
}

#endif
