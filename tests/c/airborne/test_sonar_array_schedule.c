/* The sonar ring's staggered round robin: order, rates, listening windows, skipped slots. Exact (integer time). */
#include "test_helpers.h"
#include "modules/sonar/sonar_array_schedule.h"

static void fires_every_slot_in_the_staggered_order(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  assert_true(sonar_array_schedule_init(&s, 20, 2, 0));
  assert_int_equal(s.slot_us, 10000);          /* 5 sonars x 20 Hz = one slot every 10 ms */
  const int8_t expected_fire[] = { 0, 2, 1, 3, 4, 0, 2 };
  const int8_t expected_read[] = { -1, -1, 0, 2, 1, 3, 4 };
  for (int k = 0; k < 7; k++) {
    struct sonar_array_slot slot;
    assert_false(k > 0 && sonar_array_schedule_poll(&s, k * 10000u - 1u, &slot));  /* not before the slot */
    assert_true(sonar_array_schedule_poll(&s, k * 10000u, &slot));
    assert_int_equal(slot.fire, expected_fire[k]);
    assert_int_equal(slot.read, expected_read[k]);
    if (slot.read >= 0) {
      assert_int_equal(slot.fired_at_us, (k - 2) * 10000u);   /* window = 2 slots */
    }
    assert_false(sonar_array_schedule_poll(&s, k * 10000u + 5000u, &slot));   /* once per slot */
  }
}

static void each_sonar_is_read_at_its_rate(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  assert_true(sonar_array_schedule_init(&s, 20, 2, 0));
  int reads[SONAR_ARRAY_NB] = {0};
  for (uint32_t t = 0; t < 10000000u; t += 1000u) {   /* 10 s polled at 1 kHz */
    struct sonar_array_slot slot;
    if (sonar_array_schedule_poll(&s, t, &slot) && slot.read >= 0) {
      reads[slot.read]++;
    }
  }
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    assert_in_range(reads[i], 199, 200);   /* 20 Hz x 10 s, less the first window */
  }
}

static void a_late_caller_skips_slots_and_never_reads_an_unfired_sonar(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  assert_true(sonar_array_schedule_init(&s, 20, 2, 0));
  struct sonar_array_slot slot;
  assert_true(sonar_array_schedule_poll(&s, 0, &slot));        /* slot 0: fires front */
  assert_true(sonar_array_schedule_poll(&s, 35000, &slot));    /* slots 1-2 missed, this is slot 3 */
  assert_int_equal(slot.fire, sonar_array_firing_order[3]);
  assert_int_equal(slot.read, -1);                             /* slot 1's sonar never fired */
  assert_true(sonar_array_schedule_poll(&s, 40000, &slot));    /* slot 4 would read slot 2's: skipped too */
  assert_int_equal(slot.read, -1);
  assert_true(sonar_array_schedule_poll(&s, 50000, &slot));    /* slot 5 reads slot 3's sonar */
  assert_int_equal(slot.read, sonar_array_firing_order[3]);
  assert_int_equal(slot.fired_at_us, 35000);
}

static void a_caller_exactly_one_slot_late_skips_that_slot(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  assert_true(sonar_array_schedule_init(&s, 20, 2, 0));
  struct sonar_array_slot slot;
  assert_true(sonar_array_schedule_poll(&s, 0, &slot));        /* slot 0 */
  assert_true(sonar_array_schedule_poll(&s, 19999, &slot));    /* slot 1, 9999 us late: not a whole slot */
  assert_int_equal(slot.fire, sonar_array_firing_order[1]);
  assert_true(sonar_array_schedule_poll(&s, 30000, &slot));    /* slot 2 was due at 20000: exactly one slot late */
  assert_int_equal(slot.fire, sonar_array_firing_order[3]);
  assert_false(sonar_array_schedule_poll(&s, 39999, &slot));   /* the next one is due at 40000 */
}

static void bad_configurations_are_rejected(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  assert_false(sonar_array_schedule_init(&s, 0, 2, 0));
  assert_false(sonar_array_schedule_init(&s, 20, 0, 0));
  assert_false(sonar_array_schedule_init(&s, 20, SONAR_ARRAY_NB, 0));
  struct sonar_array_slot slot;
  assert_false(sonar_array_schedule_poll(&s, 1000000, &slot));   /* a rejected schedule never fires */
}

static void survives_the_microsecond_clock_wrapping(void **state)
{
  (void)state;
  struct sonar_array_schedule s;
  const uint32_t start = UINT32_MAX - 15000u;
  assert_true(sonar_array_schedule_init(&s, 20, 1, start));
  struct sonar_array_slot slot;
  assert_true(sonar_array_schedule_poll(&s, start, &slot));
  assert_true(sonar_array_schedule_poll(&s, start + 10000u, &slot));
  assert_true(sonar_array_schedule_poll(&s, start + 20000u, &slot));   /* wrapped past 0 */
  assert_int_equal(slot.read, sonar_array_firing_order[1]);
  assert_int_equal(slot.fired_at_us, start + 10000u);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(fires_every_slot_in_the_staggered_order),
    cmocka_unit_test(each_sonar_is_read_at_its_rate),
    cmocka_unit_test(a_late_caller_skips_slots_and_never_reads_an_unfired_sonar),
    cmocka_unit_test(a_caller_exactly_one_slot_late_skips_that_slot),
    cmocka_unit_test(bad_configurations_are_rejected),
    cmocka_unit_test(survives_the_microsecond_clock_wrapping),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
