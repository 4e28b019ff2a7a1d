/*
 * The effects with list parameters (nps_effect.h): glitch and bias_curve, alone and in chains.
 *
 * glitch rate: p = 0.0018 from N_RATE = 2 000 000 readings has the binomial standard error sqrt(p (1 - p) / N) =
 * 3.0e-5 (1.7 % of p); the tolerance is K_SIGMA = 5 standard errors (false failure 5.7e-7, test_effect_stats.h). A
 * rate 20 % off is 12 standard errors away: the same check against 0.8 p and 1.2 p must fail on the same draws.
 * glitch shares: with p = 1, each value's share of N_SHARE = 200 000 readings within 5 binomial standard errors
 * (share 1/5: +-0.0045); a value listed twice has twice the share.
 * bias_curve: exact at the knots and beyond them, to 1e-15 m between them.
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <string.h>

#include "nps_rng.h"
#include "nps_sensor_model.h"
#include "test_model_fixtures.h"

#define N_RATE 2000000
#define N_SHARE 200000
#define GLITCH_P 0.0018

/** An effect from its name and parameters as text; the test fails with the reason when it is refused. */
static struct nps_effect make(const char *name, size_t n, const char *const key[], const char *const text[])
{
  char err[NPS_SENSOR_MODEL_ERR_LEN] = "";
  struct nps_effect e;
  if (nps_effect_init_text(&e, name, n, key, text, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  return e;
}

/** The effect is refused with `reason` as its whole error. */
static void expect_refused(const char *name, size_t n, const char *const key[], const char *const text[],
                           const char *reason)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN] = "";
  struct nps_effect e;
  assert_int_equal(nps_effect_init_text(&e, name, n, key, text, err, sizeof(err)), -1);
  assert_string_equal(err, reason);
}

static struct nps_effect_env env_at(double true_range_m, const struct nps_sensor_ctx *ctx)
{
  return (struct nps_effect_env) {
    .t_s = 0.0, .true_range_m = true_range_m, .ctx = ctx, .min_range_m = 0.2, .max_range_m = 3.0,
    .speed_of_sound_mps = 343.0,
  };
}

/** Whether count of n is within K_SIGMA binomial standard errors of probability p (assert_rate's test). */
static bool rate_within(size_t count, size_t n, double p)
{
  return fabs((double)count / (double)n - p) <= K_SIGMA * sqrt(p * (1.0 - p) / (double)n);
}

/* ---------------------------------------------------------------- glitch */

static void glitches_happen_at_rate_p(void **state)
{
  (void)state;
  const char *key[] = {"p", "values"}, *text[] = {"0.0018", "-12.84 0 270.1 1e5 inf"};
  const struct nps_effect e = make("glitch", 2, key, text);
  const struct nps_effect_env env = env_at(1.0, NULL);
  gsl_rng *r = nps_rng_stream_new(11, 1, NPS_RNG_SENSOR_SONAR_FRONT);
  size_t glitches = 0;
  for (size_t i = 0; i < N_RATE; i++) {
    glitches += nps_effect_apply(&e, &env, 1.0, r) != 1.0;
  }
  gsl_rng_free(r);
  assert_rate(glitches, N_RATE, GLITCH_P);
  assert_false(rate_within(glitches, N_RATE, 0.8 * GLITCH_P));   /* the check tells a rate 20 % off */
  assert_false(rate_within(glitches, N_RATE, 1.2 * GLITCH_P));
}

/** With p = 1: only the n_distinct values value[] are read, each with its share. */
static void assert_shares(const char *values, size_t n_distinct, const double *value, const double *share)
{
  const char *key[] = {"p", "values"}, *text[] = {"1", values};
  const struct nps_effect e = make("glitch", 2, key, text);
  const struct nps_effect_env env = env_at(1.0, NULL);
  gsl_rng *r = nps_rng_stream_new(12, 1, NPS_RNG_SENSOR_SONAR_FRONT);
  size_t count[8] = {0};
  for (size_t i = 0; i < N_SHARE; i++) {
    const double y = nps_effect_apply(&e, &env, 1.0, r);
    size_t k = 0;
    while (k < n_distinct && y != value[k]) {
      k++;
    }
    assert_true(k < n_distinct);   /* only the listed values */
    count[k]++;
  }
  gsl_rng_free(r);
  for (size_t k = 0; k < n_distinct; k++) {
    assert_rate(count[k], N_SHARE, share[k]);
  }
}

