/*
 * Which context values a chain reads (nps_sensor_chain_reads_ctx, nps_sensor_model_ctx.h), the answer hosts
 * use to skip computing the others (a condition's columns, cross-talk's three, a bias curve's `over`). The claim
 * checked for every effect of the library (but gmm, which needs a mixture and reads no context): an effect whose
 * output changes with a context slot is declared to read it.
 * Each effect (parameters 0.5, where the effect then acts) is applied N_READINGS times to true ranges spread over
 * [0.2, 2.5] m with the same generator seed twice: once with every slot at CTX_BASE, once with one slot at
 * CTX_MOVED. Small values, so that crosstalk's first-echo rule min(x, (path + c offset) / 2) shows both its
 * path and its trigger offset.
 */
#include "test_helpers.h"

#include <string.h>

#include "nps_rng.h"
#include "nps_sensor_model.h"
#include "test_model_fixtures.h"

#define N_READINGS 200
#define CTX_BASE 0.001
#define CTX_MOVED 0.002

/** The inline model of one sonar chain holding effect `kind` with every parameter 0.5, and text parameters where
 * it has them (a glitch reads 0.5; a bias curve over ctx_speed, b(u) = u / 2 on [0, 1]). */
static void one_effect_model(int kind, char *text, size_t len)
{
  size_t n = (size_t)snprintf(text, len, "sonar(min_range=0, max_range=3): %s(", nps_effect_name(kind));
  for (size_t j = 0; j < nps_effect_param_count(kind); j++) {
    n += (size_t)snprintf(text + n, len - n, "%s%s=0.5", j ? ", " : "", nps_effect_param_name(kind, j));
  }
  const char *text_params = kind == NPS_EFFECT_GLITCH ? "values=0.5"
                            : kind == NPS_EFFECT_BIAS_CURVE ? "over=ctx_speed, at=0 1, b=0 0.5" : "";
  snprintf(text + n, len - n, "%s%s)", nps_effect_param_count(kind) > 0 && text_params[0] ? ", " : "", text_params);
}

/** True when some reading differs between every slot at CTX_BASE and slot `slot` alone at CTX_MOVED. */
static bool output_depends_on(const struct nps_sensor_chain *chain, int slot)
{
  struct nps_sensor_ctx base, moved;
  for (int s = 0; s < NPS_CTX_SLOTS; s++) {
    nps_sensor_ctx_set(&base, s, CTX_BASE);
    nps_sensor_ctx_set(&moved, s, s == slot ? CTX_MOVED : CTX_BASE);
  }
  gsl_rng *ra = nps_rng_stream_new(7, 1, 1), *rb = nps_rng_stream_new(7, 1, 1);
  struct nps_sensor_state sa, sb;
  nps_sensor_state_init(&sa);
  nps_sensor_state_init(&sb);
  bool differs = false;
  for (int i = 0; i < N_READINGS; i++) {
    double t_s = 0.05 * i, true_m = 0.2 + 2.3 * i / (N_READINGS - 1.0);
    double a = nps_sensor_chain_apply(chain, t_s, true_m, &base, &sa, ra);
    double b = nps_sensor_chain_apply(chain, t_s, true_m, &moved, &sb, rb);
    differs = differs || !(a == b || (isnan(a) && isnan(b)));
  }
  gsl_rng_free(ra);
  gsl_rng_free(rb);
  return differs;
}

static void an_effect_that_depends_on_a_slot_reads_it(void **state)
{
  (void)state;
  for (int kind = 0; kind < NPS_EFFECT_COUNT; kind++) {
    if (kind == NPS_EFFECT_GMM) {
      continue;
    }
    char text[256];
    one_effect_model(kind, text, sizeof(text));
    struct nps_sensor_model *m = from_text(text);
    const struct nps_sensor_chain *chain = nps_sensor_model_chain(m, "sonar");
    for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
      if (output_depends_on(chain, slot) && !nps_sensor_chain_reads_ctx(chain, slot)) {
        print_error("%s depends on %s, which nps_sensor_chain_reads_ctx denies\n", text,
                    nps_sensor_ctx_fixed_name(slot) ? nps_sensor_ctx_fixed_name(slot) : "an extra slot");
        fail();
      }
    }
    nps_sensor_model_free(m);
  }
}

static void crosstalk_reads_its_three_slots_and_no_other(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: crosstalk(p=0.68)");
  const struct nps_sensor_chain *chain = nps_sensor_model_chain(m, "sonar");
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    bool expected = slot == NPS_CTX_FACING_SONARS || slot == NPS_CTX_CROSSTALK_PATH || slot == NPS_CTX_TRIGGER_OFFSET;
    assert_int_equal(nps_sensor_chain_reads_ctx(chain, slot), expected);
  }
  nps_sensor_model_free(m);
}

static void a_condition_is_read_and_only_it(void **state)
{
  (void)state;
  const char *text = "ranging(max_range=2.5): bias(b=0.1) if ctx_blocked; gaussian(sigma=0.1) if ctx_lab_humidity";
  const char *log_columns[] = {"ctx_lab_humidity"};   /* a column of a lab log, not the simulator's */
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_text_for_log(text, strlen(text), "test", 1, log_columns, &m, err,
                   sizeof(err)), 0);
  const struct nps_sensor_chain *chain = nps_sensor_model_chain(m, "ranging");
  const int extra = nps_sensor_model_ctx_slot(m, "ctx_lab_humidity");
  assert_true(extra >= NPS_CTX_EXTRA0);
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    assert_int_equal(nps_sensor_chain_reads_ctx(chain, slot), slot == NPS_CTX_BLOCKED || slot == extra);
  }
  assert_false(nps_sensor_chain_reads_ctx(chain, -1));   /* -1 is "unconditional", not a slot */
  nps_sensor_model_free(m);
}

static void a_bias_curve_reads_its_column_and_only_it(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("sonar: bias_curve(over=ctx_wall_dist, at=0 1, b=0.1 0) "
                                         "| ranging: bias_curve(over=true_range, at=0 1, b=0.1 0)");
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    assert_int_equal(nps_sensor_chain_reads_ctx(nps_sensor_model_chain(m, "sonar"), slot), slot == NPS_CTX_WALL_DIST);
    assert_false(nps_sensor_chain_reads_ctx(nps_sensor_model_chain(m, "ranging"), slot));
  }
  nps_sensor_model_free(m);
}

static void the_default_ranging_chain_reads_no_context(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("ranging(max_range=2.5): gmm(mixture=conf/sensor_models/finken_ranging_gmm_k100.xml)");
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    assert_false(nps_sensor_chain_reads_ctx(nps_sensor_model_chain(m, "ranging"), slot));
  }
  assert_false(nps_sensor_chain_reads_ctx(NULL, NPS_CTX_BLOCKED));
  nps_sensor_model_free(m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(an_effect_that_depends_on_a_slot_reads_it),
    cmocka_unit_test(crosstalk_reads_its_three_slots_and_no_other),
    cmocka_unit_test(a_condition_is_read_and_only_it),
    cmocka_unit_test(a_bias_curve_reads_its_column_and_only_it),
    cmocka_unit_test(the_default_ranging_chain_reads_no_context),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
