/*
 * Contacts: overlapping bodies end exactly touching, walls stop a copter at its radius, others stay put, bodies
 * exactly touching are no contact; poses written in place are re-indexed. Exact.
 */
#include "test_helpers.h"
#include "test_arena_fixtures.h"
#include "nps_arena_contact.h"
#include "nps_arena_grid.h"

#include <errno.h>

/** The SwarmLab rectangle (3 m x 4 m, 20 plates per wall) with no copters. */
static struct nps_arena *rectangle_3x4(void)
{
  return arena_with_copters(NULL, 0, 0.0);
}

/** turned_rectangle with 20 plates per wall. */
static struct nps_arena *turned_rectangle_20(void)
{
  return turned_rectangle(20);
}

/** The SwarmLab rectangle with copters at xy, heading east. */
static struct nps_arena *arena_with(const double xy[][2], int n)
{
  return arena_with_copters(xy, n, 0.0);
}

static void overlapping_bodies_are_pushed_apart_to_touching(void **state)
{
  (void)state;
  const double xy[3][2] = { {1.0, 2.0}, {1.3, 2.0}, {2.5, 3.5} };
  struct nps_arena *a = arena_with(xy, 3);
  int moved[3];
  assert_int_equal(nps_arena_resolve_contacts(a, moved), 1);
  const double r = a->copters[0].radius_m;
  assert_close(a->copters[0].pos_m[0], 1.15 - r, 1e-12);    /* symmetric about the old midpoint */
  assert_close(a->copters[1].pos_m[0], 1.15 + r, 1e-12);
  assert_close(a->copters[0].pos_m[1], 2.0, 0.0);
  assert_int_equal(moved[0] + moved[1] + moved[2], 2);
  assert_close(a->copters[2].pos_m[0], 2.5, 0.0);           /* far from everything: untouched */
  nps_arena_free(a);
}

static void a_wall_stops_a_copter_at_its_radius(void **state)
{
  (void)state;
  const double xy[2][2] = { {-0.3, 2.0}, {1.5, 3.95} };       /* through the west wall; into the north wall */
  struct nps_arena *a = arena_with(xy, 2);
  assert_int_equal(nps_arena_resolve_contacts(a, NULL), 2);
  const double r = a->copters[0].radius_m;
  assert_close(a->copters[0].pos_m[0], r, 1e-12);
  assert_close(a->copters[1].pos_m[1], 4.0 - r, 1e-12);
  nps_arena_free(a);
}

static void bodies_exactly_touching_are_left_alone(void **state)
{
  (void)state;
  /* centres exactly 2 r apart along x (0.9 - 0.5 == 0.4 in doubles): no contact; a hair closer along a diagonal (|dx|, |dy| < 2 r): contact */
  const double xy[4][2] = { {0.5, 1.0}, {0.9, 1.0}, {1.0, 3.0}, {1.0 + 0.4 / M_SQRT2 - 1e-9, 3.0 + 0.4 / M_SQRT2} };
  struct nps_arena *a = arena_with(xy, 4);
  int moved[4];
  assert_int_equal(nps_arena_resolve_contacts(a, moved), 1);
  assert_int_equal(moved[0] + moved[1], 0);
  assert_int_equal(moved[2] + moved[3], 2);
  assert_close(hypot(a->copters[3].pos_m[0] - a->copters[2].pos_m[0], a->copters[3].pos_m[1] - a->copters[2].pos_m[1]),
               2.0 * a->copters[2].radius_m, 1e-12);
  nps_arena_free(a);
}

static void poses_changed_in_place_are_indexed(void **state)
{
  (void)state;
  /* nps_arena_poses_moved: after moving a copter straight in a->copters, contacts see it at its new place */
  const double xy[2][2] = { {1.0, 1.0}, {2.5, 3.5} };
  struct nps_arena *a = arena_with(xy, 2);
  a->copters[1].pos_m[0] = 1.2;
  a->copters[1].pos_m[1] = 1.0;
  assert_int_equal(nps_arena_poses_moved(a), 0);
  assert_int_equal(nps_arena_resolve_contacts(a, NULL), 1);
  /* every pose field is checked: a centre coordinate or a yaw that is not finite */
  for (int field = 0; field < 4; field++) {
    struct nps_arena_copter *c = &a->copters[field % 2];
    const struct nps_arena_copter before = *c;
    double *value = field < 3 ? &c->pos_m[field] : &c->yaw_rad;
    *value = field % 2 ? INFINITY : NAN;
    errno = 0;
    assert_int_equal(nps_arena_poses_moved(a), -1);
    assert_int_equal(errno, EINVAL);
    *c = before;
    assert_int_equal(nps_arena_poses_moved(a), 0);
  }
  nps_arena_free(a);
}

