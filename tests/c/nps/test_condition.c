/*
 * Conditions of sensor-model effects (nps_condition.h): evaluation over columns (nps_condition_mask) and over a
 * reading's context, the canonical text, the parser's errors, and conditions in models (context slots, the
 * loaders' file:line errors, the columns a replay needs). Every expected value is worked out by hand.
 */
#include "test_helpers.h"

#include <float.h>
#include <string.h>

#include "nps_condition.h"
#include "nps_rng.h"
#include "nps_sensor_model.h"
#include "test_model_fixtures.h"

#define MAX_ROWS 16

static struct nps_condition parsed(const char *text)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_condition c;
  if (nps_condition_parse(&c, text, strlen(text), NULL, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  return c;
}

/** Where `condition` holds on rows of the columns ctx_nlos and ctx_rssi, as '0'/'1' characters. */
static const char *mask(const char *condition, const double *nlos, const double *rssi, size_t n)
{
  static char text[MAX_ROWS + 1];
  const char *names[] = {"ctx_nlos", "ctx_rssi"};
  const double *columns[] = {nlos, rssi};
  unsigned char out[MAX_ROWS];
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  assert_true(n <= MAX_ROWS);
  if (nps_condition_mask(condition, 2, names, columns, n, out, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  for (size_t i = 0; i < n; i++) {
    text[i] = (char)('0' + out[i]);
  }
  text[n] = '\0';
  return text;
}

static void equal_zero_on_a_flag(void **state)
{
  (void)state;
  const double nlos[] = {0.0, 1.0, -0.0, NAN, 2.0, 1e-300, -1.0};
  const size_t n = sizeof(nlos) / sizeof(nlos[0]);
  assert_string_equal(mask("ctx_nlos == 0", nlos, nlos, n), "1010000");
  assert_string_equal(mask("ctx_nlos", nlos, nlos, n), "0100111");   /* non-zero, as before */
  assert_string_equal(mask("ctx_nlos != 0", nlos, nlos, n), "0100111");
}

static void a_threshold_from_both_sides(void **state)
{
  (void)state;
  const double rssi[] = {-90.0, -85.5, nextafter(-85.5, -INFINITY), nextafter(-85.5, INFINITY), INFINITY,
                         -INFINITY, NAN
                        };
  const size_t n = sizeof(rssi) / sizeof(rssi[0]);
  assert_string_equal(mask("ctx_rssi < -85.5", rssi, rssi, n), "1010010");
  assert_string_equal(mask("ctx_rssi<=-85.5", rssi, rssi, n), "1110010");
  assert_string_equal(mask("ctx_rssi > -85.5", rssi, rssi, n), "0001100");
  assert_string_equal(mask("ctx_rssi>= -85.5", rssi, rssi, n), "0101100");
  assert_string_equal(mask("ctx_rssi == -85.5", rssi, rssi, n), "0100000");
  assert_string_equal(mask("ctx_rssi != -85.5", rssi, rssi, n), "1011110");
}

static void nan_satisfies_no_term(void **state)
{
  (void)state;
  struct nps_condition_term term = {.column = "ctx_x", .value = 0.0, .slot = -1};
  for (int op = NPS_CONDITION_NONZERO; op <= NPS_CONDITION_GE; op++) {
    term.op = (enum nps_condition_op)op;
    assert_false(nps_condition_term_holds(&term, NAN));
  }
}

static void two_terms_must_both_hold(void **state)
{
  (void)state;
  const double nlos[] = {0.0, 0.0, 1.0, NAN, 0.0};
  const double rssi[] = {-90.0, -80.0, -90.0, -90.0, NAN};
  assert_string_equal(mask("ctx_nlos == 0 and ctx_rssi < -85.5", nlos, rssi, 5), "10000");
  /* one column twice: an interval */
  const double d[] = {0.5, 1.0, 1.5, 2.0};
  assert_string_equal(mask("ctx_rssi > 0.5 and ctx_rssi <= 1.5", d, d, 4), "0110");
}

static void an_effect_applies_where_its_condition_holds(void **state)
{
  (void)state;
  struct nps_sensor_model *m = from_text("ranging(max_range=10): bias(b=1) if ctx_blocked == 0 and "
                                         "ctx_wall_dist < 0.5");
  const struct nps_sensor_chain *chain = nps_sensor_model_chain(m, "ranging");
  gsl_rng *r = nps_rng_stream_new(1, 0, NPS_RNG_SENSOR_RANGING_BASE);
  const struct nps_sensor_ctx near = {.wall_dist_m = 0.3}, blocked = {.blocked = 1.0, .wall_dist_m = 0.3},
                              far = {.wall_dist_m = 0.7}, unknown = {.wall_dist_m = NAN};
  assert_true(nps_sensor_chain_apply(chain, 0.0, 2.0, &near, NULL, r) == 3.0);
  assert_true(nps_sensor_chain_apply(chain, 0.0, 2.0, &blocked, NULL, r) == 2.0);
  assert_true(nps_sensor_chain_apply(chain, 0.0, 2.0, &far, NULL, r) == 2.0);
  assert_true(nps_sensor_chain_apply(chain, 0.0, 2.0, &unknown, NULL, r) == 2.0);
  assert_true(nps_sensor_chain_apply(chain, 0.0, 2.0, NULL, NULL, r) == 3.0);   /* NULL: all zero */
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    assert_int_equal(nps_sensor_chain_reads_ctx(chain, slot), slot == NPS_CTX_BLOCKED || slot == NPS_CTX_WALL_DIST);
  }
  gsl_rng_free(r);
  nps_sensor_model_free(m);
}

static void the_canonical_text(void **state)
{
  (void)state;
  static const char *const cases[][2] = {
    {"ctx_blocked", "ctx_blocked"},
    {"  ctx_blocked ", "ctx_blocked"},
    {"ctx_rssi<-85", "ctx_rssi < -85"},
    {"ctx_rssi<=-85.50", "ctx_rssi <= -85.5"},
    {"ctx_a==0.0   and ctx_b!=1e3", "ctx_a == 0 and ctx_b != 1000"},
    {"ctx_a > 1e-5", "ctx_a > 1e-05"},
    {"ctx_a > 0.0001", "ctx_a > 0.0001"},
    {"ctx_a >= 1e16", "ctx_a >= 1e+16"},
    {"ctx_a >= 1e15", "ctx_a >= 1000000000000000"},
    {"ctx_a >= 123456789012345678", "ctx_a >= 1.2345678901234568e+17"},
    {"ctx_a < 0x1p-2", "ctx_a < 0.25"},
    {"ctx_a < 0.1", "ctx_a < 0.1"},
    {"ctx_a < -0", "ctx_a < -0"},
  };
  char text[NPS_CONDITION_TEXT_LEN], err[NPS_SENSOR_MODEL_ERR_LEN];
  for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
    assert_int_equal(nps_condition_canonical(cases[i][0], text, sizeof(text), err, sizeof(err)), 0);
    assert_string_equal(text, cases[i][1]);
  }
  /* the number reads back as the same double, and the text is a fixed point */
  uint32_t x = 11;
  const double special[] = {1.0 / 3.0, DBL_MAX, -DBL_MIN, -0.0, 0.1 + 0.2, 4503599627370497.0};
  for (int i = 0; i < 2000; i++) {
    const double v = i < 6 ? special[i] : (lcg_uniform(&x, -1.0, 1.0) * pow(10.0, floor(lcg_uniform(&x, -300, 300))));
    char given[64];
    snprintf(given, sizeof(given), "ctx_a < %.17g", v);
    const struct nps_condition c = parsed(given), again = parsed(c.text);
    assert_true(memcmp(&c.term[0].value, &v, sizeof(v)) == 0 && memcmp(&again.term[0].value, &v, sizeof(v)) == 0);
    assert_string_equal(again.text, c.text);
  }
}

static void the_columns_of_a_condition(void **state)
{
  (void)state;
  char columns[NPS_CONDITION_TEXT_LEN], err[NPS_SENSOR_MODEL_ERR_LEN];
  assert_int_equal(nps_condition_columns("ctx_nlos == 0 and ctx_rssi < -85.5", columns, sizeof(columns), err,
                                         sizeof(err)), 2);
  assert_string_equal(columns, "ctx_nlos ctx_rssi");
  assert_int_equal(nps_condition_columns("ctx_d > 0.5 and ctx_d <= 1.5", columns, sizeof(columns), err, sizeof(err)),
                   1);
  assert_string_equal(columns, "ctx_d");
  assert_int_equal(nps_condition_columns("ctx_d >", columns, sizeof(columns), err, sizeof(err)), -1);
  assert_string_equal(err, "condition 'ctx_d >': expected a number after '>'");
  /* a mask needs every column */
  const char *names[] = {"ctx_nlos"};
  const double zero = 0.0, *column[] = {&zero};
  unsigned char out;
  assert_int_equal(nps_condition_mask("ctx_nlos and ctx_rssi > 1", 1, names, column, 1, &out, err, sizeof(err)), -1);
  assert_string_equal(err, "condition 'ctx_nlos and ctx_rssi > 1': no column 'ctx_rssi' was given");
}

/** The parser refuses `text` with `reason`, at offset `pos`. */
static void expect_parse_error(const char *text, size_t pos, const char *reason)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN], expected[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_condition c;
  size_t at = 999;
  assert_int_equal(nps_condition_parse(&c, text, strlen(text), &at, err, sizeof(err)), -1);
  snprintf(expected, sizeof(expected), "condition '%s': %s", text, reason);
  assert_string_equal(err, expected);
  assert_int_equal(at, pos);
}

