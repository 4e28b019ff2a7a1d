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
 * @file nps_arena_contact.h
 * Contacts in the arena: copter bodies do not pass through each other, and the curtain walls stop a copter.
 * A position-based correction after each flight-model step (the flight model itself knows no obstacles).
 */

#ifndef NPS_ARENA_CONTACT_H
#define NPS_ARENA_CONTACT_H

#include "nps_arena.h"

/**
 * Move the copters of the arena (nps_arena_set_copters) out of each other and back inside the wall polygon
 * at rest: two overlapping bodies are pushed apart along the line between their centres, each by half the
 * overlap; a body closer to a wall than its radius is pushed back along the wall's inward normal.
 * Neighbours come from the copter grid (no all-pairs scan). The grid is re-indexed when anything moved.
 * @param moved  per copter (arena order), set to 1 when it was moved (may be NULL)
 * @return the number of contacts resolved (pairs and wall pushes), or -1 on ENOMEM
 */
int nps_arena_resolve_contacts(struct nps_arena *a, int *moved);

#endif /* NPS_ARENA_CONTACT_H */
