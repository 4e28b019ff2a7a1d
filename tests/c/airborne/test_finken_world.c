/*
 * The finken_world module (the arena inside Paparazzi's NPS): the NED -> arena frame conversion by hand-computed
 * values; the attitude quaternion of the pose rows against rotation matrices built from Paparazzi's Euler angles
 * (body FRD -> NED, then NED -> ENU), and its heading against the pose's yaw; that the module puts the flight model
 * at the aircraft's start; that readings through the module (poses from NPS's fdm) are bit for bit those of the
 * simulator driven directly with the same arena poses, seed and aircraft id, as our host drives it.
 */
#include "test_helpers.h"
#include "modules/finken_world/finken_world.h"
#include "mcu_periph/sys_time.h"
#include "nps_arena_start.h"
#include "nps_fdm.h"
#include "nps_swarm.h"
#include "nps_swarm_shared.h"
#include "pprz_host_vehicle.h"

#include <stdlib.h>
#include <unistd.h>

static void converts_ned_to_the_arena_frame(void **state)
{
  (void)state;
  const double pos[3] = { 1.0, 2.0, -0.6 }, vel[3] = { 3.0, 4.0, -1.0 };
  struct finken_world_pose p = finken_world_pose_from_ned(pos, vel, 0.0);
  assert_close(p.pos_m[0], 2.0, 1e-12);        /* x = east */
  assert_close(p.pos_m[1], 1.0, 1e-12);        /* y = north */
  assert_close(p.pos_m[2], 0.6, 1e-12);        /* up = -down */
  assert_close(p.yaw_rad, M_PI / 2, 1e-12);    /* facing north */
  assert_close(p.speed_mps, 5.0, 1e-12);       /* horizontal only */
  p = finken_world_pose_from_ned(pos, vel, M_PI / 2);
  assert_close(p.yaw_rad, 0.0, 1e-12);         /* facing east: the arena's x */
}

/** Paparazzi's double_quat_of_eulers (ZYX): the NED -> body FRD quaternion (qi, qx, qy, qz). */
static void quat_of_eulers(double phi, double theta, double psi, double q[4])
{
  const double cf = cos(phi / 2), sf = sin(phi / 2), ct = cos(theta / 2), st = sin(theta / 2);
  const double cp = cos(psi / 2), sp = sin(psi / 2);
  q[0] = cf * ct * cp + sf * st * sp;
  q[1] = -cf * st * sp + sf * ct * cp;
  q[2] = cf * st * cp + sf * ct * sp;
  q[3] = cf * ct * sp - sf * st * cp;
}

/** v rotated by the unit quaternion (x, y, z, w): q v q*. */
static void rotate(const double q[4], const double v[3], double out[3])
{
  const double x = q[0], y = q[1], z = q[2], w = q[3];
  const double m[3][3] = {
    { 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y) },
    { 2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x) },
    { 2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y) },
  };
  for (int i = 0; i < 3; i++) {
    out[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  }
}

/** A body FRD vector in the arena: the Euler angles' matrix (body -> NED), then ENU. */
static void frd_to_arena(double phi, double theta, double psi, const double frd[3], double out[3])
{
  const double cf = cos(phi), sf = sin(phi), ct = cos(theta), st = sin(theta), cp = cos(psi), sp = sin(psi);
  const double ned_of_body[3][3] = {   /* the transpose of Paparazzi's ltp_to_body matrix */
    { ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp },
    { ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp },
    { -st, sf * ct, cf * ct },
  };
  double ned[3];
  for (int i = 0; i < 3; i++) {
    ned[i] = ned_of_body[i][0] * frd[0] + ned_of_body[i][1] * frd[1] + ned_of_body[i][2] * frd[2];
  }
  out[0] = ned[1];
  out[1] = ned[0];
  out[2] = -ned[2];
}