/** What makes the second of two arenas with the same copters resolve contacts another way (the first is the
 * shortcut under test). */
typedef void (*contact_variant_fn)(struct nps_arena *tested, struct nps_arena *reference);

/**
 * 500 random swarms of 8 copters uniform in [x_lo, x_hi) x [y_lo, y_hi) (LCG from `seed`): the contacts of the tested
 * arena equal those of the reference arena, made so by `variant`, count and positions bit for bit. Returns the
 * contacts counted over all swarms.
 */
static int contacts_equal_on_random_swarms(uint32_t seed, double x_lo, double x_hi, double y_lo, double y_hi,
                                           contact_variant_fn variant)
{
  uint32_t x = seed;
  int pushed = 0;
  for (int trial = 0; trial < 500; trial++) {
    double xy[8][2];
    for (int i = 0; i < 8; i++) {
      xy[i][0] = lcg_uniform(&x, x_lo, x_hi);
      xy[i][1] = lcg_uniform(&x, y_lo, y_hi);
    }
    struct nps_arena *tested = arena_with(xy, 8), *reference = arena_with(xy, 8);
    variant(tested, reference);
    const int count = nps_arena_resolve_contacts(tested, NULL);
    assert_int_equal(count, nps_arena_resolve_contacts(reference, NULL));
    pushed += count;
    for (int i = 0; i < 8; i++) {
      assert_memory_equal(tested->copters[i].pos_m, reference->copters[i].pos_m, sizeof tested->copters[i].pos_m);
    }
    nps_arena_free(tested);
    nps_arena_free(reference);
  }
  return pushed;
}

/** The reference tests every wall (no per-cell wall clearance). */
static void every_wall_tested(struct nps_arena *tested, struct nps_arena *reference)
{
  (void)tested;
  for (int c = 0; c < reference->grid->nx * reference->grid->ny; c++) {
    reference->grid->wall_clear_m[c] = -INFINITY;
  }
}

static void the_wall_shortcut_changes_nothing(void **state)
{
  (void)state;
  /* 500 random swarms of 8 copters over and around the 3 m x 4 m arena (some outside, near walls, overlapping):
   * contacts with the per-cell wall clearance equal contacts with every wall tested, bit for bit */
  const int pushed = contacts_equal_on_random_swarms(7u, -0.5, 3.5, -0.5, 4.5, every_wall_tested);
  assert_true(pushed > 500);   /* the swarms did touch the walls and each other */
}

/**
 * One copter of radius r at (x, y) in arena `tested` and in `reference` (made by the same function, every wall
 * tested there): the same contacts, bit for bit. Returns whether a wall pushed it.
 */
static int one_copter_contacts_equal(struct nps_arena *tested, struct nps_arena *reference, double x, double y,
                                     double r)
{
  struct nps_arena_copter c = nps_arena_copter_make(tested, 1, x, y, 0.6, 0.0);
  c.radius_m = r;
  assert_int_equal(nps_arena_set_copters(tested, &c, 1), 0);
  assert_int_equal(nps_arena_set_copters(reference, &c, 1), 0);
  const int count = nps_arena_resolve_contacts(tested, NULL);
  assert_int_equal(count, nps_arena_resolve_contacts(reference, NULL));
  assert_memory_equal(tested->copters[0].pos_m, reference->copters[0].pos_m, sizeof c.pos_m);
  return count;
}

static void the_wall_shortcut_holds_at_each_cells_clearance(void **state)
{
  (void)state;
  /* In the 3 m x 4 m rectangle and in the turned one (oblique walls: clearances of every size), a copter at each
   * corner of each cell (1e-8 m inside it), of a radius 1e-7 m below and 1e-7 m above the cell's wall clearance
   * (1 m if the cell faces no wall): with the clearance, the copter is pushed exactly as with every wall tested.
   * The corner nearest a wall is within 1e-9 (the clearance's margin) + 1.5e-8 of the clearance, so the larger
   * body is pushed there: a clearance 1e-7 m too large, or one that leaves out a wall the cell faces, fails. */
  struct nps_arena *(*const make[2])(void) = { rectangle_3x4, turned_rectangle_20 };
  int pushed = 0, facing = 0;
  for (int m = 0; m < 2; m++) {
    struct nps_arena *tested = make[m](), *reference = make[m]();
    every_wall_tested(tested, reference);
    const struct nps_arena_grid *g = tested->grid;
    for (int cell = 0; cell < g->nx * g->ny; cell++) {
      const double clear = g->wall_clear_m[cell];
      facing += clear > 1e-4 && clear < INFINITY;
      const double x0 = g->x0_m + (cell % g->nx) * g->cell_m, y0 = g->y0_m + (cell / g->nx) * g->cell_m;
      for (int k = 0; k < 8 && clear > 1e-4; k++) {
        const double x = k & 1 ? x0 + g->cell_m - 1e-8 : x0 + 1e-8, y = k & 2 ? y0 + g->cell_m - 1e-8 : y0 + 1e-8;
        const double r = clear == INFINITY ? 1.0 : clear + (k & 4 ? 1e-7 : -1e-7);
        pushed += one_copter_contacts_equal(tested, reference, x, y, r);
      }
    }
    nps_arena_free(tested);
    nps_arena_free(reference);
  }
  print_message("# %d cells facing a wall with a clearance, %d copters pushed\n", facing, pushed);
  assert_true(pushed >= facing);   /* in each such cell, at least the larger body at the corner nearest the wall */
}

