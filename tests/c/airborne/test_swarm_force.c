/*
 * The swarm law against hand-computed values (a = 1, b = 4, c = 1.5 m^2, weights 0.8 / 0.2, gain 1 /s,
 * speed bound 0.5 m/s): f(d) = a d - b d' exp(-d'^2 / c), d' = max(d, sqrt(c / 2)), along each sonar; a sonar
 * reading "no echo" adds nothing (the FINken V-REP swarm sums over the objects its sonars detect).
 */
#include "test_helpers.h"
#include "modules/swarm/swarm_force.h"

static const struct swarm_params params = {
  .a = 1.f, .b = 4.f, .c_m2 = 1.5f, .cohesion_weight = 0.8f, .target_weight = 0.2f, .gain_per_s = 1.f,
  .max_speed_mps = 0.5f, .echo_timeout_s = 0.5f,
};

static void the_echo_term_is_gazi_passino_along_the_sonar(void **state)
{
  (void)state;
  /* d = 1: 1 - 4 exp(-2/3) = 1 - 4 x 0.513417119 = -1.053668476 */
  assert_close(swarm_echo_term_m(&params, 1.f, 1.f), -1.053668476, 1e-6);
  /* d = 2: 2 - 8 exp(-8/3) = 2 - 8 x 0.069483451 = 1.444132390 */
  assert_close(swarm_echo_term_m(&params, 2.f, 2.f), 1.444132390, 1e-6);
  /* zero at d = sqrt(c ln(b / a)) = sqrt(1.5 ln 4) = 1.4420269 m */
  assert_close(swarm_echo_term_m(&params, 1.4420269f, 1.4420269f), 0.0, 1e-6);
  /* no attraction (a wall with the detector on): repulsion only, -4 x 1 x exp(-2/3) */
  assert_close(swarm_echo_term_m(&params, -1.f, 1.f), -2.053668476, 1e-6);
  /* closer than sqrt(c / 2) = 0.866025 m the repulsion keeps its peak 4 x 0.866025 x exp(-1/2) = 2.101084 */
  assert_close(swarm_echo_term_m(&params, 0.5f, 0.5f), 0.5 - 2.101084, 1e-5);
  assert_close(swarm_echo_term_m(&params, -1.f, 0.2f), -2.101084, 1e-5);
  assert_close(swarm_echo_term_m(&params, -1.f, 0.9f), -4.0 * 0.9 * exp(-0.81 / 1.5), 1e-6);
  /* an echo just inside the sonar maximum still repels a little: -4 x 2.9 x exp(-8.41 / 1.5) */
  assert_close(swarm_echo_term_m(&params, -1.f, 2.9f), -0.042610202, 1e-7);
  /* a NaN reading repels with the peak value, as fmaxf(NaN, peak) is the peak */
  assert_close(swarm_echo_term_m(&params, -1.f, NAN), -2.101084, 1e-5);
}

static void sonar_directions_turn_with_the_yaw(void **state)
{
  (void)state;
  struct FloatVect2 u;
  /* yaw 0 (north): front north, right east */
  swarm_sonar_direction_ned(0.f, 0.f, &u);
  assert_close(u.x, 1.0, 1e-7);
  assert_close(u.y, 0.0, 1e-7);
  swarm_sonar_direction_ned(0.f, (float)M_PI_2, &u);
  assert_close(u.x, 0.0, 1e-7);
  assert_close(u.y, 1.0, 1e-7);
  /* yaw pi/2 (east): front east, right south, left north */
  swarm_sonar_direction_ned((float)M_PI_2, 0.f, &u);
  assert_close(u.y, 1.0, 1e-7);
  swarm_sonar_direction_ned((float)M_PI_2, (float)M_PI_2, &u);
  assert_close(u.x, -1.0, 1e-7);
  swarm_sonar_direction_ned((float)M_PI_2, (float)-M_PI_2, &u);
  assert_close(u.x, 1.0, 1e-7);
}

