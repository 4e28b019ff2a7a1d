/*
 * The range recorder's Paparazzi glue on the host's ABI, two copters (aircraft 3 and 7): sonar readings
 * (OBSTACLE_DETECTION with sonar_array's senders, AGL), ranging distances and wall-detector decisions fed by hand
 * become rows in each copter's own files in $FINKEN_WORLD_OUT and telemetry messages (range_recorder_telemetry.h,
 * replaced here by stubs that keep what they were given); other senders are not recorded; rows reach the disk at
 * the flush period; a file that cannot be written is reported once on stderr and the recording goes on without it.
 */
#include "test_helpers.h"
#include "modules/range_recorder/range_recorder.h"
#include "modules/range_recorder/range_recorder_telemetry.h"
#include "modules/ranging/virtual_ranging.h"
#include "modules/sonar/sonar_array.h"
#include "modules/wall_detector/wall_detector.h"
#include "modules/core/abi.h"
#include "mcu_periph/sys_time.h"
#include "pprz_host_vehicle.h"

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define VEHICLES 2
static const uint16_t ac_ids[VEHICLES] = { 3, 7 };

/* ---- the telemetry stubs: what each message would carry ---- */
struct sent {
  unsigned vehicle;          ///< index of the vehicle that sent it
  uint32_t stamp;
  uint8_t sensor, detector_class, baseline_class;
  uint16_t peer;
  float measured, confidence;
};
static struct sent readings_sent[64], decisions_sent[64];
static int n_readings_sent, n_decisions_sent;

void range_recorder_telemetry_reading(uint32_t stamp_us, uint8_t sensor, uint16_t peer, float measured_m)
{
  assert_true(n_readings_sent < 64);
  readings_sent[n_readings_sent++] = (struct sent) {
    .vehicle = pprz_vehicle_index, .stamp = stamp_us, .sensor = sensor, .peer = peer, .measured = measured_m
  };
}

void range_recorder_telemetry_decision(uint32_t stamp_us, uint8_t sonar, uint8_t detector_class, float confidence,
                                       float measured_m, uint8_t baseline_class)
{
  assert_true(n_decisions_sent < 64);
  decisions_sent[n_decisions_sent++] = (struct sent) {
    .vehicle = pprz_vehicle_index, .stamp = stamp_us, .sensor = sonar, .detector_class = detector_class,
    .confidence = confidence, .measured = measured_m, .baseline_class = baseline_class
  };
}

/* ---- a folder of the test's own ---- */
static char dir[64];

static const char *in_dir(const char *name, unsigned ac_id)
{
  static char path[2][128];
  static int which;
  which ^= 1;
  snprintf(path[which], sizeof(path[which]), "%s/%s_%u.csv", dir, name, ac_id);
  return path[which];
}

/** The whole text of a file ("" when it cannot be read). */
static const char *file_text(const char *path)
{
  static char text[4096];
  text[0] = '\0';
  FILE *f = fopen(path, "r");
  if (f != NULL) {
    text[fread(text, 1, sizeof(text) - 1, f)] = '\0';
    fclose(f);
  }
  return text;
}

static long file_size(const char *path)
{
  struct stat st;
  return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

/** The files in the folder. */
static int files_in_dir(void)
{
  DIR *d = opendir(dir);
  assert_non_null(d);
  int n = 0;
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d)) {
    n += e->d_name[0] != '.';
  }
  closedir(d);
  return n;
}

static void start(bool with_folder)
{
  snprintf(dir, sizeof(dir), "/tmp/range_recorder_test_XXXXXX");
  assert_non_null(mkdtemp(dir));
  if (with_folder) {
    assert_int_equal(setenv("FINKEN_WORLD_OUT", dir, 1), 0);
  } else {
    assert_int_equal(unsetenv("FINKEN_WORLD_OUT"), 0);
  }
  n_readings_sent = n_decisions_sent = 0;
  sys_time_host_set(12.35);
  pprz_vehicles_setup(VEHICLES, ac_ids);
  for (unsigned v = 0; v < VEHICLES; v++) {
    pprz_vehicle_select(v);
    range_recorder_init();
  }
}

static int setup(void **state)
{
  (void)state;
  start(true);
  return 0;
}

