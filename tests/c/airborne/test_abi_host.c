/* The host's ABI stand-in: Paparazzi's bind/send semantics, one set of queues per simulated vehicle, and a
 * current vehicle per thread (the host runs the copters' modules on several threads). */
#define PPRZ_VEHICLE_CHECKS 1   /* VEHICLE_LOCAL checks its use in this file in every build (vehicle_local.h) */
#include "test_helpers.h"
#include "nps_fdm.h"
#include "state_host.h"
#include "modules/multi_vehicle/vehicle_local.h"
#include "modules/core/abi.h"
#include "pprz_host_vehicle.h"
#include "mcu_periph/sys_time.h"

#include <pthread.h>
#include <signal.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static float last_distance[2];
static uint8_t last_sender[2];
static int calls[2];

static void on_agl(uint8_t sender_id, uint32_t stamp, float distance)
{
  (void)stamp;
  last_sender[pprz_vehicle_index] = sender_id;
  last_distance[pprz_vehicle_index] = distance;
  calls[pprz_vehicle_index]++;
}

static int setup(void **state)
{
  (void)state;
  pprz_vehicles_setup(2, NULL);
  calls[0] = calls[1] = 0;
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  pprz_vehicles_teardown();
  return 0;
}

static void messages_reach_only_the_sending_vehicle(void **state)
{
  (void)state;
  static abi_event ev[2];
  for (unsigned v = 0; v < 2; v++) {
    pprz_vehicle_select(v);
    AbiBindMsgAGL(ABI_BROADCAST, &ev[v], on_agl);
  }
  pprz_vehicle_select(1);
  AbiSendMsgAGL(42, 0, 1.5f);
  assert_int_equal(calls[0], 0);
  assert_int_equal(calls[1], 1);
  assert_int_equal(last_sender[1], 42);
  assert_close(last_distance[1], 1.5, 0.0);
}

static void a_sender_filter_drops_other_senders(void **state)
{
  (void)state;
  static abi_event ev;
  pprz_vehicle_select(0);
  AbiBindMsgAGL(7, &ev, on_agl);
  AbiSendMsgAGL(8, 0, 1.0f);
  assert_int_equal(calls[0], 0);
  AbiSendMsgAGL(7, 0, 2.0f);
  assert_int_equal(calls[0], 1);
}

static void aircraft_ids_follow_the_vehicle(void **state)
{
  (void)state;
  const uint16_t ids[2] = {11, 12};
  pprz_vehicles_setup(2, ids);
  pprz_vehicle_select(1);
  assert_int_equal(pprz_vehicle_ac_id(), 12);
}

static void sys_time_reads_back_the_simulated_time(void **state)
{
  (void)state;
  sys_time_host_set(12.345678);
  assert_int_equal(get_sys_time_usec(), 12345678);
  assert_int_equal(get_sys_time_msec(), 12345);
  assert_close(get_sys_time_float(), 12.345678, 1e-5);
  /* a time just below a full second rounds up to it: the seconds carry, and seconds and ticks agree */
  sys_time_host_set(4.9999996);
  assert_int_equal(sys_time.nb_sec, 5);
  assert_int_equal(sys_time.nb_sec_rem, 0);
  assert_int_equal(get_sys_time_usec(), 5000000);
  /* every host step of 1/100 s for a simulated hour reads back as its whole number of microseconds */
  for (uint32_t step = 1; step <= 360000; step++) {
    sys_time_host_set(step * 0.01);
    assert_int_equal(get_sys_time_usec(), step * 10000);
    assert_int_equal(sys_time.nb_tick, step * 10000);
  }
}

static void *send_as_vehicle_1(void *arg)
{
  (void)arg;
  pprz_vehicle_select(1);
  AbiSendMsgAGL(9, 0, 3.0f);
  return NULL;
}

static void each_thread_has_its_own_current_vehicle(void **state)
{
  (void)state;
  static abi_event ev[2];
  for (unsigned v = 0; v < 2; v++) {
    pprz_vehicle_select(v);
    AbiBindMsgAGL(ABI_BROADCAST, &ev[v], on_agl);
  }
  pprz_vehicle_select(0);
  pthread_t other;
  assert_int_equal(pthread_create(&other, NULL, send_as_vehicle_1, NULL), 0);
  assert_int_equal(pthread_join(other, NULL), 0);
  assert_int_equal(pprz_vehicle_index, 0);   /* the other thread's select left this thread's vehicle alone */
  assert_int_equal(calls[0], 0);
  assert_int_equal(calls[1], 1);
  assert_close(last_distance[1], 3.0, 0.0);
}

/** A flight-model source for nps_fdm_current: altitude 10 + vehicle index. */
static void fdm_from_index(struct NpsFdm *f, unsigned vehicle)
{
  f->agl = 10.0 + vehicle;
}

static void the_fdm_is_filled_from_its_source_when_read(void **state)
{
  (void)state;
  pprz_vehicle_select(1);
  nps_fdm_current()->agl = 3.0;
  assert_close(fdm.agl, 3.0, 0.0);            /* no source: what was written */
  pprz_vehicle_select(0);
  nps_fdm_current()->agl = 4.0;               /* one NpsFdm per vehicle: vehicle 1's stays */
  pprz_vehicle_select(1);
  assert_close(fdm.agl, 3.0, 0.0);
  nps_fdm_set_source(fdm_from_index);
  assert_close(fdm.agl, 11.0, 0.0);           /* the current vehicle's, from the source */
  pprz_vehicle_select(0);
  assert_close(nps_fdm_current()->agl, 10.0, 0.0);
  nps_fdm_set_source(NULL);
}

