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
 * @file modules/wander/wander.h
 * Wander: fly circles around a centre point in guided mode. A minimal behaviour for exercising the
 * simulator host and the sensors without a swarm.
 */

#ifndef WANDER_H
#define WANDER_H

#include "std.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Circle centre, local ENU [m] */
#ifndef WANDER_CENTER_X
#define WANDER_CENTER_X 0.0f
#endif
#ifndef WANDER_CENTER_Y
#define WANDER_CENTER_Y 0.0f
#endif
/** Circle radius [m] */
#ifndef WANDER_RADIUS
#define WANDER_RADIUS 1.0f
#endif
/** Speed along the circle [m/s] */
#ifndef WANDER_SPEED
#define WANDER_SPEED 0.3f
#endif
/** Gain pulling the copter back onto the circle [1/s] */
#ifndef WANDER_RADIAL_GAIN
#define WANDER_RADIAL_GAIN 0.5f
#endif

/**
 * Velocity command (ENU [m/s]) at position (x, y): WANDER_SPEED along the circle, counter-clockwise,
 * plus WANDER_RADIAL_GAIN times the radial distance to the circle, toward it.
 */
extern void wander_velocity(float x, float y, float *vx, float *vy);

extern void wander_periodic(void);

#ifdef __cplusplus
}
#endif

#endif /* WANDER_H */
