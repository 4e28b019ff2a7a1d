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
 * @file modules/wander/wander.c
 * Wander: fly circles around a centre point (see wander.h).
 */

#include "modules/wander/wander.h"
#include "state.h"
#include "firmwares/rotorcraft/autopilot_guided.h"

void wander_velocity(float x, float y, float *vx, float *vy)
{
  const float dx = x - WANDER_CENTER_X, dy = y - WANDER_CENTER_Y;
  const float r = sqrtf(dx * dx + dy * dy);
  if (r < 1e-3f) {
    *vx = WANDER_SPEED;  /* at the centre: leave it along x */
    *vy = 0.0f;
    return;
  }
  const float radial = WANDER_RADIAL_GAIN * (WANDER_RADIUS - r);
  *vx = (-dy * WANDER_SPEED + dx * radial) / r;
  *vy = (dx * WANDER_SPEED + dy * radial) / r;
}

void wander_periodic(void)
{
  const struct EnuCoor_f *pos = stateGetPositionEnu_f();
  float ve, vn;
  wander_velocity(pos->x, pos->y, &ve, &vn);
  /* guided commands are NED: north first; heading along the motion (from north toward east) */
  autopilot_guided_move_ned(vn, ve, 0.0f, atan2f(ve, vn));
}
