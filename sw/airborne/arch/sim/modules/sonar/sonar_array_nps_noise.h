/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file arch/sim/modules/sonar/sonar_array_nps_noise.h
 * Sonar noise of the NPS simulation, tunable from the ground station (settings of sonar_array.xml):
 * they overwrite the parameters of the simulator's sensor model (one per simulator process).
 */

#ifndef SONAR_ARRAY_NPS_NOISE_H
#define SONAR_ARRAY_NPS_NOISE_H

#ifdef __cplusplus
extern "C" {
#endif

struct sonar_array_nps_noise {
  float rayleigh_sigma;  ///< sigma of the rayleigh_short effect [m] (NAN: the model has none)
  float crosstalk_p;     ///< probability of the crosstalk effect (NAN: the model has none)
};

extern struct sonar_array_nps_noise sonar_array_nps_noise;

/** Read the settings' start values from the sensor model. */
extern void sonar_array_nps_noise_init(void);
/** Write settings changed since the last call into the sensor model. */
extern void sonar_array_nps_noise_apply(void);

#ifdef __cplusplus
}
#endif

#endif /* SONAR_ARRAY_NPS_NOISE_H */
