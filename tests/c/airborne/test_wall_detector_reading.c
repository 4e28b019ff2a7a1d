/*
 * The wall detector's per-reading model: the closed-form shortfall density and survival function against
 * numerical integration and samples, the log-likelihood ratio's limits and parts, the remembered wall's ratio,
 * the peer prior, the baseline check.
 *
 * Statistical test (samples_follow_the_shortfall_distribution): N = 20000 draws, fixed seed; the
 * Kolmogorov-Smirnov statistic D must stay below sqrt(ln(2 / alpha) / (2 N)) with alpha = 1e-6 (the
 * asymptotic bound P(sqrt(N) D > x) <= 2 exp(-2 x^2)), so a correct model fails with probability < 1e-6;
 * the same samples against a model with sigma 20 % too large must exceed it (a wrong model fails).
 */
#include "test_helpers.h"
#include "wall_detector_fixtures.h"

#include <gsl/gsl_integration.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <stdlib.h>

static const struct wall_detector_model model = {
  .sonar_sigma_m = 0.05f, .sonar_offset_m = 0.0327568f, .ranging_sigma_m = 0.12f, .copter_offset_m = 0.24f,
  .crosstalk_prob = 0.2f, .outlier_prob = 0.1f, .sonar_min_m = 0.2f, .sonar_max_m = 3.0f, .ranging_max_m = 2.5f,
  .copter_radius_m = 0.2f, .track_sigma_m = 0.05f,
};

/** The terms of a model (the per-reading functions take them; one model at a time). */
static const struct wall_detector_model_terms *terms_of(const struct wall_detector_model *m)
{
  static struct wall_detector_model_terms terms;
  wall_detector_model_terms_init(&terms, m);
  return &terms;
}

/** (sonar sigma, ranging sigma) pairs covering narrow, wide and either-dominated cases [m] */
static const double sigmas[][2] = { { 0.05, 0.12 }, { 0.1, 0.02 }, { 0.2, 0.3 } };

struct conv_args { double u, s, r; };

/* Integrand of the convolution definition: Rayleigh(x; s) x N(u - x; 0, r^2). */
static double convolution_integrand(double x, void *p)
{
  const struct conv_args *a = p;
  const double z = (a->u - x) / a->r;
  return gsl_ran_rayleigh_pdf(x, a->s) * exp(-0.5 * z * z) / (a->r * sqrt(2.0 * M_PI));
}

static double pdf_integrand(double u, void *p)
{
  const double *sr = p;
  return wall_detector_shortfall_pdf(u, sr[0], sr[1]);
}

static double u_pdf_integrand(double u, void *p)
{
  const double *sr = p;
  return u * wall_detector_shortfall_pdf(u, sr[0], sr[1]);
}

static double integrate(double (*f)(double, void *), void *params, double lo, double hi)
{
  gsl_integration_workspace *w = gsl_integration_workspace_alloc(1000);
  gsl_function fn = { f, params };
  double result, error;
  gsl_integration_qags(&fn, lo, hi, 1e-12, 1e-10, 1000, w, &result, &error);
  gsl_integration_workspace_free(w);
  return result;
}

static void shortfall_pdf_is_the_rayleigh_gaussian_convolution(void **state)
{
  (void)state;
  for (size_t i = 0; i < sizeof(sigmas) / sizeof(sigmas[0]); i++) {
    for (double u = -0.5; u <= 1.0; u += 0.05) {
      struct conv_args a = { u, sigmas[i][0], sigmas[i][1] };
      const double numeric = integrate(convolution_integrand, &a, 0.0, 20.0 * a.s);
      assert_close(wall_detector_shortfall_pdf(u, a.s, a.r), numeric, 1e-9 + 1e-8 * numeric);
    }
  }
}

