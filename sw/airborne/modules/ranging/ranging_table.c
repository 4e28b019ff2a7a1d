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
 * @file modules/ranging/ranging_table.c
 * The newest distance to each peer (see ranging_table.h).
 */

#include "modules/ranging/ranging_table.h"

#include <string.h>

_Static_assert(RANGING_TABLE_MAX_PEERS <= 256, "the look-up hint holds entry indices in a uint8_t");

void ranging_table_init(struct ranging_table *t, uint32_t stale_after_us)
{
  memset(t, 0, sizeof(*t));
  t->stale_after_us = stale_after_us;
}

/** Index of the entry holding peer_id, or -1. */
static int ranging_table_index(const struct ranging_table *t, uint16_t peer_id)
{
  if (peer_id == 0) {
    return -1;
  }
  /* ids are unique in the table: the hinted entry, if it holds the id, is the one the scan would find */
  const unsigned hinted = t->hint[peer_id % RANGING_TABLE_HINTS];
  if (t->peers[hinted].id == peer_id) {
    return (int)hinted;
  }
  for (unsigned i = 0; i < RANGING_TABLE_MAX_PEERS; i++) {
    if (t->peers[i].id == peer_id) {
      return (int)i;
    }
  }
  return -1;
}

const struct ranging_peer *ranging_table_find(const struct ranging_table *t, uint16_t peer_id)
{
  const int index = ranging_table_index(t, peer_id);
  return index < 0 ? NULL : &t->peers[index];
}

const struct ranging_peer *ranging_table_update(struct ranging_table *t, uint16_t peer_id, float distance_m,
                                                uint32_t stamp_us)
{
  const int index = ranging_table_index(t, peer_id);
  struct ranging_peer *slot = index < 0 ? NULL : &t->peers[index];
  if (slot == NULL) {
    /* a free entry, else the one heard longest ago */
    slot = &t->peers[0];
    for (unsigned i = 0; i < RANGING_TABLE_MAX_PEERS && slot->id != 0; i++) {
      if (t->peers[i].id == 0 || (int32_t)(t->peers[i].stamp_us - slot->stamp_us) < 0) {
        slot = &t->peers[i];
      }
    }
    *slot = (struct ranging_peer) { .id = peer_id };
  }
  t->hint[peer_id % RANGING_TABLE_HINTS] = (uint8_t)(slot - t->peers);
  slot->distance_m = distance_m;
  slot->stamp_us = stamp_us;
  slot->count++;
  return slot;
}

bool ranging_table_is_fresh(const struct ranging_table *t, const struct ranging_peer *p, uint32_t now_us)
{
  return p != NULL && p->id != 0 && p->count > 0 && now_us - p->stamp_us < t->stale_after_us;
}

unsigned ranging_table_fresh_distances(const struct ranging_table *t, uint32_t now_us, float *out, unsigned max)
{
  unsigned n = 0;
  for (unsigned i = 0; i < RANGING_TABLE_MAX_PEERS && n < max; i++) {
    if (ranging_table_is_fresh(t, &t->peers[i], now_us)) {
      out[n++] = t->peers[i].distance_m;
    }
  }
  return n;
}
