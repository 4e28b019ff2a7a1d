/*
 * Conditional Gaussian mixture (nps_gmm.h): conditioning in log space, the O(1) alias-table sampler and the
 * exact sampler against the mixture's own conditional law, and the report's sampler as the counter-example.
 *
 * Conventions in test_effect_stats.h. Specific to this file:
 *   - the criterion: at every true range 0, 0.25, ..., 2.5 m the sampled conditional mean is within
 *     2 % of the conditional standard deviation of the mixture's mean, and the sampled variance within 2 % of
 *     the mixture's variance (law of total variance: sum w_i (v_i + m_i^2) - mean^2);
 *   - the draws per true range are chosen from the mixture's exact fourth moment so that K_SIGMA standard
 *     errors of the mean and variance estimates stay below that 2 % (draws_needed(); heavy tails need up to
 *     a few million), so the criterion is neither met nor missed by chance;
 *   - the report's sampler (sum_i w_i * draw_i, finken-environment-report.md 4.3) gets N_REPORT = 20000 draws
 *     per true range: its variance is wrong by far more than 10 standard errors, which the test also asserts;
 *   - KS against the conditional CDF, N_KS = 20000 draws per true range, for the alias-table sampler and the
 *     exact O(K) sampler (which shows the tables lose nothing).
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <pthread.h>
#include <string.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>

#include "nps_gmm.h"
#include "nps_rng.h"
#include "nps_sensor_model_xml.h"

#define DEFAULT_MIXTURE "conf/sensor_models/finken_ranging_gmm_k100.xml"
#define N_MOMENT_MAX 8000000
#define N_REPORT 20000
#define N_KS 20000
#define MOMENT_TOL 0.02
#define SEED 42u

typedef double (*sampler_fn)(const struct nps_gmm *gmm, double t_m, gsl_rng *r);

static struct nps_gmm *default_mixture(void)
{
  char err[512];
  struct nps_gmm *g = nps_sensor_model_load_mixture(DEFAULT_MIXTURE, err, sizeof(err));
  if (g == NULL) {
    print_error("%s (run the tests from the repository root)\n", err);
  }
  assert_non_null(g);
  assert_int_equal(nps_gmm_size(g), 100);
  return g;
}

/** The report's sampler: one draw per component, summed with the conditional weights. NOT the model. */
static double report_sampler(const struct nps_gmm *g, double t_m, gsl_rng *r)
{
  size_t k = nps_gmm_size(g);
  double w[k], m[k], sd[k], x = 0.0;
  nps_gmm_condition(g, t_m, w, m, sd);
  for (size_t i = 0; i < k; i++) {
    x += w[i] * (m[i] + gsl_ran_gaussian_ziggurat(r, sd[i]));
  }
  return x;
}

struct moment_check {
  double rel_mean_err;   /**< |mean_hat - mean| / sd */
  double rel_var_err;    /**< |var_hat - var| / var */
  double var_se_rel;     /**< standard error of var_hat / var, from the sample's fourth moment */
};

/** Moments of n draws at t_m against the mixture's own, accumulated about the mixture mean (no storage). */
static struct moment_check check_moments(const struct nps_gmm *g, sampler_fn f, double t_m, size_t n, gsl_rng *r)
{
  double mean, var, s1 = 0.0, s2 = 0.0, s3 = 0.0, s4 = 0.0;
  nps_gmm_conditional_moments(g, t_m, &mean, &var);
  for (size_t i = 0; i < n; i++) {
    double d = f(g, t_m, r) - mean, d2 = d * d;
    s1 += d;
    s2 += d2;
    s3 += d2 * d;
    s4 += d2 * d2;
  }
  double dn = (double)n, md = s1 / dn;
  double var_hat = (s2 / dn - md * md) * dn / (dn - 1.0);
  double m4_hat = s4 / dn - 4.0 * md * s3 / dn + 6.0 * md * md * s2 / dn - 3.0 * md * md * md * md;
  return (struct moment_check) {
    .rel_mean_err = fabs(md) / sqrt(var),
    .rel_var_err = fabs(var_hat - var) / var,
    .var_se_rel = sqrt((m4_hat - var_hat * var_hat) / dn) / var_hat,
  };
}