static void each_value_is_drawn_with_its_share(void **state)
{
  (void)state;
  const double five[] = {-12.84, 0.0, 270.1, 1e5, INFINITY}, fifths[] = {0.2, 0.2, 0.2, 0.2, 0.2};
  assert_shares("-12.84 0 270.1 1e5 inf", 5, five, fifths);
  const double two[] = {0.0, -INFINITY}, thirds[] = {2.0 / 3.0, 1.0 / 3.0};
  assert_shares("0 -inf 0", 2, two, thirds);   /* an empirical distribution: a value seen twice, twice as often */
}

static void a_glitch_replaces_any_reading_and_nothing_changes_it(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar(min_range=0.2, max_range=3, beyond_max=none): bias(b=0.5); "
                                         "glitch(p=1, values=-12.84); bias(b=1); quantization(step=1) "
                                         "| ranging(max_range=2.5, beyond_max=max): dropout(p=1); "
                                         "glitch(p=1, values=1e5)");
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar"), *g = nps_sensor_model_chain(m, "ranging");
  gsl_rng *r = nps_rng_stream_new(1, 0, 1);
  /* a reading, no echo (true range beyond the maximum: no reading with beyond_max none): all read -12.84, not
   * clamped to 0.2 m and not moved by the bias or rounded by the quantization after it in the file */
  assert_true(nps_sensor_chain_apply(s, 0.0, 1.0, NULL, NULL, r) == -12.84);
  assert_true(nps_sensor_chain_apply(s, 0.0, 5.0, NULL, NULL, r) == -12.84);
  /* no echo (dropout) with beyond_max max: 1e5 m, not the maximum 2.5 m */
  assert_true(nps_sensor_chain_apply(g, 0.0, 1.0, NULL, NULL, r) == 1e5);
  nps_sensor_model_free(m);
  m = from_text("sonar(beyond_max=max): glitch(p=1, values=inf) | ranging: glitch(p=1, values=-inf)");
  assert_true(nps_sensor_chain_apply(nps_sensor_model_chain(m, "sonar"), 0.0, 1.0, NULL, NULL, r) == INFINITY);
  assert_true(nps_sensor_chain_apply(nps_sensor_model_chain(m, "ranging"), 0.0, 1.0, NULL, NULL, r) == -INFINITY);
  gsl_rng_free(r);
  nps_sensor_model_free(m);
}

static void a_glitch_may_carry_a_condition(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: glitch(p=1, values=7) if ctx_vehicle == 2");
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar");
  const struct nps_sensor_ctx one = {.vehicle = 1}, two = {.vehicle = 2};
  gsl_rng *r = nps_rng_stream_new(1, 0, 1);
  assert_true(nps_sensor_chain_apply(s, 0.0, 1.25, &one, NULL, r) == 1.25);
  assert_true(nps_sensor_chain_apply(s, 0.0, 1.25, &two, NULL, r) == 7.0);
  gsl_rng_free(r);
  nps_sensor_model_free(m);
}

static void glitches_are_reproducible_and_p_moves_no_other_reading(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: gaussian(sigma=0.05); glitch(p=0.01, values=-1) "
                                         "| ranging: gaussian(sigma=0.05); glitch(p=0.02, values=-1)");
  const struct nps_sensor_chain *low = nps_sensor_model_chain(m, "sonar"), *high = nps_sensor_model_chain(m, "ranging");
  gsl_rng *a = nps_rng_stream_new(5, 1, 1), *b = nps_rng_stream_new(5, 1, 1), *c = nps_rng_stream_new(5, 1, 1);
  gsl_rng *other = nps_rng_stream_new(6, 1, 1);
  size_t same_seed_differs = 0, other_seed_same = 0, both_clear = 0, clear_differs = 0;
  for (int i = 0; i < 10000; i++) {
    const double x = nps_sensor_chain_apply(low, 0.0, 1.0, NULL, NULL, a);
    const double again = nps_sensor_chain_apply(low, 0.0, 1.0, NULL, NULL, b);
    const double y = nps_sensor_chain_apply(high, 0.0, 1.0, NULL, NULL, c);
    same_seed_differs += x != again;
    other_seed_same += x == nps_sensor_chain_apply(low, 0.0, 1.0, NULL, NULL, other);
    if (x != -1.0 && y != -1.0) {   /* the continuous error is the same draw whatever p is */
      both_clear++;
      clear_differs += x != y;
    }
  }
  assert_int_equal(same_seed_differs, 0);
  assert_true(other_seed_same < 10);
  assert_true(both_clear > 9500);
  assert_int_equal(clear_differs, 0);
  gsl_rng_free(a);
  gsl_rng_free(b);
  gsl_rng_free(c);
  gsl_rng_free(other);
  nps_sensor_model_free(m);
}

