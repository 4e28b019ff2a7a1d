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
 * @file nps_arena_contact.h
 * Contacts in the arena: copter bodies do not pass through each other, and the curtain walls stop a copter.
 * A position-based correction after each flight-model step (the flight model itself knows no obstacles).
 */

#ifndef NPS_ARENA_CONTACT_H
#define NPS_ARENA_CONTACT_H

#include "nps_arena.h"

#include <float.h>
#include <math.h>

/**
 * Whether two bodies whose radii sum to reach_m, with centres dx_m, dy_m apart, overlap: their centre distance
 * d = sqrt(dx^2 + dy^2) (computed so) is below reach_m. *d_m receives d when it was worked out (when they may overlap).
 * Most pairs that do not overlap cost one branch and no square root, exactly: s = fl(dx^2 + dy^2) >= r = fl(reach^2)
 * gives fl(sqrt(s)) >= fl(sqrt(r)) == reach (sqrt is correctly rounded, so monotone, and sqrt(fl(x^2)) == |x| in
 * radix 2 with rounding to nearest when x^2 neither under- nor overflows: r a normal number). Otherwise the bodies
 * are apart if |dx| >= reach or |dy| >= reach (d >= max(|dx|, |dy|) in floating point too, by the same two facts;
 * with a subnormal r only this test is exact), else d decides.
 */
static inline int nps_arena_bodies_overlap(double dx_m, double dy_m, double reach_m, double *d_m)
{
  const double s = dx_m * dx_m + dy_m * dy_m, r = reach_m * reach_m;
  if (s >= r && r >= DBL_MIN) {
    return 0;
  }
  if (fabs(dx_m) >= reach_m || fabs(dy_m) >= reach_m) {
    return 0;
  }
  /* no hypot call: centre distances in metres neither overflow nor underflow when squared */
  *d_m = sqrt(s);
  return *d_m < reach_m;
}

/**
 * A flight model takes a contact's correction (nps_arena_resolve_contacts moved its copter to to_m): its horizontal
 * position pos_m becomes to_m, and the part of its horizontal velocity vel_mps into the push p = to - pos is removed,
 * v -= (v . p / |p|^2) p when v . p < 0 (an inelastic stop against the obstacle; motion along it is kept). Both in
 * the same frame (our host's ENU, fdm_finken's NED). Inline so that a flight model needs no arena to link.
 */
static inline void nps_arena_contact_take(double pos_m[2], double vel_mps[2], const double to_m[2])
{
  const double push[2] = { to_m[0] - pos_m[0], to_m[1] - pos_m[1] };
  const double into = vel_mps[0] * push[0] + vel_mps[1] * push[1];   /* v . p [m^2/s] */
  if (into < 0.0) {
    /* contact pushes in metres neither overflow nor underflow when squared */
    const double along = into / (push[0] * push[0] + push[1] * push[1]);  /* [1/s] */
    vel_mps[0] -= along * push[0];
    vel_mps[1] -= along * push[1];
  }
  pos_m[0] = to_m[0];
  pos_m[1] = to_m[1];
}

/**
 * Move the copters of the arena (nps_arena_set_copters) out of each other and back inside the wall polygon
 * at rest: two overlapping bodies are pushed apart along the line between their centres, each by half the
 * overlap; a body closer to a wall than its radius is pushed back along the wall's inward normal.
 * Neighbours come from the copter grid (no all-pairs scan). The grid is re-indexed when anything moved.
 * @param moved  per copter (arena order), set to 1 when it was moved (may be NULL)
 * @return the number of contacts resolved (pairs and wall pushes), or -1 on ENOMEM
 */
int nps_arena_resolve_contacts(struct nps_arena *a, int *moved);

#endif /* NPS_ARENA_CONTACT_H */
