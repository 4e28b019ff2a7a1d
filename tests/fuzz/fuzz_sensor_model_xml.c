/*
 * libFuzzer harness: sensor model files (XML, <sensor_model> root) and mixture files (<mixture> root),
 * sw/simulator/nps/nps_sensor_model_xml.c. Each input is read three ways: as a model for the simulator (mixture
 * files named relative to conf/sensor_models), as a model for the replay of a range log with its own context
 * columns (mixture files relative to tests/data/models/good), and as a mixture file. A model that loads is used
 * (fuzz_sensor_model.h).
 */
#include "fuzz_sensor_model.h"

#include "nps_sensor_model_xml.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *model = NULL;
  if (nps_sensor_model_load_memory((const char *)data, size, "fuzz.xml", "conf/sensor_models", &model, err,
                                   sizeof(err)) == 0) {
    fuzz_sensor_model_use(model);
    nps_sensor_model_free(model);
  } else {
    fuzz_require(model == NULL && strncmp(err, "fuzz.xml:", 9) == 0);
  }
  if (nps_sensor_model_load_memory_for_log((const char *)data, size, "fuzz.xml", "tests/data/models/good",
                                           FUZZ_LOG_COLUMNS, fuzz_log_column, &model, err, sizeof(err)) == 0) {
    fuzz_sensor_model_use(model);
    nps_sensor_model_free(model);
  } else {
    fuzz_require(model == NULL && strncmp(err, "fuzz.xml:", 9) == 0);
  }
  struct nps_gmm *gmm = nps_sensor_model_load_mixture(fuzz_file(data, size), err, sizeof(err));
  if (gmm != NULL) {
    (void)nps_gmm_conditional_logpdf(gmm, 1.0, 1.05);
    nps_gmm_free(gmm);
  }
  return 0;
}
