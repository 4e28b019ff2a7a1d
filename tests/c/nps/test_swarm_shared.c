/*
 * Two NPS processes (forked) share one arena (nps_swarm_shared.h): each one's sonar sees the other copter and hears
 * its pulses, each one ranges the other, the walls bulge in both toward the copter beside them, and every peer pose
 * is read at the reading's time (interpolated, age 0, with no sync window; but maybe on the first step).
 *
 * Aircraft 1 at (1.5, 2) facing east, aircraft 2 at (2.5, 2) facing west, 1 m apart: their front sonars face each
 * other; aircraft 2 is 0.5 m from the east wall (x = 3 m), within the walls' 1 m threshold, aircraft 1 is not
 * within 1 m of any wall. The sonar model has no noise and cross-talk with p = 1: a reading shorter than the ray
 * cast comes from the other copter's pulse.
 */
#include "test_helpers.h"
#include "nps_raycast.h"
#include "nps_swarm.h"
#include "nps_swarm_shared.h"

#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define STEPS 300
#define DT_S 0.01

static char world_name[64];
static int to_child[2], to_parent[2];   ///< start together: each joins, then tells the other

/** Both have joined: start flying together (a process that joins later flies alone until it comes). */
static void meet(bool child)
{
  char c = 'x';
  if (write(child ? to_parent[1] : to_child[1], &c, 1) != 1 || read(child ? to_child[0] : to_parent[0], &c, 1) != 1) {
    abort();
  }
}

struct outcome {
  int copter_echoes;        ///< front readings whose first hit was the other copter
  int short_readings;       ///< front readings shorter than the ray cast by > 5 cm: cross-talk
  double ranged_m;          ///< last distance ranged to the other aircraft (0: none)
  double east_wall_rad;     ///< largest hinge angle of the east wall's plates at the end
  double west_wall_rad;     ///< ... of the west wall's
  struct nps_swarm_shared_stats stats;
};

static void on_range(void *ctx, uint16_t peer_id, double distance_m)
{
  (void)peer_id;
  *(double *)ctx = distance_m;
}

static int fly(unsigned ac_id, const double pos[3], double yaw_rad, struct outcome *out, bool child)
{
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = NPS_WORLD_MAX_AIRCRAFT, .first_id = ac_id, .max_id = NPS_WORLD_MAX_AIRCRAFT,
    .arena_file = "conf/arena/swarmlab.xml", .sensor_model = "sonar(min_range=0.2, max_range=3.0): crosstalk(p=1)",
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    fprintf(stderr, "%s\n", err);
    return -1;
  }
  nps_swarm_set_pose(0, pos, yaw_rad, 0.0);
  const struct nps_swarm_shared_config shared = {
    /* a world clock that barely moves (time factor 1e-6): both start at world time ~0 whenever they join, so that
     * their rings fire together and each hears the other's pulse within its window */
    .name = world_name, .run = "", .ac_id = ac_id, .time_factor = 1e-6, .peer_timeout_s = 2.0, .sync_window_s = 0.0,
  };
  if (nps_swarm_share(&shared, 0.0, err, sizeof(err)) < 0) {
    fprintf(stderr, "%s\n", err);
    return -1;
  }
  nps_swarm_sonar_attach(0, 0.0);   /* both rings fire together: each hears the other's pulse first */
  nps_swarm_ranging_equip(0);
  *out = (struct outcome) { 0 };
  meet(child);
  for (int k = 0; k < STEPS; k++) {
    const double t_s = k * DT_S;
    nps_swarm_set_pose(0, pos, yaw_rad, 0.0);
    if (nps_swarm_shared_step(t_s) < 0) {
      return -1;
    }
    if (k % 5 == 0) {
      nps_swarm_sonar_trigger(0, NPS_SONAR_FRONT, t_s);
    }
    if (k % 5 == 4) {
      const double measured = nps_swarm_sonar_read(0, NPS_SONAR_FRONT, t_s - 4 * DT_S, t_s);
      double truth;
      bool copter;
      nps_swarm_sonar_last_truth(0, NPS_SONAR_FRONT, &truth, &copter);
      out->copter_echoes += copter;
      out->short_readings += measured < truth - 0.05;
    }
    if (k % 10 == 0) {
      nps_swarm_ranging_measure(0, t_s, on_range, &out->ranged_m);
    }
  }
  const struct nps_arena *a = nps_swarm_arena();
  for (int i = 0; i < a->num_segments; i++) {
    const double x = 0.5 * (a->segs[i].a[0] + a->segs[i].b[0]);
    if (x > 2.9) {
      out->east_wall_rad = fmax(out->east_wall_rad, a->segs[i].angle_rad);
    } else if (x < 0.1) {
      out->west_wall_rad = fmax(out->west_wall_rad, a->segs[i].angle_rad);
    }
  }
  out->stats = *nps_swarm_shared_stats();
  nps_swarm_unshare();
  return nps_swarm_free();
}