/**
 * Draws needed at t_m for the 2 % criterion to hold with K_SIGMA margin: the sample mean's SE is sd / sqrt(n),
 * the sample variance's sqrt((mu4 - var^2) / n), with the mixture's exact fourth central moment
 * mu4 = sum w_i [(m_i - mean)^4 + 6 (m_i - mean)^2 v_i + 3 v_i^2]. So n >= (K_SIGMA / 0.02)^2 (mu4 / var^2 - 1).
 */
static size_t draws_needed(const struct nps_gmm *g, double t_m)
{
  size_t k = nps_gmm_size(g);
  double w[k], m[k], sd[k], mean, var, mu4 = 0.0;
  nps_gmm_condition(g, t_m, w, m, sd);
  nps_gmm_conditional_moments(g, t_m, &mean, &var);
  for (size_t i = 0; i < k; i++) {
    double d2 = (m[i] - mean) * (m[i] - mean), v = sd[i] * sd[i];
    mu4 += w[i] * (d2 * d2 + 6.0 * d2 * v + 3.0 * v * v);
  }
  double factor = (K_SIGMA / MOMENT_TOL) * (K_SIGMA / MOMENT_TOL);
  return (size_t)ceil(factor * fmax(mu4 / (var * var) - 1.0, 1.0));
}

/**
 * Number of true ranges 0, 0.25, ..., 2.5 m where the 2 % criterion fails. n_fixed = 0: draws_needed() per
 * point (at most N_MOMENT_MAX); the smallest variance error in standard errors goes to *min_var_err_in_se.
 */
static int moment_failures(const struct nps_gmm *g, sampler_fn f, size_t n_fixed, const char *label,
                           double *min_var_err_in_se)
{
  gsl_rng *r = nps_rng_stream_new(SEED, 0, 0);
  int failures = 0;
  *min_var_err_in_se = INFINITY;
  for (int j = 0; j <= 10; j++) {
    double t = 0.25 * j;
    size_t n = n_fixed ? n_fixed : draws_needed(g, t);
    assert_true(n <= N_MOMENT_MAX);
    struct moment_check c = check_moments(g, f, t, n, r);
    bool ok = c.rel_mean_err <= MOMENT_TOL && c.rel_var_err <= MOMENT_TOL;
    failures += !ok;
    *min_var_err_in_se = fmin(*min_var_err_in_se, c.rel_var_err / c.var_se_rel);
    print_message("# %s t=%.2f n=%zu: mean err %.4f sd, var err %.4f (SE %.4f) %s\n", label, t, n, c.rel_mean_err,
                  c.rel_var_err, c.var_se_rel, ok ? "ok" : "FAILS");
  }
  gsl_rng_free(r);
  return failures;
}

static void alias_sampler_matches_the_mixture_moments_within_2_percent(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  double min_se;
  assert_int_equal(moment_failures(g, nps_gmm_sample, 0, "alias", &min_se), 0);
  nps_gmm_free(g);
}

static void the_reports_weighted_sum_sampler_fails_the_same_test(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  double min_err_in_se;
  assert_int_equal(moment_failures(g, report_sampler, N_REPORT, "report", &min_err_in_se), 11);
  assert_true(min_err_in_se > 10.0);  /* wrong beyond any sampling noise */
  nps_gmm_free(g);
}

struct cdf_at {
  const struct nps_gmm *g;
  double t_m;
};

static double conditional_cdf(double x, const void *p)
{
  const struct cdf_at *c = p;
  return nps_gmm_conditional_cdf(c->g, c->t_m, x);
}

static double ks_p(const struct nps_gmm *g, sampler_fn f, double t_draw, double t_model, gsl_rng *r)
{
  double *x = malloc(N_KS * sizeof(double));
  for (size_t i = 0; i < N_KS; i++) {
    x[i] = f(g, t_draw, r);
  }
  struct cdf_at c = {g, t_model};
  double p = stats_ks_test(x, N_KS, conditional_cdf, &c);
  free(x);
  return p;
}

