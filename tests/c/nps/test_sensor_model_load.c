/*
 * Loading sensor models (nps_sensor_model.h): the shipped model files, the XML format, the one-line text
 * form for airframe defines, and every kind of bad input rejected with "file:line: reason" and no model.
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
  assert_int_equal(sonar->effect[0].condition_slot, -1);
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
             "    <effect name=\"bias\" b=\"0.1\" condition=\"ctx_rotor_wash\"/>\n"  /* a model-defined column */
             "  </ranging>\n"
             "  <sonar speed_of_sound=\"340\">\n"
             "    <effect name=\"gmm\">\n" "<mixture components=\"2\">"
             "  <component weight=\"0.4\" mean_true=\"0.5\" mean_measured=\"0.52\" var_true=\"0.04\" var_measured=\"0.01\" cov=\"0\"/>\n"
             "  <component weight=\"0.6\" mean_true=\"1.8\" mean_measured=\"1.85\" var_true=\"0.09\" var_measured=\"0.02\" cov=\"0\"/>\n"
             "</mixture></effect>\n"
             "  </sonar>\n"
             "</sensor_model>\n", model_path, sizeof(model_path));
  struct nps_sensor_model *m;
  if (nps_sensor_model_load(model_path, &m, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  const struct nps_sensor_chain *r = nps_sensor_model_chain(m, "ranging"), *s = nps_sensor_model_chain(m, "sonar");
  assert_int_equal(r->beyond_max, NPS_BEYOND_MAX_NO_READING);
  assert_int_equal(r->effect[1].condition_slot, NPS_CTX_BLOCKED);
  assert_int_equal(r->effect[2].condition_slot, NPS_CTX_EXTRA0);
  assert_string_equal(nps_sensor_model_ctx_slot_name(m, NPS_CTX_EXTRA0), "ctx_rotor_wash");
  assert_null(nps_sensor_model_ctx_slot_name(m, NPS_CTX_EXTRA0 + 1));
  assert_int_equal(nps_sensor_model_ctx_slot(m, "ctx_rotor_wash"), NPS_CTX_EXTRA0);
  assert_true(nps_gmm_is_diagonal(s->effect[0].gmm));
  assert_close(s->speed_of_sound_mps, 340.0, 0.0);
  assert_close(s->min_range_m, 0.2, 0.0);  /* the sonar defaults */
  nps_sensor_model_free(m);
}

/** A model file that must be rejected at `line` with `reason`, leaving no model. */
static void expect_rejected(const char *text, int line, const char *reason)
{
  char path[256], err[NPS_SENSOR_MODEL_ERR_LEN] = "", where[300];
  write_file("bad.xml", text, path, sizeof(path));
  struct nps_sensor_model *m = (struct nps_sensor_model *)1;
  assert_int_equal(nps_sensor_model_load(path, &m, err, sizeof(err)), -1);
  assert_null(m);
  snprintf(where, sizeof(where), "%s:%d: ", path, line);
  if (strncmp(err, where, strlen(where)) != 0 || strstr(err, reason) == NULL) {
    print_error("error '%s'\nexpected '%s...%s'\n", err, where, reason);
    fail();
  }
}

#define COMPONENT(w, vt, vm, c) "<component weight=\"" w "\" mean_true=\"1\" mean_measured=\"1\" var_true=\"" vt \
  "\" var_measured=\"" vm "\" cov=\"" c "\"/>\n"
#define MODEL_WITH(mixture) "<sensor_model>\n<ranging>\n<effect name=\"gmm\">\n" mixture "</effect>\n</ranging>\n</sensor_model>\n"

static void bad_model_files_name_file_line_and_reason(void **state)
{
  (void)state;
  /* the issue's list: negative variance, weights not summing to 1, NaN, singular covariance,
   * unknown effect or parameter, missing component */
  expect_rejected(MODEL_WITH("<mixture components=\"2\">\n" COMPONENT("0.5", "0.1", "0.1", "0") COMPONENT("0.5", "0.1", "-0.1", "0") "</mixture>\n"),
                  6, "variances must be > 0");
  expect_rejected(MODEL_WITH("<mixture components=\"2\">\n" COMPONENT("0.5", "0.1", "0.1", "0") COMPONENT("0.4", "0.1", "0.1", "0") "</mixture>\n"),
                  4, "weights sum to 0.9");
  expect_rejected(MODEL_WITH("<mixture components=\"1\">\n" COMPONENT("1", "NaN", "0.1", "0") "</mixture>\n"),
                  5, "var_true = 'NaN' is not a finite number");
  expect_rejected(MODEL_WITH("<mixture components=\"1\">\n" COMPONENT("1", "0.1", "0.4", "0.2") "</mixture>\n"),
                  5, "singular covariance");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"wobble\" a=\"1\"/>\n</sonar>\n</sensor_model>\n",
                  3, "unknown effect 'wobble'");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gaussian\" sigma=\"0.1\" mu=\"0\"/>\n</sonar>\n</sensor_model>\n",
                  3, "unknown parameter 'mu' for effect 'gaussian'");
  expect_rejected(MODEL_WITH("<mixture components=\"3\">\n" COMPONENT("0.5", "0.1", "0.1", "0") COMPONENT("0.5", "0.1", "0.1", "0") "</mixture>\n"),
                  4, "declares 3 components but has 2 (missing component)");
  expect_rejected(MODEL_WITH("<mixture components=\"1\">\n<component weight=\"1\" mean_true=\"1\" mean_measured=\"1\" "
                             "var_true=\"0.1\" var_measured=\"0.1\"/>\n</mixture>\n"), 5, "lacks 'cov'");
  /* and the rest of the format */
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gaussian\" sigma=\"0.1\">\n</sonar>\n</sensor_model>\n",
                  4, "malformed XML");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gaussian\" sigma=\"-0.1\"/>\n</sonar>\n</sensor_model>\n",
                  3, "outside");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gaussian\"/>\n</sonar>\n</sensor_model>\n",
                  3, "needs parameter 'sigma'");
  expect_rejected("<sensor_model>\n<sonar/>\n<sonar/>\n</sensor_model>\n", 3, "defined twice");
  expect_rejected("<sensor_model>\n<lidar/>\n</sensor_model>\n", 2, "unexpected <lidar>");
  expect_rejected("<sensor_model>\n<sonar beyond_max=\"last\"/>\n</sensor_model>\n", 2, "expected 'max' or 'none'");
  expect_rejected("<sensor_model>\n<sonar min_range=\"3\" max_range=\"1\"/>\n</sensor_model>\n", 2, "min_range < max_range");
  expect_rejected("<sensor_model>\n<sonar max_rang=\"3\"/>\n</sensor_model>\n", 2, "unknown sonar attribute 'max_rang'");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"bias\" b=\"1\" condition=\"blocked\"/>\n</sonar>\n</sensor_model>\n",
                  3, "not a context column");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gmm\"/>\n</sonar>\n</sensor_model>\n", 3, "needs a mixture");
  expect_rejected("<sensor_model>\n<sonar>\n<effect name=\"gmm\" mixture=\"absent.xml\"/>\n</sonar>\n</sensor_model>\n",
                  3, "absent.xml:0: cannot read");
  expect_rejected("<sensor_model>\n</sensor_model>\n", 1, "neither a <sonar> nor a <ranging>");
  expect_rejected("<model/>\n", 1, "root element must be <sensor_model>");
  expect_rejected("<sensor_model>\n<sonar>text</sonar>\n</sensor_model>\n", 2, "unexpected text");
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
  assert_int_equal(r->effect[1].condition_slot, NPS_CTX_BLOCKED);
  nps_sensor_model_free(m);
  /* chains without effects, with or without the colon */
  assert_int_equal(nps_sensor_model_from_string("sonar: | ranging(max_range=100)", "X", &m, err, sizeof(err)), 0);
  assert_int_equal(nps_sensor_model_chain(m, "sonar")->n_effects, 0);
  assert_int_equal(nps_sensor_model_chain(m, "ranging")->n_effects, 0);
  assert_close(nps_sensor_model_chain(m, "ranging")->max_range_m, 100.0, 0.0);
  nps_sensor_model_free(m);
}