/** The tested arena is a few copters (it tests later copters before a query); the reference finds neighbours in
 * the grid. */
static void neighbours_from_the_grid(struct nps_arena *tested, struct nps_arena *reference)
{
  assert_true(nps_arena_grid_few_copters(tested->grid));
  reference->grid->direct_max_copters = 0;
}

static void the_few_copters_test_changes_nothing(void **state)
{
  (void)state;
  /* 500 random swarms of 8 copters crowded into the west half of the arena (many touching, chains of three):
   * contacts that test each later copter before a neighbour query (a few copters) equal contacts that find
   * neighbours in the grid (direct_max_copters 0), bit for bit */
  const int pushed = contacts_equal_on_random_swarms(11u, 0.1, 1.5, 0.1, 2.0, neighbours_from_the_grid);
  assert_true(pushed > 2000);   /* about 5 contacts per swarm: pairs, chains and walls */
}

/** The first cell border at or east of x = 1.2 m in arena_with's grid [m], with a copter's radius and the cell size. */
static double a_cell_border(double *radius_m, double *cell_m)
{
  struct nps_arena *probe = arena_with((const double[1][2]) { { 1.5, 2.0 } }, 1);
  *radius_m = probe->copters[0].radius_m;
  *cell_m = probe->grid->cell_m;
  const double border = probe->grid->x0_m + *cell_m * ceil((1.2 - probe->grid->x0_m) / *cell_m);
  nps_arena_free(probe);
  return border;
}

static void a_copter_pushed_out_of_its_indexed_cell_is_left_to_the_query(void **state)
{
  (void)state;
  /* Copter 0 pushes copter 2 west into copter 1 in the same pass, but the index (made before the pass) still holds
   * copter 2 in the cell east of copter 1's query box: copter 1's query does not visit it, so the pair waits for
   * the next pass. A few copters (which push a single overlap without the query only while nothing was pushed
   * in the pass) must do what the grid's cell lists do, bit for bit. */
  double r, cell;
  const double border = a_cell_border(&r, &cell);
  const double x2 = border + 0.001;   /* 2 r + 2 mm east of copter 1, in the cell beyond its query box */
  const double xy[3][2] = { { x2 + 2.0 * r - 0.02, 2.0 }, { border - 2.0 * r - 0.001, 2.0 }, { x2, 2.0 } };
  struct nps_arena *few = arena_with(xy, 3), *grid = arena_with(xy, 3);
  assert_true(nps_arena_grid_few_copters(few->grid));
  grid->grid->direct_max_copters = 0;
  assert_int_equal(nps_arena_resolve_contacts(few, NULL), 1);   /* copters 0 and 2 only */
  assert_int_equal(nps_arena_resolve_contacts(grid, NULL), 1);
  for (int i = 0; i < 3; i++) {
    assert_memory_equal(few->copters[i].pos_m, grid->copters[i].pos_m, sizeof few->copters[i].pos_m);
  }
  assert_true(few->copters[2].pos_m[0] - few->copters[1].pos_m[0] < 2.0 * r);   /* copters 1 and 2 overlap now */
  nps_arena_free(few);
  nps_arena_free(grid);
}