static void a_malformed_condition_is_refused_with_its_reason(void **state)
{
  (void)state;
  expect_parse_error("", 0, "expected a context column");
  expect_parse_error("1 < ctx_a", 0, "expected a context column");
  expect_parse_error("ctx_a or ctx_b", 6, "'or' is not supported (terms are joined by 'and')");
  expect_parse_error("ctx_a = 1", 6, "unknown operator '=' (expected ==, !=, <, <=, >, >=)");
  expect_parse_error("ctx_a =< 1", 6, "unknown operator '=<' (expected ==, !=, <, <=, >, >=)");
  expect_parse_error("ctx_a <", 7, "expected a number after '<'");
  expect_parse_error("ctx_a < x", 8, "'x' is not a finite number");
  expect_parse_error("ctx_a < nan", 8, "'nan' is not a finite number");
  expect_parse_error("ctx_a < 1e999", 8, "'1e999' is not a finite number");
  expect_parse_error("ctx_a < 5and ctx_b", 8, "'5and' is not a finite number");
  expect_parse_error("ctx_a and ctx_b and ctx_c", 16, "at most 2 terms are joined by 'and'");
  expect_parse_error("ctx_a > 1 ctx_b", 10, "unexpected 'ctx_b' (expected 'and' or the end)");
  expect_parse_error("ctx_a ctx_b", 6, "unexpected 'ctx_b' (expected an operator (==, !=, <, <=, >, >=), 'and' or "
                     "the end)");
  expect_parse_error("ctx_a and", 9, "expected a context column after 'and'");
  expect_parse_error("ctx_a_column_name_of_forty_eight_characters_xxxx", 0, "a column name has at most 47 characters");
}

