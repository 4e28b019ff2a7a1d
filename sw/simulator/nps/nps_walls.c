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
 * @file nps_walls.c
 * Paparazzi-NPS-shaped hook (nps_walls_init, nps_walls_run_step) over one simulator-wide arena.
 */

#include "nps_walls.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

static struct nps_arena *walls_arena;
static char walls_error[512];

int nps_walls_init(const char *arena_file)
{
  walls_error[0] = '\0';
  struct nps_arena *a = nps_arena_load(arena_file, walls_error, sizeof walls_error);
  if (!a) {
    return -1;
  }
  nps_arena_free(walls_arena);
  walls_arena = a;
  return 0;
}

const char *nps_walls_error(void)
{
  return walls_error;
}

int nps_walls_set_copters(const struct nps_arena_copter *copters, int n)
{
  if (!walls_arena) {
    snprintf(walls_error, sizeof walls_error, "nps_walls_set_copters: nps_walls_init was not called");
    return -1;
  }
  if (nps_arena_set_copters(walls_arena, copters, n) != 0) {
    snprintf(walls_error, sizeof walls_error, "nps_walls_set_copters: %s", strerror(errno));
    return -1;
  }
  return 0;
}

void nps_walls_run_step(double time)
{
  if (walls_arena && nps_arena_walls_step(walls_arena, time) != 0) {
    snprintf(walls_error, sizeof walls_error,
             "nps_walls_run_step: time %.9g s is not finite or before the last step at %.9g s", time, walls_arena->time_s);
  }
}

struct nps_arena *nps_walls_arena(void)
{
  return walls_arena;
}

void nps_walls_free(void)
{
  nps_arena_free(walls_arena);
  walls_arena = NULL;
}