static void the_attitude_turns_the_body_axes_as_paparazzis_angles_do(void **state)
{
  (void)state;
  /* by hand: level, heading north (psi 0): the arena's yaw pi/2, a turn about up */
  const double level_north[4] = { 1.0, 0.0, 0.0, 0.0 };
  double q[4];
  finken_world_attitude_from_ned(level_north, q);
  assert_close(q[0], 0.0, 1e-15);
  assert_close(q[1], 0.0, 1e-15);
  assert_close(q[2], M_SQRT1_2, 1e-15);
  assert_close(q[3], M_SQRT1_2, 1e-15);
  /* any attitude: the body's forward, left and up axes (FLU) land where the Euler angles put them */
  uint32_t seed = 7;
  for (int k = 0; k < 2000; k++) {
    const double phi = lcg_uniform(&seed, -1.5, 1.5), theta = lcg_uniform(&seed, -1.5, 1.5);
    const double psi = lcg_uniform(&seed, -M_PI, M_PI);
    double ned_quat[4];
    quat_of_eulers(phi, theta, psi, ned_quat);
    finken_world_attitude_from_ned(ned_quat, q);
    assert_close(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0, 1e-14);
    const double flu[3][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 } };
    const double frd[3][3] = { { 1, 0, 0 }, { 0, -1, 0 }, { 0, 0, -1 } };   /* the same axes in FRD */
    for (int a = 0; a < 3; a++) {
      double got[3], want[3];
      rotate(q, flu[a], got);
      frd_to_arena(phi, theta, psi, frd[a], want);
      for (int i = 0; i < 3; i++) {
        assert_close(got[i], want[i], 1e-13);
      }
    }
    /* the quaternion's heading is the pose's yaw (finken_world_pose_from_ned), modulo 2 pi */
    const double zero[3] = { 0.0, 0.0, 0.0 };
    const struct finken_world_pose p = finken_world_pose_from_ned(zero, zero, psi);
    const double yaw = atan2(2 * (q[3] * q[2] + q[0] * q[1]), 1 - 2 * (q[1] * q[1] + q[2] * q[2]));
    assert_close(remainder(yaw - p.yaw_rad, 2 * M_PI), 0.0, 1e-12);
  }
}

/* Where copter v of n starts in the loaded arena (nps_arena_start_poses): arena x, y [m] and yaw [rad]. */
static void start_of(unsigned v, unsigned n, double xy_m[2], double *yaw_rad)
{
  double pos_m[NPS_WORLD_MAX_AIRCRAFT][2], yaws_rad[NPS_WORLD_MAX_AIRCRAFT];
  char err[256] = "";
  assert_int_equal(nps_arena_start_poses(nps_swarm_arena(), n, pos_m, yaws_rad, err, sizeof err), 0);
  xy_m[0] = pos_m[v][0];
  xy_m[1] = pos_m[v][1];
  *yaw_rad = yaws_rad[v];
}

/* Where aircraft 1 of 1 starts (the arena is loaded): NED north and east [m] and heading [rad]. */
static void start_ned(double ned_m[2], double *psi_rad)
{
  double xy_m[2], yaw_rad;
  start_of(0, 1, xy_m, &yaw_rad);
  ned_m[0] = xy_m[1];
  ned_m[1] = xy_m[0];
  *psi_rad = M_PI / 2 - yaw_rad;
}

/* A copter circling at 0.6 m through its start, given to the module as NPS's fdm (NED about the arena's origin). */
static double script_t_s;
static void circle_ned(double t_s, double pos[3], double *psi)
{
  double start[2], psi0;
  start_ned(start, &psi0);
  pos[0] = start[0] + 0.5 * sin(0.5 * t_s);
  pos[1] = start[1] + 0.5 * cos(0.5 * t_s) - 0.5;
  pos[2] = -0.6;
  *psi = psi0 + 0.3 * t_s;
}

