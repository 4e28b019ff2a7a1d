/*
 * What a sensor model that loaded must stand (fuzz_sensor_model_xml.c, fuzz_sensor_model_text.c): every chain
 * applied to readings of every kind of context, the effects' likelihoods, its mixtures evaluated, and the
 * canonical text of each condition read back as itself.
 */
#ifndef FUZZ_SENSOR_MODEL_H
#define FUZZ_SENSOR_MODEL_H

#include "fuzz_common.h"

#include <math.h>

#include "nps_rng.h"
#include "nps_sensor_model.h"

/** The context columns of the range log a replay's model is read for: one the simulator has, one of the lab's. */
#define FUZZ_LOG_COLUMNS 2
static const char *const fuzz_log_column[FUZZ_LOG_COLUMNS] = { "ctx_wall_dist", "ctx_lab_humidity" };

/** Whether x is one of the values of the chain's glitches (the only readings its limits do not bound). */
static inline bool fuzz_is_glitch_value(const struct nps_sensor_chain *chain, double x)
{
  for (size_t e = 0; e < nps_sensor_chain_effect_count(chain); e++) {
    size_t n;
    const double *value = nps_effect_glitch_values(nps_sensor_chain_effect(chain, e), &n);
    for (size_t i = 0; i < n; i++) {
      if (value[i] == x) {
        return true;
      }
    }
  }
  return false;
}

/** A chain's readings are NaN (none), within its limits or a glitch's value, whatever its effects did. */
static inline void fuzz_sensor_chain_use(const struct nps_sensor_chain *chain, gsl_rng *r)
{
  static const double true_range_m[] = { 0.0, 0.05, 0.4, 1.2, 2.45, 2.9, 3.2, 40.0 };
  struct nps_sensor_ctx busy = {
    .facing_sonars = 2, .target_copter = 1, .blocked = 1, .wall_dist_m = 0.3, .speed_mps = 0.8,
    .crosstalk_path_m = 1.1, .trigger_offset_s = 0.002, .floor = 3, .vehicle = 2, .extra = { 1, 1, 1, 1, 1, 1, 1, 1 },
  };
  const struct nps_sensor_ctx quiet = { 0 };
  struct nps_sensor_state state;
  nps_sensor_state_init(&state);
  const size_t n = sizeof(true_range_m) / sizeof(true_range_m[0]);
  for (size_t i = 0; i < 2 * n; i++) {
    const double x = nps_sensor_chain_apply(chain, 0.05 * (double)i, true_range_m[i % n], i < n ? &quiet : &busy,
                                            &state, r);
    fuzz_require(isnan(x) || (x >= nps_sensor_chain_min_range(chain) && x <= nps_sensor_chain_max_range(chain)) ||
                 fuzz_is_glitch_value(chain, x));
  }
  for (size_t e = 0; e < nps_sensor_chain_effect_count(chain); e++) {
    const struct nps_effect *effect = nps_sensor_chain_effect(chain, e);
    const char *condition = nps_effect_condition(effect);
    if (condition != NULL) {
      struct nps_condition again;
      fuzz_require(nps_condition_parse(&again, condition, strlen(condition), NULL, NULL, 0) == 0 &&
                   strcmp(again.text, condition) == 0);
    }
    if (nps_effect_has_logpdf(nps_effect_kind(effect))) {
      (void)nps_effect_logpdf(effect, 1.0, 1.05);
    }
    const struct nps_gmm *gmm = nps_effect_gmm(effect);
    if (gmm != NULL) {
      (void)nps_gmm_conditional_logpdf(gmm, 1.0, 1.05);
      (void)nps_gmm_conditional_cdf(gmm, 1.0, 1.05);
    }
  }
}

static inline void fuzz_sensor_model_use(const struct nps_sensor_model *model)
{
  gsl_rng *r = nps_rng_stream_new(1, 0, NPS_RNG_SENSOR_REPLAY_SONAR);
  if (r == NULL) {
    abort();
  }
  for (int k = 0; k < NPS_SENSOR_KINDS; k++) {
    const struct nps_sensor_chain *chain = nps_sensor_model_chain_of(model, (enum nps_sensor_kind)k);
    if (chain != NULL) {
      fuzz_sensor_chain_use(chain, r);
    }
  }
  gsl_rng_free(r);
}

#endif /* FUZZ_SENSOR_MODEL_H */
