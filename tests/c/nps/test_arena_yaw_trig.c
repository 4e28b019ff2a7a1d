/*
 * The yaw memo of the arena's copters (nps_arena_copter_refresh_yaw_trig): after every step of a turning copter
 * it holds cos and sin of the current yaw within 2^-52 of libm's, whether it came from libm (a new base) or from
 * the base turned by the angle-addition formula; it is of the current yaw; libm is called only beyond the largest
 * turn. Deterministic (a fixed LCG), so the bound is checked on the same 60 000 yaws every run.
 */
#include "test_helpers.h"
#include "test_arena_fixtures.h"
#include "nps_arena.h"

/** Bound on |memo - libm| [-]: the rounding of the formula's few operations and of libm's own results. */
#define MEMO_TOL 0x1p-52

/** The SwarmLab rectangle with one copter at (1.5, 2) heading yaw_rad. */
static struct nps_arena *arena_with_one_copter(double yaw_rad)
{
  return arena_with_copters((const double[1][2]) { { 1.5, 2.0 } }, 1, yaw_rad);
}

/** The memo of a's copter is of its yaw and within MEMO_TOL of libm's cos and sin. */
static void assert_memo_current(const struct nps_arena *a)
{
  const struct nps_arena_copter *c = &a->copters[0];
  assert_true(c->yaw_trig_valid && c->trig_yaw_rad == c->yaw_rad);
  assert_close(c->cos_yaw, cos(c->yaw_rad), MEMO_TOL);
  assert_close(c->sin_yaw, sin(c->yaw_rad), MEMO_TOL);
  double cos_yaw, sin_yaw;
  nps_arena_copter_yaw_trig(c, &cos_yaw, &sin_yaw);
  assert_true(cos_yaw == c->cos_yaw && sin_yaw == c->sin_yaw);   /* the readers get the memo */
}

static void a_turning_copter_keeps_its_memo_within_rounding(void **state)
{
  (void)state;
  /* 6 walks of 10 000 steps from yaws on both sides of +-pi, 0 and pi/2: each step turns by up to 10^-e rad
   * (e drawn in [3, 15]), mostly on in the same direction, so that the turn from the base covers (0, 2^-16]
   * (where a missing d^3/6 term would be off by up to 2^-48/6; a largest turn of 2^-10 fails by d^4/24) and
   * the walks cross +-pi (a jump of 2 pi in the stored yaw, wrapped as the flight model wraps it) */
  const double start_rad[6] = { M_PI - 1e-4, -M_PI + 1e-4, 0.0, 1e-9, M_PI / 2.0, -2.0 };
  uint32_t x = 11;
  int libm_bases = 0, turned = 0;
  for (int w = 0; w < 6; w++) {
    struct nps_arena *a = arena_with_one_copter(start_rad[w]);
    assert_memo_current(a);
    double direction = 1.0;
    for (int step = 0; step < 10000; step++) {
      struct nps_arena_copter *c = &a->copters[0];
      if (lcg_uniform(&x, 0.0, 1.0) < 0.01) {
        direction = -direction;
      }
      const double turn_rad = direction * pow(10.0, -lcg_uniform(&x, 3.0, 15.0));
      const double before_base = c->base_yaw_rad;
      c->yaw_rad = remainder(c->yaw_rad + turn_rad, 2.0 * M_PI);
      assert_int_equal(nps_arena_poses_moved(a), 0);
      assert_memo_current(a);
      if (c->base_yaw_rad != before_base) {
        libm_bases++;
        assert_true(c->cos_base == cos(c->yaw_rad) && c->sin_base == sin(c->yaw_rad) && c->base_yaw_rad == c->yaw_rad);
      } else {
        turned++;
        assert_true(fabs(c->yaw_rad - c->base_yaw_rad) <= NPS_ARENA_YAW_TRIG_TURN_MAX_RAD);
      }
    }
    nps_arena_free(a);
  }
  /* both ways were taken, the formula on most steps */
  assert_true(libm_bases > 100 && turned > 50000);
}

static void an_unchanged_yaw_keeps_its_memo_and_a_copter_by_hand_gets_libm(void **state)
{
  (void)state;
  struct nps_arena *a = arena_with_one_copter(0.3);
  struct nps_arena_copter *c = &a->copters[0];
  c->yaw_rad += 1e-6;
  assert_int_equal(nps_arena_poses_moved(a), 0);
  const struct nps_arena_copter before = *c;
  /* same yaw: the memo is not worked out again (recomputing it would give the same bits, so a marked memo shows it) */
  c->cos_yaw = c->sin_yaw = 2.0;
  assert_int_equal(nps_arena_poses_moved(a), 0);
  assert_true(c->cos_yaw == 2.0 && c->sin_yaw == 2.0);
  c->cos_yaw = before.cos_yaw;
  c->sin_yaw = before.sin_yaw;
  assert_memory_equal(c, &before, sizeof(before));
  /* a copter given by hand (no valid memo) takes libm's values, whatever its stale base fields say */
  struct nps_arena_copter by_hand = before;
  by_hand.yaw_trig_valid = 0;
  by_hand.yaw_rad = 0.3 + 2e-6;
  assert_int_equal(nps_arena_set_copters(a, &by_hand, 1), 0);
  assert_true(c->cos_yaw == cos(by_hand.yaw_rad) && c->sin_yaw == sin(by_hand.yaw_rad));
  nps_arena_free(a);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(a_turning_copter_keeps_its_memo_within_rounding),
    cmocka_unit_test(an_unchanged_yaw_keeps_its_memo_and_a_copter_by_hand_gets_libm),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