static void scripted_fdm(struct NpsFdm *f, unsigned vehicle)
{
  (void)vehicle;
  double pos[3], psi;
  circle_ned(script_t_s, pos, &psi);
  f->ltpprz_pos = (struct NedCoor_d) { pos[0], pos[1], pos[2] };
  f->ltpprz_ecef_vel = (struct NedCoor_d) { 0.0, 0.0, 0.0 };
  f->ltpprz_to_body_eulers.psi = psi;
}

/* The scripted pose in the arena (the module's conversion, tested above). */
static void set_scripted_pose(double t_s)
{
  double pos[3], psi;
  circle_ned(t_s, pos, &psi);
  const double vel[3] = { 0.0, 0.0, 0.0 };
  const struct finken_world_pose p = finken_world_pose_from_ned(pos, vel, psi);
  nps_swarm_set_pose(0, p.pos_m, p.yaw_rad, 0.0);
}

#define STEPS 400
#define DT_S 0.01

/* Sonar readings over STEPS steps, each sonar fired every 5 steps; `through_module` picks the path (first: the
 * direct path takes its world clock). */
static void read_sonars(bool through_module, double readings[STEPS])
{
  static double world_offset_s;
  sys_time_host_set(0.0);
  if (through_module) {
    script_t_s = 0.0;
    finken_world_init();
    world_offset_s = nps_swarm_shared_offset_s();
  } else {
    char err[512];
    const struct nps_swarm_config cfg = {
      .seed = 1, .vehicles = 1, .first_id = pprz_vehicle_ac_id(), .arena_file = "conf/arena/swarmlab.xml",
      .sensor_model = "conf/sensor_models/finken_default.xml", .walls_period_s = 1.0,
    };
    assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
    nps_swarm_set_clock_offset(world_offset_s);
    set_scripted_pose(0.0);   /* the circle at t = 0, as the host starts: pose, step */
    assert_int_equal(nps_swarm_step(0.0), 0);
  }
  for (int k = 0; k < STEPS; k++) {
    const double t_s = (k + 1) * DT_S;
    sys_time_host_set(t_s);
    script_t_s = t_s;
    if (through_module) {
      finken_world_periodic();
    } else {
      set_scripted_pose(t_s);
      assert_int_equal(nps_swarm_step(get_sys_time_usec() * 1e-6), 0);   /* the module's clock */
    }
    const unsigned sonar = (unsigned)(k / 5) % 4;
    if (k % 5 == 0) {
      nps_swarm_sonar_trigger(0, sonar, t_s);
    }
    readings[k] = k % 5 == 4 ? nps_swarm_sonar_read(0, sonar, t_s - 4 * DT_S, t_s) : 0.0;
  }
  if (through_module) {
    nps_swarm_unshare();
  }
  assert_int_equal(nps_swarm_free(), 0);
}

/* A world of this test's own (named after the test and the process), without logs or PAPARAZZI_HOME. */
static void world_of_this_test(const char *tag)
{
  unsetenv("PAPARAZZI_HOME");
  unsetenv("FINKEN_WORLD_OUT");
  char world[64];
  snprintf(world, sizeof(world), "%s.%d", tag, (int)getpid());
  setenv("FINKEN_WORLD", world, 1);
}

/* Without a flight model's source, the module's start leaves the copter at rest where our host starts it, in the
 * flight plan's frame (the arena's), for a swarm of 4; a contact with a wall moves the flight model too. */
