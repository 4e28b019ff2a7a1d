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
 * @file modules/sonar/sonar_array_schedule.c
 * Staggered round robin of the FINken sonar ring (see sonar_array_schedule.h).
 */

#include "modules/sonar/sonar_array_schedule.h"

const uint8_t sonar_array_firing_order[SONAR_ARRAY_NB] = {
  SONAR_ARRAY_FRONT, SONAR_ARRAY_BACK, SONAR_ARRAY_RIGHT, SONAR_ARRAY_LEFT, SONAR_ARRAY_DOWN
};

bool sonar_array_schedule_init(struct sonar_array_schedule *s, uint32_t rate_hz, uint8_t read_delay_slots,
                               uint32_t start_us)
{
  s->slot_us = 0;
  if (rate_hz == 0 || read_delay_slots < 1 || read_delay_slots >= SONAR_ARRAY_NB) {
    return false;
  }
  s->slot_us = 1000000u / (rate_hz * SONAR_ARRAY_NB);
  s->read_delay_slots = read_delay_slots;
  s->next_slot_us = start_us;
  s->slot_count = 0;
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    s->fired_at_us[i] = start_us;
    s->fired_in_slot[i] = UINT32_MAX;  /* never fired */
  }
  return s->slot_us > 0;
}

bool sonar_array_schedule_poll(struct sonar_array_schedule *s, uint32_t now_us, struct sonar_array_slot *slot)
{
  if (s->slot_us == 0 || (int32_t)(now_us - s->next_slot_us) < 0) {
    return false;
  }
  /* skip the slots we are too late for: firing late would shorten the listening windows (the division, slow,
   * only when at least one slot is missed: on time, the usual case, none is) */
  const uint32_t behind_us = now_us - s->next_slot_us;
  const uint32_t late_slots = behind_us < s->slot_us ? 0 : behind_us / s->slot_us;
  s->slot_count += late_slots;
  s->next_slot_us += (late_slots + 1) * s->slot_us;

  const uint32_t k = s->slot_count++;
  slot->fire = (int8_t)sonar_array_firing_order[k % SONAR_ARRAY_NB];
  slot->read = -1;
  slot->fired_at_us = 0;
  if (k >= s->read_delay_slots) {
    const uint8_t read = sonar_array_firing_order[(k - s->read_delay_slots) % SONAR_ARRAY_NB];
    if (s->fired_in_slot[read] == k - s->read_delay_slots) {  /* it did fire then: not a skipped slot */
      slot->read = (int8_t)read;
      slot->fired_at_us = s->fired_at_us[read];
    }
  }
  s->fired_at_us[slot->fire] = now_us;
  s->fired_in_slot[slot->fire] = k;
  return true;
}
