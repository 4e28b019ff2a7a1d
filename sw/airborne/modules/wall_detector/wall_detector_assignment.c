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
 * @file modules/wall_detector/wall_detector_assignment.c
 * The wall detector's decision sum over assignments (see wall_detector_assignment.h).
 */

#include "modules/wall_detector/wall_detector_assignment.h"

#include <math.h>

/*
 * The sums over assignments by a dynamic programme over the peers (each peer on one sonar at most, each sonar
 * seeing one peer at most): after peers 0..i-1, sum[taken] is the sum, over the ways of putting each of them on a
 * distinct sonar of the set `taken` (bit o: sonar o) or on none, of the product of their weights; the sonars not
 * taken see walls (weight 1). Every assignment of the four sonars is counted once, with positive terms only (no
 * subtraction to cancel when one weight dominates): the copter odds of sonar s are the sum over the sets holding s
 * against the sum over the others (the file comment's L, whose sums over A are both multiplied by the walls' 1).
 * peer_nb x 32 multiply-adds (each of the 16 sets gains a term per sonar in it).
 */
void wall_detector_assignment_sums(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb,
                                   double sum[WALL_DETECTOR_SONAR_SETS])
{
  sum[0] = 1.0;  // no peer placed yet: the empty set only
  for (int taken = 1; taken < WALL_DETECTOR_SONAR_SETS; taken++) {
    sum[taken] = 0.0;
  }
  for (unsigned i = 0; i < peer_nb; i++) {
    /* a set gains the ways in which peer i is on one of its sonars o and the others on the rest (the set without
     * o, before peer i: sets in decreasing order, each read before it grows) */
    for (int taken = WALL_DETECTOR_SONAR_SETS - 1; taken > 0; taken--) {
      double gained = 0.0;
      for (int o = 0; o < WALL_DETECTOR_SONAR_NB; o++) {
        if (taken & (1 << o)) {
          gained += sum[taken & ~(1 << o)] * weight[i][o];
        }
      }
      sum[taken] += gained;
    }
  }
}

/** The sums over the sets of sonars without sonar s (a wall there) and with it (a copter), each in increasing order. */
static void sonar_sums(const double sum[WALL_DETECTOR_SONAR_SETS], int sonar, double *copter, double *wall)
{
  const int own = 1 << sonar;
  *copter = 0.0;
  *wall = 0.0;
  for (int taken = 0; taken < WALL_DETECTOR_SONAR_SETS; taken++) {
    if (taken & own) {
      *copter += sum[taken];
    } else {
      *wall += sum[taken];
    }
  }
}

double wall_detector_assignment_sonar_log_odds(const double sum[WALL_DETECTOR_SONAR_SETS], int sonar)
{
  double copter, wall;
  sonar_sums(sum, sonar, &copter, &wall);
  return log(copter / wall);
}

void wall_detector_assignment_sonar_decision(const double sum[WALL_DETECTOR_SONAR_SETS], int sonar,
    double *odds, double *confidence)
{
  double copter, wall;
  sonar_sums(sum, sonar, &copter, &wall);
  *odds = copter / wall;
  /* wall >= sum[0] = 1 (the empty set): the denominator is never 0 */
  *confidence = (copter > wall ? copter : wall) / (copter + wall);
}

double wall_detector_assignment_log_odds(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb, int sonar)
{
  double sum[WALL_DETECTOR_SONAR_SETS];
  wall_detector_assignment_sums(weight, peer_nb, sum);
  return wall_detector_assignment_sonar_log_odds(sum, sonar);
}
