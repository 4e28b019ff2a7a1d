/*
 * nps_world_peer: which shared data is used, and a peer's pose at the reading's time.
 */
#include "test_helpers.h"
#include "nps_world_peer.h"

#include <string.h>

/* A peer moving along x at 1 m/s, turning at 1 rad/s, sampled every 2 ms from t = 10 s. */
static void moving_peer(struct nps_world_peer *p, unsigned n)
{
  memset(p, 0, sizeof(*p));
  p->ac_id = 2;
  p->n_samples = n;
  for (unsigned i = 0; i < n; i++) {
    const double t = 10.0 + 0.002 * i;
    p->samples[i] = (struct nps_world_sample) { t, { t, 2.0, 0.6 }, remainder(t, 2 * M_PI), 1.0 };
  }
}

static void interpolates_between_the_samples_around_the_time(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, 10);
  struct nps_world_sample pose;
  double age;
  assert_int_equal(nps_world_peer_pose_at(&p, 10.0051, 0.01, &pose, &age), 0);
  assert_close(pose.pos_m[0], 10.0051, 1e-12);
  assert_close(pose.yaw_rad, remainder(10.0051, 2 * M_PI), 1e-12);
  assert_close(age, 0.0, 0.0);
  assert_close(pose.t_s, 10.0051, 0.0);
}

static void yaw_goes_the_short_way_across_pi(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, 2);
  p.samples[0].yaw_rad = M_PI - 0.1;
  p.samples[1].yaw_rad = -M_PI + 0.1;   /* 0.2 rad on, through pi */
  struct nps_world_sample pose;
  double age;
  nps_world_peer_pose_at(&p, 10.001, 0.01, &pose, &age);
  assert_close(remainder(pose.yaw_rad, 2 * M_PI), M_PI, 1e-12);
}

static void after_the_newest_sample_moves_on_for_at_most_the_limit(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, 10);   /* newest at 10.018 s */
  struct nps_world_sample pose;
  double age;
  nps_world_peer_pose_at(&p, 10.023, 0.01, &pose, &age);
  assert_close(pose.pos_m[0], 10.023, 1e-9);   /* 1 m/s for 5 ms */
  assert_close(age, 0.005, 1e-12);
  nps_world_peer_pose_at(&p, 11.0, 0.01, &pose, &age);
  assert_close(pose.pos_m[0], 10.028, 1e-9);   /* held after 10 ms */
  assert_close(age, 0.982, 1e-9);
}

static void before_the_oldest_sample_takes_the_oldest(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, 10);
  struct nps_world_sample pose;
  double age;
  nps_world_peer_pose_at(&p, 9.5, 0.01, &pose, &age);
  assert_close(pose.pos_m[0], 10.0, 0.0);
  assert_close(age, 0.5, 1e-12);
  assert_int_equal(nps_world_peer_pose_at(&p, NAN, 0.01, &pose, &age), -1);   /* found by fuzz_world_peer */
  p.n_samples = 1;
  assert_int_equal(nps_world_peer_pose_at(&p, NAN, 0.01, &pose, &age), -1);
  p.n_samples = 0;
  assert_int_equal(nps_world_peer_pose_at(&p, 9.5, 0.01, &pose, &age), -1);
}

static void implausible_samples_and_pulses_are_dropped(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, 8);
  p.samples[1].pos_m[0] = 1e100;        /* out of range */
  p.samples[2].yaw_rad = NAN;           /* not a number */
  p.samples[3].speed_mps = -1.0;        /* no speed */
  p.samples[5].t_s = p.samples[4].t_s;  /* time does not advance */
  p.n_pings = 4;
  p.pings[0] = (struct nps_world_ping) { 10.0, 0 };
  p.pings[1] = (struct nps_world_ping) { INFINITY, 1 };
  p.pings[2] = (struct nps_world_ping) { 10.001, 7 };   /* no such sonar */
  p.pings[3] = (struct nps_world_ping) { 10.002, 4 };
  assert_int_equal(nps_world_peer_sanitize(&p), 6);
  assert_int_equal(p.n_samples, 4);
  const double kept[4] = { 10.0, 10.008, 10.012, 10.014 };
  for (int i = 0; i < 4; i++) {
    assert_close(p.samples[i].t_s, kept[i], 1e-12);
  }
  assert_int_equal(p.n_pings, 2);
  assert_int_equal(p.pings[1].sonar, 4);
}

static void counts_beyond_the_arrays_are_cut(void **state)
{
  (void)state;
  struct nps_world_peer p;
  moving_peer(&p, NPS_WORLD_SAMPLES);
  p.n_samples = 1000;   /* a damaged count is never read past the array */
  p.n_pings = 1000;
  nps_world_peer_sanitize(&p);
  assert_int_equal(p.n_samples, NPS_WORLD_SAMPLES);
  assert_true(p.n_pings <= NPS_WORLD_PINGS);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(interpolates_between_the_samples_around_the_time),
    cmocka_unit_test(yaw_goes_the_short_way_across_pi),
    cmocka_unit_test(after_the_newest_sample_moves_on_for_at_most_the_limit),
    cmocka_unit_test(before_the_oldest_sample_takes_the_oldest),
    cmocka_unit_test(implausible_samples_and_pulses_are_dropped),
    cmocka_unit_test(counts_beyond_the_arrays_are_cut),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
