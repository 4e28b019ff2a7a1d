/*
 * Shared includes for the cmocka unit tests (one cmocka_run_group_tests per binary; output as TAP
 * through CMOCKA_MESSAGE_OUTPUT=TAP, run by prove).
 */
#ifndef TEST_HELPERS_H
#define TEST_HELPERS_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

/** Assert |actual - expected| <= tol, printing both with full precision (cmocka prints 6 decimals). */
#define assert_close(actual, expected, tol) do { \
    double a_ = (actual), e_ = (expected), t_ = (tol); \
    if (!(fabs(a_ - e_) <= t_)) { \
      print_error("%s = %.9g, expected %.9g +- %.3g\n", #actual, a_, e_, t_); \
      fail(); \
    } \
  } while (0)

/** A uniform double in [lo, hi) from a 32-bit LCG (Numerical Recipes constants): fixed and portable. */
static inline double lcg_uniform(uint32_t *x, double lo, double hi)
{
  *x = *x * 1664525u + 1013904223u;
  return lo + (hi - lo) * (*x >> 8) / 16777216.0;
}

/** x moved by k doubles: k > 0 up, k < 0 down (nextafter |k| times). */
static inline double ulps_from(double x, int k)
{
  for (; k > 0; k--) {
    x = nextafter(x, INFINITY);
  }
  for (; k < 0; k++) {
    x = nextafter(x, -INFINITY);
  }
  return x;
}

#endif /* TEST_HELPERS_H */
