/*
 * Loading sensor models (nps_sensor_model.h): the shipped model files, the XML format, the one-line text
 * form for airframe defines, conditions on a replayed log's columns. Bad input of every kind is in the shared
 * corpus (tests/data/models, test_sensor_model_corpus.c), read by the C and the Python tests alike.
 */
#include "test_helpers.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "nps_sensor_model.h"

#define GAUSSIAN_ONLY "conf/sensor_models/gaussian_only.xml"
#define DEFAULT_MODEL "conf/sensor_models/finken_default.xml"

static char dir[] = "/tmp/test_sensor_model_XXXXXX";

static int setup(void **state)
{
  (void)state;
  return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
  (void)state;
  char cmd[128];
  snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
  return system(cmd) == 0 ? 0 : -1;
}

/** Write `text` to dir/name; the path goes to `path`. */
static void write_file(const char *name, const char *text, char *path, size_t len)
{
  snprintf(path, len, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static const char *const mixture_ok =
  "<mixture components=\"2\" covariance=\"full\">\n"
  "  <component weight=\"0.4\" mean_true=\"0.5\" mean_measured=\"0.52\" var_true=\"0.04\" var_measured=\"0.01\" cov=\"0.018\"/>\n"
  "  <component weight=\"0.6\" mean_true=\"1.8\" mean_measured=\"1.85\" var_true=\"0.09\" var_measured=\"0.02\" cov=\"0.04\"/>\n"
  "</mixture>\n";

static void the_gaussian_only_model_is_what_issue_8_asks(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_load(GAUSSIAN_ONLY, &m, err, sizeof(err)), 0);
  const struct nps_sensor_chain *sonar = nps_sensor_model_chain(m, "sonar"), *ranging = nps_sensor_model_chain(m, "ranging");
  assert_non_null(sonar);
  assert_non_null(ranging);
  assert_int_equal(sonar->n_effects, 1);
  assert_int_equal(ranging->n_effects, 1);
  assert_int_equal(sonar->effect[0].kind, NPS_EFFECT_GAUSSIAN);
  assert_int_equal(ranging->effect[0].kind, NPS_EFFECT_GAUSSIAN);
  assert_true(sonar->effect[0].param[0] == 0.02 && ranging->effect[0].param[0] == 0.05);
  assert_true(sonar->min_range_m == 0.2 && sonar->max_range_m == 3.0);
  assert_true(ranging->min_range_m == 0.0 && ranging->max_range_m == 2.5);
  assert_int_equal(sonar->effect[0].condition.n_terms, 0);
  nps_sensor_model_free(m);
}

static void the_default_model_loads_with_its_mixture(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  if (nps_sensor_model_load(DEFAULT_MODEL, &m, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  const struct nps_sensor_chain *sonar = nps_sensor_model_chain(m, "sonar"), *ranging = nps_sensor_model_chain(m, "ranging");
  assert_int_equal(sonar->effect[0].kind, NPS_EFFECT_RAYLEIGH_SHORT);
  assert_int_equal(sonar->effect[1].kind, NPS_EFFECT_CROSSTALK);
  assert_close(sonar->effect[1].param[0], 0.68, 0.0);
  assert_int_equal(ranging->effect[0].kind, NPS_EFFECT_GMM);
  assert_int_equal(nps_gmm_size(ranging->effect[0].gmm), 100);
  nps_sensor_model_free(m);
}

static void inline_and_referenced_mixtures_and_conditions(void **state)
{
  (void)state;
  char mix_path[256], model_path[256], err[NPS_SENSOR_MODEL_ERR_LEN];
  write_file("mix.xml", mixture_ok, mix_path, sizeof(mix_path));
  write_file("model.xml",
             "<sensor_model name=\"t\">\n"
             "  <ranging max_range=\"2.5\" beyond_max=\"none\">\n"
             "    <effect name=\"gmm\" mixture=\"mix.xml\"/>\n"       /* relative to the model file */
             "    <effect name=\"nlos_bias\" mean=\"0.2\" condition=\"ctx_blocked\"/>\n"
             "    <effect name=\"bias\" b=\"0.1\" condition=\"ctx_rotor_wash\"/>\n"  /* a column of the log */
             "  </ranging>\n"
             "  <sonar speed_of_sound=\"340\">\n"
             "    <effect name=\"gmm\">\n" "<mixture components=\"2\">"
             "  <component weight=\"0.4\" mean_true=\"0.5\" mean_measured=\"0.52\" var_true=\"0.04\" var_measured=\"0.01\" cov=\"0\"/>\n"
             "  <component weight=\"0.6\" mean_true=\"1.8\" mean_measured=\"1.85\" var_true=\"0.09\" var_measured=\"0.02\" cov=\"0\"/>\n"
             "</mixture></effect>\n"
             "  </sonar>\n"
             "</sensor_model>\n", model_path, sizeof(model_path));
  struct nps_sensor_model *m;
  const char *log_columns[] = {"ctx_lab_humidity", "ctx_rotor_wash"};
  if (nps_sensor_model_load_for_log(model_path, 2, log_columns, &m, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  assert_string_equal(nps_sensor_model_name(m), "t");
  const struct nps_sensor_chain *r = nps_sensor_model_chain(m, "ranging"), *s = nps_sensor_model_chain(m, "sonar");
  assert_int_equal(r->beyond_max, NPS_BEYOND_MAX_NO_READING);
  assert_int_equal(r->effect[1].condition.term[0].slot, NPS_CTX_BLOCKED);
  assert_int_equal(r->effect[2].condition.term[0].slot, NPS_CTX_EXTRA0);
  assert_string_equal(nps_sensor_model_ctx_slot_name(m, NPS_CTX_EXTRA0), "ctx_rotor_wash");
  assert_null(nps_sensor_model_ctx_slot_name(m, NPS_CTX_EXTRA0 + 1));
  assert_int_equal(nps_sensor_model_ctx_slot(m, "ctx_rotor_wash"), NPS_CTX_EXTRA0);
  assert_true(nps_gmm_is_diagonal(s->effect[0].gmm));
  assert_close(s->speed_of_sound_mps, 340.0, 0.0);
  assert_close(s->min_range_m, 0.2, 0.0);  /* the sonar defaults */
  nps_sensor_model_free(m);
}

static void a_missing_file_is_reported(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_load("/nonexistent/model.xml", &m, err, sizeof(err)), -1);
  assert_non_null(strstr(err, "/nonexistent/model.xml:0: cannot read"));
  assert_null(m);
}

static void the_text_form_builds_the_same_chains(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  const char *text = "sonar(min_range=0.2, max_range=3.0, beyond_max=none): rayleigh_short(sigma=0.05); "
                     "crosstalk(p=0.68) | ranging(max_range=2.5): gmm(mixture=conf/sensor_models/finken_ranging_gmm_k100.xml);"
                     " gaussian(sigma=0.1) if ctx_blocked";
  if (nps_sensor_model_from_string(text, "SONAR_ARRAY_MODEL", &m, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  const struct nps_sensor_chain *s = nps_sensor_model_chain(m, "sonar"), *r = nps_sensor_model_chain(m, "ranging");
  assert_int_equal(s->n_effects, 2);
  assert_int_equal(s->beyond_max, NPS_BEYOND_MAX_NO_READING);
  assert_close(s->effect[1].param[0], 0.68, 0.0);
  assert_int_equal(r->n_effects, 2);
  assert_int_equal(nps_gmm_size(r->effect[0].gmm), 100);
  assert_int_equal(r->effect[1].condition.term[0].slot, NPS_CTX_BLOCKED);
  nps_sensor_model_free(m);
  /* chains without effects, with or without the colon */
  assert_int_equal(nps_sensor_model_from_string("sonar: | ranging(max_range=100)", "X", &m, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_chain(m, "sonar")->n_effects, 0);
  assert_int_equal(nps_sensor_model_chain(m, "ranging")->n_effects, 0);
  assert_close(nps_sensor_model_chain(m, "ranging")->max_range_m, 100.0, 0.0);
  nps_sensor_model_free(m);
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

static void a_condition_names_a_column_of_the_simulator_or_of_the_replayed_log(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN], path[256];
  struct nps_sensor_model *m;
  const char *log_columns[] = {"ctx_quality_pct", "ctx_rotor_wash"};
  const char *xml = "<sensor_model>\n<ranging>\n<effect name=\"bias\" b=\"0.1\" condition=\"ctx_rotor_wash\"/>\n"
                    "</ranging>\n</sensor_model>\n";
  const char *text = "ranging: gaussian(sigma=0.1); bias(b=0.1) if ctx_rotor_wash";
  write_file("rotor_wash.xml", xml, path, sizeof(path));
  /* for the simulator (the loaders without a log): refused, naming the column, the file and the line */
  char expected[NPS_SENSOR_MODEL_ERR_LEN];
  snprintf(expected, sizeof(expected), "%s:3: condition 'ctx_rotor_wash': unknown context column (the simulator has "
           SIMULATOR_COLUMNS ")", path);
  expect_refused(nps_sensor_model_load(path, &m, err, sizeof(err)), &m, err, expected);
  expect_refused(nps_sensor_model_load_memory(xml, strlen(xml), "mem", NULL, &m, err, sizeof(err)), &m, err,
                 "mem:3: condition 'ctx_rotor_wash': unknown context column (the simulator has " SIMULATOR_COLUMNS ")");
  expect_refused(nps_sensor_model_from_string(text, "RANGING_MODEL", &m, err, sizeof(err)), &m, err,
                 "RANGING_MODEL:1: condition 'ctx_rotor_wash': unknown context column (the simulator has "
                 SIMULATOR_COLUMNS ") (column 46)");
  expect_refused(nps_sensor_model_from_define(text, "RANGING_MODEL", &m, err, sizeof(err)), &m, err,
                 "RANGING_MODEL:1: condition 'ctx_rotor_wash': unknown context column (the simulator has "
                 SIMULATOR_COLUMNS ") (column 46)");
  /* for the replay of a log that has it: loaded, in a model-defined slot */
  assert_int_equal(nps_sensor_model_load_for_log(path, 2, log_columns, &m, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_ctx_slot(m, "ctx_rotor_wash"), NPS_CTX_EXTRA0);
  nps_sensor_model_free(m);
  assert_int_equal(nps_sensor_model_load_memory_for_log(xml, strlen(xml), "mem", NULL, 2, log_columns, &m, err,
                   sizeof(err)), 0);
  nps_sensor_model_free(m);
  assert_int_equal(nps_sensor_model_from_text_for_log(text, strlen(text), "X", 2, log_columns, &m, err, sizeof(err)),
                   0);
  nps_sensor_model_free(m);
  /* a log without it: the error names the log's columns too */
  const int rc = nps_sensor_model_from_text_for_log(text, strlen(text), "X", 1, log_columns, &m, err, sizeof(err));
  expect_refused(rc, &m, err, "X:1: condition 'ctx_rotor_wash': unknown context column (the simulator has "
                 SIMULATOR_COLUMNS "; the log has ctx_quality_pct) (column 46)");
}

static void a_nul_byte_is_refused_not_the_end_of_the_text(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  const char text[] = "sonar: gaussian(sigma=0.1)\0 | ranging: blur(x=1)";
  expect_refused(nps_sensor_model_from_text_for_log(text, sizeof(text) - 1, "X", 0, NULL, &m, err, sizeof(err)), &m,
                 err, "X:1: NUL byte in the model (column 27)");
  const char xml[] = "<sensor_model>\n<sonar/>\n</sensor_model>\n\0<!-- after the NUL -->";
  expect_refused(nps_sensor_model_load_memory(xml, sizeof(xml) - 1, "mem", NULL, &m, err, sizeof(err)), &m, err,
                 "mem:4: NUL byte in the model (column 1)");
  /* the text before it loads: what from_string (a C string) sees */
  assert_int_equal(nps_sensor_model_from_string(text, "X", &m, err, sizeof(err)), 0);
  assert_null(nps_sensor_model_name(m));
  nps_sensor_model_free(m);
}

static void a_define_names_a_file_or_holds_the_text(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_define(" " GAUSSIAN_ONLY " ", "SONAR_ARRAY_MODEL", &m, err, sizeof(err)), 0);
  assert_non_null(nps_sensor_model_chain(m, "ranging"));
  nps_sensor_model_free(m);
  assert_int_equal(nps_sensor_model_from_define("sonar: gaussian(sigma=0.02)", "SONAR_ARRAY_MODEL", &m, err, sizeof(err)), 0);
  assert_null(nps_sensor_model_chain(m, "ranging"));
  nps_sensor_model_free(m);
  assert_int_equal(nps_sensor_model_from_define("missing.xml", "SONAR_ARRAY_MODEL", &m, err, sizeof(err)), -1);
  assert_non_null(strstr(err, "missing.xml:0: cannot read"));
}

static void models_built_from_code(void **state)
{
  (void)state;
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m = nps_sensor_model_new();
  const char *ck[] = {"max_range"}, *cv[] = {"4.0"}, *ek[] = {"sigma"}, *ev[] = {"0.01"};
  assert_int_equal(nps_sensor_model_add_chain(m, "sonar", 1, ck, cv, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_add_effect(m, "sonar", "gaussian", 1, ek, ev, NULL, NULL, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_add_effect(m, "ranging", "gaussian", 1, ek, ev, NULL, NULL, err, sizeof(err)), -1);
  assert_non_null(strstr(err, "has no chain"));
  /* a mixture handed to a non-gmm effect is refused and freed (the sanitizer run checks the free) */
  const double w[] = {1.0}, mu[] = {1.0, 1.0}, cov[] = {0.1, 0.0, 0.0, 0.1};
  struct nps_gmm *g = nps_gmm_new(1, w, mu, cov, NULL, NULL, 0);
  assert_int_equal(nps_sensor_model_add_effect(m, "sonar", "gaussian", 1, ek, ev, NULL, g, err, sizeof(err)), -1);
  assert_non_null(strstr(err, "takes no mixture"));
  /* at most NPS_CTX_EXTRA_MAX model-defined context columns */
  const char *bk[] = {"b"}, *bv[] = {"0"};
  for (int i = 0; i <= NPS_CTX_EXTRA_MAX; i++) {
    char text[32];
    struct nps_condition cond;
    snprintf(text, sizeof(text), "ctx_extra_%d", i);
    assert_int_equal(nps_condition_parse(&cond, text, strlen(text), NULL, err, sizeof(err)), 0);
    int rc = nps_sensor_model_add_effect(m, "sonar", "bias", 1, bk, bv, &cond, NULL, err, sizeof(err));
    assert_int_equal(rc, i < NPS_CTX_EXTRA_MAX ? 0 : -1);
  }
  assert_non_null(strstr(err, "at most"));
  assert_int_equal(nps_sensor_model_chain(m, "sonar")->n_effects, 1 + NPS_CTX_EXTRA_MAX);
  nps_sensor_model_free(m);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_gaussian_only_model_is_what_issue_8_asks),
    cmocka_unit_test(the_default_model_loads_with_its_mixture),
    cmocka_unit_test(inline_and_referenced_mixtures_and_conditions),
    cmocka_unit_test(a_missing_file_is_reported),
    cmocka_unit_test(the_text_form_builds_the_same_chains),
    cmocka_unit_test(a_condition_names_a_column_of_the_simulator_or_of_the_replayed_log),
    cmocka_unit_test(a_nul_byte_is_refused_not_the_end_of_the_text),
    cmocka_unit_test(a_define_names_a_file_or_holds_the_text),
    cmocka_unit_test(models_built_from_code),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