static void shortfall_pdf_integrates_to_one_with_the_rayleigh_mean(void **state)
{
  (void)state;
  for (size_t i = 0; i < sizeof(sigmas) / sizeof(sigmas[0]); i++) {
    double sr[2] = { sigmas[i][0], sigmas[i][1] };
    const double span = 12.0 * (sr[0] + sr[1]);
    assert_close(integrate(pdf_integrand, sr, -span, span), 1.0, 1e-9);
    /* E[R + n] = E[R] = s sqrt(pi / 2) */
    assert_close(integrate(u_pdf_integrand, sr, -span, span), sr[0] * sqrt(M_PI / 2.0), 1e-9);
  }
}

static void shortfall_pdf_tends_to_rayleigh_without_ranging_noise(void **state)
{
  (void)state;
  for (double u = 0.01; u < 0.2; u += 0.01) {
    const double rayleigh = gsl_ran_rayleigh_pdf(u, 0.05);
    assert_close(wall_detector_shortfall_pdf(u, 0.05, 1e-5), rayleigh, 1e-4 * rayleigh);
  }
  assert_close(wall_detector_shortfall_pdf(-0.01, 0.05, 1e-5), 0.0, 1e-12);
}

static void shortfall_sf_is_the_upper_integral_of_the_pdf(void **state)
{
  (void)state;
  for (size_t i = 0; i < sizeof(sigmas) / sizeof(sigmas[0]); i++) {
    double sr[2] = { sigmas[i][0], sigmas[i][1] };
    for (double a = -0.6; a <= 0.8; a += 0.1) {
      const double upper = integrate(pdf_integrand, sr, a, a + 12.0 * (sr[0] + sr[1]));
      assert_close(wall_detector_shortfall_sf(a, sr[0], sr[1]), upper, 1e-9);
    }
  }
}

