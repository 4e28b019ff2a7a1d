/* Sonar echo logic (modules/sonar/sonar_echo.h): edge pairs -> pulse width -> distance, temperature, timeout,
 * glitches and bounce, lost edges, and that a reading is handed out once. */
#include "test_helpers.h"
#include "modules/sonar/sonar_echo.h"

#include <string.h>

/** Relative float tolerance of a distance computed in single precision (a few ulp of the operations) */
#define REL_TOL 1e-6

static const struct sonar_echo_config cfg = {
  .min_range_m = 0.02f, .max_range_m = 4.0f, .timeout_us = 30000, .min_pulse_us = 50, .bounce_us = 20,
};

static struct sonar_echo se;

static int setup(void **state)
{
  (void)state;
  sonar_echo_init(&se, &cfg);
  return 0;
}

/** One clean cycle: trigger at 1000 us (poll clock), echo from rise_us lasting width_us (edge clock). */
static bool clean_cycle(uint32_t rise_us, uint32_t width_us, float temp_c, struct sonar_echo_reading *r)
{
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, rise_us);
  sonar_echo_edge(&se, false, rise_us + width_us);
  return sonar_echo_poll(&se, 2000, temp_c, r);
}

static void pulse_width_gives_distance(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  /* 1 m at 20 deg C: c = 331.3 + 0.606 * 20 = 343.42 m/s, width = 2 * 1 / 343.42 s = 5823.77 us */
  assert_true(clean_cycle(500000, 5824, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_VALID);
  assert_int_equal(r.width_us, 5824);
  assert_close(r.distance_m, 343.42 * 5824e-6 / 2.0, 1.0 * REL_TOL);
  assert_int_equal(r.trigger_us, 1000);
  assert_int_equal(r.done_us, 2000);
  assert_close(r.temperature_c, 20.0, 0.0);
}

static void speed_of_sound_follows_temperature(void **state)
{
  (void)state;
  assert_close(sonar_echo_speed_of_sound(0.0f), 331.3, 331.3 * REL_TOL);
  assert_close(sonar_echo_speed_of_sound(20.0f), 343.42, 343.42 * REL_TOL);
  assert_close(sonar_echo_speed_of_sound(-20.0f), 319.18, 319.18 * REL_TOL);
  /* against the ideal-gas law c = 331.3 sqrt(1 + T / 273.15): within 0.25 % from -20 to 40 deg C */
  for (int t = -20; t <= 40; t += 5) {
    const double ideal = 331.3 * sqrt(1.0 + t / 273.15);
    assert_close(sonar_echo_speed_of_sound((float)t), ideal, 0.0025 * ideal);
  }
  /* the same echo reads 7.3 % farther at 40 deg C than at 0 deg C */
  struct sonar_echo_reading cold, warm;
  assert_true(clean_cycle(100, 10000, 0.0f, &cold));
  assert_true(clean_cycle(100, 10000, 40.0f, &warm));
  assert_close(warm.distance_m / cold.distance_m, 355.54 / 331.3, 4 * REL_TOL);
  assert_close(cold.distance_m, 331.3 * 0.01 / 2.0, 1.66 * REL_TOL);
}

static void a_missing_echo_times_out_out_of_range(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  assert_false(sonar_echo_poll(&se, 1000 + cfg.timeout_us - 1, 20.0f, &r));
  assert_true(sonar_echo_poll(&se, 1000 + cfg.timeout_us, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_true(isinf(r.distance_m));
  assert_int_equal(r.width_us, 0);
  assert_int_equal(se.stats.timeouts, 1);
  /* handed out once: a later poll has nothing */
  assert_false(sonar_echo_poll(&se, 1000 + 2 * cfg.timeout_us, 20.0f, &r));
}

static void an_echo_that_never_falls_times_out(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 0xFFFFF000U);  /* the poll clock wraps during the cycle */
  sonar_echo_edge(&se, true, 7);
  assert_false(sonar_echo_poll(&se, 0xFFFFF000U + 1000, 20.0f, &r));
  assert_true(sonar_echo_poll(&se, 0xFFFFF000U + cfg.timeout_us, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_true(isinf(r.distance_m));
}

static void the_edge_clock_may_wrap(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  assert_true(clean_cycle(0xFFFFFF00U, 1000, 20.0f, &r));
  assert_int_equal(r.width_us, 1000);
}

static void a_bounce_at_the_rise_keeps_the_first_rise(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, 10000);   /* rise */
  sonar_echo_edge(&se, false, 10003);  /* bounce: 3 us high (a glitch)... */
  sonar_echo_edge(&se, true, 10005);   /* ...high again 2 us later (within bounce_us) */
  sonar_echo_edge(&se, false, 15824);
  assert_true(sonar_echo_poll(&se, 2000, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_VALID);
  assert_int_equal(r.width_us, 5824);
  assert_int_equal(se.stats.glitches, 1);
}

static void a_glitch_before_the_echo_is_ignored(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, 9000);    /* noise spike, 10 us */
  sonar_echo_edge(&se, false, 9010);
  sonar_echo_edge(&se, true, 10000);   /* the echo, 990 us later (far beyond bounce_us) */
  sonar_echo_edge(&se, false, 12000);
  assert_true(sonar_echo_poll(&se, 2000, 20.0f, &r));
  assert_int_equal(r.width_us, 2000);
  assert_int_equal(se.stats.glitches, 1);
}

static void a_bounce_at_the_fall_is_late(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, 10000);
  sonar_echo_edge(&se, false, 13000);  /* the echo ends here */
  sonar_echo_edge(&se, true, 13002);   /* bounce */
  sonar_echo_edge(&se, false, 13004);
  assert_true(sonar_echo_poll(&se, 2000, 20.0f, &r));
  assert_int_equal(r.width_us, 3000);
  assert_int_equal(se.stats.late_edges, 2);
}

static void a_fall_without_a_rise_is_spurious(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, false, 9000);
  sonar_echo_edge(&se, true, 10000);
  sonar_echo_edge(&se, false, 11000);
  assert_true(sonar_echo_poll(&se, 2000, 20.0f, &r));
  assert_int_equal(r.width_us, 1000);
  assert_int_equal(se.stats.spurious_edges, 1);
}

static void a_lost_falling_edge_rejects_the_cycle(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, 10000);
  sonar_echo_edge(&se, true, 15000);  /* high again without a fall: the fall was lost */
  sonar_echo_edge(&se, false, 16000);
  assert_true(sonar_echo_poll(&se, 2000, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_REJECTED);
  assert_true(isnan(r.distance_m));
  assert_int_equal(se.stats.missing_edges, 1);
  assert_int_equal(se.stats.late_edges, 1);
}

static void echoes_outside_the_range_are_out_of_range(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  assert_true(clean_cycle(10000, 60, 20.0f, &r));      /* 1.03 cm < 2 cm */
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_close(r.distance_m, 343.42 * 60e-6 / 2, 1e-8);
  assert_true(clean_cycle(10000, 25000, 20.0f, &r));   /* 4.29 m > 4 m */
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_close(r.distance_m, 343.42 * 25e-3 / 2, 4.29 * REL_TOL);
  assert_int_equal(se.stats.out_of_range, 2);
  assert_int_equal(se.stats.valid, 0);
}

static void a_reading_is_never_handed_out_twice(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  sonar_echo_arm(&se, 1000);
  sonar_echo_edge(&se, true, 10000);
  sonar_echo_edge(&se, false, 12000);
  /* not read before the next trigger: dropped, and the new cycle does not report the old echo */
  assert_true(sonar_echo_arm(&se, 51000));
  assert_int_equal(se.stats.overruns, 1);
  assert_false(sonar_echo_poll(&se, 52000, 20.0f, &r));
  assert_true(sonar_echo_poll(&se, 51000 + cfg.timeout_us, 20.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_int_equal(r.trigger_us, 51000);
  /* edges while nothing is armed are late */
  sonar_echo_edge(&se, true, 90000);
  assert_int_equal(se.stats.late_edges, 1);
  assert_false(sonar_echo_poll(&se, 90000, 20.0f, &r));
}

static void a_bad_temperature_rejects_the_reading(void **state)
{
  (void)state;
  struct sonar_echo_reading r;
  assert_true(clean_cycle(100, 1000, NAN, &r));
  assert_int_equal(r.status, SONAR_ECHO_REJECTED);
  assert_true(clean_cycle(100, 1000, 120.0f, &r));
  assert_int_equal(r.status, SONAR_ECHO_REJECTED);
  assert_true(clean_cycle(100, 1000, SONAR_ECHO_TEMP_MIN_C, &r));
  assert_int_equal(r.status, SONAR_ECHO_VALID);
}

static void bad_configurations_are_named(void **state)
{
  (void)state;
  const char *why = NULL;
  assert_int_equal(sonar_echo_config_check(&cfg, &why), 0);
  struct sonar_echo_config c = cfg;
  c.min_range_m = 5.0f;
  assert_int_equal(sonar_echo_config_check(&c, &why), -1);
  assert_non_null(strstr(why, "max_range_m"));
  c = cfg;
  c.timeout_us = 20000;  /* 4 m needs 24.1 ms at 0 deg C */
  assert_int_equal(sonar_echo_config_check(&c, &why), -1);
  assert_non_null(strstr(why, "timeout_us"));
  c = cfg;
  c.min_range_m = -1.0f;
  assert_int_equal(sonar_echo_config_check(&c, &why), -1);
  assert_non_null(strstr(why, "min_range_m"));
  c = cfg;
  c.min_pulse_us = 0;
  assert_int_equal(sonar_echo_config_check(&c, &why), -1);
  assert_non_null(strstr(why, "min_pulse_us"));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup(pulse_width_gives_distance, setup),
    cmocka_unit_test_setup(speed_of_sound_follows_temperature, setup),
    cmocka_unit_test_setup(a_missing_echo_times_out_out_of_range, setup),
    cmocka_unit_test_setup(an_echo_that_never_falls_times_out, setup),
    cmocka_unit_test_setup(the_edge_clock_may_wrap, setup),
    cmocka_unit_test_setup(a_bounce_at_the_rise_keeps_the_first_rise, setup),
    cmocka_unit_test_setup(a_glitch_before_the_echo_is_ignored, setup),
    cmocka_unit_test_setup(a_bounce_at_the_fall_is_late, setup),
    cmocka_unit_test_setup(a_fall_without_a_rise_is_spurious, setup),
    cmocka_unit_test_setup(a_lost_falling_edge_rejects_the_cycle, setup),
    cmocka_unit_test_setup(echoes_outside_the_range_are_out_of_range, setup),
    cmocka_unit_test_setup(a_reading_is_never_handed_out_twice, setup),
    cmocka_unit_test_setup(a_bad_temperature_rejects_the_reading, setup),
    cmocka_unit_test(bad_configurations_are_named),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