static void bad_glitches_are_refused(void **state)
{
  (void)state;
  const char *key[] = {"p", "values"};
  const char *nan_value[] = {"0.1", "-12.84 nan 3"}, *none[] = {"0.1", "  "}, *huge[] = {"0.1", "1 1e999"};
  const char *p_above[] = {"1.5", "1"}, *word[] = {"0.1", "1 far"};
  expect_refused("glitch", 2, key, nan_value,
                 "glitch values: 'nan' is not a number (finite or +-inf, never NaN)");
  expect_refused("glitch", 2, key, none, "glitch values: none given (1 to 64 numbers)");
  expect_refused("glitch", 2, key, huge, "glitch values: '1e999' is not a number (finite or +-inf, never NaN)");
  expect_refused("glitch", 2, key, word, "glitch values: 'far' is not a number (finite or +-inf, never NaN)");
  expect_refused("glitch", 2, key, p_above, "glitch p = 1.5 is outside [0, 1]");
  expect_refused("glitch", 1, key, nan_value, "effect 'glitch' needs parameter 'values'");
  char many[64 * 4 + 8] = "";
  for (int i = 0; i <= NPS_GLITCH_MAX_VALUES; i++) {
    strcat(many, "1.5 ");
  }
  const char *too_many[] = {"0.1", many};
  expect_refused("glitch", 2, key, too_many, "glitch values: more than 64 values");
  /* the numeric set-up takes no list: */
  const double p = 0.1;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_effect e;
  assert_int_equal(nps_effect_init(&e, "glitch", 1, &key[1], &p, err, sizeof(err)), -1);
  assert_string_equal(err, "parameter 'values' of effect 'glitch' is text (nps_effect_init_text)");
}

/* ---------------------------------------------------------------- bias_curve */

static const char *const curve_key[] = {"over", "at", "b"};

static void a_bias_curve_is_exact_at_its_knots_linear_between_and_constant_beyond(void **state)
{
  (void)state;
  const char *text[] = {"true_range", "0 10 30 60", "0.02 0.05 0.2 0.3"};
  const struct nps_effect e = make("bias_curve", 3, curve_key, text);
  const double knot[] = {0, 10, 30, 60}, b[] = {0.02, 0.05, 0.2, 0.3};
  for (int i = 0; i < 4; i++) {
    const struct nps_effect_env env = env_at(knot[i], NULL);
    assert_true(nps_effect_apply(&e, &env, 0.0, NULL) == b[i]);
  }
  const double between[][2] = {{5, 0.035}, {20, 0.125}, {17.5, 0.10625}, {45, 0.25}, {59, 0.3 - 0.1 / 30}};
  for (int i = 0; i < 5; i++) {
    const struct nps_effect_env env = env_at(between[i][0], NULL);
    assert_close(nps_effect_apply(&e, &env, 0.0, NULL), between[i][1], 1e-15);
  }
  const double beyond[][2] = {{-3, 0.02}, {-1e300, 0.02}, {60.5, 0.3}, {1e300, 0.3}, {INFINITY, 0.3}};
  for (int i = 0; i < 5; i++) {
    const struct nps_effect_env env = env_at(beyond[i][0], NULL);
    assert_true(nps_effect_apply(&e, &env, 0.0, NULL) == beyond[i][1]);
  }
  /* added to the reading; no echo and no reading pass through */
  const struct nps_effect_env env = env_at(30, NULL);
  assert_true(nps_effect_apply(&e, &env, 2.0, NULL) == 2.0 + 0.2);
  assert_true(nps_effect_apply(&e, &env, INFINITY, NULL) == INFINITY);
  assert_true(isnan(nps_effect_apply(&e, &env, NAN, NULL)));
}

