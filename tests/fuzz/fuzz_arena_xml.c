/*
 * libFuzzer harness: arena files (XML, <arena> root), sw/simulator/nps/nps_arena_xml.c and the checks and build
 * behind nps_arena_load(). An arena that loads is flown in: four copters at their start poses, one of them close
 * to the middle of wall 0 (its plates are driven), ten wall steps of 10 ms, the floor material under each copter
 * (one of the file's) and every sonar's ray cast.
 */
#include "fuzz_common.h"

#include <math.h>

#include "nps_arena.h"
#include "nps_arena_start.h"
#include "nps_raycast.h"
#include "nps_walls.h"

#define COPTERS 4

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

static void fly(struct nps_arena *a)
{
  struct nps_arena_copter copter[COPTERS];
  double pos_m[COPTERS][2], yaw_rad[COPTERS];
  char err[256];
  if (nps_arena_start_poses(a, COPTERS, pos_m, yaw_rad, err, sizeof err) != 0) {
    return;   /* an arena too small for the copters: refused with the reason */
  }
  for (int v = 0; v < COPTERS; v++) {
    copter[v] = nps_arena_copter_make(a, v, pos_m[v][0], pos_m[v][1], a->flight_height_m, yaw_rad[v]);
  }
  const struct nps_wall *w = &a->walls[0];
  const double inside_m = a->copter_radius_m + 0.05;
  copter[0].pos_m[0] = 0.5 * (w->a[0] + w->b[0]) + inside_m * w->n[0];
  copter[0].pos_m[1] = 0.5 * (w->a[1] + w->b[1]) + inside_m * w->n[1];
  if (nps_arena_set_copters(a, copter, COPTERS) != 0) {
    return;
  }
  for (int step = 0; step < 10; step++) {
    fuzz_require(nps_arena_walls_step(a, 0.01 * step) == 0);
  }
  for (int v = 0; v < COPTERS; v++) {
    const enum nps_floor_material m = nps_floor_material_at(&a->floor, a->copters[v].pos_m[0], a->copters[v].pos_m[1]);
    fuzz_require(m > NPS_FLOOR_NONE && m < NPS_FLOOR_MATERIALS);   /* a floor material under every copter */
    for (int s = 0; s < NPS_SONAR_COUNT; s++) {
      struct nps_ray_hit hit;
      (void)nps_raycast_sonar(a, &a->copters[v], (enum nps_sonar)s, a->sonar_range_m, &hit);
    }
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char err[512] = "";
  struct nps_arena *a = nps_arena_load(fuzz_file(data, size), err, sizeof(err));
  if (a == NULL) {
    fuzz_require(err[0] != '\0');
    return 0;
  }
  fly(a);
  nps_arena_free(a);
  return 0;
}
