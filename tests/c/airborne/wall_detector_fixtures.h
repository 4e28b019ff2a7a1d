/*
 * What the wall detector's tests share: the module's default parameters, and g_sonar as a log.
 */
#ifndef WALL_DETECTOR_FIXTURES_H
#define WALL_DETECTOR_FIXTURES_H

#include "modules/wall_detector/wall_detector.h"
#include "pprz_host_vehicle.h"

#include <math.h>

/** The module's default parameters, as wall_detector_init() sets them from the defines. */
static inline struct wall_detector_params wall_detector_default_params(void)
{
  pprz_vehicles_setup(1, NULL);
  wall_detector_init();
  const struct wall_detector_params params = VEHICLE_LOCAL(wall_detector)->filter.params;
  pprz_vehicles_teardown();
  return params;
}

/** g_sonar: the log of the remembered wall's ratio (wall_detector_track_ratio). */
static inline double track_llr(const struct wall_detector_model_terms *terms, float range_m, float predicted_m,
                               float keep)
{
  return log(wall_detector_track_ratio(terms, range_m, predicted_m, keep));
}

#endif /* WALL_DETECTOR_FIXTURES_H */