static void a_copter_pushed_against_a_lone_body_is_found_by_its_query(void **state)
{
  (void)state;
  /* Cell lists (direct_max_copters 0), a cell border between the bodies of copters 1 and 2, 2 mm apart: the index
   * (made before the pass) lists each body in its own cells only, so copter 1 looks alone there. Copter 0 pushes
   * copter 2 west into copter 1 in the same pass; copter 2's centre stays listed in a cell of copter 1's query box,
   * so copter 1's query pushes the pair apart. Copter 1 may skip its query only while nothing was pushed yet. */
  double r, cell;
  const double border = a_cell_border(&r, &cell);
  assert_true(r + 0.001 < cell);   /* copter 2's centre in the cell east of the border, within copter 1's reach */
  const double x1 = border - r - 0.001, x2 = border + r + 0.001;
  /* copter 0 overlaps copter 2 by 2 cm from the east */
  const double xy[3][2] = { { x2 + 2.0 * r - 0.02, 2.0 }, { x1, 2.0 }, { x2, 2.0 } };
  struct nps_arena *a = arena_with(xy, 3);
  a->grid->direct_max_copters = 0;
  assert_int_equal(nps_arena_resolve_contacts(a, NULL), 2);   /* copters 0 and 2, then 1 and 2 */
  assert_true(a->copters[2].pos_m[0] - a->copters[1].pos_m[0] >= 2.0 * r * (1.0 - 1e-12));   /* touching */
  nps_arena_free(a);
}

/** The pair test as it was before its squared-distance shortcut: box reject, then the distance. */
static int overlap_by_distance(double dx, double dy, double reach, double *d)
{
  if (fabs(dx) >= reach || fabs(dy) >= reach) {
    return 0;
  }
  *d = sqrt(dx * dx + dy * dy);
  return *d < reach;
}

static void the_pair_test_is_the_distance_test(void **state)
{
  (void)state;
  /* Pairs on and near the border d = reach (a few ulps each side), in random directions, for reaches from normal
   * sizes down to ones whose square is subnormal or 0 (where only the box test is exact): the shortcut must give
   * the decision and distance of the plain test every time. Fails if the shortcut skips its normal-square check
   * (tiny reaches) or its box test, or tests s > fl(reach^2) (1 - 1e-15). */
  const double reaches[] = { 0.4, 0.3, 1.0, 3e-7, 2.5e3, 1.2e-154, 1e-160, 3e-162, 1e-200 };
  unsigned long long x = 88172645463325252ull;   /* xorshift64 */
  int wrong_if_looser = 0, tested = 0;
  for (size_t k = 0; k < sizeof reaches / sizeof reaches[0]; k++) {
    const double reach = reaches[k];
    for (int n = 0; n < 4000; n++) {
      x ^= x << 13; x ^= x >> 7; x ^= x << 17;
      const double angle = (double)(x >> 11) * 0x1p-53 * 2.0 * M_PI;
      const double scale = ulps_from(reach, (int)(x % 9) - 6);
      double dx = scale * cos(angle), dy = scale * sin(angle);
      if (n % 8 == 0) {   /* on the axes too: |dx| at, just below and just above the reach */
        dx = ulps_from(reach, (int)(x % 5) - 2);
        dy = n % 16 == 0 ? 0.0 : -0.0;
      }
      double d_fast = -1.0, d_plain = -1.0;
      const int fast = nps_arena_bodies_overlap(dx, dy, reach, &d_fast);
      const int plain = overlap_by_distance(dx, dy, reach, &d_plain);
      assert_int_equal(fast, plain);
      if (plain) {
        assert_memory_equal(&d_fast, &d_plain, sizeof d_fast);
      }
      wrong_if_looser += (dx * dx + dy * dy >= reach * reach * (1.0 - 1e-15)) && plain;
      tested++;
    }
  }
  assert_int_equal(tested, 36000);
  assert_true(wrong_if_looser > 0);   /* the sample has overlaps that the looser s > fl(reach^2) (1 - 1e-15) rejects */
  /* no overlap for NaN or infinite offsets (and a NaN reach), as with the plain test */
  double d;
  assert_int_equal(nps_arena_bodies_overlap(NAN, 0.0, 0.4, &d), 0);
  assert_int_equal(nps_arena_bodies_overlap(0.1, INFINITY, 0.4, &d), 0);
  assert_int_equal(nps_arena_bodies_overlap(0.1, 0.1, NAN, &d), 0);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(overlapping_bodies_are_pushed_apart_to_touching),
    cmocka_unit_test(a_wall_stops_a_copter_at_its_radius),
    cmocka_unit_test(bodies_exactly_touching_are_left_alone),
    cmocka_unit_test(poses_changed_in_place_are_indexed),
    cmocka_unit_test(the_wall_shortcut_changes_nothing),
    cmocka_unit_test(the_wall_shortcut_holds_at_each_cells_clearance),
    cmocka_unit_test(the_few_copters_test_changes_nothing),
    cmocka_unit_test(a_copter_pushed_out_of_its_indexed_cell_is_left_to_the_query),
    cmocka_unit_test(a_copter_pushed_against_a_lone_body_is_found_by_its_query),
    cmocka_unit_test(the_pair_test_is_the_distance_test),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
