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
 * peer_nb x 16 x 4 steps instead of (peer_nb + 1)^3 x peer_nb.
 */
void wall_detector_assignment_sums(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb,
                                   double sum[WALL_DETECTOR_SONAR_SETS])
{
  enum { SET_NB = WALL_DETECTOR_SONAR_SETS };
  sum[0] = 1.0;  // no peer placed yet: the empty set only
  for (int taken = 1; taken < SET_NB; taken++) {
    sum[taken] = 0.0;
  }
  for (unsigned i = 0; i < peer_nb; i++) {
    /* a set gains the ways in which peer i is on one of its sonars o and the others on the rest (the set without
     * o, before peer i: sets in decreasing order, each read before it grows); i + 1 peers take i + 1 sonars at
     * most, larger sets stay empty */
#pragma GCC unroll 16
    for (int taken = SET_NB - 1; taken > 0; taken--) {
      if (__builtin_popcount((unsigned)taken) > (int)i + 1) {
        continue;
      }
      double gained = -0.0;  // -0 + x is x for every x: the first term is taken as it is, without an addition
#pragma GCC unroll 4
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
  enum { SET_NB = WALL_DETECTOR_SONAR_SETS };
  const int own = 1 << sonar;
  *copter = 0.0;
  *wall = 0.0;
#pragma GCC unroll 16
  for (int taken = 0; taken < SET_NB; taken++) {
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

struct wall_detector_odds_band wall_detector_odds_band_of(float threshold)
{
  const double delta = 1e-6 * fmax(1.0, fabs((double)threshold));
  return (struct wall_detector_odds_band) { .below = exp(threshold - delta), .above = exp(threshold + delta) };
}

/* Both comparisons: below the band log(q) < t - delta + (log's and exp's rounding) < t - (half a float step), so
 * (float)log(q) < t; above it (float)log(q) > t likewise. The comparisons are false for a NaN bound: the log. */
bool wall_detector_log_odds_at_most(double odds, float threshold, const struct wall_detector_odds_band *band)
{
  if (odds <= band->below) {
    return true;
  }
  if (odds >= band->above) {
    return false;
  }
  return (float)log(odds) <= threshold;
}

bool wall_detector_log_odds_at_least(double odds, float threshold, const struct wall_detector_odds_band *band)
{
  if (odds >= band->above) {
    return true;
  }
  if (odds <= band->below) {
    return false;
  }
  return (float)log(odds) >= threshold;
}

double wall_detector_assignment_log_odds(const double weight[][WALL_DETECTOR_SONAR_NB], unsigned peer_nb, int sonar)
{
  double sum[WALL_DETECTOR_SONAR_SETS];
  wall_detector_assignment_sums(weight, peer_nb, sum);
  return wall_detector_assignment_sonar_log_odds(sum, sonar);
}