static void places_the_aircraft_and_feeds_contacts_back(void **state)
{
  (void)state;
  world_of_this_test("test_finken_world_start");
  setenv("FINKEN_WORLD_AIRCRAFT", "4", 1);
  pprz_vehicles_setup(1, NULL);
  sys_time_host_set(0.0);
  finken_world_init();
  double xy_m[2], yaw_rad;
  start_of((unsigned)pprz_vehicle_ac_id() - 1, 4, xy_m, &yaw_rad);
  assert_close(fdm.ltpprz_pos.x, xy_m[1], 1e-12);
  assert_close(fdm.ltpprz_pos.y, xy_m[0], 1e-12);
  assert_close(fdm.ltpprz_pos.z, 0.0, 1e-12);
  assert_close(remainder(fdm.ltpprz_to_body_eulers.psi - (M_PI / 2 - yaw_rad), 2 * M_PI), 0.0, 1e-12);
  double pos_m[3];
  nps_swarm_get_position(0, pos_m);   /* the world has it there too (the module's first step) */
  assert_close(pos_m[0], xy_m[0], 1e-9);
  assert_close(pos_m[1], xy_m[1], 1e-9);
  /* flown into the west wall (x = 0), 5 cm from it: the world's contact pushes it out to its radius from the wall,
   * and the flight model takes that position */
  fdm.ltpprz_pos = (struct NedCoor_d) { 2.0, 0.05, -0.6 };
  for (int k = 1; k <= 8; k++) {   /* up to the next meeting, where the contacts are resolved */
    sys_time_host_set(0.01 * k);
    finken_world_periodic();
  }
  nps_swarm_get_position(0, pos_m);
  assert_close(pos_m[0], 0.2, 1e-9);   /* the copter's radius (nps_arena.c's default) */
  assert_close(fdm.ltpprz_pos.y, pos_m[0], 1e-12);
  assert_close(fdm.ltpprz_pos.x, pos_m[1], 1e-12);
  nps_swarm_unshare();
  assert_int_equal(nps_swarm_free(), 0);
  pprz_vehicles_teardown();
  unsetenv("FINKEN_WORLD_AIRCRAFT");
}

/* One build flown as another aircraft of the world (make bench): FINKEN_WORLD_AC_ID picks its start, aircraft 3 of 4. */
static void the_world_id_may_come_from_the_environment(void **state)
{
  (void)state;
  world_of_this_test("test_finken_world_id");
  setenv("FINKEN_WORLD_AIRCRAFT", "4", 1);
  setenv("FINKEN_WORLD_AC_ID", "3", 1);
  pprz_vehicles_setup(1, NULL);
  sys_time_host_set(0.0);
  finken_world_init();
  double xy_m[2], yaw_rad;
  start_of(2, 4, xy_m, &yaw_rad);
  assert_close(fdm.ltpprz_pos.x, xy_m[1], 1e-12);
  assert_close(fdm.ltpprz_pos.y, xy_m[0], 1e-12);
  assert_true(pprz_vehicle_ac_id() != 3);   /* the build's own id is another */
  nps_swarm_unshare();
  assert_int_equal(nps_swarm_free(), 0);
  pprz_vehicles_teardown();
  unsetenv("FINKEN_WORLD_AC_ID");
  unsetenv("FINKEN_WORLD_AIRCRAFT");
}

static void readings_are_the_simulators_with_the_same_poses(void **state)
{
  (void)state;
  world_of_this_test("test_finken_world");
  pprz_vehicles_setup(1, NULL);
  nps_fdm_set_source(scripted_fdm);
  static double via_module[STEPS], direct[STEPS];
  read_sonars(true, via_module);
  read_sonars(false, direct);
  int echoes = 0;
  for (int k = 0; k < STEPS; k++) {
    assert_memory_equal(&via_module[k], &direct[k], sizeof(double));
    echoes += k % 5 == 4 && via_module[k] < 3.0;
  }
  assert_true(echoes > 20);   /* the copter hears the walls: the comparison is not between two empty worlds */
  nps_fdm_set_source(NULL);
  pprz_vehicles_teardown();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(converts_ned_to_the_arena_frame),
    cmocka_unit_test(the_attitude_turns_the_body_axes_as_paparazzis_angles_do),
    cmocka_unit_test(places_the_aircraft_and_feeds_contacts_back),
    cmocka_unit_test(the_world_id_may_come_from_the_environment),
    cmocka_unit_test(readings_are_the_simulators_with_the_same_poses),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