/** The loader's result rc and model *m: refused with `expected` as its whole error, no model. */
static void expect_refused(int rc, struct nps_sensor_model *const *m, const char *err, const char *expected)
{
  assert_int_equal(rc, -1);
  assert_null(*m);
  assert_string_equal(err, expected);
}

#define SIMULATOR_COLUMNS "ctx_facing_sonars, ctx_target_copter, ctx_blocked, ctx_wall_dist, ctx_speed, " \
  "ctx_crosstalk_path, ctx_trigger_offset, ctx_floor, ctx_target_obstacle, ctx_vehicle"

static int load_xml_condition(const char *condition, struct nps_sensor_model **m, char *err, size_t err_len)
{
  char xml[512];
  snprintf(xml, sizeof(xml), "<sensor_model>\n<ranging>\n<effect name=\"bias\" b=\"0.1\" condition=\"%s\"/>\n"
           "</ranging>\n</sensor_model>\n", condition);
  return nps_sensor_model_load_memory(xml, strlen(xml), "mem", NULL, m, err, err_len);
}

static void the_loaders_name_file_line_and_column(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  /* XML: the condition attribute, '<' written &lt; */
  assert_int_equal(load_xml_condition("ctx_wall_dist &lt; 0.5 and ctx_speed&gt;=1", &m, err, sizeof(err)), 0);
  assert_string_equal(nps_effect_condition(nps_sensor_chain_effect(nps_sensor_model_chain(m, "ranging"), 0)),
                      "ctx_wall_dist < 0.5 and ctx_speed >= 1");
  nps_sensor_model_free(m);
  expect_refused(load_xml_condition("ctx_blocked or ctx_speed", &m, err, sizeof(err)), &m, err,
                 "mem:3: condition 'ctx_blocked or ctx_speed': 'or' is not supported (terms are joined by 'and')");
  expect_refused(load_xml_condition("ctx_a and ctx_b and ctx_c", &m, err, sizeof(err)), &m, err,
                 "mem:3: condition 'ctx_a and ctx_b and ctx_c': at most 2 terms are joined by 'and'");
  expect_refused(load_xml_condition("ctx_blocked and ctx_nope &lt; 1", &m, err, sizeof(err)), &m, err,
                 "mem:3: condition 'ctx_nope': unknown context column (the simulator has " SIMULATOR_COLUMNS ")");
  /* the one-line form: the condition is the rest of the effect, the column where the error is */
  expect_refused(nps_sensor_model_from_string("ranging: bias(b=0.1) if ctx_blocked and ctx_speed > fast; "
                 "gaussian(sigma=0.1)", "X", &m, err, sizeof(err)), &m, err,
                 "X:1: condition 'ctx_blocked and ctx_speed > fast': 'fast' is not a finite number (column 53)");
  expect_refused(nps_sensor_model_from_string("ranging: bias(b=0.1) if ctx_blocked and ctx_nope < 1", "X", &m, err,
                 sizeof(err)), &m, err,
                 "X:1: condition 'ctx_nope': unknown context column (the simulator has " SIMULATOR_COLUMNS ") "
                 "(column 25)");
  expect_refused(nps_sensor_model_from_string("ranging: bias(b=0.1) if ctx_blocked and speed > 1", "X", &m, err,
                 sizeof(err)), &m, err,
                 "X:1: condition 'speed' is not a context column (expected ctx_ followed by a-z, 0-9, _) (column 10)");
  m = from_text("sonar: bias(b=0.1) if ctx_blocked | ranging: gaussian(sigma=0.1) if ctx_speed<=2; bias(b=1)");
  assert_string_equal(nps_effect_condition(nps_sensor_chain_effect(nps_sensor_model_chain(m, "sonar"), 0)),
                      "ctx_blocked");
  assert_string_equal(nps_effect_condition(nps_sensor_chain_effect(nps_sensor_model_chain(m, "ranging"), 0)),
                      "ctx_speed <= 2");
  assert_null(nps_effect_condition(nps_sensor_chain_effect(nps_sensor_model_chain(m, "ranging"), 1)));
  nps_sensor_model_free(m);
}