static int setup_without_folder(void **state)
{
  (void)state;
  start(false);
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  for (unsigned v = 0; v < VEHICLES; v++) {
    pprz_vehicle_select(v);
    range_recorder_close();
  }
  pprz_vehicles_teardown();
  unsetenv("FINKEN_WORLD_OUT");
  DIR *d = opendir(dir);
  for (struct dirent *e = d != NULL ? readdir(d) : NULL; e != NULL; e = readdir(d)) {
    if (e->d_name[0] != '.') {
      char path[sizeof(dir) + sizeof(e->d_name) + 1];
      snprintf(path, sizeof(path), "%s/%s", dir, e->d_name);
      unlink(path);
    }
  }
  if (d != NULL) {
    closedir(d);
  }
  rmdir(dir);
  return 0;
}

static void close_all(void)
{
  for (unsigned v = 0; v < VEHICLES; v++) {
    pprz_vehicle_select(v);
    assert_int_equal(range_recorder_close(), 0);
  }
}

static void assert_sent_reading(int i, unsigned vehicle, uint32_t stamp, uint8_t sensor, uint16_t peer, float m)
{
  assert_true(i < n_readings_sent);
  const struct sent *s = &readings_sent[i];
  assert_int_equal(s->vehicle, vehicle);
  assert_int_equal(s->stamp, stamp);
  assert_int_equal(s->sensor, sensor);
  assert_int_equal(s->peer, peer);
  assert_close(s->measured, m, 0.0);
}

static void every_reading_is_a_row_of_its_copter_and_a_message(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.27f, 0.f, 0.f);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_RIGHT_ID, 0.2f, 0.f, (float)M_PI_2);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_BACK_ID, 3.0f, 0.f, (float)M_PI);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_LEFT_ID, 0.61234f, 0.f, (float)-M_PI_2);
  AbiSendMsgAGL(SONAR_ARRAY_DOWN_ID, 12340000u, 0.6f);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, 12355120u, 7, 1.44f);
  pprz_vehicle_select(1);
  sys_time_host_set(12.36);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_BACK_ID, 2.5f, 0.f, (float)M_PI);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, 12360000u, 3, 1.5f);
  assert_int_equal(VEHICLE_LOCAL(range_recorder)->readings.rows, 2);
  pprz_vehicle_select(0);
  assert_int_equal(VEHICLE_LOCAL(range_recorder)->readings.rows, 6);
  assert_int_equal(VEHICLE_LOCAL(range_recorder)->decisions.rows, 0);
  close_all();

  assert_string_equal(file_text(in_dir("record", 3)),
                      "t,vehicle,sensor,peer,measured\n"
                      "12.350000,3,sonar_front,,1.27\n"
                      "12.350000,3,sonar_right,,0.2\n"
                      "12.350000,3,sonar_back,,3\n"
                      "12.350000,3,sonar_left,,0.61234\n"
                      "12.340000,3,sonar_down,,0.6\n"
                      "12.355120,3,ranging,7,1.44\n");
  assert_string_equal(file_text(in_dir("record", 7)),
                      "t,vehicle,sensor,peer,measured\n"
                      "12.360000,7,sonar_back,,2.5\n"
                      "12.360000,7,ranging,3,1.5\n");
  assert_string_equal(file_text(in_dir("record_decisions", 3)),
                      "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n");
  assert_int_equal(files_in_dir(), 4);

  assert_int_equal(n_readings_sent, 8);
  assert_sent_reading(0, 0, 12350000u, 0, 65535, 1.27f);
  assert_sent_reading(1, 0, 12350000u, 1, 65535, 0.2f);
  assert_sent_reading(2, 0, 12350000u, 2, 65535, 3.0f);
  assert_sent_reading(3, 0, 12350000u, 3, 65535, 0.61234f);
  assert_sent_reading(4, 0, 12340000u, 4, 65535, 0.6f);
  assert_sent_reading(5, 0, 12355120u, 5, 7, 1.44f);
  assert_sent_reading(6, 1, 12360000u, 2, 65535, 2.5f);
  assert_sent_reading(7, 1, 12360000u, 5, 3, 1.5f);
  assert_int_equal(n_decisions_sent, 0);
}

