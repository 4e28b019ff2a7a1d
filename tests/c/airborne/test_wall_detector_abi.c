/*
 * The wall detector's and the swarm's Paparazzi glue on the host's ABI: what goes in (OBSTACLE_DETECTION with
 * sonar_array's sender ids and headings, RANGING_DISTANCE), what comes out (WALL_DETECTION: sender, sonar,
 * units, the split of the reading), one state per copter, and the swarm's guided command from it.
 */
#include "test_helpers.h"
#include "modules/wall_detector/wall_detector.h"
#include "modules/swarm/swarm.h"
#include "modules/sonar/sonar_array.h"
#include "modules/ranging/virtual_ranging.h"
#include "firmwares/rotorcraft/autopilot_guided.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"
#include "state.h"

#define VEHICLES 2

/* sonar_array's OBSTACLE_DETECTION headings and elevations (sonar_array.h: front 0, right pi/2, back pi,
 * left -pi/2, Paparazzi's body frame; down: elevation -pi/2), written out so this test does not link the
 * sonar driver */
static const float heading_rad[SONAR_ARRAY_NB] = { 0.f, (float)M_PI_2, (float)M_PI, (float)-M_PI_2, 0.f };
static const float elevation_rad[SONAR_ARRAY_NB] = { 0.f, 0.f, 0.f, 0.f, (float)-M_PI_2 };

/** What the test's WALL_DETECTION callback received, per vehicle. */
struct received {
  int count;
  uint8_t sender_id, sonar, target_class, baseline_class;
  uint32_t stamp;
  float heading, confidence, attraction, repulsion;
};
static struct received received[VEHICLES];
static abi_event wall_detection_ev[VEHICLES];

static void on_wall_detection(uint8_t sender_id, uint32_t stamp, uint8_t sonar, float heading, uint8_t target_class,
                              float confidence, float attraction_distance, float repulsion_distance,
                              uint8_t baseline_class)
{
  received[pprz_vehicle_index] = (struct received) {
    received[pprz_vehicle_index].count + 1, sender_id, sonar, target_class, baseline_class, stamp, heading,
    confidence, attraction_distance, repulsion_distance,
  };
}

/** Put vehicle v at (east, north) [m] with heading psi [rad] (from north, clockwise). */
static void place(unsigned v, float east_m, float north_m, float psi_rad)
{
  pprz_vehicle_select(v);
  struct State *st = state_current();
  st->enu_pos_f = (struct EnuCoor_f) { east_m, north_m, 0.6f };
  st->ned_pos_f = (struct NedCoor_f) { north_m, east_m, -0.6f };
  st->ned_to_body_eulers_f = (struct FloatEulers) { 0.f, 0.f, psi_rad };
}

static int setup(void **state)
{
  (void)state;
  const uint16_t ids[VEHICLES] = { 11, 12 };
  pprz_vehicles_setup(VEHICLES, ids);
  for (unsigned v = 0; v < VEHICLES; v++) {
    pprz_vehicle_select(v);
    wall_detector_init();
    swarm_init();
    AbiBindMsgWALL_DETECTION(ABI_BROADCAST, &wall_detection_ev[v], on_wall_detection);
    received[v] = (struct received) { 0 };
    place(v, 1.0f + v, 1.0f, 0.f);
  }
  sys_time_host_set(5.0);
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  pprz_vehicles_teardown();
  return 0;
}

static void each_horizontal_sonar_reading_is_judged_once(void **state)
{
  (void)state;
  const enum sonar_array_index horizontal[4] = {
    SONAR_ARRAY_FRONT, SONAR_ARRAY_RIGHT, SONAR_ARRAY_BACK, SONAR_ARRAY_LEFT
  };
  const uint8_t sender[4] = { SONAR_ARRAY_FRONT_ID, SONAR_ARRAY_RIGHT_ID, SONAR_ARRAY_BACK_ID, SONAR_ARRAY_LEFT_ID };
  pprz_vehicle_select(0);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, get_sys_time_usec(), 12, 2.4f);
  for (int i = 0; i < 4; i++) {
    const float distance_m = 0.3f + 0.15f * i;
    AbiSendMsgOBSTACLE_DETECTION(sender[i], distance_m, elevation_rad[horizontal[i]],
                                 heading_rad[horizontal[i]]);
    const struct received *r = &received[0];
    assert_int_equal(r->count, i + 1);
    assert_int_equal(r->sender_id, WALL_DETECTOR_SENDER_ID);
    assert_int_equal(r->sonar, i);  // the detector's index: 0 front, 1 right, 2 back, 3 left
    assert_close(r->heading, heading_rad[horizontal[i]], 0.0);
    assert_int_equal(r->stamp, 5000000u);
    assert_close(r->repulsion, distance_m, 0.0);
    /* a peer 2.4 m away (echo 2.2 m, cross-talk 1.2 m) explains none of these: walls, no attraction */
    assert_int_equal(r->target_class, WALL_DETECTOR_WALL);
    assert_int_equal(r->baseline_class, WALL_DETECTOR_WALL);
    assert_close(r->attraction, -1.0, 0.0);
    assert_true(r->confidence >= 0.5f && r->confidence <= 1.0f);
  }
  /* the other copter heard nothing */
  assert_int_equal(received[1].count, 0);
}

