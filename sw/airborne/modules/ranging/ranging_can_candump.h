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
 * @file modules/ranging/ranging_can_candump.h
 * One line of a can-utils `candump -l` log, parsed without any OS call (for replays on the host and in tests).
 *
 * Line format (can-utils lib.c, candump.c):
 *
 *     (1700000000.123456) can0 123#DEADBEEF        classical frame, 3 hex digits: standard id
 *     (1700000000.123456) can0 1F334455#11.22      8 hex digits: extended id ('.' between bytes allowed)
 *     (1700000000.123456) can0 123#R  or  123#R4   remote request (optional length digit)
 *     (1700000000.123456) can0 123##1112233        CAN FD: one hex digit of flags (BRS 1, ESI 2), then data
 *     (1700000000.123456) can0 20000040#0000000000000000   error frame (8 digits with bit 29 set)
 *
 * Optional: a `_<hex digit>` DLC suffix after 8 data bytes (classical frames with a DLC above 8, kept as 8
 * bytes) and a trailing direction flag ` T` or ` R` (candump -x). The time stamp may carry 1 to 9 decimals
 * (kept to the microsecond). Blank lines are skipped. Anything else (a CAN XL frame, an id of another width,
 * an odd number of hex digits, too much data, ...) is an error that says what was expected.
 *
 * The Python tools parse logs with this code too (tools/finken/can/_native.py copies the declarations).
 */

#ifndef RANGING_CAN_CANDUMP_H
#define RANGING_CAN_CANDUMP_H

#include "modules/ranging/ranging_can_frame.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Longest interface name + 1 (Linux IFNAMSIZ) */
#define RANGING_CAN_CANDUMP_IFNAME_LEN 16

struct ranging_can_candump_line {
  uint64_t time_us;                              ///< log time stamp [us since the epoch]
  char ifname[RANGING_CAN_CANDUMP_IFNAME_LEN];   ///< interface the frame was logged on
  struct ranging_can_raw frame;                  ///< the frame (bytes beyond len are zero)
};

/**
 * Parse one line (with or without its trailing newline).
 * @param why on error: what was wrong and what was expected (a static string)
 * @return 1 a frame in *out, 0 a blank line, -1 an error
 */
extern int ranging_can_candump_parse(const char *line, struct ranging_can_candump_line *out, const char **why);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_CAN_CANDUMP_H */
