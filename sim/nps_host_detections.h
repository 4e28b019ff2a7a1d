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
 * @file nps_host_detections.h
 * The host's log of the wall detector's decisions: detections.csv, one row per WALL_DETECTION message of any
 * copter, with the ground truth of the sonar reading it judged (format: tools/finken/run_logs.py).
 * Nothing is written for an airframe without the wall_detector module.
 */

#ifndef NPS_HOST_DETECTIONS_H
#define NPS_HOST_DETECTIONS_H

/** Bind every copter's WALL_DETECTION (after pprz_vehicles_setup); the file `path` is created on the first message. */
extern void nps_host_detections_start(const char *path);
/** The file's path when it could not be created or written, NULL while every write succeeded. */
extern const char *nps_host_detections_write_error(void);
/** Close the file; -1 with errno set if it could not be written. */
extern int nps_host_detections_stop(void);

#endif /* NPS_HOST_DETECTIONS_H */