static void both_samplers_follow_the_conditional_cdf(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  gsl_rng *r = nps_rng_stream_new(SEED, 1, 0);
  double lo, hi;
  size_t cells;
  nps_gmm_grid(g, &lo, &hi, &cells);
  const double t[] = {0.0, 0.37, 1.25, 2.5, 3.2, hi + 1.0 /* beyond the grid: exact fallback */};
  for (size_t j = 0; j < sizeof(t) / sizeof(t[0]); j++) {
    assert_ks_accepts(ks_p(g, nps_gmm_sample, t[j], t[j], r));
    assert_ks_accepts(ks_p(g, nps_gmm_sample_exact, t[j], t[j], r));
  }
  /* power: draws at a true range 3 cm off, or by the report's sampler, are told apart */
  assert_ks_rejects(ks_p(g, nps_gmm_sample, 1.25, 1.28, r));
  assert_ks_rejects(ks_p(g, report_sampler, 1.25, 1.25, r));
  gsl_rng_free(r);
  nps_gmm_free(g);
}

static void far_from_every_component_nothing_is_nan(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  gsl_rng *r = nps_rng_stream_new(SEED, 2, 0);
  const double t[] = {-1e3, -50.0, 40.0, 1e3, 1e8};
  double w[100];
  for (size_t j = 0; j < sizeof(t) / sizeof(t[0]); j++) {
    double mean, var, sum = 0.0;
    nps_gmm_condition(g, t[j], w, NULL, NULL);
    for (size_t i = 0; i < 100; i++) {
      assert_false(isnan(w[i]));
      sum += w[i];
    }
    assert_close(sum, 1.0, 1e-12);
    nps_gmm_conditional_moments(g, t[j], &mean, &var);
    assert_true(isfinite(mean) && isfinite(var) && var > 0.0);
    assert_true(isfinite(nps_gmm_conditional_logpdf(g, t[j], t[j])));
    assert_true(isfinite(nps_gmm_sample(g, t[j], r)));
    assert_true(isfinite(nps_gmm_sample_exact(g, t[j], r)));
  }
  assert_true(isnan(nps_gmm_sample(g, NAN, r)));
  gsl_rng_free(r);
  nps_gmm_free(g);
}

/**
 * A component 1e36 m wide (found by tests/fuzz/fuzz_sensor_model_xml.c) stretches the grid over cells far too wide
 * for their bounds: at 40 m the narrow component, proposed almost always, is never accepted. The draw ends (the
 * exact method after NPS_GMM_MAX_PROPOSALS) and follows the narrow component's conditional law at 0.5 m.
 */
static void a_draw_ends_in_cells_too_wide_for_their_bounds(void **state)
{
  (void)state;
  const double w[] = {0.5, 0.5}, mu[] = {0.0, 1.0, 1.0, 1.0};
  const double cov[] = {0.1, 0.0, 0.0, 0.1, 1e73, 0.0, 0.0, 0.1};
  struct nps_gmm *g = nps_gmm_new(2, w, mu, cov, NULL, NULL, 0);
  assert_non_null(g);
  gsl_rng *r = nps_rng_stream_new(SEED, 5, 0);
  for (int n = 0; n < 100; n++) {
    assert_true(isfinite(nps_gmm_sample(g, 40.0, r)));
    assert_true(isfinite(nps_gmm_sample(g, 0.5, r)));
  }
  gsl_rng_free(r);
  nps_gmm_free(g);
}

/** One full-covariance component: the conditional law is the textbook conditional normal. */
static void one_component_gives_the_conditional_normal(void **state)
{
  (void)state;
  const double w[] = {1.0}, mu[] = {1.0, 1.2}, cov[] = {0.04, 0.018, 0.018, 0.01};
  struct nps_gmm *g = nps_gmm_new(1, w, mu, cov, NULL, NULL, 0);
  assert_non_null(g);
  double mean, var, t = 1.5;
  nps_gmm_conditional_moments(g, t, &mean, &var);
  assert_close(mean, 1.2 + 0.018 / 0.04 * (t - 1.0), 1e-12);
  assert_close(var, 0.01 - 0.018 * 0.018 / 0.04, 1e-12);
  double sd = sqrt(0.01 - 0.018 * 0.018 / 0.04);
  assert_close(nps_gmm_conditional_logpdf(g, t, 1.5), log(gsl_ran_gaussian_pdf(1.5 - mean, sd)), 1e-12);
  nps_gmm_free(g);
}

