/*
 * Applying sensor-model chains (nps_sensor_model.h): range limits and beyond-max behaviour (exact), the
 * default sonar chain's law, and log replay (nps_sensor_chain_simulate) being the per-reading path run per
 * stream. Statistical conventions in test_effect_stats.h; N = 200000 readings per check.
 */
#include "test_helpers.h"
#include "test_effect_stats.h"

#include <string.h>
#include <gsl/gsl_cdf.h>

#include "nps_rng.h"
#include "nps_sensor_model.h"
#include "test_model_fixtures.h"

#define N 200000

static void limits_are_exact(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar(min_range=0.2, max_range=3.0, beyond_max=max): "
                                         "| ranging(min_range=0, max_range=2.5, beyond_max=none):");
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar"), *r = nps_sensor_model_chain(m, "ranging");
  assert_true(nps_sensor_chain_limit(s, 0.1) == 0.2);
  assert_true(nps_sensor_chain_limit(s, -INFINITY) == 0.2);
  assert_true(nps_sensor_chain_limit(s, 1.234) == 1.234);
  assert_true(nps_sensor_chain_limit(s, 3.01) == 3.0);
  assert_true(nps_sensor_chain_limit(s, INFINITY) == 3.0);   /* no echo: the maximum */
  assert_true(isnan(nps_sensor_chain_limit(r, INFINITY)));   /* no echo: no reading */
  assert_true(nps_sensor_chain_limit(r, 2.6) == 2.5);        /* a finite reading above: clamped */
  assert_true(isnan(nps_sensor_chain_limit(s, NAN)));
  gsl_rng *rng = nps_rng_stream_new(1, 0, 1);
  /* a true range beyond the maximum gives no echo */
  assert_true(nps_sensor_chain_apply(s, 0.0, 3.5, NULL, NULL, rng) == 3.0);
  assert_true(isnan(nps_sensor_chain_apply(r, 0.0, 2.6, NULL, NULL, rng)));
  assert_true(nps_sensor_chain_apply(r, 0.0, 2.5, NULL, NULL, rng) == 2.5);
  gsl_rng_free(rng);
  nps_sensor_model_free(m);
}

static void no_echo_effects_follow_the_sensor_configuration(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar(beyond_max=max): dropout(p=1) | ranging(beyond_max=none): dropout(p=1)");
  gsl_rng *rng = nps_rng_stream_new(1, 0, 1);
  assert_true(nps_sensor_chain_apply(nps_sensor_model_chain(m, "sonar"), 0, 1.0, NULL, NULL, rng) == 3.0);
  assert_true(isnan(nps_sensor_chain_apply(nps_sensor_model_chain(m, "ranging"), 0, 1.0, NULL, NULL, rng)));
  gsl_rng_free(rng);
  nps_sensor_model_free(m);
}

static void gaussian_only_clamps_at_the_minimum(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_load("conf/sensor_models/gaussian_only.xml", &m, err, sizeof(err)), 0);
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar");
  gsl_rng *rng = nps_rng_stream_new(2, 0, 1);
  size_t at_min = 0;
  for (size_t i = 0; i < N; i++) {
    double y = nps_sensor_chain_apply(s, 0, 0.2, NULL, NULL, rng);
    assert_true(y >= 0.2 && y <= 3.0);
    at_min += y == 0.2;
  }
  assert_rate(at_min, N, 0.5);  /* true range at the minimum: half the noisy readings fall below it */
  for (size_t i = 0; i < 1000; i++) {
    assert_true(nps_sensor_chain_apply(s, 0, 0.0, NULL, NULL, rng) == 0.2);  /* 10 sigma below: always clamped */
  }
  gsl_rng_free(rng);
  nps_sensor_model_free(m);
}

static double rayleigh_cdf(double x, const void *p)
{
  return x <= 0.0 ? 0.0 : gsl_cdf_rayleigh_P(x, *(const double *)p);
}

