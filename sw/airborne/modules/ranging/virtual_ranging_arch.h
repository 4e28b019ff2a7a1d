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
 * @file modules/ranging/virtual_ranging_arch.h
 * What the ranging module needs from the hardware. Implementations call virtual_ranging_report() for each
 * distance: arch/linux from CAN frames in the event loop, arch/sim (NPS) from the simulated peers.
 */

#ifndef VIRTUAL_RANGING_ARCH_H
#define VIRTUAL_RANGING_ARCH_H

#include "std.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Open the ranging unit; false if it cannot be used. */
extern bool virtual_ranging_arch_init(void);
/** Periodic work at the module's rate (NPS: measure every peer). */
extern void virtual_ranging_arch_periodic(uint32_t now_us);
/** Event-loop work (Linux: read the frames that arrived). */
extern void virtual_ranging_arch_event(uint32_t now_us);

#ifdef __cplusplus
}
#endif

#endif /* VIRTUAL_RANGING_ARCH_H */