/** Two components: log p(m|t) by hand from the joint's formulas (Bishop 2.81-2.82). */
static void two_components_logpdf_by_hand(void **state)
{
  (void)state;
  const double w[] = {0.3, 0.7}, mu[] = {0.5, 0.55, 2.0, 2.1};
  const double cov[] = {0.01, 0.004, 0.004, 0.004, 0.09, 0.0, 0.0, 0.04};
  struct nps_gmm *g = nps_gmm_new(2, w, mu, cov, NULL, NULL, 0);
  assert_non_null(g);
  assert_false(nps_gmm_is_diagonal(g));
  double t = 1.1, m = 1.0;
  double u0 = 0.3 * gsl_ran_gaussian_pdf(t - 0.5, 0.1), u1 = 0.7 * gsl_ran_gaussian_pdf(t - 2.0, 0.3);
  double m0 = 0.55 + 0.4 * (t - 0.5), s0 = sqrt(0.004 - 0.004 * 0.004 / 0.01), m1 = 2.1, s1 = 0.2;
  double p = (u0 * gsl_ran_gaussian_pdf(m - m0, s0) + u1 * gsl_ran_gaussian_pdf(m - m1, s1)) / (u0 + u1);
  assert_close(nps_gmm_conditional_logpdf(g, t, m), log(p), 1e-12);
  double cdf = (u0 * gsl_cdf_gaussian_P(m - m0, s0) + u1 * gsl_cdf_gaussian_P(m - m1, s1)) / (u0 + u1);
  assert_close(nps_gmm_conditional_cdf(g, t, m), cdf, 1e-12);
  nps_gmm_free(g);
}

/** A diagonal mixture: component means do not move with t, only the weights do; samplers still exact. */
static void diagonal_mixture_samples_its_own_law(void **state)
{
  (void)state;
  const double w[] = {0.3, 0.4, 0.3}, mu[] = {0.5, 0.55, 1.5, 1.45, 2.5, 2.6};
  const double cov[] = {0.3, 0, 0, 0.04, 0.3, 0, 0, 0.05, 0.3, 0, 0, 0.06};
  struct nps_gmm *g = nps_gmm_new(3, w, mu, cov, NULL, NULL, 0);
  assert_non_null(g);
  assert_true(nps_gmm_is_diagonal(g));
  double min_se;
  assert_int_equal(moment_failures(g, nps_gmm_sample, 0, "diag", &min_se), 0);
  gsl_rng *r = nps_rng_stream_new(SEED, 3, 0);
  assert_ks_accepts(ks_p(g, nps_gmm_sample, 0.8, 0.8, r));
  gsl_rng_free(r);
  nps_gmm_free(g);
}

static void same_seed_same_draws(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  gsl_rng *a = nps_rng_stream_new(SEED, 4, 0), *b = nps_rng_stream_new(SEED, 4, 0);
  for (int i = 0; i < 10000; i++) {
    double t = 0.00025 * i;
    assert_true(nps_gmm_sample(g, t, a) == nps_gmm_sample(g, t, b));
  }
  gsl_rng_free(a);
  gsl_rng_free(b);
  nps_gmm_free(g);
}

/**
 * The alias-table sampler draws exactly what it drew with GSL's gsl_ran_discrete() over the same tables (GSL
 * 2.7.1): every simulation log depends on it. Recorded from that implementation with gsl_rng_mt19937 seeded as
 * stream (5, 0) of seed 42, true ranges -2.5 .. 4.5 m in steps of 0.07 mm (outside the grid the exact method
 * answers): the sum of 100000 draws, a few single draws, and the next uniform, which shows that the same number of
 * variates was used.
 */
