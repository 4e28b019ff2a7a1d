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
 * @file nps_world_peer.c
 * Plausibility and time interpolation of another aircraft's shared data (see nps_world_peer.h).
 */

#include "nps_world_peer.h"
#include "nps_raycast.h"   /* NPS_SONAR_COUNT */

#include <math.h>

static bool sample_plausible(const struct nps_world_sample *s, double previous_t_s)
{
  for (int k = 0; k < 3; k++) {
    if (!(fabs(s->pos_m[k]) <= NPS_WORLD_PEER_MAX_COORD_M)) {   /* false for NaN too */
      return false;
    }
  }
  return isfinite(s->t_s) && s->t_s > previous_t_s && isfinite(s->yaw_rad) &&
         s->speed_mps >= 0.0 && s->speed_mps <= NPS_WORLD_PEER_MAX_SPEED_MPS;
}

unsigned nps_world_peer_sanitize(struct nps_world_peer *peer)
{
  unsigned kept = 0, dropped = 0;
  double previous_t_s = -INFINITY;
  for (unsigned i = 0; i < peer->n_samples && i < NPS_WORLD_SAMPLES; i++) {
    if (sample_plausible(&peer->samples[i], previous_t_s)) {
      previous_t_s = peer->samples[i].t_s;
      peer->samples[kept++] = peer->samples[i];
    } else {
      dropped++;
    }
  }
  dropped += peer->n_samples > NPS_WORLD_SAMPLES ? peer->n_samples - NPS_WORLD_SAMPLES : 0;
  peer->n_samples = kept;
  kept = 0;
  for (unsigned i = 0; i < peer->n_pings && i < NPS_WORLD_PINGS; i++) {
    if (isfinite(peer->pings[i].t_s) && peer->pings[i].sonar < NPS_SONAR_COUNT) {
      peer->pings[kept++] = peer->pings[i];
    } else {
      dropped++;
    }
  }
  dropped += peer->n_pings > NPS_WORLD_PINGS ? peer->n_pings - NPS_WORLD_PINGS : 0;
  peer->n_pings = kept;
  return dropped;
}

/** b - a wrapped into (-pi, pi]. */
static double angle_difference(double a, double b)
{
  return remainder(b - a, 2.0 * M_PI);
}

int nps_world_peer_pose_at(const struct nps_world_peer *peer, double t_s, double max_extrapolation_s,
                           struct nps_world_sample *pose, double *age_s)
{
  const unsigned n = peer->n_samples;
  if (n == 0 || isnan(t_s)) {   /* a NaN time fell through to the interpolation: samples[-1] with one sample */
    return -1;
  }
  const struct nps_world_sample *first = &peer->samples[0], *last = &peer->samples[n - 1];
  if (t_s <= first->t_s) {
    *pose = *first;
    *age_s = first->t_s - t_s;
  } else if (t_s >= last->t_s) {
    *pose = *last;
    *age_s = t_s - last->t_s;
    if (n >= 2) {   /* dead reckoning: the velocity of the last two samples */
      const struct nps_world_sample *before = &peer->samples[n - 2];
      const double dt = fmin(*age_s, max_extrapolation_s) / (last->t_s - before->t_s);
      for (int k = 0; k < 3; k++) {
        pose->pos_m[k] += dt * (last->pos_m[k] - before->pos_m[k]);
      }
    }
  } else {
    unsigned i = n - 1;   /* the newest samples are the likeliest: search backwards */
    while (peer->samples[i - 1].t_s > t_s) {
      i--;
    }
    const struct nps_world_sample *a = &peer->samples[i - 1], *b = &peer->samples[i];
    const double f = (t_s - a->t_s) / (b->t_s - a->t_s);
    for (int k = 0; k < 3; k++) {
      pose->pos_m[k] = a->pos_m[k] + f * (b->pos_m[k] - a->pos_m[k]);
    }
    pose->yaw_rad = a->yaw_rad + f * angle_difference(a->yaw_rad, b->yaw_rad);
    pose->speed_mps = a->speed_mps + f * (b->speed_mps - a->speed_mps);
    *age_s = 0.0;
  }
  pose->t_s = t_s;
  return 0;
}