static void decisions_are_rows_and_messages(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, 12350000u, 0, 0.f, 1, 0.98f, -1.f, 1.27f, 1);
  AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, 12400000u, 2, (float)M_PI, 2, 0.8f, 1.1f, 1.1f, 1);
  AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, 12450000u, 3, (float)-M_PI_2, 3, 1.0f, -1.f, 3.0f, 3);
  pprz_vehicle_select(1);
  AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, 12500000u, 1, (float)M_PI_2, 0, 0.6f, -1.f, 0.9f, 2);
  close_all();

  assert_string_equal(file_text(in_dir("record_decisions", 3)),
                      "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n"
                      "12.350000,3,sonar_front,1.27,wall,0.98,wall\n"
                      "12.400000,3,sonar_back,1.1,copter,0.8,wall\n"
                      "12.450000,3,sonar_left,3,none,1,none\n");
  assert_string_equal(file_text(in_dir("record_decisions", 7)),
                      "t,vehicle,sensor,measured,detector_class,confidence,baseline_class\n"
                      "12.500000,7,sonar_right,0.9,unknown,0.6,copter\n");
  assert_string_equal(file_text(in_dir("record", 3)), "t,vehicle,sensor,peer,measured\n");

  assert_int_equal(n_decisions_sent, 4);
  const struct sent *s = &decisions_sent[1];
  assert_int_equal(s->vehicle, 0);
  assert_int_equal(s->stamp, 12400000u);
  assert_int_equal(s->sensor, 2);
  assert_int_equal(s->detector_class, 2);
  assert_close(s->confidence, 0.8f, 0.0);
  assert_close(s->measured, 1.1f, 0.0);   /* the repulsion distance: always the reading */
  assert_int_equal(s->baseline_class, 1);
  s = &decisions_sent[3];
  assert_int_equal(s->vehicle, 1);
  assert_int_equal(s->sensor, 1);
  assert_int_equal(s->detector_class, 0);
  assert_int_equal(s->baseline_class, 2);
  assert_int_equal(n_readings_sent, 0);
}

static void other_senders_are_not_sonar_readings(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  AbiSendMsgOBSTACLE_DETECTION(1, 1.0f, 0.f, 0.f);                         /* another obstacle sensor */
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_DOWN_ID, 0.6f, (float)-M_PI_2, 0.f);
  AbiSendMsgAGL(1, 12350000u, 0.7f);                                      /* another height sensor */
  close_all();
  assert_string_equal(file_text(in_dir("record", 3)), "t,vehicle,sensor,peer,measured\n");
  assert_int_equal(n_readings_sent, 0);
}

static void stamps_past_32_bits_keep_counting(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, 4294967000u, 7, 1.0f);
  AbiSendMsgAGL(SONAR_ARRAY_DOWN_ID, 200u, 0.6f);   /* 496 us later: the 32-bit clock wrapped */
  close_all();
  assert_string_equal(file_text(in_dir("record", 3)),
                      "t,vehicle,sensor,peer,measured\n"
                      "4294.967000,3,ranging,7,1\n"
                      "4294.967496,3,sonar_down,,0.6\n");
  assert_sent_reading(1, 0, 200u, 4, 65535, 0.6f);   /* the message carries the stamp as it came */
}

static void rows_reach_the_disk_at_the_flush_period(void **state)
{
  (void)state;
  pprz_vehicle_select(0);
  char path[128];
  snprintf(path, sizeof(path), "%s", in_dir("record", 3));
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.27f, 0.f, 0.f);
  range_recorder_periodic();
  assert_int_equal(file_size(path), 0);   /* in the buffer */
  sys_time_host_set(12.35 + 0.99);
  range_recorder_periodic();
  assert_int_equal(file_size(path), 0);
  sys_time_host_set(12.35 + 1.0);
  range_recorder_periodic();
  const long flushed = (long)strlen("t,vehicle,sensor,peer,measured\n12.350000,3,sonar_front,,1.27\n");
  assert_int_equal(file_size(path), flushed);
  assert_int_equal(file_size(in_dir("record_decisions", 3)), strlen(RANGE_RECORDER_DECISIONS_HEADER));
  /* the other copter's files are its own: flushed when its own periodic task runs */
  pprz_vehicle_select(1);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.5f, 0.f, 0.f);
  assert_int_equal(file_size(in_dir("record", 7)), 0);
  range_recorder_periodic();
  assert_true(file_size(in_dir("record", 7)) > 0);
  pprz_vehicle_select(0);
  AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.3f, 0.f, 0.f);
  range_recorder_periodic();
  assert_int_equal(file_size(path), flushed);   /* the next flush a period after the last */
}