VEHICLE_LOCAL_DEFINE(int, probe);   /* a registered per-vehicle variable */

/** In a child process: set up `vehicles` vehicles (none if 0), select `index`, write the probe; how it ended. */
static int probe_in_child(unsigned vehicles, unsigned index, char *message, size_t message_len)
{
  int out[2];
  assert_int_equal(pipe(out), 0);
  fflush(NULL);
  const pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    /* a crash ends the child: cmocka's handlers would report it here and run the remaining tests in the child */
    const int crashes[] = { SIGSEGV, SIGBUS, SIGILL, SIGFPE };
    for (unsigned i = 0; i < sizeof(crashes) / sizeof(crashes[0]); i++) {
      signal(crashes[i], SIG_DFL);
    }
    dup2(out[1], STDERR_FILENO);
    if (vehicles > 0) {
      pprz_vehicles_setup(vehicles, NULL);
    }
    pprz_vehicle_index = index;   /* what a thread that never selected (0) or a stale selection would have */
    *VEHICLE_LOCAL(probe) = 1;
    pprz_vehicles_teardown();
    _exit(0);
  }
  close(out[1]);
  const ssize_t got = read(out[0], message, message_len - 1);
  message[got > 0 ? got : 0] = '\0';
  close(out[0]);
  int status;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  return status;
}

static void a_checked_vehicle_local_stops_a_misuse_with_a_message(void **state)
{
  (void)state;
  /* two misuses abort with their message: a use before set-up, a use with a vehicle index out of range */
  char message[256];
  int status = probe_in_child(0, 0, message, sizeof message);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT);
  assert_non_null(strstr(message, "before pprz_vehicles_setup()"));
  status = probe_in_child(2, 2, message, sizeof message);
  assert_true(WIFSIGNALED(status) && WTERMSIG(status) == SIGABRT);
  assert_non_null(strstr(message, "no vehicle selected in range"));
  status = probe_in_child(2, 1, message, sizeof message);   /* the right use passes the checks */
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
}

static void the_ned_state_follows_the_enu_state_when_read(void **state)
{
  (void)state;
  pprz_vehicle_select(1);
  struct State *st = state_current();
  st->enu_pos_f = (struct EnuCoor_f) { 1.25f, -2.5f, 0.6f };
  st->enu_speed_f = (struct EnuCoor_f) { -0.3f, 0.7f, -0.1f };
  const struct NedCoor_f *pos = stateGetPositionNed_f();
  assert_true(pos->x == -2.5f && pos->y == 1.25f && pos->z == -0.6f);
  const struct NedCoor_f *speed = stateGetSpeedNed_f();
  assert_true(speed->x == 0.7f && speed->y == -0.3f && speed->z == 0.1f);
  st->enu_pos_f.z = 1.0f;   /* a later read sees a later ENU state */
  assert_true(stateGetPositionNed_f()->z == -1.0f);
}

static void the_state_follows_the_flight_model_when_read(void **state)
{
  (void)state;
  pprz_vehicle_select(1);
  struct State *st = state_current();
  struct nps_finken_lag_state flight = { .pos_m = { 1.25, -2.5, 0.6 }, .vel_mps = { -0.3, 0.7, -0.1 }, .yaw_rad = 0.3,
                                         .yaw_rate_rps = 0.2 };
  state_follow_flight_model(st, &flight, NULL);
  const struct EnuCoor_f *enu = stateGetPositionEnu_f();
  assert_true(enu->x == 1.25f && enu->y == -2.5f && enu->z == 0.6f);
  const struct NedCoor_f *speed = stateGetSpeedNed_f();
  assert_true(speed->x == 0.7f && speed->y == -0.3f && speed->z == 0.1f);
  assert_true(stateGetSpeedEnu_f()->y == 0.7f);
  assert_true(stateGetNedToBodyEulers_f()->psi == (float)(M_PI / 2.0 - 0.3) && stateGetNedToBodyEulers_f()->phi == 0.f);
  assert_true(stateGetBodyRates_f()->r == -0.2f);
  flight.pos_m[0] = 3.5;   /* the flight model moves on: the next read follows it */
  flight.yaw_rad = -1.0;
  assert_true(stateGetPositionNed_f()->y == 3.5f);
  assert_true(stateGetNedToBodyEulers_f()->psi == (float)(M_PI / 2.0 + 1.0));
  pprz_vehicle_select(0);   /* another vehicle's state has no flight model: as written */
  assert_null(state_current()->flight.pos_m);
  pprz_vehicle_select(1);
  state_follow_flight_model(st, NULL, NULL);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(messages_reach_only_the_sending_vehicle, setup, teardown),
    cmocka_unit_test_setup_teardown(a_sender_filter_drops_other_senders, setup, teardown),
    cmocka_unit_test_setup_teardown(aircraft_ids_follow_the_vehicle, setup, teardown),
    cmocka_unit_test(sys_time_reads_back_the_simulated_time),
    cmocka_unit_test_setup_teardown(each_thread_has_its_own_current_vehicle, setup, teardown),
    cmocka_unit_test_setup_teardown(the_fdm_is_filled_from_its_source_when_read, setup, teardown),
    cmocka_unit_test(a_checked_vehicle_local_stops_a_misuse_with_a_message),
    cmocka_unit_test_setup_teardown(the_state_follows_the_flight_model_when_read, setup, teardown),
    cmocka_unit_test_setup_teardown(the_ned_state_follows_the_enu_state_when_read, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
