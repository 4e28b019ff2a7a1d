/*
 * The FINken flight model: exact first-order responses (x(t) = x_cmd (1 - exp(-t / tau))),
 * speed limiting, altitude hold, heading wrap. Deterministic: tolerances are rounding only.
 */
#include "test_helpers.h"
#include "nps_fdm_finken.h"

static const struct nps_fdm_finken_params params = {
  .velocity_tau_s = 0.5, .yaw_tau_s = 0.3, .altitude_m = 0.6, .altitude_tau_s = 0.5, .max_speed_mps = 1.0,
};

static void velocity_follows_first_order_law(void **state)
{
  (void)state;
  struct nps_fdm_finken_state s = { .pos_m = {0, 0, 0.6} };
  const double dt = 0.01;
  for (int i = 0; i < 50; i++) {   /* t = tau = 0.5 s */
    nps_fdm_finken_step(&s, &params, 0.8, 0.0, 0.0, dt);
  }
  assert_close(s.vel_mps[0], 0.8 * (1.0 - exp(-1.0)), 1e-12);
  assert_close(s.vel_mps[1], 0.0, 0.0);
}

static void the_result_does_not_depend_on_the_step(void **state)
{
  (void)state;
  struct nps_fdm_finken_state fine = { .pos_m = {0, 0, 0.6} }, coarse = fine;
  for (int i = 0; i < 100; i++) {
    nps_fdm_finken_step(&fine, &params, 0.5, -0.5, 1.0, 0.001);
  }
  nps_fdm_finken_step(&coarse, &params, 0.5, -0.5, 1.0, 0.1);
  assert_close(coarse.vel_mps[0], fine.vel_mps[0], 1e-12);
  assert_close(coarse.yaw_rad, fine.yaw_rad, 1e-12);
}

static void speed_command_is_limited(void **state)
{
  (void)state;
  struct nps_fdm_finken_state s = { .pos_m = {0, 0, 0.6} };
  for (int i = 0; i < 2000; i++) {
    nps_fdm_finken_step(&s, &params, 3.0, 4.0, 0.0, 0.01);
  }
  assert_close(hypot(s.vel_mps[0], s.vel_mps[1]), params.max_speed_mps, 1e-9);
  assert_close(s.vel_mps[1] / s.vel_mps[0], 4.0 / 3.0, 1e-9);  /* direction kept */
}

static void altitude_settles_at_the_held_height(void **state)
{
  (void)state;
  struct nps_fdm_finken_state s = { .pos_m = {0, 0, 0.0} };
  for (int i = 0; i < 1000; i++) {
    nps_fdm_finken_step(&s, &params, 0.0, 0.0, 0.0, 0.01);
  }
  assert_close(s.pos_m[2], 0.6, 1e-6);
}

static void heading_takes_the_short_way_round(void **state)
{
  (void)state;
  struct nps_fdm_finken_state s = { .pos_m = {0, 0, 0.6}, .yaw_rad = 3.0 };
  nps_fdm_finken_step(&s, &params, 0.0, 0.0, -3.0, 0.01);
  assert_true(s.yaw_rate_rps > 0.0);   /* from 3.0 to -3.0 rad is +0.28 rad through pi */
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(velocity_follows_first_order_law),
    cmocka_unit_test(the_result_does_not_depend_on_the_step),
    cmocka_unit_test(speed_command_is_limited),
    cmocka_unit_test(altitude_settles_at_the_held_height),
    cmocka_unit_test(heading_takes_the_short_way_round),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