static void without_a_folder_our_host_writes_no_file(void **state)
{
  (void)state;
  for (unsigned v = 0; v < VEHICLES; v++) {
    pprz_vehicle_select(v);
    assert_null(VEHICLE_LOCAL(range_recorder)->readings.f);
    assert_null(VEHICLE_LOCAL(range_recorder)->decisions.f);
  }
  pprz_vehicle_select(1);
  AbiSendMsgRANGING_DISTANCE(VIRTUAL_RANGING_ID, 12350000u, 3, 1.2f);
  AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, 12350000u, 0, 0.f, 1, 0.98f, -1.f, 1.27f, 1);
  sys_time_host_set(20.0);
  range_recorder_periodic();
  assert_int_equal(n_readings_sent, 1);    /* telemetry all the same */
  assert_int_equal(n_decisions_sent, 1);
  assert_sent_reading(0, 1, 12350000u, 5, 3, 1.2f);
  assert_int_equal(files_in_dir(), 0);
}

/** Run `what` with stderr into a file; returns that file's text. */
static const char *stderr_of(void (*what)(void))
{
  char path[128];
  snprintf(path, sizeof(path), "%s/stderr.txt", dir);
  fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  FILE *capture = fopen(path, "w");
  assert_non_null(capture);
  dup2(fileno(capture), STDERR_FILENO);
  what();
  fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  fclose(capture);
  const char *text = file_text(path);
  unlink(path);
  return text;
}

static int lines_with(const char *text, const char *what)
{
  int n = 0;
  for (const char *p = strstr(text, what); p != NULL; p = strstr(p + 1, what)) {
    n++;
  }
  return n;
}

static int open_result;

static void open_a_full_device_and_a_missing_folder(void)
{
  char missing[128];
  snprintf(missing, sizeof(missing), "%s/no/such/folder.csv", dir);
  open_result = range_recorder_open("/dev/full", missing);
}

static void record_and_flush_a_while(void)
{
  for (int i = 0; i < 50; i++) {
    sys_time_host_set(13.0 + 0.1 * i);
    AbiSendMsgOBSTACLE_DETECTION(SONAR_ARRAY_FRONT_ID, 1.0f + 0.01f * i, 0.f, 0.f);
    AbiSendMsgWALL_DETECTION(WALL_DETECTOR_SENDER_ID, get_sys_time_usec(), 0, 0.f, 1, 0.9f, -1.f, 1.0f, 1);
    range_recorder_periodic();
  }
  open_result = range_recorder_close();
}

static void a_file_that_cannot_be_written_is_reported_once(void **state)
{
  (void)state;
  if (access("/dev/full", W_OK) != 0) {
    skip();   /* no /dev/full on this system */
  }
  pprz_vehicle_select(0);
  const char *opened = stderr_of(open_a_full_device_and_a_missing_folder);
  assert_int_equal(open_result, -1);
  assert_int_equal(lines_with(opened, "range_recorder:"), 1);
  assert_int_equal(lines_with(opened, "no/such/folder.csv"), 1);
  assert_non_null(VEHICLE_LOCAL(range_recorder)->readings.f);   /* /dev/full takes the header into the buffer */
  assert_null(VEHICLE_LOCAL(range_recorder)->decisions.f);

  const char *written = stderr_of(record_and_flush_a_while);
  assert_int_equal(lines_with(written, "range_recorder:"), 1);   /* the first flush fails, and only it is said */
  assert_int_equal(lines_with(written, "/dev/full"), 1);
  assert_int_equal(lines_with(written, strerror(ENOSPC)), 1);
  assert_null(VEHICLE_LOCAL(range_recorder)->readings.f);
  assert_int_equal(open_result, 0);                               /* nothing left to close */
  assert_int_equal(n_readings_sent, 50);                          /* the telemetry went on */
  assert_int_equal(n_decisions_sent, 50);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(every_reading_is_a_row_of_its_copter_and_a_message, setup, teardown),
    cmocka_unit_test_setup_teardown(decisions_are_rows_and_messages, setup, teardown),
    cmocka_unit_test_setup_teardown(other_senders_are_not_sonar_readings, setup, teardown),
    cmocka_unit_test_setup_teardown(stamps_past_32_bits_keep_counting, setup, teardown),
    cmocka_unit_test_setup_teardown(rows_reach_the_disk_at_the_flush_period, setup, teardown),
    cmocka_unit_test_setup_teardown(without_a_folder_our_host_writes_no_file, setup_without_folder, teardown),
    cmocka_unit_test_setup_teardown(a_file_that_cannot_be_written_is_reported_once, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