static void default_sonar_chain_rayleigh_then_geometric_crosstalk(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_load("conf/sensor_models/finken_default.xml", &m, err, sizeof(err)), 0);
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar");
  double sigma = s->effect[0].param[0], offset = s->effect[0].param[1], truth = 1.5;
  gsl_rng *rng = nps_rng_stream_new(3, 0, 1);
  double *r = malloc(N * sizeof(double));
  for (size_t i = 0; i < N; i++) {
    r[i] = truth - nps_sensor_chain_apply(s, 0, truth, NULL, NULL, rng) + offset;  /* the Rayleigh variate */
  }
  assert_ks_accepts(stats_ks_test(r, N, rayleigh_cdf, &sigma));
  double wrong = 1.03 * sigma;
  assert_ks_rejects(stats_ks_test(r, N, rayleigh_cdf, &wrong));
  /* a facing emitter 2.2 m away fired 1 ms later: 68 % of readings are (2.2 + 0.343) / 2 */
  struct nps_sensor_ctx facing = {.facing_sonars = 1, .crosstalk_path_m = 2.2, .trigger_offset_s = 0.001};
  size_t heard = 0;
  for (size_t i = 0; i < N; i++) {
    heard += nps_sensor_chain_apply(s, 0, truth, &facing, NULL, rng) == 0.5 * (2.2 + 343.0 * 0.001);
  }
  assert_rate(heard, N, 0.68);
  free(r);
  gsl_rng_free(rng);
  nps_sensor_model_free(m);
}

/** Rows of three interleaved streams with context, for replay. */
struct rows {
  size_t n;
  double t[300], truth[300], blocked[300];
  uint32_t index[300];
};

static void what_a_chain_reads(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: rayleigh_short(sigma=0.05); crosstalk(p=0.5) "
                                         "| ranging: bias(b=0.1) if ctx_wall_dist; latency(tau=0.1)");
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar"), *r = nps_sensor_model_chain(m, "ranging");
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    const bool crosstalk_slot = slot == NPS_CTX_FACING_SONARS || slot == NPS_CTX_CROSSTALK_PATH ||
                                slot == NPS_CTX_TRIGGER_OFFSET;
    assert_int_equal(nps_sensor_chain_reads_ctx(s, slot), crosstalk_slot);
    assert_int_equal(nps_sensor_chain_reads_ctx(r, slot), slot == NPS_CTX_WALL_DIST);
  }
  assert_false(nps_sensor_chain_reads_state(s));
  assert_true(nps_sensor_chain_reads_state(r));
  nps_sensor_model_free(m);
}

static void a_chain_without_latency_ignores_the_state(void **state)
{
  (void)state;
  /* the host passes no state to such a chain: the readings are the same draws either way */
  struct nps_sensor_model *m = from_text("sonar: rayleigh_short(sigma=0.05); crosstalk(p=0.5); dropout(p=0.1)");
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar");
  gsl_rng *a = nps_rng_stream_new(3, 1, 1), *b = nps_rng_stream_new(3, 1, 1);
  struct nps_sensor_state st;
  nps_sensor_state_init(&st);
  const struct nps_sensor_ctx ctx = {.facing_sonars = 1, .crosstalk_path_m = 1.0};
  for (int i = 0; i < 1000; i++) {
    const double t_s = 0.05 * i, true_m = 0.3 + 0.002 * i;
    const double with_state = nps_sensor_chain_apply(s, t_s, true_m, &ctx, &st, a);
    const double without = nps_sensor_chain_apply(s, t_s, true_m, &ctx, NULL, b);
    assert_memory_equal(&with_state, &without, sizeof(double));
  }
  gsl_rng_free(a);
  gsl_rng_free(b);
  nps_sensor_model_free(m);
}

static void make_rows(struct rows *rows)
{
  rows->n = 300;
  for (size_t i = 0; i < rows->n; i++) {
    rows->index[i] = (uint32_t)(i % 3);
    rows->t[i] = 0.05 * (double)(i / 3);
    rows->truth[i] = 1.0 + 0.4 * sin(rows->t[i] + (double)rows->index[i]);
    rows->blocked[i] = (i / 7) % 2;
  }
}