static void the_downward_sonar_is_ignored(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_DOWN_ID, 0.6f, elevation_rad[SONAR_ARRAY_DOWN],
                               heading_rad[SONAR_ARRAY_DOWN]);
  assert_int_equal(received[0].count, 0);
}

static void a_reading_at_the_maximum_is_passed_on_for_repulsion(void **state)
{
  (void)state;
  pprz_vehicle_select(1);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_BACK_ID, SONAR_ARRAY_MAX_RANGE, 0.f, (float)M_PI);
  assert_int_equal(received[1].count, 1);
  assert_int_equal(received[1].target_class, WALL_DETECTOR_NO_ECHO);
  assert_close(received[1].repulsion, SONAR_ARRAY_MAX_RANGE, 0.0);
  assert_close(received[1].attraction, -1.0, 0.0);
}

static void ranging_reaches_only_its_own_copters_detector(void **state)
{
  (void)state;
  /* vehicle 1 ranges its peer at 1.24 m (echo expected at 1.0 m); vehicle 0 ranges nothing */
  pprz_vehicle_select(1);
  for (int i = 0; i < 10; i++) {
    sys_time_host_set(5.0 + 0.05 * i);
    AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, get_sys_time_usec(), 11, 1.24f);
    AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.0f, 0.f, 0.f);
  }
  assert_int_equal(received[1].target_class, WALL_DETECTOR_COPTER);
  assert_close(received[1].attraction, 1.0, 0.0);
  pprz_vehicle_select(0);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.0f, 0.f, 0.f);
  assert_int_equal(received[0].target_class, WALL_DETECTOR_WALL);
}

static void the_swarm_flies_the_law_from_the_detections(void **state)
{
  (void)state;
  /* vehicle 0 heads east (psi pi/2) at (1, 1); its front sonar sees a wall 1 m ahead. Target at t = 5 s:
   * ENU (1.5 + cos(pi/6), 2 + sin(pi/6)) = (2.366025, 2.5). With the detector the wall only repels:
   * v = 0.8 x (-2.053668, east) + 0.2 x (target - position) = east 0.8 x -2.053668 + 0.2 x 1.366025,
   * north 0.2 x 1.5; |v| > 0.5 m/s: scaled to 0.5 m/s. */
  place(0, 1.0f, 1.0f, (float)M_PI_2);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.0f, 0.f, 0.f);
  swarm_periodic();
  const double east = 0.8 * -2.053668476 + 0.2 * 1.366025404, north = 0.2 * 1.5;
  const double scale = 0.5 / hypot(east, north);
  const struct autopilot_guided_command *cmd = autopilot_guided_current();
  assert_true(cmd->active);
  assert_close(cmd->vx, north * scale, 1e-5);
  assert_close(cmd->vy, east * scale, 1e-5);
  assert_close(cmd->heading, M_PI_2, 1e-6);
  /* detector off (the original behaviour): the same wall also attracts with a d = 1 */
  VEHICLE_LOCAL(swarm)->use_wall_detector = false;
  swarm_periodic();
  const double east_off = 0.8 * -1.053668476 + 0.2 * 1.366025404;
  const double scale_off = 0.5 / hypot(east_off, north);
  assert_close(cmd->vx, north * fmin(scale_off, 1.0), 1e-5);
  assert_close(cmd->vy, east_off * fmin(scale_off, 1.0), 1e-5);
  /* the other copter's swarm saw nothing: it flies to the target only */
  pprz_vehicle_select(1);
  swarm_periodic();
  assert_close(autopilot_guided_current()->vy, 0.2 * (2.366025404 - 2.0), 1e-5);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(each_horizontal_sonar_reading_is_judged_once, setup, teardown),
    cmocka_unit_test_setup_teardown(the_downward_sonar_is_ignored, setup, teardown),
    cmocka_unit_test_setup_teardown(a_reading_at_the_maximum_is_passed_on_for_repulsion, setup, teardown),
    cmocka_unit_test_setup_teardown(ranging_reaches_only_its_own_copters_detector, setup, teardown),
    cmocka_unit_test_setup_teardown(the_swarm_flies_the_law_from_the_detections, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
