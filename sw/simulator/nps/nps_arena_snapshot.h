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
 * @file nps_arena_snapshot.h
 * Wall state as CSV for plots (tools/finken/sim_report/arena_plot.py), one row per segment and snapshot:
 *   t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven
 * t [s] time of the last wall step; (x0, y0)-(x1, y1) rest endpoints [m]; (nx, ny) unit normal into the
 * arena; angle_deg hinge angle; disp_flight_m inward displacement of the plate at the flight height [m];
 * disp_bottom_m of its bottom edge [m]; target_deg PID target; driven 1 while a copter drives the plate.
 */

#ifndef NPS_ARENA_SNAPSHOT_H
#define NPS_ARENA_SNAPSHOT_H

#include "nps_arena.h"

#include <stdio.h>

/** Write the header line. @return 0, or -1 (errno from stdio) */
int nps_arena_snapshot_header(FILE *f);

/** Write one row per segment at the arena's current time. @return 0, or -1 (errno from stdio) */
int nps_arena_snapshot_write(const struct nps_arena *a, FILE *f);

/**
 * Append a snapshot to the CSV file at path (header first when the file is new or append is 0).
 * @return 0, or -1 with "path: reason" in err
 */
int nps_arena_snapshot_file(const struct nps_arena *a, const char *path, int append, char *err, size_t err_len);

#endif /* NPS_ARENA_SNAPSHOT_H */
