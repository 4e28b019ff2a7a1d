/*
 * Simulated radio ranging in the shared world (nps_swarm_ranging.c): every equipped peer within the radio
 * horizon is measured through the ranging chain, and a context value is computed whenever the chain reads it,
 * also when no range log is written (the host skips ctx_blocked and ctx_wall_dist only when nothing reads them);
 * ctx_vehicle is the measuring copter's aircraft id, so a per-vehicle effect changes that copter's readings only.
 * Three copters on a line 0.8 m apart at 0.6 m in the SwarmLab arena (bodies of radius 0.2 m): copter 1's body
 * cuts the line between copters 0 and 2. The models have no random effect, so every value is exact.
 */
#include "test_helpers.h"
#include "nps_swarm.h"

#define N_COPTERS 3
/** Copter spacing along x [m]. */
#define SPACING_M 0.8

struct heard {
  unsigned n;
  uint16_t peer_id[N_COPTERS];
  double distance_m[N_COPTERS];
};

static void remember(void *ctx, uint16_t peer_id, double distance_m)
{
  struct heard *h = ctx;
  assert_true(h->n < N_COPTERS);
  h->peer_id[h->n] = peer_id;
  h->distance_m[h->n++] = distance_m;
}

/** The world with the given ranging chain, no log; copters equipped as `equipped` says. */
static int setup_line(const char *model, const bool equipped[N_COPTERS])
{
  char err[512];
  const struct nps_swarm_config cfg = {
    .seed = 1, .vehicles = N_COPTERS, .arena_file = "conf/arena/swarmlab.xml", .sensor_model = model,
  };
  if (nps_swarm_init(&cfg, err, sizeof(err)) < 0) {
    print_error("%s\n", err);
    return -1;
  }
  for (unsigned v = 0; v < N_COPTERS; v++) {
    const double pos_m[3] = {1.0 + SPACING_M * v, 2.0, 0.6};
    nps_swarm_set_pose(v, pos_m, 0.0, 0.0);
    if (equipped[v]) {
      nps_swarm_ranging_equip(v);
    }
  }
  return nps_swarm_step(0.0);
}

static int teardown(void **state)
{
  (void)state;
  nps_swarm_free();
  return 0;
}

/** What copter v hears at time 0, peers in the order the world visits them, sorted by id here. */
static struct heard measure(unsigned v)
{
  struct heard h = {0};
  nps_swarm_ranging_measure(v, 0.0, remember, &h);
  for (unsigned i = 1; i < h.n; i++) {   /* insertion sort by peer id */
    for (unsigned j = i; j > 0 && h.peer_id[j - 1] > h.peer_id[j]; j--) {
      uint16_t id = h.peer_id[j];
      double d = h.distance_m[j];
      h.peer_id[j] = h.peer_id[j - 1];
      h.distance_m[j] = h.distance_m[j - 1];
      h.peer_id[j - 1] = id;
      h.distance_m[j - 1] = d;
    }
  }
  return h;
}

static void every_equipped_peer_is_measured_at_its_true_range(void **state)
{
  (void)state;
  const bool all[N_COPTERS] = {true, true, true};
  assert_int_equal(setup_line("ranging(max_range=2.5): bias(b=0)", all), 0);
  struct heard h = measure(0);
  assert_int_equal(h.n, 2);
  assert_int_equal(h.peer_id[0], 2);
  assert_close(h.distance_m[0], SPACING_M, 1e-12);
  assert_int_equal(h.peer_id[1], 3);
  assert_close(h.distance_m[1], 2.0 * SPACING_M, 1e-12);
}

static void a_peer_without_a_ranging_unit_is_not_heard(void **state)
{
  (void)state;
  const bool no_middle[N_COPTERS] = {true, false, true};
  assert_int_equal(setup_line("ranging(max_range=2.5): bias(b=0)", no_middle), 0);
  struct heard h = measure(0);
  assert_int_equal(h.n, 1);
  assert_int_equal(h.peer_id[0], 3);
}

static void a_chain_conditioned_on_ctx_blocked_gets_it_without_a_log(void **state)
{
  (void)state;
  const bool all[N_COPTERS] = {true, true, true};
  assert_int_equal(setup_line("ranging(max_range=2.5): bias(b=0.5) if ctx_blocked", all), 0);
  struct heard h = measure(0);
  assert_int_equal(h.n, 2);
  assert_close(h.distance_m[0], SPACING_M, 1e-12);              /* copter 2: a free line */
  assert_close(h.distance_m[1], 2.0 * SPACING_M + 0.5, 1e-12);  /* copter 3: behind copter 2's body */
}

static void a_chain_conditioned_on_ctx_wall_dist_gets_it_without_a_log(void **state)
{
  (void)state;
  const bool all[N_COPTERS] = {true, true, true};
  /* every copter is inside the arena, away from the walls: ctx_wall_dist > 0 and the bias applies */
  assert_int_equal(setup_line("ranging(max_range=2.5): bias(b=0.25) if ctx_wall_dist", all), 0);
  struct heard h = measure(1);
  assert_int_equal(h.n, 2);
  assert_close(h.distance_m[0], SPACING_M + 0.25, 1e-12);
  assert_close(h.distance_m[1], SPACING_M + 0.25, 1e-12);
}

static void a_per_vehicle_bias_applies_to_that_vehicle_only(void **state)
{
  (void)state;
  const bool all[N_COPTERS] = {true, true, true};
  /* ids 1, 2, 3 (the world's first id is 1): ctx_vehicle is the measuring copter's id */
  assert_int_equal(setup_line("ranging(max_range=2.5): bias(b=-0.11) if ctx_vehicle == 2", all), 0);
  for (unsigned v = 0; v < N_COPTERS; v++) {
    struct heard h = measure(v);
    assert_int_equal(h.n, 2);
    for (unsigned i = 0; i < h.n; i++) {
      const double true_m = SPACING_M * fabs((double)h.peer_id[i] - (double)(v + 1));
      assert_close(h.distance_m[i], true_m + (v == 1 ? -0.11 : 0.0), 1e-12);
    }
  }
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_teardown(every_equipped_peer_is_measured_at_its_true_range, teardown),
    cmocka_unit_test_teardown(a_peer_without_a_ranging_unit_is_not_heard, teardown),
    cmocka_unit_test_teardown(a_chain_conditioned_on_ctx_blocked_gets_it_without_a_log, teardown),
    cmocka_unit_test_teardown(a_chain_conditioned_on_ctx_wall_dist_gets_it_without_a_log, teardown),
    cmocka_unit_test_teardown(a_per_vehicle_bias_applies_to_that_vehicle_only, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
