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
 * @file nps_world_shm_layout.h
 * The layout of a shared world's segment (nps_world_link_shm.c; its tests read it to damage a segment on purpose).
 */

#ifndef NPS_WORLD_SHM_LAYOUT_H
#define NPS_WORLD_SHM_LAYOUT_H

#include "nps_world_link.h"

#define NPS_WORLD_SHM_MAGIC 0x444c5746u          /* "FWLD" */
#define NPS_WORLD_SHM_VERSION 2u
#define NPS_WORLD_SHM_RUN_LEN 64

struct nps_world_seqlock {
  uint32_t seq;        ///< odd while written
};

struct nps_world_shm_slot {
  struct nps_world_seqlock lock;
  int32_t pid;                ///< process of this aircraft, 0 when free
  uint32_t ranging_equipped;
  uint64_t heartbeat_ns;      ///< CLOCK_MONOTONIC of its last sign of life (atomic, outside the lock)
  double time_s;              ///< world time of its newest sample (atomic, outside the lock: for waiting)
  double waiting_for_s;       ///< the world time its process waits for the others to reach; +inf when not waiting
  uint32_t wake;              ///< futex word its waiting process sleeps on: bumped by whoever completes the wait
  uint32_t sample_count, ping_count;   ///< published so far: ring positions
  struct nps_world_sample samples[NPS_WORLD_SAMPLES];
  struct nps_world_ping pings[NPS_WORLD_PINGS];
};

struct nps_world_shm {
  uint32_t magic, version, size;
  int32_t creator_pid;
  char run[NPS_WORLD_SHM_RUN_LEN];
  uint64_t epoch_ns;          ///< CLOCK_MONOTONIC when world time was 0
  double time_factor;
  uint64_t arena_id;
  uint32_t plates;
  struct nps_world_seqlock walls_lock;
  struct nps_world_walls walls;
  uint32_t walls_published;
  struct nps_world_shm_slot slot[NPS_WORLD_MAX_AIRCRAFT + 1];   ///< by aircraft id; 0 unused
};

#endif /* NPS_WORLD_SHM_LAYOUT_H */
