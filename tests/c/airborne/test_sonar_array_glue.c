/*
 * The sonar_array module's Paparazzi glue with a scripted sonar behind sonar_array_arch.h: what is published
 * on ABI (message, sender id, body-frame heading and elevation, units), how out-of-range readings are
 * reported, and that every simulated copter keeps its own ring. Exact.
 */
#include "test_helpers.h"
#include "modules/sonar/sonar_array.h"
#include "modules/sonar/sonar_array_arch.h"
#include "modules/core/abi.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"

#include <string.h>

/* ---- the scripted sonars (replace the arch layer) ---- */
static float scripted_m[SONAR_ARRAY_NB];
static int triggers[2][SONAR_ARRAY_NB];

bool sonar_array_arch_init(void)
{
  return true;
}

void sonar_array_arch_trigger(uint8_t sonar, uint32_t now_us)
{
  (void)now_us;
  triggers[pprz_vehicle_index][sonar]++;
}

float sonar_array_arch_read(uint8_t sonar, uint32_t fired_us, uint32_t now_us)
{
  assert_int_equal(now_us - fired_us, SONAR_ARRAY_READ_DELAY * 10000u);   /* the listening window */
  return scripted_m[sonar];
}

/* ---- what the ring publishes ---- */
struct obstacle { uint8_t sender; float distance, elevation, heading; };
static struct obstacle obstacles[64];
static int n_obstacles;
static float agl_m;
static uint32_t agl_stamp;
static int n_agl;

static void on_obstacle(uint8_t sender_id, float distance, float elevation, float heading)
{
  obstacles[n_obstacles++] = (struct obstacle) { sender_id, distance, elevation, heading };
}

static void on_agl(uint8_t sender_id, uint32_t stamp, float distance)
{
  assert_int_equal(sender_id, SONAR_ARRAY_DOWN_ID);
  agl_m = distance;
  agl_stamp = stamp;
  n_agl++;
}

static abi_event obstacle_ev[2], agl_ev[2];

static int setup(void **state)
{
  (void)state;
  pprz_vehicles_setup(2, NULL);
  memset(triggers, 0, sizeof(triggers));
  n_obstacles = n_agl = 0;
  sys_time_host_set(0.0);
  for (unsigned v = 0; v < 2; v++) {
    pprz_vehicle_select(v);
    AbiBindMsgOBSTACLE_DETECTION(ABI_BROADCAST, &obstacle_ev[v], on_obstacle);
    AbiBindMsgAGL(ABI_BROADCAST, &agl_ev[v], on_agl);
    sonar_array_init();
  }
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  pprz_vehicles_teardown();
  return 0;
}

/** Run vehicle 0's ring through `slots` round-robin slots of 10 ms. */
static void run_slots(int slots)
{
  pprz_vehicle_select(0);
  for (int k = 0; k < slots; k++) {
    sys_time_host_set(k * 0.01);
    sonar_array_periodic();
  }
}

static void horizontal_readings_are_obstacles_in_the_body_frame(void **state)
{
  (void)state;
  for (int i = 0; i < SONAR_ARRAY_NB; i++) {
    scripted_m[i] = 1.0f + 0.1f * i;
  }
  run_slots(7);   /* slots 2..6 read every sonar once */
  assert_int_equal(n_obstacles, 4);
  const uint8_t ids[4] = { SONAR_ARRAY_FRONT_ID, SONAR_ARRAY_RIGHT_ID, SONAR_ARRAY_BACK_ID, SONAR_ARRAY_LEFT_ID };
  const float headings[4] = { 0.0f, M_PI / 2.0, M_PI, -M_PI / 2.0 };
  for (int k = 0; k < n_obstacles; k++) {
    const struct obstacle *o = &obstacles[k];
    int sonar = -1;
    for (int i = 0; i < 4; i++) {
      sonar = ids[i] == o->sender ? i : sonar;
    }
    assert_true(sonar >= 0);
    assert_close(o->heading, headings[sonar], 1e-6);
    assert_close(o->elevation, 0.0, 0.0);
    assert_close(o->distance, scripted_m[sonar], 0.0);
  }
  assert_int_equal(n_agl, 1);
  assert_close(agl_m, scripted_m[SONAR_ARRAY_DOWN], 0.0);
  assert_int_equal(agl_stamp, 60000);   /* down fired in slot 4, read in slot 6: stamp [us] of the reading */
}

static void out_of_range_readings_are_reported_as_the_sensor_does(void **state)
{
  (void)state;
  assert_close(sonar_array_reported_distance(0.05f), SONAR_ARRAY_MIN_RANGE, 0.0);
  assert_close(sonar_array_reported_distance(7.0f), SONAR_ARRAY_MAX_RANGE, 0.0);
  assert_close(sonar_array_reported_distance(NAN), SONAR_ARRAY_MAX_RANGE, 0.0);   /* no echo: the maximum */
  assert_close(sonar_array_reported_distance(1.234f), 1.234f, 0.0);
}

static void every_copter_runs_its_own_ring(void **state)
{
  (void)state;
  run_slots(3);
  assert_int_equal(triggers[0][SONAR_ARRAY_FRONT] + triggers[0][SONAR_ARRAY_BACK] + triggers[0][SONAR_ARRAY_RIGHT], 3);
  assert_int_equal(triggers[1][SONAR_ARRAY_FRONT], 0);
  pprz_vehicle_select(1);
  assert_int_equal(VEHICLE_LOCAL(sonar_array)->count[SONAR_ARRAY_FRONT], 0);
  pprz_vehicle_select(0);
  assert_int_equal(VEHICLE_LOCAL(sonar_array)->count[SONAR_ARRAY_FRONT], 1);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(horizontal_readings_are_obstacles_in_the_body_frame, setup, teardown),
    cmocka_unit_test(out_of_range_readings_are_reported_as_the_sensor_does),
    cmocka_unit_test_setup_teardown(every_copter_runs_its_own_ring, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
