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
 * @file modules/ranging/virtual_ranging.c
 * Radio ranging between FINken: Paparazzi glue (see virtual_ranging.h).
 */

#include "modules/ranging/virtual_ranging.h"
#include "modules/ranging/virtual_ranging_arch.h"
#include "modules/core/abi.h"
#include "mcu_periph/sys_time.h"

/* the checks of the header's configuration (here, not in the header: C++ sources include it too) */
_Static_assert(VIRTUAL_RANGING_MAX_RANGE > 0.0f, "VIRTUAL_RANGING_MAX_RANGE must be positive");
_Static_assert(VIRTUAL_RANGING_STALE_TIME > 0.0f, "VIRTUAL_RANGING_STALE_TIME must be positive");

VEHICLE_LOCAL_DEFINE(struct virtual_ranging, virtual_ranging);

const struct ranging_table *virtual_ranging_table(void)
{
  return &VEHICLE_LOCAL(virtual_ranging)->table;
}

void virtual_ranging_report(uint16_t peer_id, float distance_m, uint32_t stamp_us)
{
  if (isnan(distance_m)) {
    return;
  }
  Bound(distance_m, 0.0f, VIRTUAL_RANGING_MAX_RANGE);
  ranging_table_update(&VEHICLE_LOCAL(virtual_ranging)->table, peer_id, distance_m, stamp_us);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, stamp_us, peer_id, distance_m);
}

void virtual_ranging_init(void)
{
  struct virtual_ranging *vr = VEHICLE_LOCAL(virtual_ranging);
  ranging_table_init(&vr->table, (uint32_t)(VIRTUAL_RANGING_STALE_TIME * 1e6f));
  vr->running = virtual_ranging_arch_init();
}

void virtual_ranging_periodic(void)
{
  if (VEHICLE_LOCAL(virtual_ranging)->running) {
    virtual_ranging_arch_periodic(get_sys_time_usec());
  }
}

void virtual_ranging_event(void)
{
  if (VEHICLE_LOCAL(virtual_ranging)->running) {
    virtual_ranging_arch_event(get_sys_time_usec());
  }
}
