/*
 * Sensor models written inline, shared by the chain and context tests.
 */
#ifndef TEST_MODEL_FIXTURES_H
#define TEST_MODEL_FIXTURES_H

#include "test_helpers.h"
#include "nps_sensor_model.h"

/** The model of an inline text (nps_sensor_model_from_string); the test fails with the loader's message. */
static inline struct nps_sensor_model *from_text(const char *text)
{
  char err[NPS_SENSOR_MODEL_ERR_LEN];
  struct nps_sensor_model *m;
  if (nps_sensor_model_from_string(text, "test", &m, err, sizeof(err)) != 0) {
    print_error("%s\n", err);
    fail();
  }
  return m;
}

#endif /* TEST_MODEL_FIXTURES_H */