static void attraction_follows_the_detector_and_repulsion_every_echo(void **state)
{
  (void)state;
  struct swarm_peak_repulsion peak = { .known = false };
  /* yaw 0: a wall 1 m ahead (front), a copter 2 m to the right, nothing behind (sonar maximum) */
  const uint32_t now_us = 10000000u;
  const struct swarm_echo echoes[3] = {
    { true, now_us, 0.f, WALL_DETECTOR_WALL, -1.f, 1.f },
    { true, now_us, (float)M_PI_2, WALL_DETECTOR_COPTER, 2.f, 2.f },
    { true, now_us, (float)M_PI, WALL_DETECTOR_NO_ECHO, -1.f, 3.f },
  };
  struct FloatVect2 sum;
  /* detector on: the wall only repels; the reading behind is no echo and adds nothing */
  swarm_cohesion_ned(&params, echoes, 3, 0.f, now_us, true, &peak, &sum);
  assert_close(sum.x, -2.053668476, 1e-5);
  assert_close(sum.y, 1.444132390, 1e-5);
  /* detector off: every echo attracts, the wall as well (the no-echo reading still adds nothing) */
  swarm_cohesion_ned(&params, echoes, 3, 0.f, now_us, false, &peak, &sum);
  assert_close(sum.x, -1.053668476, 1e-5);
  assert_close(sum.y, 1.444132390, 1e-5);
}

static void without_the_detector_a_wall_holds_the_copter(void **state)
{
  (void)state;
  struct swarm_peak_repulsion peak = { .known = false };
  /* one wall ahead, nothing else in range. Off: a swarm member, pushed away at 1.3 m (1.3 - 4 x 1.3 x
   * exp(-1.69 / 1.5) = -0.385381519), pulled back at 1.6 m (+0.438594019), zero at 1.4420269 m: the copter is
   * held there. On (the detector calls it a wall): pushed away at any distance, -1.685381519 at 1.3 m,
   * -1.161405981 at 1.6 m, and at 2.5 m the wall still pushes (-0.155038536) where it would pull (+2.344961464). */
  const uint32_t now_us = 10000000u;
  const float ranges_m[] = { 1.3f, 1.6f, 2.5f };
  const double off[] = { -0.385381519, 0.438594019, 2.344961464 };
  const double on[] = { -1.685381519, -1.161405981, -0.155038536 };
  for (int i = 0; i < 3; i++) {
    const struct swarm_echo wall = { true, now_us, 0.f, WALL_DETECTOR_WALL, -1.f, ranges_m[i] };
    struct FloatVect2 sum;
    swarm_cohesion_ned(&params, &wall, 1, 0.f, now_us, false, &peak, &sum);
    assert_close(sum.x, off[i], 1e-5);
    swarm_cohesion_ned(&params, &wall, 1, 0.f, now_us, true, &peak, &sum);
    assert_close(sum.x, on[i], 1e-5);
  }
  const struct swarm_echo zero = { true, now_us, 0.f, WALL_DETECTOR_WALL, -1.f, 1.4420269f };
  struct FloatVect2 sum;
  swarm_cohesion_ned(&params, &zero, 1, 0.f, now_us, false, &peak, &sum);
  assert_close(sum.x, 0.0, 1e-6);
}

static void the_cached_peak_repulsion_is_the_echo_term(void **state)
{
  (void)state;
  /* one echo straight ahead at distances below, at and beyond the peak sqrt(c / 2) = 0.866 m (a NaN reading: the
   * peak), b changed for one round and later c (settings): the sum is bit for bit swarm_echo_term_m's, so the cache
   * follows b and c (a stale peak repulsion fails) */
  struct swarm_peak_repulsion peak = { .known = false };
  struct swarm_params changed = params;
  const uint32_t now_us = 10000000u;
  const float ranges_m[] = { 0.2f, 0.5f, 0.8660254f, 0.87f, 1.3f, NAN };
  for (int round = 0; round < 6; round++) {
    changed.b = round == 1 ? 3.f : params.b;
    changed.c_m2 = round >= 4 ? 2.f : params.c_m2;
    for (unsigned i = 0; i < sizeof(ranges_m) / sizeof(ranges_m[0]); i++) {
      const struct swarm_echo echo = { true, now_us, 0.f, WALL_DETECTOR_COPTER, ranges_m[i], ranges_m[i] };
      struct FloatVect2 sum;
      swarm_cohesion_ned(&changed, &echo, 1, 0.f, now_us, true, &peak, &sum);
      const float term_m = swarm_echo_term_m(&changed, ranges_m[i], ranges_m[i]);
      const float x = 0.f + term_m * cosf(0.f);   // the sum of one term, along the front
      assert_memory_equal(&sum.x, &x, sizeof(float));
    }
  }
  /* the cache is used while b and c are the same: a planted peak repulsion comes back (an echo at 0.5 m) */
  peak.repulsion = 7.f;
  const struct swarm_echo close = { true, now_us, 0.f, WALL_DETECTOR_COPTER, -1.f, 0.5f };
  struct FloatVect2 sum;
  swarm_cohesion_ned(&changed, &close, 1, 0.f, now_us, true, &peak, &sum);
  assert_close(sum.x, -7.0, 0.0);
}