static void check_outcome(const struct outcome *o, const char *who)
{
  print_message("%s: %d copter echoes, %d short readings, ranged %.3f m, east wall %.3f rad, west %.3f rad, "
                "%lu peer poses, %lu moved on, age max %.3g s\n", who, o->copter_echoes, o->short_readings,
                o->ranged_m, o->east_wall_rad, o->west_wall_rad, o->stats.peer_poses, o->stats.extrapolated,
                o->stats.age_max_s);
  assert_true(o->copter_echoes >= STEPS / 5 - 2);   /* the other copter stands in the beam from the start */
  assert_true(o->short_readings >= STEPS / 20);      /* its pulses are heard */
  assert_close(o->ranged_m, 1.0, 1e-9);              /* no ranging chain: the true distance */
  assert_true(o->east_wall_rad > 0.01);              /* bulged toward aircraft 2 ... */
  assert_close(o->west_wall_rad, 0.0, 0.0);          /* ... and nowhere near aircraft 1 */
  assert_true(o->stats.peer_poses >= STEPS / 5);     /* met at every reading, at least */
  /* interpolated (the other had published past T) but maybe on the first step, when the other's first sample may
   * still be on its way: it waits for nobody that has not published yet */
  assert_true(o->stats.extrapolated <= 1);
  assert_true(o->stats.age_max_s < DT_S);
}

static void two_processes_see_hear_and_range_each_other_in_one_arena(void **state)
{
  (void)state;
  snprintf(world_name, sizeof(world_name), "test_swarm_shared.%d", (int)getpid());
  const double pos1[3] = { 1.5, 2.0, 0.6 }, pos2[3] = { 2.5, 2.0, 0.6 };
  assert_int_equal(pipe(to_child), 0);
  assert_int_equal(pipe(to_parent), 0);
  const pid_t child = fork();
  if (child == 0) {
    struct outcome o;
    if (fly(2, pos2, M_PI, &o, true) < 0) {
      _exit(2);
    }
    /* the child reports through its exit status: the same checks, without cmocka */
    const bool ok = o.copter_echoes >= STEPS / 5 - 2 && o.short_readings >= STEPS / 20 && fabs(o.ranged_m - 1.0) < 1e-9 &&
                    o.east_wall_rad > 0.01 && o.west_wall_rad == 0.0 && o.stats.extrapolated <= 1 &&
                    o.stats.age_max_s < DT_S;
    if (!ok) {
      fprintf(stderr, "aircraft 2: %d copter echoes, %d short, ranged %.3f, east %.3f, west %.3f, %lu moved on\n",
              o.copter_echoes, o.short_readings, o.ranged_m, o.east_wall_rad, o.west_wall_rad, o.stats.extrapolated);
    }
    _exit(ok ? 0 : 1);
  }
  struct outcome o;
  assert_int_equal(fly(1, pos1, 0.0, &o, false), 0);
  int status;
  waitpid(child, &status, 0);
  check_outcome(&o, "aircraft 1");
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 0);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(two_processes_see_hear_and_range_each_other_in_one_arena),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