static void replay_is_the_per_reading_path_per_stream(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("ranging: gmm(mixture=conf/sensor_models/finken_ranging_gmm_k100.xml); "
                                         "latency(tau=0.12); nlos_bias(mean=0.3) if ctx_blocked; quantization(step=0.01)");
  const struct nps_sensor_chain *c = nps_sensor_model_chain(m, "ranging");
  static struct rows rows;
  make_rows(&rows);
  const int64_t keys[3] = {11, 12, 40};
  const double *columns[NPS_CTX_SLOTS] = {NULL};
  columns[NPS_CTX_BLOCKED] = rows.blocked;
  double out[300], again[300], other_seed[300];
  char err[256];
  assert_int_equal(nps_sensor_chain_simulate(c, 99, rows.n, rows.t, rows.truth, rows.index, 3, keys, columns, out,
                                             err, sizeof(err)), 0);
  /* the same rows through nps_sensor_chain_apply, one state and generator per stream */
  struct nps_sensor_state st[3];
  gsl_rng *rng[3];
  for (int s = 0; s < 3; s++) {
    nps_sensor_state_init(&st[s]);
    rng[s] = nps_rng_stream_new(99, (uint64_t)keys[s], NPS_RNG_SENSOR_REPLAY_RANGING);
  }
  for (size_t i = 0; i < rows.n; i++) {
    struct nps_sensor_ctx ctx = {.blocked = rows.blocked[i]};
    uint32_t s = rows.index[i];
    assert_true(out[i] == nps_sensor_chain_apply(c, rows.t[i], rows.truth[i], &ctx, &st[s], rng[s]));
  }
  for (int s = 0; s < 3; s++) {
    gsl_rng_free(rng[s]);
  }
  /* reproducible for a seed, different for another */
  assert_int_equal(nps_sensor_chain_simulate(c, 99, rows.n, rows.t, rows.truth, rows.index, 3, keys, columns, again,
                                             err, sizeof(err)), 0);
  assert_memory_equal(out, again, sizeof(out));
  assert_int_equal(nps_sensor_chain_simulate(c, 100, rows.n, rows.t, rows.truth, rows.index, 3, keys, columns,
                                             other_seed, err, sizeof(err)), 0);
  assert_true(memcmp(out, other_seed, sizeof(out)) != 0);
  /* a bad stream index is an error, not a crash */
  rows.index[5] = 3;
  assert_int_equal(nps_sensor_chain_simulate(c, 99, rows.n, rows.t, rows.truth, rows.index, 3, keys, columns, out,
                                             err, sizeof(err)), -1);
  assert_non_null(strstr(err, "row 5: stream index 3"));
  nps_sensor_model_free(m);
}

static void replay_refuses_a_condition_on_a_column_the_log_lacks(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("ranging: gaussian(sigma=0.1); nlos_bias(mean=0.3) if ctx_blocked");
  const struct nps_sensor_chain *c = nps_sensor_model_chain(m, "ranging");
  static struct rows rows;
  make_rows(&rows);
  const int64_t keys[3] = {1, 2, 3};
  const double *columns[NPS_CTX_SLOTS] = {NULL};
  columns[NPS_CTX_SPEED] = rows.blocked;   /* a log with another column only */
  double out[300];
  char err[256];
  for (int with_columns = 0; with_columns < 2; with_columns++) {
    assert_int_equal(nps_sensor_chain_simulate(c, 1, rows.n, rows.t, rows.truth, rows.index, 3, keys,
                                               with_columns ? columns : NULL, out, err, sizeof(err)), -1);
    assert_string_equal(err, "condition 'ctx_blocked' of the ranging chain's effect 2 (nlos_bias): the log has no "
                        "such column");
  }
  columns[NPS_CTX_BLOCKED] = rows.blocked;
  assert_int_equal(nps_sensor_chain_check_columns(c, columns, err, sizeof(err)), 0);
  nps_sensor_model_free(m);
}

static void a_stream_does_not_depend_on_the_others(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: rayleigh_short(sigma=0.05); latency(tau=0.1)");
  const struct nps_sensor_chain *c = nps_sensor_model_chain(m, "sonar");
  static struct rows rows;
  make_rows(&rows);
  const int64_t keys[3] = {1, 2, 3};
  double all[300], alone[100], t[100], truth[100];
  uint32_t zero[100] = {0};
  char err[256];
  assert_int_equal(nps_sensor_chain_simulate(c, 5, rows.n, rows.t, rows.truth, rows.index, 3, keys, NULL, all, err,
                                             sizeof(err)), 0);
  for (size_t i = 0; i < 100; i++) {
    t[i] = rows.t[3 * i + 1];
    truth[i] = rows.truth[3 * i + 1];
  }
  assert_int_equal(nps_sensor_chain_simulate(c, 5, 100, t, truth, zero, 1, &keys[1], NULL, alone, err, sizeof(err)), 0);
  for (size_t i = 0; i < 100; i++) {
    assert_true(all[3 * i + 1] == alone[i]);
  }
  nps_sensor_model_free(m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(limits_are_exact),
    cmocka_unit_test(no_echo_effects_follow_the_sensor_configuration),
    cmocka_unit_test(gaussian_only_clamps_at_the_minimum),
    cmocka_unit_test(default_sonar_chain_rayleigh_then_geometric_crosstalk),
    cmocka_unit_test(what_a_chain_reads),
    cmocka_unit_test(a_chain_without_latency_ignores_the_state),
    cmocka_unit_test(replay_is_the_per_reading_path_per_stream),
    cmocka_unit_test(replay_refuses_a_condition_on_a_column_the_log_lacks),
    cmocka_unit_test(a_stream_does_not_depend_on_the_others),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
