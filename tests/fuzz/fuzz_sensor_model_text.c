/*
 * libFuzzer harness: one-line sensor models (airframe defines, --sensor-model TEXT, the replay's models),
 * sw/simulator/nps/nps_sensor_model_text.c. Each input is read as a C string for the simulator and as the whole
 * bytes (NUL bytes included) for the replay of a range log with its own context columns. A model that loads is
 * used (fuzz_sensor_model.h). Mixture paths are relative to the top of the tree.
 */
#include "fuzz_sensor_model.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char *text = fuzz_string(data, size);
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *model = NULL;
  if (nps_sensor_model_from_string(text, "fuzz", &model, err, sizeof(err)) == 0) {
    fuzz_sensor_model_use(model);
    nps_sensor_model_free(model);
  } else {
    fuzz_require(model == NULL && strlen(err) > 0);
  }
  if (nps_sensor_model_from_text_for_log((const char *)data, size, "fuzz", FUZZ_LOG_COLUMNS, fuzz_log_column, &model,
                                         err, sizeof(err)) == 0) {
    fuzz_sensor_model_use(model);
    nps_sensor_model_free(model);
  } else {
    fuzz_require(model == NULL && strlen(err) > 0);
  }
  free(text);
  return 0;
}
