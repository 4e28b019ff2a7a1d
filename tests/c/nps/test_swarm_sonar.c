/*
 * The simulated sonar ring in the shared world (nps_swarm): cross-talk happens exactly when the geometry and
 * the timing allow it, and the reading is then (one-way path + c x trigger offset) / 2 when that pulse arrives
 * before the sonar's own echo (a sonar reports the first echo); without noise a reading
 * is the ray-cast truth; a per-vehicle effect (condition ctx_vehicle == id) changes that aircraft's readings only. The
 * models have no random effect except crosstalk with p = 1, so every value is exact.
 * Two copters 1 m apart at 0.6 m in the SwarmLab arena (bodies of radius 0.2 m, sonars at the centre).
 */
#include "test_helpers.h"
#include "nps_swarm.h"
#include "nps_crosstalk.h"
#include "nps_swarm_world.h"

#include <math.h>

#define C_SOUND NPS_CROSSTALK_SPEED_OF_SOUND_MPS

static int setup_two_copters(double yaw1_rad, double crosstalk_p)
{
  char model[128], err[512];
  snprintf(model, sizeof(model), "sonar(min_range=0.2, max_range=3.0): crosstalk(p=%g)", crosstalk_p);
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 2, .arena_file = "conf/arena/swarmlab.xml", .sensor_model = model,
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    print_error("%s\n", err);
    return -1;
  }
  const double p0[3] = {1.0, 2.0, 0.6}, p1[3] = {2.0, 2.0, 0.6};
  nps_swarm_set_pose(0, p0, 0.0, 0.0);        /* front points east, at copter 1 */
  nps_swarm_set_pose(1, p1, yaw1_rad, 0.0);
  nps_swarm_sonar_attach(0, 0.0);             /* no phase shift: times are exact */
  nps_swarm_sonar_attach(1, 0.0);
  return nps_swarm_step(0.0);
}

static int teardown(void **state)
{
  (void)state;
  nps_swarm_free();
  return 0;
}

static void facing_pulses_fired_together_read_half_the_path(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI, 1.0), 0);   /* copter 1 faces copter 0 */
  nps_swarm_sonar_trigger(0, 0, 0.0);
  nps_swarm_sonar_trigger(1, 0, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 1.0 / 2.0, 1e-12);
}

static void a_later_pulse_reads_longer_if_it_beats_the_own_echo(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI, 1.0), 0);
  nps_swarm_sonar_trigger(0, 0, 0.0);
  nps_swarm_sonar_trigger(1, 0, 0.001);   /* arrives at 3.9 ms, before the own echo from 0.8 m (4.7 ms) */
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), (1.0 + C_SOUND * 0.001) / 2.0, 1e-12);
}

static void a_pulse_after_the_own_echo_is_not_what_the_sonar_reports(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI, 1.0), 0);
  nps_swarm_sonar_trigger(0, 0, 0.0);
  nps_swarm_sonar_trigger(1, 0, 0.01);    /* heard within the window, but after the echo from 0.8 m */
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.8, 1e-12);
}

static void a_pulse_that_arrives_before_the_window_is_not_heard(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI, 1.0), 0);
  nps_swarm_sonar_trigger(1, 0, 0.0);
  nps_swarm_sonar_trigger(0, 0, 0.03);   /* copter 1's pulse passed 27 ms before copter 0 listens */
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.03, 0.05), 0.8, 1e-12);   /* the truth: copter 1's body */
}

/* In Paparazzi's NPS each copter is a process whose clock is offset from the world's by wherever it joined; its
 * ring must keep the seeded phase on the world clock, or the processes' start times would set the cross-talk. Here
 * copter 1's process runs 12.3 ms (and then two 50-ms cycles more) behind the world, copter 0's on it; both rings
 * have phase 0 and fire at local time 0 (of a cycle): the pulses leave together on the world clock. */
