/*
 * Goodness-of-fit helpers for the statistical tests of the sensor-model library (tests/c/nps/test_effect*,
 * test_gmm*, test_rng*, test_sensor_model*). Header-only; include after test_helpers.h.
 *
 * Conventions of every statistical test here:
 *   - fixed seeds;
 *   - moments: |estimate - expected| <= K_SIGMA * SE, SE from the estimator's variance
 *     (mean: sigma / sqrt(n); variance: sqrt((mu4 - sigma^4) / n), mu4 = 3 sigma^4 for a normal;
 *      a proportion: sqrt(p (1 - p) / n)); K_SIGMA = 5 gives a two-sided false failure of 5.7e-7 per check;
 *   - distributions: one-sample Kolmogorov-Smirnov against the analytical CDF (GSL), rejecting at
 *     KS_ALPHA = 1e-4 per test; each KS test is paired with a slightly wrong model that must be rejected
 *     (the sample is large enough that a wrong model fails).
 */
#ifndef TEST_EFFECT_STATS_H
#define TEST_EFFECT_STATS_H

#include <math.h>
#include <stdlib.h>

#define K_SIGMA 5.0
#define KS_ALPHA 1e-4

typedef double (*stats_cdf_fn)(double x, const void *params);

static inline int stats_cmp_double(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/** KS statistic D = sup |F_n - F| of the sample x[0..n-1] (sorted in place). */
static inline double stats_ks_d(double *x, size_t n, stats_cdf_fn cdf, const void *params)
{
  qsort(x, n, sizeof(double), stats_cmp_double);
  double d = 0.0;
  for (size_t i = 0; i < n; i++) {
    double f = cdf(x[i], params);
    d = fmax(d, fmax(fabs((double)(i + 1) / (double)n - f), fabs(f - (double)i / (double)n)));
  }
  return d;
}

/**
 * P(D_n >= d) under the null: Kolmogorov's limiting distribution with Stephens' small-sample correction,
 * lambda = (sqrt(n) + 0.12 + 0.11 / sqrt(n)) d, p = 2 sum_k (-1)^(k-1) exp(-2 k^2 lambda^2)
 * (Press et al., Numerical Recipes 3rd ed., 14.3.3).
 */
static inline double stats_ks_p(double d, size_t n)
{
  double sn = sqrt((double)n), lambda = (sn + 0.12 + 0.11 / sn) * d, p = 0.0, sign = 1.0;
  if (lambda < 0.2) {
    return 1.0;
  }
  for (int k = 1; k <= 100; k++) {
    p += sign * 2.0 * exp(-2.0 * k * k * lambda * lambda);
    sign = -sign;
  }
  return fmin(fmax(p, 0.0), 1.0);
}

/** KS p-value of a sample (sorted in place). */
static inline double stats_ks_test(double *x, size_t n, stats_cdf_fn cdf, const void *params)
{
  return stats_ks_p(stats_ks_d(x, n, cdf, params), n);
}

static inline double stats_mean(const double *x, size_t n)
{
  double s = 0.0;
  for (size_t i = 0; i < n; i++) {
    s += x[i];
  }
  return s / (double)n;
}

/** Unbiased sample variance. */
static inline double stats_var(const double *x, size_t n)
{
  double m = stats_mean(x, n), s = 0.0;
  for (size_t i = 0; i < n; i++) {
    s += (x[i] - m) * (x[i] - m);
  }
  return s / (double)(n - 1);
}

/** Fourth central moment. */
static inline double stats_m4(const double *x, size_t n)
{
  double m = stats_mean(x, n), s = 0.0;
  for (size_t i = 0; i < n; i++) {
    double d = (x[i] - m) * (x[i] - m);
    s += d * d;
  }
  return s / (double)n;
}

/** Assert a count of successes out of n matches probability p within K_SIGMA binomial standard errors. */
#define assert_rate(count, n, p) do { \
    double n_ = (double)(n), p_ = (p); \
    assert_close((double)(count) / n_, p_, K_SIGMA * sqrt(fmax(p_ * (1.0 - p_), 1.0 / n_) / n_)); \
  } while (0)

/** Assert a KS test accepts (p >= KS_ALPHA), printing the p-value when it does not. */
#define assert_ks_accepts(p_value) do { \
    double pv_ = (p_value); \
    if (!(pv_ >= KS_ALPHA)) { \
      print_error("%s: KS p = %.3g < %.3g: the sample does not follow the model\n", #p_value, pv_, KS_ALPHA); \
      fail(); \
    } \
  } while (0)

/** Assert a KS test rejects (p < KS_ALPHA): the sample is large enough to tell a wrong model. */
#define assert_ks_rejects(p_value) do { \
    double pv_ = (p_value); \
    if (!(pv_ < KS_ALPHA)) { \
      print_error("%s: KS p = %.3g: a wrong model was not rejected (too few samples)\n", #p_value, pv_); \
      fail(); \
    } \
  } while (0)

#endif /* TEST_EFFECT_STATS_H */