static void a_bias_curve_follows_a_context_column(void **state)
{
  (void)state;
  /* the simulator's ctx_speed, and a replayed log's ctx_rssi (a model-defined slot) */
  const char *text = "sonar: bias_curve(over=ctx_speed, at=0 1 2, b=0 0.1 0.15) "
                     "| ranging: bias_curve(over=ctx_rssi, at=-90 -60, b=0.3 0)";
  const char *log_columns[] = {"ctx_rssi"};
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_text_for_log(text, strlen(text), "t", 1, log_columns, &m, err, sizeof(err)),
                   0);
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar"), *g = nps_sensor_model_chain(m, "ranging");
  const double speed[][2] = {{0, 0}, {0.5, 0.05}, {1, 0.1}, {1.5, 0.125}, {2, 0.15}, {7, 0.15}, {NAN, 0}};
  for (int i = 0; i < 7; i++) {
    const struct nps_sensor_ctx ctx = {.speed_mps = speed[i][0]};
    assert_close(nps_sensor_chain_apply(s, 0.0, 1.0, &ctx, NULL, NULL), 1.0 + speed[i][1], 1e-15);
  }
  const int rssi = nps_sensor_model_ctx_slot(m, "ctx_rssi");
  assert_true(rssi >= NPS_CTX_EXTRA0);
  const double power[][2] = {{-100, 0.3}, {-90, 0.3}, {-75, 0.15}, {-60, 0}, {-40, 0}};
  for (int i = 0; i < 5; i++) {
    struct nps_sensor_ctx ctx = {0};
    nps_sensor_ctx_set(&ctx, rssi, power[i][0]);
    assert_close(nps_sensor_chain_apply(g, 0.0, 1.0, &ctx, NULL, NULL), 1.0 + power[i][1], 1e-15);
  }
  /* the same text for the simulator: it has no ctx_rssi; a replay needs the column */
  nps_sensor_model_free(m);
  assert_int_equal(nps_sensor_model_from_string(text, "T", &m, err, sizeof(err)), -1);
  assert_string_equal(err, "T:1: bias_curve over 'ctx_rssi': unknown context column (the simulator has "
                      "ctx_facing_sonars, ctx_target_copter, ctx_blocked, ctx_wall_dist, ctx_speed, "
                      "ctx_crosstalk_path, ctx_trigger_offset, ctx_floor, ctx_target_obstacle, ctx_vehicle) (column 70)");
  m = from_text("ranging: bias_curve(over=ctx_speed, at=0 1, b=0 1)");
  const double *columns[NPS_CTX_SLOTS] = {NULL};
  assert_int_equal(nps_sensor_chain_check_columns(nps_sensor_model_chain(m, "ranging"), columns, err, sizeof(err)), -1);
  assert_string_equal(err, "bias_curve over 'ctx_speed' of the ranging chain's effect 1: the log has no such column");
  nps_sensor_model_free(m);
}

static void bad_bias_curves_are_refused(void **state)
{
  (void)state;
  const char *flat[] = {"true_range", "0 10 10 60", "0 1 2 3"}, *down[] = {"true_range", "0 -1", "0 1"};
  const char *lengths[] = {"true_range", "0 1 2", "0 1"}, *one[] = {"true_range", "0", "1"};
  const char *seventeen[] = {"true_range", "0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16", "0"};
  const char *inf_at[] = {"true_range", "0 inf", "0 1"}, *nan_b[] = {"true_range", "0 1", "0 nan"};
  expect_refused("bias_curve", 3, curve_key, flat, "bias_curve at: the knots must increase strictly (10 then 10)");
  expect_refused("bias_curve", 3, curve_key, down, "bias_curve at: the knots must increase strictly (0 then -1)");
  expect_refused("bias_curve", 3, curve_key, lengths,
                 "bias_curve: at has 3 values and b has 2 (need 2 to 16 knots, one b per knot)");
  expect_refused("bias_curve", 3, curve_key, one,
                 "bias_curve: at has 1 values and b has 1 (need 2 to 16 knots, one b per knot)");
  expect_refused("bias_curve", 3, curve_key, seventeen, "bias_curve at: more than 16 values");
  expect_refused("bias_curve", 3, curve_key, inf_at, "bias_curve at: 'inf' is not a finite number");
  expect_refused("bias_curve", 3, curve_key, nan_b, "bias_curve b: 'nan' is not a finite number");
  expect_refused("bias_curve", 2, curve_key, flat, "effect 'bias_curve' needs parameter 'b'");
  /* over must be true_range or a context column (the model's check, with the loaders' file:line) */
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_string("sonar: bias_curve(over=range, at=0 1, b=0 1)", "M", &m, err,
                   sizeof(err)), -1);
  assert_string_equal(err, "M:1: bias_curve over 'range' is not a context column (expected true_range or ctx_ followed "
                      "by a-z, 0-9, _) (column 8)");
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(glitches_happen_at_rate_p),
    cmocka_unit_test(each_value_is_drawn_with_its_share),
    cmocka_unit_test(a_glitch_replaces_any_reading_and_nothing_changes_it),
    cmocka_unit_test(a_glitch_may_carry_a_condition),
    cmocka_unit_test(glitches_are_reproducible_and_p_moves_no_other_reading),
    cmocka_unit_test(bad_glitches_are_refused),
    cmocka_unit_test(a_bias_curve_is_exact_at_its_knots_linear_between_and_constant_beyond),
    cmocka_unit_test(a_bias_curve_follows_a_context_column),
    cmocka_unit_test(bad_bias_curves_are_refused),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