static void a_replay_needs_every_column_of_a_condition(void **state)
{
  (void)state;
  const char *text = "ranging(max_range=100): bias(b=1) if ctx_nlos == 0 and ctx_rssi < -85.5";
  const char *log_columns[] = {"ctx_nlos", "ctx_rssi"};
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_text_for_log(text, strlen(text), "X", 2, log_columns, &m, err, sizeof(err)),
                   0);
  const struct nps_sensor_chain *chain = nps_sensor_model_chain(m, "ranging");
  const int nlos_slot = nps_sensor_model_ctx_slot(m, "ctx_nlos"), rssi_slot = nps_sensor_model_ctx_slot(m, "ctx_rssi");
  assert_int_equal(nlos_slot, NPS_CTX_EXTRA0);
  assert_int_equal(rssi_slot, NPS_CTX_EXTRA0 + 1);
  for (int slot = 0; slot < NPS_CTX_SLOTS; slot++) {
    assert_int_equal(nps_sensor_chain_reads_ctx(chain, slot), slot == nlos_slot || slot == rssi_slot);
  }
  const double nlos[] = {0, 0, 1, 0}, rssi[] = {-90, -80, -90, NAN}, t[] = {0, 1, 2, 3}, truth[] = {5, 5, 5, 5};
  const uint32_t stream[] = {0, 0, 0, 0};
  const int64_t key = 1;
  const double *columns[NPS_CTX_SLOTS] = {NULL};
  double out[4];
  columns[nlos_slot] = nlos;
  assert_int_equal(nps_sensor_chain_check_columns(chain, columns, err, sizeof(err)), -1);
  assert_string_equal(err, "condition 'ctx_nlos == 0 and ctx_rssi < -85.5' of the ranging chain's effect 1 (bias): "
                      "the log has no column ctx_rssi");
  columns[rssi_slot] = rssi;
  assert_int_equal(nps_sensor_chain_simulate(chain, 1, 4, t, truth, stream, 1, &key, columns, out, err, sizeof(err)),
                   0);
  assert_true(out[0] == 6.0 && out[1] == 5.0 && out[2] == 5.0 && out[3] == 5.0);
  nps_sensor_model_free(m);
}

