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
 * @file nps_world_peer.h
 * What a process makes of another aircraft's shared data (nps_world_link.h): only plausible data is used, and the
 * peer's pose is read at the reading's time.
 */

#ifndef NPS_WORLD_PEER_H
#define NPS_WORLD_PEER_H

#include "nps_world_link.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A coordinate farther than this from the arena origin is no pose [m]. */
#define NPS_WORLD_PEER_MAX_COORD_M 1e4
/** A horizontal speed above this is no FINken's [m/s]. */
#define NPS_WORLD_PEER_MAX_SPEED_MPS 100.0

/**
 * Drop what cannot be a pose or a pulse: samples with a non-finite or out-of-range value or a time not after the
 * previous sample's, pulses with a non-finite time or an unknown sonar. The rest keeps its order.
 * @return the number of samples and pulses dropped
 */
extern unsigned nps_world_peer_sanitize(struct nps_world_peer *peer);

/**
 * The peer's pose at world time t_s: interpolated linearly between the two samples around t_s (yaw along the
 * shorter arc); after the newest sample, the newest position moved on at the velocity of the last two samples
 * for at most max_extrapolation_s (then held); before the oldest sample, the oldest.
 * @param age_s  0 when interpolated, else the distance in time to the sample used [s]
 * @return 0, or -1 when the peer has no sample or t_s is NaN
 */
extern int nps_world_peer_pose_at(const struct nps_world_peer *peer, double t_s, double max_extrapolation_s,
                                  struct nps_world_sample *pose, double *age_s);

#ifdef __cplusplus
}
#endif

#endif /* NPS_WORLD_PEER_H */