static int compare_doubles(const void *a, const void *b)
{
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/** Kolmogorov-Smirnov statistic of sorted samples against the shortfall model (s, r). */
static double ks_statistic(const double *sorted, size_t n, double s, double r)
{
  double d = 0.0;
  for (size_t i = 0; i < n; i++) {
    const double cdf = 1.0 - wall_detector_shortfall_sf(sorted[i], s, r);
    d = fmax(d, fmax(fabs(cdf - (double)i / n), fabs((double)(i + 1) / n - cdf)));
  }
  return d;
}

static void samples_follow_the_shortfall_distribution(void **state)
{
  (void)state;
  enum { N = 20000 };
  const double alpha = 1e-6;
  const double bound = sqrt(log(2.0 / alpha) / (2.0 * N));
  static double u[N];
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  gsl_rng_set(rng, 7);
  const double s = 0.05, r = 0.12;
  for (size_t i = 0; i < N; i++) {
    u[i] = gsl_ran_rayleigh(rng, s) + gsl_ran_gaussian_ziggurat(rng, r);
  }
  gsl_rng_free(rng);
  qsort(u, N, sizeof(u[0]), compare_doubles);
  const double d_right = ks_statistic(u, N, s, r);
  const double d_wrong = ks_statistic(u, N, 1.2 * s, r);
  if (d_right >= bound || d_wrong <= bound) {
    print_error("KS D = %.5f (model), %.5f (sigma x 1.2), bound %.5f\n", d_right, d_wrong, bound);
  }
  assert_true(d_right < bound);
  assert_true(d_wrong > bound);
}

static void llr_is_log_outlier_prob_far_from_the_peer(void **state)
{
  (void)state;
  /* 2.5 m reading, peer at 0.6 m: neither the echo (0.39 m) nor the cross-talk (0.3 m) model reaches it */
  assert_close(wall_detector_reading_llr(terms_of(&model), 2.5f, 0.6f), log(model.outlier_prob), 1e-6);
  for (float range = 0.2f; range < 3.0f; range += 0.05f) {
    for (float peer = 0.0f; peer < 2.5f; peer += 0.1f) {
      assert_true(wall_detector_reading_llr(terms_of(&model), range, peer) >= logf(model.outlier_prob) - 1e-6f);
    }
  }
}

static void llr_favours_the_copter_at_its_echo_and_cross_talk_ranges(void **state)
{
  (void)state;
  const float peer_m = 1.5f;
  const float echo_m = peer_m - model.copter_offset_m;
  const float llr_echo = wall_detector_reading_llr(terms_of(&model), echo_m, peer_m);
  /* at the echo: ((1 - eps - chi) p(shortfall = offset) span + eps), the cross-talk part negligible */
  const double peak = wall_detector_shortfall_pdf(model.sonar_offset_m, 0.05, 0.12);
  const double expected = log((1.0 - 0.1 - 0.2) * peak * 2.8 + 0.1);
  assert_close(llr_echo, expected, 1e-5);
  assert_true(llr_echo > 1.0f);
  /* cross-talk: half the ranged distance, a Gaussian of sd sqrt(r^2 / 4 + s^2), plus the echo part's tail */
  const double sd = sqrt(0.25 * 0.12 * 0.12 + 0.05 * 0.05);
  const double echo_tail = wall_detector_shortfall_pdf(echo_m + model.sonar_offset_m - 0.5 * peer_m, 0.05, 0.12);
  const double expected_ct = log((0.7 * echo_tail + 0.2 / (sd * sqrt(2.0 * M_PI))) * 2.8 + 0.1);
  assert_close(wall_detector_reading_llr(terms_of(&model), 0.5f * peer_m, peer_m), expected_ct, 1e-5);
}

static void llr_judges_a_clamped_reading_by_probabilities(void **state)
{
  (void)state;
  /* peer 0.3 m away (bodies nearly touching): its echo would read below the minimum -> strong copter evidence */
  assert_true(wall_detector_reading_llr(terms_of(&model), model.sonar_min_m, 0.3f) > 3.0f);
  /* peer 2 m away: a reading at the minimum is a wall a few centimetres off */
  assert_close(wall_detector_reading_llr(terms_of(&model), model.sonar_min_m, 2.0f), log(model.outlier_prob), 1e-6);
}

static void the_best_part_names_echo_cross_talk_or_outlier(void **state)
{
  (void)state;
  /* peer at 1.5 m: its echo reads about 1.26 m, its cross-talk 0.75 m; 2.5 m is neither */
  assert_int_equal(wall_detector_reading_part(terms_of(&model), 1.26f, 1.5f), WALL_DETECTOR_PART_ECHO);
  assert_int_equal(wall_detector_reading_part(terms_of(&model), 0.75f, 1.5f), WALL_DETECTOR_PART_CROSSTALK);
  assert_int_equal(wall_detector_reading_part(terms_of(&model), 2.5f, 1.5f), WALL_DETECTOR_PART_OUTLIER);
}

static void the_remembered_wall_ratio_is_a_gaussian_mixed_with_a_new_wall(void **state)
{
  (void)state;
  /* at the prediction: log(keep span / (t sqrt(2 pi)) + 1 - keep), span 2.8 m, t = 0.05 m:
   * keep 0.9 -> log(0.9 x 2.8 x 7.978845608 + 0.1) = log(20.206691) = 3.006014 */
  assert_close(track_llr(terms_of(&model), 1.0f, 1.0f, 0.9f), log(0.9 * 2.8 / (0.05 * sqrt(2.0 * M_PI)) + 0.1),
               1e-5);
  assert_close(track_llr(terms_of(&model), 1.0f, 1.0f, 0.9f), 3.006014, 1e-5);
  /* one sd off: the Gaussian times exp(-1/2) */
  assert_close(track_llr(terms_of(&model), 1.05f, 1.0f, 0.5f),
               log(0.5 * 2.8 / (0.05 * sqrt(2.0 * M_PI)) * exp(-0.5) + 0.5), 1e-4);
  /* far from it (a body in front of the wall): log(1 - keep), the least it can be; keep 0: nothing remembered */
  assert_close(track_llr(terms_of(&model), 0.5f, 1.5f, 0.9f), log(0.1), 1e-6);
  assert_close(track_llr(terms_of(&model), 0.7f, 1.0f, 0.0f), 0.0, 1e-7);
  /* clamped at the minimum with the wall predicted there: P(reading <= min) = 1/2 against a random wall's
   * s sqrt(2 pi) (1 - Phi(offset / s)) / span = 0.05 x 2.506628 x 0.256190 / 2.8 = 0.011467 */
  const double wall_p = 0.05 * sqrt(2.0 * M_PI) * 0.5 * erfc(0.0327568 / 0.05 / M_SQRT2) / 2.8;
  assert_close(track_llr(terms_of(&model), 0.2f, 0.2f, 0.9f), log(0.9 * 0.5 / wall_p + 0.1), 1e-4);
}

static void a_peer_on_a_boresight_has_the_prior_of_its_angular_width(void **state)
{
  (void)state;
  /* asin(0.2 / 1) / pi = 0.064094; asin(0.2 / 2) / pi = 0.031884; below contact (0.4 m) as at contact: 1/6 */
  assert_close(wall_detector_peer_prior(&model, 1.0f), asin(0.2) / M_PI, 1e-6);
  assert_close(wall_detector_peer_prior(&model, 2.0f), 0.031884, 1e-6);
  assert_close(wall_detector_peer_prior(&model, 0.4f), 1.0 / 6.0, 1e-6);
  assert_close(wall_detector_peer_prior(&model, 0.1f), 1.0 / 6.0, 1e-6);
  /* as with fmaxf: a NaN distance is raised to contact; a NaN radius gives NaN */
  assert_close(wall_detector_peer_prior(&model, NAN), 1.0 / 6.0, 1e-6);
  const struct wall_detector_model no_radius = { .copter_radius_m = NAN };
  assert_true(isnan(wall_detector_peer_prior(&no_radius, 1.0f)));
}

static void baseline_is_the_original_single_reading_check(void **state)
{
  (void)state;
  const float peers[] = { 2.5f, 1.0f };
  /* within 0.286 m of 1.0 m: copter */
  assert_int_equal(wall_detector_baseline_class(&model, 1.2f, peers, 2, 0.286319104f), WALL_DETECTOR_COPTER);
  assert_int_equal(wall_detector_baseline_class(&model, 0.72f, peers, 2, 0.286319104f), WALL_DETECTOR_COPTER);
  /* 0.3 m off: wall */
  assert_int_equal(wall_detector_baseline_class(&model, 1.3f, peers, 2, 0.286319104f), WALL_DETECTOR_WALL);
  /* an out-of-range peer (2.5 m) explains nothing, even at 2.4 m */
  assert_int_equal(wall_detector_baseline_class(&model, 2.4f, peers, 2, 0.286319104f), WALL_DETECTOR_WALL);
  /* no peer: wall; the sonar maximum: no echo */
  assert_int_equal(wall_detector_baseline_class(&model, 1.0f, peers, 0, 0.286319104f), WALL_DETECTOR_WALL);
  assert_int_equal(wall_detector_baseline_class(&model, 3.0f, peers, 2, 0.286319104f), WALL_DETECTOR_NO_ECHO);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(shortfall_pdf_is_the_rayleigh_gaussian_convolution),
    cmocka_unit_test(shortfall_pdf_integrates_to_one_with_the_rayleigh_mean),
    cmocka_unit_test(shortfall_pdf_tends_to_rayleigh_without_ranging_noise),
    cmocka_unit_test(shortfall_sf_is_the_upper_integral_of_the_pdf),
    cmocka_unit_test(samples_follow_the_shortfall_distribution),
    cmocka_unit_test(llr_is_log_outlier_prob_far_from_the_peer),
    cmocka_unit_test(llr_favours_the_copter_at_its_echo_and_cross_talk_ranges),
    cmocka_unit_test(llr_judges_a_clamped_reading_by_probabilities),
    cmocka_unit_test(the_best_part_names_echo_cross_talk_or_outlier),
    cmocka_unit_test(the_remembered_wall_ratio_is_a_gaussian_mixed_with_a_new_wall),
    cmocka_unit_test(a_peer_on_a_boresight_has_the_prior_of_its_angular_width),
    cmocka_unit_test(baseline_is_the_original_single_reading_check),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