static void a_ring_keeps_its_phase_on_the_world_clock_whatever_its_process_offset(void **state)
{
  (void)state;
  const double cycle_s = 0.05, behind_s[] = { 0.0123, 2 * 0.05 + 0.0123 };
  for (unsigned i = 0; i < 2; i++) {
    assert_int_equal(setup_two_copters(M_PI, 1.0), 0);   /* copter 1 faces copter 0 */
    for (unsigned v = 0; v < 2; v++) {
      nps_swarm_sonar_attach(v, cycle_s);
      nps_swarm_world.vehicles[v].sonar_phase_s = 0.0;
    }
    nps_swarm_set_clock_offset(behind_s[i]);   /* copter 1's process */
    nps_swarm_sonar_trigger(1, 0, 0.0);
    nps_swarm_sonar_publish_pings();
    nps_swarm_set_clock_offset(0.0);           /* copter 0's process */
    const double whole_cycles_s = 2 * cycle_s * i;
    assert_close(nps_swarm_sonar_read(0, 0, whole_cycles_s, whole_cycles_s + 0.02), 1.0 / 2.0, 1e-12);
    nps_swarm_free();
  }
}

static void no_cross_talk_without_a_facing_emitter(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI / 2.0, 1.0), 0);   /* copter 1 looks north: its left sonar faces west */
  for (unsigned s = 0; s < 3; s++) {                          /* front (north), right (east), back (south) */
    nps_swarm_sonar_trigger(1, s, 0.0);
  }
  nps_swarm_sonar_trigger(0, 0, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.8, 1e-12);
  nps_swarm_sonar_trigger(1, 3, 0.04);                        /* its left sonar does point at copter 0 */
  nps_swarm_sonar_trigger(0, 0, 0.04);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.04, 0.06), 0.5, 1e-12);
}

static void every_pending_ping_is_published_once(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI / 2.0, 1.0), 0);   /* copter 1's left sonar (3) faces copter 0 */
  nps_swarm_sonar_trigger(1, 0, 0.0);   /* its front sonar (north, facing nothing) pending too: both are published */
  nps_swarm_sonar_trigger(1, 3, 0.0);
  nps_swarm_sonar_publish_pings();
  nps_swarm_sonar_trigger(1, 3, 0.04);
  nps_swarm_sonar_publish_pings();
  nps_swarm_sonar_publish_pings();   /* nothing pending: the pulse of 0 s stays among the last two */
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.5, 1e-12);
}

static void a_copter_never_hears_its_own_ring(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI / 2.0, 1.0), 0);
  for (unsigned s = 0; s < 5; s++) {
    nps_swarm_sonar_trigger(0, s, 0.0);
  }
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.8, 1e-12);
}

static void without_noise_a_reading_is_the_ray_cast_truth(void **state)
{
  (void)state;
  assert_int_equal(setup_two_copters(M_PI, 0.0), 0);   /* crosstalk p = 0: the identity */
  nps_swarm_sonar_trigger(0, 2, 0.0);
  nps_swarm_sonar_trigger(0, 4, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 2, 0.0, 0.02), 1.0, 1e-12);   /* back: west wall at x = 0 */
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 4, 0.0, 0.02), 0.6, 1e-12);   /* down: the floor */
}

static void a_blocked_emitter_is_not_heard(void **state)
{
  (void)state;
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 3, .arena_file = "conf/arena/swarmlab.xml",
    .sensor_model = "sonar(min_range=0.2, max_range=3.0): crosstalk(p=1)",
  };
  assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
  /* copter 1 faces copter 0 at 1 m; copter 2 (none of its sonars within 15 deg of copter 0) stands between */
  const double p0[3] = {1.0, 2.0, 0.6}, p1[3] = {2.0, 2.0, 0.6}, p2[3] = {1.5, 2.0, 0.6};
  nps_swarm_set_pose(0, p0, 0.0, 0.0);
  nps_swarm_set_pose(1, p1, M_PI, 0.0);
  nps_swarm_set_pose(2, p2, M_PI / 4.0, 0.0);
  for (unsigned v = 0; v < 3; v++) {
    nps_swarm_sonar_attach(v, 0.0);
  }
  assert_int_equal(nps_swarm_step(0.0), 0);
  /* heard (arrives at 1.4 ms) and earlier than the own echo from copter 2's body at 0.3 m if the path were
   * clear ((1 - 343 x 0.0015) / 2 = 0.24 m), but copter 2 cuts the line: the reading is the truth */
  nps_swarm_sonar_trigger(1, 0, -0.0015);
  nps_swarm_sonar_trigger(0, 0, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 0, 0.0, 0.02), 0.3, 1e-12);
}