static void draws_are_those_of_gsl_alias_tables(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
  assert_non_null(r);
  gsl_rng_set(r, nps_rng_stream_seed(SEED, 5, 0));
  const struct { int i; double draw_m; } recorded[] = {
    {0, -0.82041599570774237}, {1, -0.69567138947697971}, {2, -0.15745594868733304},
    {40000, 0.23838471557542484}, {60000, 1.8219665141331436}, {80000, 2.4522923639950336},
  };
  size_t next = 0;
  double sum = 0.0;
  for (int i = 0; i < 100000; i++) {
    double x = nps_gmm_sample(g, -2.5 + 0.00007 * i, r);
    sum += x;
    if (next < sizeof(recorded) / sizeof(recorded[0]) && recorded[next].i == i) {
      assert_true(x == recorded[next++].draw_m);
    }
  }
  assert_true(sum == 146428.83698450858);
  assert_true(gsl_rng_uniform(r) == 0.4021489683073014);
  gsl_rng_free(r);
  nps_gmm_free(g);
}

/** The true range [m] at `cells` cell widths from the lower end of g's grid (negative: below it). */
static double grid_point_m(const struct nps_gmm *g, double cells)
{
  double lo_m, hi_m;
  size_t n_cells;
  nps_gmm_grid(g, &lo_m, &hi_m, &n_cells);
  return lo_m + cells * (hi_m - lo_m) / (double)n_cells;
}

/** A cell's alias table is built on the first draw at a true range in it, once; outside the grid none is. */
static void cells_are_built_on_their_first_draw(void **state)
{
  (void)state;
  struct nps_gmm *g = default_mixture();
  gsl_rng *r = nps_rng_stream_new(SEED, 6, 0);
  assert_int_equal(nps_gmm_cells_built(g), 0);
  nps_gmm_sample(g, grid_point_m(g, 10.5), r);
  assert_int_equal(nps_gmm_cells_built(g), 1);
  nps_gmm_sample(g, grid_point_m(g, 10.25), r);   /* the same cell */
  nps_gmm_sample(g, grid_point_m(g, -1.0), r);    /* below the grid: the exact method */
  nps_gmm_sample(g, grid_point_m(g, 1e6), r);     /* above it */
  assert_int_equal(nps_gmm_cells_built(g), 1);
  nps_gmm_sample(g, grid_point_m(g, 11.5), r);
  assert_int_equal(nps_gmm_cells_built(g), 2);
  gsl_rng_free(r);
  nps_gmm_free(g);
}

#define THREADED_STREAMS 4
#define THREADED_DRAWS 20000

/**
 * One stream's draws from a shared mixture, sweeping every cell of the grid: streams 0 and 1 from its lower end,
 * 2 and 3 from its middle, so that threads ask for the same cell at once and build different cells at once.
 */
struct threaded_draws {
  const struct nps_gmm *g;
  unsigned stream;
  double draw_m[THREADED_DRAWS];
};

static void *draw_stream(void *arg)
{
  struct threaded_draws *d = arg;
  gsl_rng *r = nps_rng_stream_new(SEED, 7, d->stream);
  double lo_m, hi_m;
  size_t n_cells;
  nps_gmm_grid(d->g, &lo_m, &hi_m, &n_cells);
  const int start = d->stream / 2 * THREADED_DRAWS / 2;
  for (int i = 0; i < THREADED_DRAWS; i++) {
    const int at = (start + i) % THREADED_DRAWS;
    d->draw_m[i] = nps_gmm_sample(d->g, lo_m + (hi_m - lo_m) * (at + 0.5) / THREADED_DRAWS, r);
  }
  gsl_rng_free(r);
  return NULL;
}

/**
 * Threads drawing from one fresh mixture at once (the host's threads share the sensor model) build each cell once and
 * draw what one thread drawing the streams in turn from another fresh mixture draws: a table built twice at once, or
 * read before it is complete, would change draws.
 */
