/*
 * Poses in the shared world (nps_swarm.c): a pose given with nps_swarm_set_pose is taken at the next
 * nps_swarm_step, so a copter whose flight model has moved on (the host runs each copter's modules and then its
 * flight model, copters on several threads) changes nothing the other copters' sensors read in the same step.
 * Two copters 1 m apart at 0.6 m in the SwarmLab arena (bodies of radius 0.2 m), the identity sonar model:
 * readings are the ray-cast truth, exact.
 */
#include "test_helpers.h"
#include "nps_swarm.h"

#include <stdlib.h>
#include <unistd.h>

static int teardown(void **state)
{
  (void)state;
  nps_swarm_free();
  return 0;
}

/** Copter 0 at (1, 2) facing east, copter 1 at (x1, 2): the front sonar reads x1 - 1 - 0.2 m. */
static void set_poses(double x1_m)
{
  const double p0[3] = {1.0, 2.0, 0.6}, p1[3] = {x1_m, 2.0, 0.6};
  nps_swarm_set_pose(0, p0, 0.0, 0.0);
  nps_swarm_set_pose(1, p1, 0.0, 0.0);
}

/** The world with copter 1 at x1_m (set_poses), after its first step. */
static void start_two_copters(double x1_m)
{
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 2, .arena_file = "conf/arena/swarmlab.xml", .sensor_model = "sonar(min_range=0.2, max_range=3.0)",
  };
  assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
  set_poses(x1_m);
  assert_int_equal(nps_swarm_step(0.0), 0);
}

static void a_pose_is_taken_at_the_next_step(void **state)
{
  (void)state;
  start_two_copters(2.0);
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.8, 1e-12);

  set_poses(2.5);   /* copter 1's flight model moves on: not seen before the next step */
  double pos_m[3];
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 2.0, 0.0);
  assert_close(nps_swarm_sonar_read(0, 0, 0.05, 0.07), 0.8, 1e-12);

  assert_int_equal(nps_swarm_step(0.01), 0);
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 2.5, 0.0);
  assert_close(nps_swarm_sonar_read(0, 0, 0.1, 0.12), 1.3, 1e-12);
}

static void a_copter_without_a_new_pose_keeps_its_own(void **state)
{
  (void)state;
  start_two_copters(2.0);
  assert_int_equal(nps_swarm_step(0.01), 0);   /* nobody gave a pose: both stay */
  double pos_m[3];
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 2.0, 0.0);
  assert_close(nps_swarm_sonar_read(0, 0, 0.1, 0.12), 0.8, 1e-12);
}

static void each_copter_is_told_whether_the_contacts_moved_it(void **state)
{
  (void)state;
  start_two_copters(2.0);
  assert_int_equal(nps_swarm_step(0.01), 0);
  assert_false(nps_swarm_pushed(0));
  assert_false(nps_swarm_pushed(1));
  set_poses(1.3);   /* the bodies (radius 0.2 m) overlap by 0.1 m: each is pushed 0.05 m along x */
  assert_int_equal(nps_swarm_step(0.02), 0);
  assert_true(nps_swarm_pushed(0));
  assert_true(nps_swarm_pushed(1));
  double pos_m[3];
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 1.35, 1e-12);
  set_poses(2.0);   /* apart again: a flag holds for one step only */
  assert_int_equal(nps_swarm_step(0.03), 0);
  assert_false(nps_swarm_pushed(0));
  assert_false(nps_swarm_pushed(1));
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 2.0, 0.0);
  set_poses(2.9);   /* copter 1 into the east wall (x = 3 m): only it is told, copter 0 far from everything is not */
  assert_int_equal(nps_swarm_step(0.04), 0);
  assert_false(nps_swarm_pushed(0));
  assert_true(nps_swarm_pushed(1));
  nps_swarm_get_position(1, pos_m);
  assert_close(pos_m[0], 2.8, 1e-12);
}

/** The world of two copters with the given model and, if readings_path, a range log. */
static void start_with(const char *model, const char *readings_path)
{
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 2, .arena_file = "conf/arena/swarmlab.xml", .sensor_model = model,
    .readings_path = readings_path,
  };
  assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
}

static void speeds_are_needed_only_by_a_chain_reading_them_or_the_log(void **state)
{
  (void)state;
  start_with("sonar(min_range=0.2, max_range=3.0)", NULL);
  assert_false(nps_swarm_needs_speed());
  start_with("sonar(min_range=0.2, max_range=3.0) | ranging(max_range=2.5): bias(b=0.1) if ctx_speed", NULL);
  assert_true(nps_swarm_needs_speed());
  start_with("sonar(min_range=0.2, max_range=3.0): bias(b=0.1) if ctx_speed", NULL);
  assert_true(nps_swarm_needs_speed());
  char path[] = "/tmp/test_swarm_pose_XXXXXX";
  const int fd = mkstemp(path);
  assert_true(fd >= 0);
  close(fd);
  start_with("sonar(min_range=0.2, max_range=3.0)", path);
  assert_true(nps_swarm_needs_speed());   /* the log has every context column */
  nps_swarm_free();
  unlink(path);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_teardown(a_pose_is_taken_at_the_next_step, teardown),
    cmocka_unit_test_teardown(a_copter_without_a_new_pose_keeps_its_own, teardown),
    cmocka_unit_test_teardown(each_copter_is_told_whether_the_contacts_moved_it, teardown),
    cmocka_unit_test_teardown(speeds_are_needed_only_by_a_chain_reading_them_or_the_log, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
