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
 * @file firmwares/rotorcraft/autopilot_guided.h
 * Host stand-in for Paparazzi's guided-mode interface; the host's flight model follows the last command.
 */

#ifndef AUTOPILOT_GUIDED_H
#define AUTOPILOT_GUIDED_H

#include "std.h"

/** Command a velocity in the local NED frame [m/s] and a heading [rad] (vz is ignored: the FINken holds its altitude). */
extern bool autopilot_guided_move_ned(float vx, float vy, float vz, float heading);

/** Host only: the current vehicle's last guided command. */
struct autopilot_guided_command {
  float vx, vy, vz, heading;
  bool active;
};
extern struct autopilot_guided_command *autopilot_guided_current(void);

#endif /* AUTOPILOT_GUIDED_H */