static void threads_drawing_at_once_draw_what_one_thread_draws(void **state)
{
  (void)state;
  struct nps_gmm *shared = default_mixture(), *alone = default_mixture();
  static struct threaded_draws together[THREADED_STREAMS], in_turn[THREADED_STREAMS];
  pthread_t thread[THREADED_STREAMS];
  for (unsigned s = 0; s < THREADED_STREAMS; s++) {
    together[s].g = shared;
    together[s].stream = s;
    assert_int_equal(pthread_create(&thread[s], NULL, draw_stream, &together[s]), 0);
  }
  for (unsigned s = 0; s < THREADED_STREAMS; s++) {
    assert_int_equal(pthread_join(thread[s], NULL), 0);
    in_turn[s].g = alone;
    in_turn[s].stream = s;
    draw_stream(&in_turn[s]);
  }
  size_t n_cells;
  double lo_m, hi_m;
  nps_gmm_grid(shared, &lo_m, &hi_m, &n_cells);
  assert_int_equal(nps_gmm_cells_built(shared), n_cells);
  for (unsigned s = 0; s < THREADED_STREAMS; s++) {
    assert_memory_equal(together[s].draw_m, in_turn[s].draw_m, sizeof(together[s].draw_m));
  }
  nps_gmm_free(shared);
  nps_gmm_free(alone);
}

static void expect_rejected(size_t k, const double *w, const double *mu, const double *cov, size_t bad_expected,
                            const char *reason)
{
  char err[256] = "";
  size_t bad = 999;
  assert_null(nps_gmm_new(k, w, mu, cov, &bad, err, sizeof(err)));
  if (strstr(err, reason) == NULL) {
    print_error("error '%s' does not say '%s'\n", err, reason);
    fail();
  }
  assert_int_equal(bad, bad_expected);
}

static void bad_mixtures_are_rejected(void **state)
{
  (void)state;
  const double w[] = {0.5, 0.5}, mu[] = {0, 0, 1, 1}, ok[] = {1, 0, 0, 1, 1, 0.5, 0.5, 1};
  const double neg_var[] = {1, 0, 0, 1, 1, 0, 0, -0.1}, singular[] = {1, 0, 0, 1, 1, 2, 2, 4};
  const double asym[] = {1, 0, 0, 1, 1, 0.5, 0.4, 1}, w_bad[] = {0.5, 0.4}, w_neg[] = {1.5, -0.5};
  const double mu_nan[] = {0, 0, NAN, 1};
  struct nps_gmm *g = nps_gmm_new(2, w, mu, ok, NULL, NULL, 0);
  assert_non_null(g);
  nps_gmm_free(g);
  expect_rejected(2, w, mu, neg_var, 1, "variances must be > 0");
  expect_rejected(2, w, mu, singular, 1, "singular covariance");
  expect_rejected(2, w, mu, asym, 1, "not symmetric");
  expect_rejected(2, w_bad, mu, ok, 2, "weights sum to 0.9");
  expect_rejected(2, w_neg, mu, ok, 1, "negative weight");
  expect_rejected(2, w, mu_nan, ok, 1, "NaN");
  expect_rejected(0, w, mu, ok, 0, "1 to");
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(alias_sampler_matches_the_mixture_moments_within_2_percent),
    cmocka_unit_test(the_reports_weighted_sum_sampler_fails_the_same_test),
    cmocka_unit_test(both_samplers_follow_the_conditional_cdf),
    cmocka_unit_test(far_from_every_component_nothing_is_nan),
    cmocka_unit_test(a_draw_ends_in_cells_too_wide_for_their_bounds),
    cmocka_unit_test(one_component_gives_the_conditional_normal),
    cmocka_unit_test(two_components_logpdf_by_hand),
    cmocka_unit_test(diagonal_mixture_samples_its_own_law),
    cmocka_unit_test(same_seed_same_draws),
    cmocka_unit_test(draws_are_those_of_gsl_alias_tables),
    cmocka_unit_test(cells_are_built_on_their_first_draw),
    cmocka_unit_test(threads_drawing_at_once_draw_what_one_thread_draws),
    cmocka_unit_test(bad_mixtures_are_rejected),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
