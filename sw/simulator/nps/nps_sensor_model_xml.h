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
 * @file nps_sensor_model_xml.h
 * Reading mixture files (<mixture> root) for gmm effects; model files are read by nps_sensor_model_load().
 */

#ifndef NPS_SENSOR_MODEL_XML_H
#define NPS_SENSOR_MODEL_XML_H

#include <stddef.h>

#include "nps_gmm.h"

/**
 * Load a mixture file.
 * @return the mixture, or NULL with "file:line: reason" in err
 */
struct nps_gmm *nps_sensor_model_load_mixture(const char *path, char *err, size_t err_len);

#endif /* NPS_SENSOR_MODEL_XML_H */
