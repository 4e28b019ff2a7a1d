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
 * @file modules/sonar/sonar_array_schedule.h
 * Staggered round robin of the FINken sonar ring: one sonar fires while an earlier one is read.
 *
 * Time is cut into slots of 1 / (SONAR_ARRAY_NB x rate) seconds. In each slot the next sonar of the firing
 * order is triggered, and the sonar triggered `read_delay_slots` slots earlier is read: its listening
 * window is read_delay_slots slots long, which must cover the echo's round trip at the maximum range
 * (2 x max_range / c). Consecutive sonars of the order point away from each other.
 * Pure logic: the caller passes the time in.
 */

#ifndef SONAR_ARRAY_SCHEDULE_H
#define SONAR_ARRAY_SCHEDULE_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** The sonars of the ring, by position (body frame). */
enum sonar_array_index {
  SONAR_ARRAY_FRONT = 0,
  SONAR_ARRAY_RIGHT = 1,
  SONAR_ARRAY_BACK = 2,
  SONAR_ARRAY_LEFT = 3,
  SONAR_ARRAY_DOWN = 4,
  SONAR_ARRAY_NB = 5
};

/** What happens in one slot; -1 = nothing. */
struct sonar_array_slot {
  int8_t fire;          ///< sonar to trigger now
  int8_t read;          ///< sonar whose listening window ends now
  uint32_t fired_at_us; ///< when the sonar being read was triggered
};

struct sonar_array_schedule {
  uint32_t slot_us;          ///< slot length [us]
  uint8_t read_delay_slots;  ///< listening window in slots (1 .. SONAR_ARRAY_NB - 1)
  uint32_t next_slot_us;     ///< start of the next slot
  uint32_t slot_count;       ///< slots started so far
  uint32_t fired_at_us[SONAR_ARRAY_NB];   ///< last trigger time of each sonar
  uint32_t fired_in_slot[SONAR_ARRAY_NB]; ///< slot number of that trigger
};

/** Firing order: front, back, right, left, down (each one turned away from the one before). */
extern const uint8_t sonar_array_firing_order[SONAR_ARRAY_NB];

/**
 * Set up for `rate_hz` readings per sonar per second, starting at start_us.
 * Returns false (and leaves the schedule unusable) if rate_hz is 0 or read_delay_slots is out of range.
 */
extern bool sonar_array_schedule_init(struct sonar_array_schedule *s, uint32_t rate_hz, uint8_t read_delay_slots,
                                      uint32_t start_us);

/**
 * The slot due at now_us, if one is: returns true and fills *slot once per slot. If the caller falls
 * behind by several slots, the missed slots are skipped (their sonars neither fire nor read).
 */
extern bool sonar_array_schedule_poll(struct sonar_array_schedule *s, uint32_t now_us, struct sonar_array_slot *slot);

/** Listening window [s] of a schedule. */
static inline float sonar_array_schedule_window_s(const struct sonar_array_schedule *s)
{
  return s->read_delay_slots * s->slot_us * 1e-6f;
}

#ifdef __cplusplus
}
#endif

#endif /* SONAR_ARRAY_SCHEDULE_H */