static void stale_echoes_are_dropped(void **state)
{
  (void)state;
  struct swarm_peak_repulsion peak = { .known = false };
  const struct swarm_echo echoes[2] = {
    { true, 1000000u, 0.f, WALL_DETECTOR_COPTER, 2.f, 2.f },     // 0.6 s old
    { false, 1600000u, (float)M_PI, WALL_DETECTOR_COPTER, 2.f, 2.f },  // never received
  };
  struct FloatVect2 sum;
  swarm_cohesion_ned(&params, echoes, 2, 0.f, 1600000u, true, &peak, &sum);
  assert_close(sum.x, 0.0, 0.0);
  assert_close(sum.y, 0.0, 0.0);
}

static void the_velocity_is_weighted_and_bounded(void **state)
{
  (void)state;
  const struct FloatVect2 pos = { 0.f, 0.f };
  const struct FloatVect2 target = { 0.f, 0.5f };
  struct FloatVect2 v;
  /* 0.8 x (0.25, 0) + 0.2 x 1 x (0, 0.5) = (0.2, 0.1), below the bound */
  const struct FloatVect2 small = { 0.25f, 0.f };
  swarm_velocity_ned(&params, &small, &pos, &target, &v);
  assert_close(v.x, 0.2, 1e-7);
  assert_close(v.y, 0.1, 1e-7);
  /* 0.8 x (1, 0) + 0.2 x (0, 0.5) = (0.8, 0.1): |v| = 0.806226 -> scaled to 0.5 m/s */
  const struct FloatVect2 big = { 1.f, 0.f };
  swarm_velocity_ned(&params, &big, &pos, &target, &v);
  assert_close(hypot(v.x, v.y), 0.5, 1e-6);
  assert_close(v.x, 0.5 * 0.8 / 0.806225775, 1e-6);
  assert_close(v.y, 0.5 * 0.1 / 0.806225775, 1e-6);
}

static void the_target_circles_the_centre(void **state)
{
  (void)state;
  const struct swarm_target target = { 1.5f, 2.0f, 1.0f, 60.0f };
  struct FloatVect2 t;
  /* t = 0: ENU (2.5, 2.0) -> NED (2.0, 2.5); a quarter period later ENU (1.5, 3.0) -> NED (3.0, 1.5) */
  swarm_target_ned(&target, 0.f, &t);
  assert_close(t.x, 2.0, 1e-6);
  assert_close(t.y, 2.5, 1e-6);
  swarm_target_ned(&target, 15.f, &t);
  assert_close(t.x, 3.0, 1e-6);
  assert_close(t.y, 1.5, 1e-6);
  /* radius 0 or period 0: a fixed point */
  const struct swarm_target fixed = { 1.5f, 2.0f, 0.0f, 0.0f };
  swarm_target_ned(&fixed, 7.f, &t);
  assert_close(t.x, 2.0, 0.0);
  assert_close(t.y, 1.5, 0.0);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_echo_term_is_gazi_passino_along_the_sonar),
    cmocka_unit_test(sonar_directions_turn_with_the_yaw),
    cmocka_unit_test(attraction_follows_the_detector_and_repulsion_every_echo),
    cmocka_unit_test(without_the_detector_a_wall_holds_the_copter),
    cmocka_unit_test(the_cached_peak_repulsion_is_the_echo_term),
    cmocka_unit_test(stale_echoes_are_dropped),
    cmocka_unit_test(the_velocity_is_weighted_and_bounded),
    cmocka_unit_test(the_target_circles_the_centre),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