static void a_refused_condition_takes_no_context_slot(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN], text[64];
  struct nps_sensor_model *m = nps_sensor_model_new();
  const char *bk[] = {"b"}, *bv[] = {"0"};
  assert_int_equal(nps_sensor_model_add_chain(m, "sonar", 0, NULL, NULL, err, sizeof(err)), 0);
  for (int i = 0; i < NPS_CTX_EXTRA_MAX - 1; i++) {
    snprintf(text, sizeof(text), "ctx_extra_%d", i);
    const struct nps_condition c = parsed(text);
    assert_int_equal(nps_sensor_model_add_effect(m, "sonar", "bias", 1, bk, bv, &c, NULL, err, sizeof(err)), 0);
  }
  /* one slot left: two new columns are refused and the first of them is not kept */
  struct nps_condition two = parsed("ctx_new_a > 1 and ctx_new_b > 1");
  assert_int_equal(nps_sensor_model_add_effect(m, "sonar", "bias", 1, bk, bv, &two, NULL, err, sizeof(err)), -1);
  assert_string_equal(err, "condition 'ctx_new_b': a model may name at most 8 context columns besides the fixed ones");
  assert_int_equal(m->n_ctx_extra, NPS_CTX_EXTRA_MAX - 1);
  assert_int_equal(nps_sensor_model_ctx_slot(m, "ctx_new_a"), -1);
  /* a new column and a known one fit */
  two = parsed("ctx_new_b > 1 and ctx_extra_0");
  assert_int_equal(nps_sensor_model_add_effect(m, "sonar", "bias", 1, bk, bv, &two, NULL, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_ctx_slot(m, "ctx_new_b"), NPS_CTX_EXTRA0 + NPS_CTX_EXTRA_MAX - 1);
  nps_sensor_model_free(m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(equal_zero_on_a_flag),
    cmocka_unit_test(a_threshold_from_both_sides),
    cmocka_unit_test(nan_satisfies_no_term),
    cmocka_unit_test(two_terms_must_both_hold),
    cmocka_unit_test(an_effect_applies_where_its_condition_holds),
    cmocka_unit_test(the_canonical_text),
    cmocka_unit_test(the_columns_of_a_condition),
    cmocka_unit_test(a_malformed_condition_is_refused_with_its_reason),
    cmocka_unit_test(the_loaders_name_file_line_and_column),
    cmocka_unit_test(a_replay_needs_every_column_of_a_condition),
    cmocka_unit_test(a_refused_condition_takes_no_context_slot),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
