/*
 * The cheap bounds of expf and logf (wall_detector_bounds.h) lie beyond glibc's expf and logf: the log bounds (lower
 * and upper) on every float mantissa at exponent 0 ([1, 2)) and at the smallest and largest normal exponents
 * (exhaustive there: the bound is log 2 times the float's bits less those of 1, whose conversion rounds most at the
 * extremes) and on 4096 mantissas at every other normal exponent; the exp lower bound on a grid 1e-7 apart near
 * 0, where it is tightest relative to expf (its margin must beat the rounding there), and 3e-4 apart down to -60.
 * Both are also checked to be close enough to be of use (the filter's shortcuts must decide most readings): within
 * their stated distance. Deterministic, no random draws.
 */

#include "test_helpers.h"
#include "modules/wall_detector/wall_detector_bounds.h"

#include <stdint.h>
#include <string.h>

/** The float with these bits. */
static float from_bits(uint32_t bits)
{
  float x;
  memcpy(&x, &bits, sizeof(x));
  return x;
}

static void the_exp_bound_is_below_expf(void **state)
{
  (void)state;
  int checked = 0;
  for (int k = 0; k <= 200000; k++) {
    const float near_zero = (float)(-1e-7 * k);
    const float wide = (float)(-3e-4 * k);
    const float xs[] = { near_zero, wide };
    for (int i = 0; i < 2; i++) {
      const float x = xs[i];
      const float bound = wall_detector_expf_lower_bound(x);
      const float exact = expf(x);
      if (!(bound <= exact)) {
        print_error("x = %.9g: bound %.9g above expf %.9g\n", x, bound, exact);
        fail();
      }
      /* close enough where the filter needs it, |x| <= 1: within the stated x^2 / 32 + 1e-5 relative, checked as
       * x^2 / 30 + 1.1e-5 (the next term of the gap, -x^3 / 768, adds about 4 % of x^2 / 32 at x = -1; 1e-6 for
       * the rounding); a bound with one squaring less (x^2 / 16) or a margin of 3e-5 fails */
      assert_true(exact - bound <= exact * (x * x / 30.f + 1.1e-5f) || x < -1.f);
      checked++;
    }
  }
  assert_true(wall_detector_expf_lower_bound(0.f) < 1.f && wall_detector_expf_lower_bound(0.f) > 0.99998f);
  assert_true(wall_detector_expf_lower_bound(-20.f) == 0.f && wall_detector_expf_lower_bound(NAN) == 0.f);
  print_message("# %d arguments checked\n", checked);
}

/** Check both log bounds at y (positive, normal), returning the lower one's distance below logf. */
static float check_log_bound(float y)
{
  const float lower = wall_detector_logf_lower_bound(y);
  const float upper = wall_detector_logf_upper_bound(y);
  const float exact = logf(y);
  if (!(lower <= exact && exact <= upper)) {
    print_error("y = %.9g: logf %.9g outside [%.9g, %.9g]\n", y, exact, lower, upper);
    fail();
  }
  return exact - lower;
}

static void the_log_bounds_enclose_logf(void **state)
{
  (void)state;
  float widest = 0.f;
  /* every mantissa at exponent 0 ([1, 2)) and at the smallest and largest exponents, where the conversion of the
   * bits' difference to float rounds the most */
  const uint32_t every_mantissa_at[] = { 127u, 1u, 254u };
  for (int e = 0; e < 3; e++) {
    for (uint32_t mantissa = 0; mantissa < (1u << 23); mantissa++) {
      const float gap = check_log_bound(from_bits(every_mantissa_at[e] << 23 | mantissa));
      widest = gap > widest ? gap : widest;
    }
  }
  for (uint32_t exponent = 1; exponent < 255; exponent++) {
    for (uint32_t mantissa = 0; mantissa < (1u << 23); mantissa += 2047) {
      const float gap = check_log_bound(from_bits(exponent << 23 | mantissa));
      widest = gap > widest ? gap : widest;
    }
    check_log_bound(from_bits(exponent << 23 | 0x007fffffu));   // just below the next power of two
  }
  assert_true(wall_detector_logf_lower_bound(INFINITY) < INFINITY);
  /* close enough: the chord's largest gap (0.05966, at m = 1 / log(2)) and the margin, within the stated width; and
   * the width, by which the upper bound lies above the lower one, no wider than that gap rounded up (measured 0.05969
   * against 0.0598): the upper bound is then within 0.0598 of logf as well, where a looser width would pass the
   * enclosure unseen */
  print_message("# largest distance below logf %.5g\n", widest);
  assert_true(widest > 0.0596f && widest <= WALL_DETECTOR_LOG_BOUND_WIDTH);
  assert_true(WALL_DETECTOR_LOG_BOUND_WIDTH - widest < 2e-4f);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_exp_bound_is_below_expf),
    cmocka_unit_test(the_log_bounds_enclose_logf),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
