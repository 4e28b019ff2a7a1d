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
 * @file arch/linux/modules/ranging/virtual_ranging_arch.c
 * The ranging unit on Linux (modules/ranging/virtual_ranging_arch.h): frames from the CAN bus
 * (modules/ranging/ranging_can.h) handed to virtual_ranging_report() in the event loop.
 *
 * Airframe defines: RANGING_CAN_IFNAME ("can0"), RANGING_CAN_ID_BASE, RANGING_CAN_NB_NODES,
 * RANGING_CAN_RANGE_MAX_MM (frame layout, ranging_can_frame.h), RANGING_CAN_SELF_ID (this copter's node id,
 * default AC_ID), RANGING_CAN_MAX_FRAMES_PER_EVENT. A distance is stale after VIRTUAL_RANGING_STALE_TIME.
 * Bus-off, restarts and socket failures are printed once each when they happen.
 */

#include "modules/ranging/virtual_ranging.h"
#include "modules/ranging/virtual_ranging_arch.h"
#include "modules/ranging/ranging_can.h"
#include "modules/multi_vehicle/vehicle_local.h"

#include <stdio.h>
#include <string.h>

#ifndef RANGING_CAN_SELF_ID
#ifdef PPRZ_HOST_MULTI_VEHICLE
#include "pprz_host_vehicle.h"
#define RANGING_CAN_SELF_ID pprz_vehicle_ac_id()
#else
#include "generated/airframe.h"
#define RANGING_CAN_SELF_ID AC_ID
#endif
#endif

struct virtual_ranging_linux {
  struct ranging_can *can;
  uint32_t bus_off_seen;    ///< bus-off count already printed
  uint32_t restarts_seen;   ///< restart count already printed
  bool read_failed;         ///< a socket failure was printed
};

VEHICLE_LOCAL_DEFINE(struct virtual_ranging_linux, virtual_ranging_linux);

bool virtual_ranging_arch_init(void)
{
  struct virtual_ranging_linux *vl = VEHICLE_LOCAL(virtual_ranging_linux);
  const struct ranging_can_config cfg = {
    .ifname = RANGING_CAN_IFNAME,
    .rx = {
      .layout = RANGING_CAN_LAYOUT_DEFAULT,
      .self_id = RANGING_CAN_SELF_ID,
      .stale_us = (uint32_t)(VIRTUAL_RANGING_STALE_TIME * 1e6f),
    },
    .max_frames_per_event = RANGING_CAN_MAX_FRAMES_PER_EVENT,
  };
  char err[256];
  ranging_can_close(vl->can);
  vl->can = ranging_can_open(&cfg, err, sizeof(err));
  if (vl->can == NULL) {
    fprintf(stderr, "virtual_ranging: %s\n", err);
    return false;
  }
  return true;
}

void virtual_ranging_arch_periodic(uint32_t now_us __attribute__((unused)))
{
  struct virtual_ranging_linux *vl = VEHICLE_LOCAL(virtual_ranging_linux);
  struct ranging_can_stats st;
  ranging_can_stats(vl->can, &st);
  if (st.rx.bus_off != vl->bus_off_seen) {
    vl->bus_off_seen = st.rx.bus_off;
    fprintf(stderr, "virtual_ranging: CAN bus-off (%u so far)\n", (unsigned)st.rx.bus_off);
  }
  if (st.rx.restarts != vl->restarts_seen) {
    vl->restarts_seen = st.rx.restarts;
    fprintf(stderr, "virtual_ranging: CAN bus back after bus-off (%u restarts so far)\n", (unsigned)st.rx.restarts);
  }
}

static void on_reading(void *user __attribute__((unused)), const struct ranging_can_reading *r)
{
  virtual_ranging_report(r->other_id, r->range_m, r->stamp_us);
}

void virtual_ranging_arch_event(uint32_t now_us)
{
  struct virtual_ranging_linux *vl = VEHICLE_LOCAL(virtual_ranging_linux);
  if (ranging_can_event(vl->can, now_us, on_reading, NULL) < 0) {
    if (!vl->read_failed) {
      vl->read_failed = true;
      fprintf(stderr, "virtual_ranging: %s\n", ranging_can_last_error(vl->can));
    }
    return;
  }
  vl->read_failed = false;
}
