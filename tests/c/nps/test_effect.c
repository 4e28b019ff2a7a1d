/*
 * The effects library (nps_effect.h): each effect's sampler against its analytical law, its closed-form
 * log-density, exact values where they are exact, conditions, the all-zero identity, set-up errors.
 * Conventions in test_effect_stats.h: N = 200000 draws per distribution check, moments within K_SIGMA = 5
 * standard errors (formula at each check), KS at KS_ALPHA = 1e-4 with a wrong model that must be rejected.
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <string.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>

#include "nps_crosstalk.h"
#include "nps_effect.h"
#include "nps_rng.h"

#define N 200000
#define SEED 7u

static gsl_rng *rng;

static int setup(void **state)
{
  (void)state;
  rng = nps_rng_stream_new(SEED, 0, NPS_RNG_SENSOR_SONAR_FRONT);
  return rng ? 0 : -1;
}

static int teardown(void **state)
{
  (void)state;
  gsl_rng_free(rng);
  return 0;
}

/** An effect from a name and up to two parameters, failing the test when set-up fails. */
static struct nps_effect make(const char *name, size_t n, const char *k0, double v0, const char *k1, double v1)
{
  const char *keys[] = {k0, k1};
  const double values[] = {v0, v1};
  char err[256] = "";
  struct nps_effect e;
  if (nps_effect_init(&e, name, n, keys, values, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  return e;
}

static struct nps_effect_env env_at(double true_range_m, const struct nps_sensor_ctx *ctx)
{
  return (struct nps_effect_env) {
    .t_s = 0.0, .true_range_m = true_range_m, .ctx = ctx, .state = NULL,
    .min_range_m = 0.2, .max_range_m = 3.0, .speed_of_sound_mps = NPS_CROSSTALK_SPEED_OF_SOUND_MPS,
  };
}

/** N outputs of the effect at input x (the true range), minus x when `residual`. */
static double *draws(const struct nps_effect *e, double x, const struct nps_sensor_ctx *ctx, bool residual)
{
  struct nps_effect_env env = env_at(x, ctx);
  double *out = malloc(N * sizeof(double));
  for (size_t i = 0; i < N; i++) {
    out[i] = nps_effect_apply(e, &env, x, rng) - (residual ? x : 0.0);
  }
  return out;
}

/* ---- CDFs of the analytical laws, parameterised by a double[2] */
static double normal_cdf(double x, const void *p)
{
  return gsl_cdf_gaussian_P(x, ((const double *)p)[0]);
}

static double rayleigh_cdf(double x, const void *p)
{
  return x <= 0.0 ? 0.0 : gsl_cdf_rayleigh_P(x, ((const double *)p)[0]);
}

static double exponential_cdf(double x, const void *p)
{
  return x <= 0.0 ? 0.0 : gsl_cdf_exponential_P(x, ((const double *)p)[0]);
}

static double flat_cdf(double x, const void *p)
{
  const double *ab = p;
  return x <= ab[0] ? 0.0 : (x >= ab[1] ? 1.0 : gsl_cdf_flat_P(x, ab[0], ab[1]));
}

/** KS of a sample against cdf(param) (accept) and cdf(wrong) (reject); consumes (sorts) x. */
static void assert_law(double *x, size_t n, stats_cdf_fn cdf, const double *param, const double *wrong)
{
  assert_ks_accepts(stats_ks_test(x, n, cdf, param));
  assert_ks_rejects(stats_ks_test(x, n, cdf, wrong));
}

/* ---------------------------------------------------------------- identity and exact effects */

static void all_zero_parameters_are_the_identity(void **state)
{
  (void)state;
  /* every effect with parameters, all set to zero; scale's parameter is a ratio, so its identity is k = 1 */
  struct nps_effect e[] = {
    make("bias", 1, "b", 0, NULL, 0), make("scale", 1, "k", 1, NULL, 0), make("gaussian", 1, "sigma", 0, NULL, 0),
    make("range_noise", 2, "sigma0", 0, "sigma1", 0), make("rayleigh_short", 2, "sigma", 0, "offset", 0),
    make("rayleigh_short", 1, "sigma", 0, NULL, 0), make("crosstalk", 1, "p", 0, NULL, 0),
    make("dropout", 2, "p", 0, "p_per_m", 0), make("outlier", 1, "p", 0, NULL, 0),
    make("quantization", 1, "step", 0, NULL, 0), make("latency", 1, "tau", 0, NULL, 0),
    make("nlos_bias", 1, "mean", 0, NULL, 0),
  };
  struct nps_sensor_ctx facing = {.facing_sonars = 1.0, .crosstalk_path_m = 1.0};
  struct nps_sensor_state hist;
  nps_sensor_state_init(&hist);
  for (size_t j = 0; j < sizeof(e) / sizeof(e[0]); j++) {
    for (int i = 0; i < 1000; i++) {
      double x = 0.003 * i + gsl_rng_uniform(rng) * 1e-3;
      nps_sensor_state_push(&hist, 0.01 * i, x);
      struct nps_effect_env env = env_at(x, &facing);
      env.t_s = 0.01 * i;
      env.state = &hist;
      double y = nps_effect_apply(&e[j], &env, x, rng);
      if (y != x) {
        print_error("%s with zero parameters changed %.17g to %.17g\n", nps_effect_name(e[j].kind), x, y);
        fail();
      }
    }
  }
}

static void bias_and_scale_are_exact(void **state)
{
  (void)state;
  struct nps_effect bias = make("bias", 1, "b", -0.125, NULL, 0), scale = make("scale", 1, "k", 1.5, NULL, 0);
  struct nps_effect_env env = env_at(1.0, NULL);
  assert_true(nps_effect_apply(&bias, &env, 1.0, rng) == 0.875);
  assert_true(nps_effect_apply(&scale, &env, 1.0, rng) == 1.5);
  /* "no echo" and "no reading" pass through */
  assert_true(nps_effect_apply(&bias, &env, INFINITY, rng) == INFINITY);
  assert_true(isnan(nps_effect_apply(&scale, &env, NAN, rng)));
}

static void quantization_rounds_to_the_step(void **state)
{
  (void)state;
  struct nps_effect q = make("quantization", 1, "step", 0.25, NULL, 0);
  struct nps_effect_env env = env_at(1.0, NULL);
  const double in[] = {1.0, 1.1, 1.125, 1.13, 1.374, 1.376, 0.0, 2.99};
  const double out[] = {1.0, 1.0, 1.25, 1.25, 1.25, 1.5, 0.0, 3.0};
  for (size_t i = 0; i < sizeof(in) / sizeof(in[0]); i++) {
    assert_true(nps_effect_apply(&q, &env, in[i], rng) == out[i]);
  }
  /* a step that is not a power of two: every output is an integer number of steps, within half a step */
  struct nps_effect cm = make("quantization", 1, "step", 0.01, NULL, 0);
  for (int i = 0; i < 100000; i++) {
    double x = 3.0 * gsl_rng_uniform(rng), y = nps_effect_apply(&cm, &env, x, rng);
    assert_close(y / 0.01, round(y / 0.01), 1e-9);
    assert_true(fabs(y - x) <= 0.005 + 1e-12);
  }
}

static void latency_reports_the_true_range_tau_earlier(void **state)
{
  (void)state;
  /* true range 1 + 0.5 t sampled every 0.05 s: linear, so the interpolated past is exact */
  struct nps_effect lat = make("latency", 1, "tau", 0.07, NULL, 0);
  struct nps_sensor_state hist;
  nps_sensor_state_init(&hist);
  for (int i = 0; i < 40; i++) {
    double t = 0.05 * i, truth = 1.0 + 0.5 * t;
    nps_sensor_state_push(&hist, t, truth);
    struct nps_effect_env env = env_at(truth, NULL);
    env.t_s = t;
    env.state = &hist;
    double y = nps_effect_apply(&lat, &env, truth, rng);
    double expected = t >= 0.07 ? 1.0 + 0.5 * (t - 0.07) : 1.0;  /* before the first reading: the oldest */
    assert_close(y, expected, 1e-12);
    /* what earlier effects added is kept: latency shifts by true(t - tau) - true(t) */
    assert_close(nps_effect_apply(&lat, &env, truth + 0.3, rng), expected + 0.3, 1e-12);
  }
  /* older than the remembered history: the oldest remembered reading */
  struct nps_effect old = make("latency", 1, "tau", 100.0, NULL, 0);
  struct nps_effect_env env = env_at(1.975, NULL);
  env.t_s = 1.95;
  env.state = &hist;
  assert_close(nps_effect_apply(&old, &env, 1.975, rng), 1.0, 0.0);
}

/* ---------------------------------------------------------------- noise effects */

static void gaussian_has_its_moments_and_law(void **state)
{
  (void)state;
  const double sigma = 0.04;
  struct nps_effect e = make("gaussian", 1, "sigma", sigma, NULL, 0);
  double *r = draws(&e, 1.5, NULL, true);
  assert_close(stats_mean(r, N), 0.0, K_SIGMA * sigma / sqrt(N));                       /* SE = sigma/sqrt(N) */
  assert_close(stats_var(r, N), sigma * sigma, K_SIGMA * sigma * sigma * sqrt(2.0 / (N - 1))); /* normal */
  assert_law(r, N, normal_cdf, (double[]) {sigma}, (double[]) {sigma * 1.03});
  free(r);
}

static void range_noise_spread_grows_with_range(void **state)
{
  (void)state;
  const double s0 = 0.01, s1 = 0.02;
  struct nps_effect e = make("range_noise", 2, "sigma0", s0, "sigma1", s1);
  const double x[] = {0.5, 2.5};
  for (int j = 0; j < 2; j++) {
    double sigma = s0 + s1 * x[j], *r = draws(&e, x[j], NULL, true);
    assert_close(stats_var(r, N), sigma * sigma, K_SIGMA * sigma * sigma * sqrt(2.0 / (N - 1)));
    assert_law(r, N, normal_cdf, (double[]) {sigma}, (double[]) {s0});
    free(r);
  }
}

static void rayleigh_short_readings_are_usually_short(void **state)
{
  (void)state;
  const double sigma = 0.05, x = 1.2;
  struct nps_effect e = make("rayleigh_short", 1, "sigma", sigma, NULL, 0);
  const double offset = sqrt((4.0 - M_PI) / 2.0) * sigma;  /* the default: the Rayleigh standard deviation */
  assert_close(e.param[1], offset, 1e-15);
  double *out = draws(&e, x, NULL, false), *r = malloc(N * sizeof(double));
  size_t short_count = 0;
  for (size_t i = 0; i < N; i++) {
    r[i] = x - out[i] + offset;  /* = R, Rayleigh(sigma) */
    short_count += out[i] < x;
  }
  /* P(short) = P(R > offset) = exp(-offset^2 / (2 sigma^2)) = exp(-(4 - pi) / 4) = 0.807 */
  assert_rate(short_count, N, exp(-(4.0 - M_PI) / 4.0));
  double mean_r = sigma * sqrt(M_PI / 2.0), sd_r = offset;
  assert_close(stats_mean(r, N), mean_r, K_SIGMA * sd_r / sqrt(N));
  assert_law(r, N, rayleigh_cdf, (double[]) {sigma}, (double[]) {sigma * 1.03});
  free(out);
  free(r);
}

/** The effect is x - (R - offset) with R gsl_ran_rayleigh's draw, bit for bit and draw for draw (two streams in step). */
static void rayleigh_short_draws_what_gsl_draws(void **state)
{
  (void)state;
  const double sigma = 0.05, offset = 0.03, x = 1.2;
  struct nps_effect e = make("rayleigh_short", 2, "sigma", sigma, "offset", offset);
  gsl_rng *a = nps_rng_stream_new(SEED, 1, NPS_RNG_SENSOR_SONAR_FRONT);
  gsl_rng *b = nps_rng_stream_new(SEED, 1, NPS_RNG_SENSOR_SONAR_FRONT);   /* the same stream, drawn by gsl directly */
  struct nps_effect_env env = env_at(x, NULL);
  for (size_t i = 0; i < N; i++) {
    const double y = nps_effect_apply(&e, &env, x, a), expected = x - (gsl_ran_rayleigh(b, sigma) - offset);
    if (y != expected) {
      fail_msg("draw %zu: %.17g, gsl_ran_rayleigh gives %.17g", i, y, expected);
    }
  }
  assert_true(gsl_rng_get(a) == gsl_rng_get(b));   /* still in step */
  gsl_rng_free(a);
  gsl_rng_free(b);
}

static void nlos_bias_adds_an_exponential_excess(void **state)
{
  (void)state;
  const double mean = 0.15;
  struct nps_effect e = make("nlos_bias", 1, "mean", mean, NULL, 0);
  double *r = draws(&e, 1.0, NULL, true);
  assert_close(stats_mean(r, N), mean, K_SIGMA * mean / sqrt(N));  /* exponential: sd = mean */
  assert_law(r, N, exponential_cdf, (double[]) {mean}, (double[]) {mean * 1.03});
  free(r);
}

/* ---------------------------------------------------------------- event effects */

static void crosstalk_needs_a_facing_emitter(void **state)
{
  (void)state;
  const double p = 0.68, path = 1.7, offset_s = 0.002;
  struct nps_effect e = make("crosstalk", 1, "p", p, NULL, 0);
  struct nps_sensor_ctx alone = {0}, facing = {.facing_sonars = 1, .crosstalk_path_m = path, .trigger_offset_s = offset_s};
  double *quiet = draws(&e, 2.4, &alone, false), *heard = draws(&e, 2.4, &facing, false);
  double reading = 0.5 * (path + 343.0 * offset_s);
  size_t fired = 0;
  for (size_t i = 0; i < N; i++) {
    assert_true(quiet[i] == 2.4);  /* never without a facing emitter */
    assert_true(heard[i] == 2.4 || heard[i] == reading);
    fired += heard[i] == reading;
  }
  assert_rate(fired, N, p);
  /* both fire together and no path is given: the report's halving of the true range */
  struct nps_sensor_ctx together = {.facing_sonars = 2};
  struct nps_effect always = make("crosstalk", 1, "p", 1.0, NULL, 0);
  struct nps_effect_env env = env_at(2.4, &together);
  assert_close(nps_effect_apply(&always, &env, 2.4, rng), 1.2, 1e-15);
  free(quiet);
  free(heard);
}

static void dropout_rate_grows_with_range(void **state)
{
  (void)state;
  struct nps_effect e = make("dropout", 2, "p", 0.05, "p_per_m", 0.1);
  const double x[] = {0.5, 2.0};
  for (int j = 0; j < 2; j++) {
    double *out = draws(&e, x[j], NULL, false);
    size_t lost = 0;
    for (size_t i = 0; i < N; i++) {
      assert_true(out[i] == x[j] || out[i] == INFINITY);
      lost += out[i] == INFINITY;
    }
    assert_rate(lost, N, 0.05 + 0.1 * x[j]);
    free(out);
  }
}

static void outliers_are_uniform_over_the_range(void **state)
{
  (void)state;
  const double p = 0.1;
  struct nps_effect e = make("outlier", 1, "p", p, NULL, 0);
  double *out = draws(&e, 1.0, NULL, false);
  size_t n = 0;
  for (size_t i = 0; i < N; i++) {
    if (out[i] != 1.0) {
      out[n++] = out[i];
    }
  }
  assert_rate(n, N, p);  /* a uniform draw equal to 1.0 exactly has probability 0 */
  assert_law(out, n, flat_cdf, (double[]) {0.2, 3.0}, (double[]) {0.2, 2.8});
  free(out);
}

/* ---------------------------------------------------------------- conditions, densities, set-up */

static void a_condition_restricts_an_effect(void **state)
{
  (void)state;
  struct nps_effect e = make("bias", 1, "b", 0.5, NULL, 0);
  assert_int_equal(nps_condition_parse(&e.condition, "ctx_blocked", 11, NULL, NULL, 0), 0);
  e.condition.term[0].slot = NPS_CTX_BLOCKED;
  struct nps_sensor_ctx clear = {0}, blocked = {.blocked = 1.0}, unknown = {.blocked = NAN};
  struct nps_effect_env a = env_at(1.0, &clear), b = env_at(1.0, &blocked), c = env_at(1.0, &unknown);
  assert_true(nps_effect_apply(&e, &a, 1.0, rng) == 1.0);
  assert_true(nps_effect_apply(&e, &b, 1.0, rng) == 1.5);
  assert_true(nps_effect_apply(&e, &c, 1.0, rng) == 1.0);  /* NaN context: unknown, not applied */
  struct nps_effect_env none = env_at(1.0, NULL);
  assert_true(nps_effect_apply(&e, &none, 1.0, rng) == 1.0);
}

/** Trapezoid integral of exp(logpdf) over x_out in [a, b] with the input fixed. */
static double integral(const struct nps_effect *e, double x_in, double a, double b)
{
  const int steps = 200000;
  double h = (b - a) / steps, s = 0.0;
  for (int i = 0; i <= steps; i++) {
    double f = exp(nps_effect_logpdf(e, x_in, a + h * i));
    s += (i == 0 || i == steps) ? 0.5 * f : f;
  }
  return s * h;
}

static void log_densities_match_gsl_and_integrate_to_one(void **state)
{
  (void)state;
  struct nps_effect g = make("gaussian", 1, "sigma", 0.04, NULL, 0);
  struct nps_effect rn = make("range_noise", 2, "sigma0", 0.01, "sigma1", 0.02);
  struct nps_effect ray = make("rayleigh_short", 2, "sigma", 0.05, "offset", 0.03);
  struct nps_effect nl = make("nlos_bias", 1, "mean", 0.15, NULL, 0);
  assert_close(nps_effect_logpdf(&g, 1.0, 1.03), log(gsl_ran_gaussian_pdf(0.03, 0.04)), 1e-12);
  assert_close(nps_effect_logpdf(&rn, 2.0, 1.9), log(gsl_ran_gaussian_pdf(-0.1, 0.05)), 1e-12);
  assert_close(nps_effect_logpdf(&ray, 1.0, 0.95), log(gsl_ran_rayleigh_pdf(0.08, 0.05)), 1e-12);
  assert_close(nps_effect_logpdf(&nl, 1.0, 1.2), log(gsl_ran_exponential_pdf(0.2, 0.15)), 1e-12);
  assert_true(nps_effect_logpdf(&ray, 1.0, 1.04) == -INFINITY);  /* R < 0: impossible */
  assert_true(nps_effect_logpdf(&nl, 1.0, 0.99) == -INFINITY);
  assert_close(integral(&g, 1.0, 0.6, 1.4), 1.0, 1e-6);
  assert_close(integral(&rn, 2.0, 1.5, 2.5), 1.0, 1e-6);
  assert_close(integral(&ray, 1.0, 0.0, 1.03), 1.0, 1e-6);
  assert_close(integral(&nl, 1.0, 1.0, 4.0), 1.0, 1e-6);
  struct nps_effect b = make("bias", 1, "b", 0.1, NULL, 0);
  assert_true(isnan(nps_effect_logpdf(&b, 1.0, 1.1)));
  assert_true(nps_effect_has_logpdf(NPS_EFFECT_GAUSSIAN) && !nps_effect_has_logpdf(NPS_EFFECT_CROSSTALK));
}

static void expect_init_error(const char *name, size_t n, const char *k0, double v0, const char *k1, double v1,
                              const char *reason)
{
  const char *keys[] = {k0, k1};
  const double values[] = {v0, v1};
  char err[256] = "";
  struct nps_effect e;
  assert_int_equal(nps_effect_init(&e, name, n, keys, values, err, sizeof(err)), -1);
  if (strstr(err, reason) == NULL) {
    print_error("error '%s' does not say '%s'\n", err, reason);
    fail();
  }
}

static void bad_effects_are_rejected(void **state)
{
  (void)state;
  expect_init_error("blur", 0, NULL, 0, NULL, 0, "unknown effect 'blur'");
  expect_init_error("gaussian", 1, "sd", 0.1, NULL, 0, "unknown parameter 'sd' for effect 'gaussian' (expected: sigma)");
  expect_init_error("gaussian", 0, NULL, 0, NULL, 0, "needs parameter 'sigma'");
  expect_init_error("gaussian", 1, "sigma", -0.1, NULL, 0, "outside");
  expect_init_error("crosstalk", 1, "p", 1.5, NULL, 0, "outside");
  expect_init_error("bias", 2, "b", 0.1, "b", 0.2, "given twice");
  assert_int_equal(nps_effect_kind_from_name("gmm"), NPS_EFFECT_GMM);
  assert_string_equal(nps_effect_param_name(NPS_EFFECT_RANGE_NOISE, 1), "sigma1");
  double v;
  assert_int_equal(nps_effect_parse_number(" 0.25 ", &v), 0);
  assert_close(v, 0.25, 0.0);
  assert_int_equal(nps_effect_parse_number("nan", &v), -1);
  assert_int_equal(nps_effect_parse_number("0.2m", &v), -1);
  assert_int_equal(nps_effect_parse_number("", &v), -1);
}

static void crosstalk_geometry(void **state)
{
  (void)state;
  const double a[3] = {0, 0, 0.6}, b[3] = {1.5, 0, 0.6}, east[3] = {1, 0, 0}, west[3] = {-1, 0, 0};
  const double north[3] = {0, 1, 0}, zero[3] = {0, 0, 0}, cone = 30.0 * M_PI / 180.0;
  double path;
  assert_true(nps_crosstalk_facing(a, east, b, west, cone, 3.0, &path));
  assert_close(path, 1.5, 1e-15);
  assert_false(nps_crosstalk_facing(a, east, b, north, cone, 3.0, NULL));  /* emitter turned away */
  assert_false(nps_crosstalk_facing(a, west, b, west, cone, 3.0, NULL));   /* listener turned away */
  assert_false(nps_crosstalk_facing(a, east, b, west, cone, 1.0, NULL));   /* out of range */
  assert_false(nps_crosstalk_facing(a, zero, b, west, cone, 3.0, NULL));
  /* the same test with the cone given by its cosine, and its halves */
  assert_true(nps_crosstalk_facing_cos(a, east, b, west, cos(cone), 3.0, NULL));
  assert_false(nps_crosstalk_facing_cos(a, east, b, north, cos(cone), 3.0, NULL));
  const double to_b[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  const double dist = sqrt(to_b[0] * to_b[0] + to_b[1] * to_b[1] + to_b[2] * to_b[2]);
  assert_true(nps_crosstalk_in_cone(east, to_b, dist, cos(cone)));
  assert_false(nps_crosstalk_in_cone(north, to_b, dist, cos(cone)));
  assert_false(nps_crosstalk_in_cone(zero, to_b, dist, cos(cone)));
  assert_false(nps_crosstalk_in_cone(east, to_b, 0.0, cos(cone)));
  /* heard when the pulse arrives within the listening window after this sensor's trigger */
  assert_true(nps_crosstalk_heard(1.5, 0.0, 343.0, 0.02));
  assert_false(nps_crosstalk_heard(1.5, -0.01, 343.0, 0.02));  /* arrived before this sensor listened */
  assert_false(nps_crosstalk_heard(1.5, 0.02, 343.0, 0.02));   /* after the window */
  /* with the travel time given: the window's ends (exact binary fractions) belong to it */
  assert_true(nps_crosstalk_arrives(0.25, -0.25, 0.5));
  assert_false(nps_crosstalk_arrives(0.25, -0.25 - 0x1p-40, 0.5));
  assert_true(nps_crosstalk_arrives(0.25, 0.25, 0.5));
  assert_false(nps_crosstalk_arrives(0.25, 0.25 + 0x1p-40, 0.5));
  assert_close(nps_crosstalk_reading_m(1.5, 0.001, 343.0), 0.5 * (1.5 + 0.343), 1e-15);
}

static void same_seed_same_outputs(void **state)
{
  (void)state;
  struct nps_effect e = make("rayleigh_short", 1, "sigma", 0.05, NULL, 0);
  gsl_rng *a = nps_rng_stream_new(3, 1, 2), *b = nps_rng_stream_new(3, 1, 2), *c = nps_rng_stream_new(3, 2, 2);
  struct nps_effect_env env = env_at(1.0, NULL);
  int differ = 0;
  for (int i = 0; i < 1000; i++) {
    double x = nps_effect_apply(&e, &env, 1.0, a);
    assert_true(x == nps_effect_apply(&e, &env, 1.0, b));
    differ += x != nps_effect_apply(&e, &env, 1.0, c);
  }
  assert_int_equal(differ, 1000);  /* another vehicle's stream */
  gsl_rng_free(a);
  gsl_rng_free(b);
  gsl_rng_free(c);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(all_zero_parameters_are_the_identity),
    cmocka_unit_test(bias_and_scale_are_exact),
    cmocka_unit_test(quantization_rounds_to_the_step),
    cmocka_unit_test(latency_reports_the_true_range_tau_earlier),
    cmocka_unit_test(gaussian_has_its_moments_and_law),
    cmocka_unit_test(range_noise_spread_grows_with_range),
    cmocka_unit_test(rayleigh_short_readings_are_usually_short),
    cmocka_unit_test(rayleigh_short_draws_what_gsl_draws),
    cmocka_unit_test(nlos_bias_adds_an_exponential_excess),
    cmocka_unit_test(crosstalk_needs_a_facing_emitter),
    cmocka_unit_test(dropout_rate_grows_with_range),
    cmocka_unit_test(outliers_are_uniform_over_the_range),
    cmocka_unit_test(a_condition_restricts_an_effect),
    cmocka_unit_test(log_densities_match_gsl_and_integrate_to_one),
    cmocka_unit_test(bad_effects_are_rejected),
    cmocka_unit_test(crosstalk_geometry),
    cmocka_unit_test(same_seed_same_outputs),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