static void expect_text_rejected(const char *text, const char *reason)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN] = "";
  struct nps_sensor_model *m;
  assert_int_equal(nps_sensor_model_from_string(text, "RANGING_MODEL", &m, err, sizeof(err)), -1);
  assert_null(m);
  if (strncmp(err, "RANGING_MODEL:1: ", 17) != 0 || strstr(err, reason) == NULL) {
    print_error("error '%s' does not say 'RANGING_MODEL:1: ...%s'\n", err, reason);
    fail();
  }
}

static void bad_text_is_rejected_with_its_column(void **state)
{
  (void)state;
  expect_text_rejected("ranging: gaussian(sigma=0.1); blur(x=1)", "unknown effect 'blur'");
  expect_text_rejected("ranging: gaussian(sigma=0.1); blur(x=1)", "(column 31)");
  expect_text_rejected("ranging: gaussian(sigma=abc)", "'abc' is not a finite number");
  expect_text_rejected("ranging gaussian(sigma=0.1)", "expected ':'");
  expect_text_rejected("ranging: gaussian(sigma=0.1", "expected ',' or ')'");
  expect_text_rejected("ranging: gaussian(sigma=0.1) extra", "unexpected 'e'");
  expect_text_rejected("radar: gaussian(sigma=0.1)", "unknown sensor 'radar'");
  expect_text_rejected("ranging: bias(b=0.1) if", "expected a ctx_ column");
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
    char cond[32];
    snprintf(cond, sizeof(cond), "ctx_extra_%d", i);
    int rc = nps_sensor_model_add_effect(m, "sonar", "bias", 1, bk, bv, cond, NULL, err, sizeof(err));
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
    cmocka_unit_test(bad_model_files_name_file_line_and_reason),
    cmocka_unit_test(a_missing_file_is_reported),
    cmocka_unit_test(the_text_form_builds_the_same_chains),
    cmocka_unit_test(bad_text_is_rejected_with_its_column),
    cmocka_unit_test(a_define_names_a_file_or_holds_the_text),
    cmocka_unit_test(models_built_from_code),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