static void a_condition_on_the_wall_distance_sees_it_without_a_log(void **state)
{
  (void)state;
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 1, .arena_file = "conf/arena/swarmlab.xml",
    .sensor_model = "sonar(min_range=0.2, max_range=3.0): bias(b=1) if ctx_wall_dist",
  };
  assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
  const double p0[3] = {1.0, 2.0, 0.6};
  nps_swarm_set_pose(0, p0, 0.0, 0.0);
  nps_swarm_sonar_attach(0, 0.0);
  assert_int_equal(nps_swarm_step(0.0), 0);
  nps_swarm_sonar_trigger(0, 2, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 2, 0.0, 0.02), 1.0 + 1.0, 1e-12);   /* west wall 1 m behind, 1 m away */
}

static void a_per_vehicle_effect_applies_to_that_vehicle_only(void **state)
{
  (void)state;
  char err[512];
  /* the first id 5: copters 0 and 1 are aircraft 5 and 6 (ctx_vehicle is the id, as in the range log) */
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = 2, .arena_file = "conf/arena/swarmlab.xml", .first_id = 5,
    .sensor_model = "sonar(min_range=0.2, max_range=3.0): scale(k=1.14) if ctx_vehicle == 6",
  };
  assert_int_equal(nps_swarm_init(&cfg, err, sizeof(err)), 0);
  const double p0[3] = {1.0, 2.0, 0.6}, p1[3] = {2.0, 1.5, 0.6};
  nps_swarm_set_pose(0, p0, 0.0, 0.0);
  nps_swarm_set_pose(1, p1, 0.0, 0.0);
  nps_swarm_sonar_attach(0, 0.0);
  nps_swarm_sonar_attach(1, 0.0);
  assert_int_equal(nps_swarm_step(0.0), 0);
  nps_swarm_sonar_trigger(0, 4, 0.0);
  nps_swarm_sonar_trigger(1, 4, 0.0);
  nps_swarm_sonar_publish_pings();
  assert_close(nps_swarm_sonar_read(0, 4, 0.0, 0.02), 0.6, 1e-12);          /* down: the floor, 0.6 m */
  assert_close(nps_swarm_sonar_read(1, 4, 0.0, 0.02), 1.14 * 0.6, 1e-12);   /* aircraft 6 reads 14 % long */
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_teardown(facing_pulses_fired_together_read_half_the_path, teardown),
    cmocka_unit_test_teardown(a_later_pulse_reads_longer_if_it_beats_the_own_echo, teardown),
    cmocka_unit_test_teardown(a_pulse_after_the_own_echo_is_not_what_the_sonar_reports, teardown),
    cmocka_unit_test_teardown(a_pulse_that_arrives_before_the_window_is_not_heard, teardown),
    cmocka_unit_test(a_ring_keeps_its_phase_on_the_world_clock_whatever_its_process_offset),
    cmocka_unit_test_teardown(no_cross_talk_without_a_facing_emitter, teardown),
    cmocka_unit_test_teardown(every_pending_ping_is_published_once, teardown),
    cmocka_unit_test_teardown(a_copter_never_hears_its_own_ring, teardown),
    cmocka_unit_test_teardown(without_noise_a_reading_is_the_ray_cast_truth, teardown),
    cmocka_unit_test_teardown(a_blocked_emitter_is_not_heard, teardown),
    cmocka_unit_test_teardown(a_condition_on_the_wall_distance_sees_it_without_a_log, teardown),
    cmocka_unit_test_teardown(a_per_vehicle_effect_applies_to_that_vehicle_only, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
