/* Ranging CAN driver (arch/linux/modules/ranging/ranging_can.h) on its seam, a socketpair standing in for
 * the CAN socket: normal and bad frames, a flood of 100,000 frames, error frames, staleness, a vanished bus,
 * a candump log replayed through the driver; and opening a missing interface or a kernel without PF_CAN. */
#define _GNU_SOURCE
#include "test_helpers.h"
#include "modules/ranging/ranging_can.h"
#include "modules/ranging/ranging_can_replay.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#ifndef TEST_DATA_DIR
#define TEST_DATA_DIR "tests/data/can"
#endif

#define SELF 5
#define STALE_US 500000
#define MAX_PER_EVENT 256

static const struct ranging_can_config cfg = {
  .ifname = "can0",
  .rx = { .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = SELF, .stale_us = STALE_US },
  .max_frames_per_event = MAX_PER_EVENT,
};

/** What the callback saw. */
struct seen {
  unsigned n;
  struct ranging_can_reading last[RANGING_CAN_NB_NODES_MAX];  ///< newest per other copter
  struct ranging_can_reading all[64];                         ///< the first 64, in order
};

static void on_reading(void *user, const struct ranging_can_reading *r)
{
  struct seen *s = user;
  if (s->n < 64) {
    s->all[s->n] = *r;
  }
  s->last[r->other_id] = *r;
  s->n++;
}

struct fixture {
  int bus;  ///< our end of the bus (the driver has the other)
  struct ranging_can *rc;
  struct seen seen;
};

static int setup(void **state)
{
  static struct fixture f;
  memset(&f, 0, sizeof(f));
  int sv[2];
  assert_int_equal(socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0, sv), 0);
  char err[256];
  f.rc = ranging_can_open_fd(sv[0], &cfg, err, sizeof(err));
  assert_non_null(f.rc);
  f.bus = sv[1];
  *state = &f;
  return 0;
}

static int teardown(void **state)
{
  struct fixture *f = *state;
  ranging_can_close(f->rc);
  if (f->bus >= 0) {
    close(f->bus);
  }
  return 0;
}

static void put(struct fixture *f, const struct ranging_can_raw *raw)
{
  struct canfd_frame out;
  memset(&out, 0, sizeof(out));
  out.can_id = raw->can_id;
  out.len = raw->len;
  memcpy(out.data, raw->data, raw->len);
  const size_t size = raw->fd ? CANFD_MTU : CAN_MTU;
  assert_int_equal(write(f->bus, &out, size), (ssize_t)size);
}

static struct ranging_can_raw ranging(uint8_t node, uint8_t peer, uint16_t range_mm, uint16_t seq)
{
  const struct ranging_can_layout layout = RANGING_CAN_LAYOUT_DEFAULT;
  const struct ranging_can_msg m = { .node_id = node, .peer_id = peer, .range_mm = range_mm, .quality_pct = 75, .seq = seq };
  struct ranging_can_raw raw;
  assert_int_equal(ranging_can_pack(&layout, &m, &raw), RANGING_CAN_FRAME_OK);
  return raw;
}

static void normal_frames_become_readings(void **state)
{
  struct fixture *f = *state;
  struct ranging_can_raw a = ranging(SELF, 9, 1234, 1);
  struct ranging_can_raw b = ranging(12, SELF, 2345, 77);
  put(f, &a);
  put(f, &b);
  assert_int_equal(ranging_can_event(f->rc, 5000000, on_reading, &f->seen), 2);
  assert_int_equal(f->seen.n, 2);
  assert_int_equal(f->seen.all[0].other_id, 9);
  assert_close(f->seen.all[0].range_m, 1.234, 1e-6);
  assert_int_equal(f->seen.all[1].other_id, 12);
  assert_int_equal(f->seen.all[1].seq, 77);
  assert_true(f->seen.all[0].stamp_us <= 5000000);  /* the kernel's reception time, on our clock */
  struct ranging_can_reading p;
  assert_int_equal(ranging_can_peer(f->rc, 12, 5000000, &p), 1);
  assert_close(p.range_m, 2.345, 1e-6);
  assert_int_equal(ranging_can_event(f->rc, 5000001, on_reading, &f->seen), 0);  /* nothing more */
}

static void bad_frames_are_counted_not_read(void **state)
{
  struct fixture *f = *state;
  struct ranging_can_raw r = ranging(SELF, 9, 1000, 1);
  r.len = 5;
  put(f, &r);                                   /* short DLC */
  r = ranging(SELF, 9, 1000, 2);
  r.can_id = 0x123;
  put(f, &r);                                   /* a foreign id */
  r = ranging(SELF, 9, 1000, 3);
  r.data[1] = 0xFF;
  r.data[2] = 0xFF;
  put(f, &r);                                   /* 65535 mm: out of range */
  r = ranging(SELF, 9, 1000, 4);
  r.data[0] = 200;
  put(f, &r);                                   /* a peer that cannot exist */
  r = ranging(SELF, 9, 1000, 5);
  r.fd = true;
  put(f, &r);                                   /* a CAN FD frame */
  const char truncated[7] = { 0x05, 0x03 };
  assert_int_equal(write(f->bus, truncated, sizeof(truncated)), sizeof(truncated));
  const struct can_frame too_long = { .can_id = 0x305, .len = CAN_MAX_DLEN + 1 };
  assert_int_equal(write(f->bus, &too_long, CAN_MTU), CAN_MTU);  /* a classical frame carries 8 bytes at most */
  assert_int_equal(ranging_can_event(f->rc, 1000, on_reading, &f->seen), 0);
  struct ranging_can_stats st;
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_DLC], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_FOREIGN_ID], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_RANGE], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_PEER], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_NOT_DATA], 1);
  assert_int_equal(st.malformed, 2);
  assert_int_equal(st.rx.readings, 0);
  struct ranging_can_reading p;
  assert_int_equal(ranging_can_peer(f->rc, 9, 1000, &p), -1);  /* nothing bad reached the table */
}

/** Flood: 100,000 frames, every 10th of another device, the rest from our unit to 20 peers in turn. */
#define FLOOD_FRAMES 100000
#define FLOOD_PEERS 20

static void a_flood_keeps_the_newest_state_in_bounded_memory(void **state)
{
  struct fixture *f = *state;
  uint16_t last_range[RANGING_CAN_NB_NODES_MAX] = { 0 };
  bool used[RANGING_CAN_NB_NODES_MAX] = { false };
  unsigned sent = 0, expected_readings = 0, events = 0;
  uint16_t seq = 0;
  uint32_t now_us = 1000;
  while (sent < FLOOD_FRAMES) {
    /* fill the socket until it is full, then let the driver read */
    for (;;) {
      if (sent == FLOOD_FRAMES) {
        break;
      }
      struct ranging_can_raw raw;
      const bool foreign = sent % 10 == 9;
      uint8_t peer = 0;
      if (foreign) {
        raw = (struct ranging_can_raw) { .can_id = 0x123, .len = 8 };
      } else {
        peer = (uint8_t)(1 + (sent % FLOOD_PEERS));
        peer = peer >= SELF ? peer + 1 : peer;
        raw = ranging(SELF, peer, (uint16_t)(sent % 60000), seq);
      }
      struct can_frame out = { .can_id = raw.can_id, .len = raw.len };
      memcpy(out.data, raw.data, 8);
      if (write(f->bus, &out, CAN_MTU) < 0) {
        assert_true(errno == EAGAIN || errno == EWOULDBLOCK);
        break;
      }
      if (!foreign) {
        last_range[peer] = (uint16_t)(sent % 60000);
        used[peer] = true;
        seq++;
        expected_readings++;
      }
      sent++;
    }
    int n;
    do {
      now_us += 100;
      n = ranging_can_event(f->rc, now_us, on_reading, &f->seen);
      assert_true(n >= 0 && n <= MAX_PER_EVENT);
      events++;
    } while (n > 0);
  }
  assert_int_equal(f->seen.n, expected_readings);
  for (uint8_t peer = 0; peer < RANGING_CAN_NB_NODES; peer++) {
    struct ranging_can_reading p;
    const int fresh = ranging_can_peer(f->rc, peer, now_us, &p);
    if (!used[peer]) {
      assert_int_equal(fresh, -1);
      continue;
    }
    assert_int_equal(fresh, 1);
    assert_int_equal((int)lround(p.range_m * 1000.0), last_range[peer]);  /* the newest one */
  }
  struct ranging_can_stats st;
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.rx.frames, FLOOD_FRAMES);
  assert_int_equal(st.rx.readings, expected_readings);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_FOREIGN_ID], FLOOD_FRAMES / 10);
  assert_int_equal(st.rx.seq_gaps, 0);
  assert_int_equal(st.rx.duplicates, 0);
  assert_int_equal(st.kernel_drops, 0);
  /* bounded memory: the driver's whole state is one fixed-size allocation (ASan checks for leaks) */
  assert_true(sizeof(struct ranging_can_rx) < 16384);
  assert_true(events >= FLOOD_FRAMES / MAX_PER_EVENT);
}

static struct ranging_can_raw error_frame(uint32_t classes, uint8_t crtl)
{
  struct ranging_can_raw e = { .can_id = CAN_ERR_FLAG | classes, .len = CAN_ERR_DLC };
  e.data[1] = crtl;
  return e;
}

static void bus_off_and_restart_are_reported(void **state)
{
  struct fixture *f = *state;
  struct ranging_can_stats st;
  struct ranging_can_raw e = error_frame(RANGING_CAN_ERR_CRTL, RANGING_CAN_ERR_CRTL_TX_PASSIVE);
  put(f, &e);
  e = error_frame(RANGING_CAN_ERR_BUSOFF, 0);
  put(f, &e);
  assert_int_equal(ranging_can_event(f->rc, 1000, on_reading, &f->seen), 0);
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.bus_state, RANGING_CAN_BUS_OFF);
  assert_int_equal(st.rx.bus_off, 1);
  assert_int_equal(st.rx.error_frames, 2);
  e = error_frame(RANGING_CAN_ERR_RESTARTED, 0);
  put(f, &e);
  struct ranging_can_raw r = ranging(SELF, 9, 1500, 1);
  put(f, &r);
  assert_int_equal(ranging_can_event(f->rc, 2000, on_reading, &f->seen), 1);
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.bus_state, RANGING_CAN_BUS_ACTIVE);
  assert_int_equal(st.rx.restarts, 1);
}

static void a_stale_peer_is_never_reported_fresh(void **state)
{
  struct fixture *f = *state;
  struct ranging_can_raw r = ranging(SELF, 9, 1500, 1);
  put(f, &r);
  assert_int_equal(ranging_can_event(f->rc, 1000000, on_reading, &f->seen), 1);
  const uint32_t stamp = f->seen.all[0].stamp_us;
  struct ranging_can_reading p;
  assert_int_equal(ranging_can_peer(f->rc, 9, stamp + STALE_US, &p), 1);
  assert_int_equal(ranging_can_peer(f->rc, 9, stamp + STALE_US + 1, &p), 0);
  assert_int_equal(ranging_can_event(f->rc, stamp + STALE_US + 1, on_reading, &f->seen), 0);
  struct ranging_can_stats st;
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.stale_peers, 1);
  assert_int_equal(st.rx.stale_events, 1);
}

static void a_vanished_bus_is_an_error_not_a_crash(void **state)
{
  struct fixture *f = *state;
  close(f->bus);
  f->bus = -1;
  errno = 0;
  assert_int_equal(ranging_can_event(f->rc, 1000, on_reading, &f->seen), -1);
  assert_int_equal(errno, EPIPE);
  assert_non_null(strstr(ranging_can_last_error(f->rc), strerror(EPIPE)));
  assert_int_equal(ranging_can_fd(f->rc), -1);
  errno = 0;
  assert_int_equal(ranging_can_event(f->rc, 5000000, on_reading, &f->seen), -1);  /* nothing to reopen */
  assert_int_equal(errno, ENOTCONN);
  struct ranging_can_stats st;
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.read_errors, 1);
}

/** Replay the whole log through the driver; returns the number of frames written. */
static uint32_t replay(struct fixture *f, const char *log, uint32_t now_us)
{
  char err[512] = "";
  struct ranging_can_replay *r = ranging_can_replay_open(log, "can0", f->bus, err, sizeof(err));
  assert_non_null(r);
  int rc;
  do {
    rc = ranging_can_replay_until(r, UINT64_MAX, err, sizeof(err));
    if (rc < 0) {
      print_error("%s\n", err);
    }
    assert_true(rc >= 0);
    while (ranging_can_event(f->rc, now_us, on_reading, &f->seen) > 0) {
    }
  } while (rc == 1);
  const uint32_t count = ranging_can_replay_count(r);
  ranging_can_replay_close(r);
  return count;
}

static void a_candump_log_replays_through_the_driver(void **state)
{
  struct fixture *f = *state;
  assert_int_equal(replay(f, TEST_DATA_DIR "/ranging_session.log", 1000000), 37);  /* the can1 line is not ours */
  /* every valid frame about copter 5 in the expected file, in order */
  FILE *expected = fopen(TEST_DATA_DIR "/ranging_session.expected.csv", "r");
  assert_non_null(expected);
  char line[256];
  assert_non_null(fgets(line, sizeof(line), expected));  /* header */
  unsigned ours = 0, others = 0;
  unsigned long long time_us;
  unsigned node, peer, range_mm, quality, seq;
  while (fscanf(expected, "%llu,%u,%u,%u,%u,%u", &time_us, &node, &peer, &range_mm, &quality, &seq) == 6) {
    if (node != SELF && peer != SELF) {
      others++;
      continue;
    }
    assert_true(ours < f->seen.n);
    const struct ranging_can_reading *r = &f->seen.all[ours++];
    assert_int_equal(r->node_id, node);
    assert_int_equal(r->other_id, node == SELF ? peer : node);
    assert_int_equal((int)lround(r->range_m * 1000.0), range_mm);
    assert_int_equal(r->quality_pct, quality);
    assert_int_equal(r->seq, seq);
  }
  fclose(expected);
  assert_int_equal(f->seen.n, ours);
  struct ranging_can_stats st;
  ranging_can_stats(f->rc, &st);
  assert_int_equal(st.rx.not_ours, others);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_DLC], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_FOREIGN_ID], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_RANGE], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_BAD_QUALITY], 1);
  assert_int_equal(st.rx.invalid[RANGING_CAN_FRAME_NOT_DATA], 3);  /* CAN FD, remote, extended */
  assert_int_equal(st.rx.duplicates, 1);
  assert_int_equal(st.rx.seq_gaps, 1);
  assert_int_equal(st.rx.frames_lost, 3);
  assert_int_equal(st.rx.node_restarts, 0);  /* node 12 wraps 65535 -> 0 in order */
  assert_int_equal(st.rx.error_frames, 3);
  assert_int_equal(st.rx.bus_off, 1);
  assert_int_equal(st.rx.restarts, 1);
  assert_int_equal(st.bus_state, RANGING_CAN_BUS_ACTIVE);
}

static void a_malformed_log_names_file_and_line(void **state)
{
  struct fixture *f = *state;
  char err[512] = "";
  struct ranging_can_replay *r = ranging_can_replay_open(TEST_DATA_DIR "/malformed.log", NULL, f->bus, err,
                                 sizeof(err));
  assert_non_null(r);
  assert_int_equal(ranging_can_replay_until(r, UINT64_MAX, err, sizeof(err)), -1);
  assert_non_null(strstr(err, "malformed.log:4: data: expected pairs of hex digits"));
  assert_int_equal(ranging_can_replay_count(r), 3);  /* the short frame of line 3 is a frame: the driver rejects it */
  ranging_can_replay_close(r);
  assert_null(ranging_can_replay_open(TEST_DATA_DIR "/no-such.log", NULL, f->bus, err, sizeof(err)));
  assert_non_null(strstr(err, "no-such.log"));
  assert_non_null(strstr(err, strerror(ENOENT)));
}

static void a_missing_interface_gives_one_clear_message(void **state)
{
  (void)state;
  struct ranging_can_config c = cfg;
  c.ifname = "nosuchcan7";
  char err[256] = "";
  errno = 0;
  assert_null(ranging_can_open(&c, err, sizeof(err)));
  assert_int_equal(errno, ENODEV);
  assert_non_null(strstr(err, "CAN interface 'nosuchcan7'"));
  assert_non_null(strstr(err, strerror(ENODEV)));
  assert_null(strchr(err, '\n'));
}

static void a_kernel_without_pf_can_gives_one_clear_message(void **state)
{
  (void)state;
  const int probe = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (probe >= 0) {
    close(probe);
    skip();  /* this kernel has SocketCAN */
  }
  const int no_can = errno;
  struct ranging_can_config c = cfg;
  c.ifname = "lo";  /* exists everywhere: the failure is the socket, not the name */
  char err[256] = "";
  errno = 0;
  assert_null(ranging_can_open(&c, err, sizeof(err)));
  assert_int_equal(errno, no_can);
  assert_non_null(strstr(err, "CAN interface 'lo'"));
  assert_non_null(strstr(err, strerror(no_can)));
  assert_non_null(strstr(err, "CAN_RAW"));
  assert_null(strchr(err, '\n'));
}

static void a_bad_configuration_is_named(void **state)
{
  (void)state;
  struct ranging_can_config c = cfg;
  c.rx.self_id = 64;
  char err[256] = "";
  errno = 0;
  assert_null(ranging_can_open(&c, err, sizeof(err)));
  assert_int_equal(errno, EINVAL);
  assert_non_null(strstr(err, "self_id"));
  c = cfg;
  c.max_frames_per_event = 0;
  assert_null(ranging_can_open_fd(0, &c, err, sizeof(err)));
  assert_non_null(strstr(err, "max_frames_per_event"));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(normal_frames_become_readings, setup, teardown),
    cmocka_unit_test_setup_teardown(bad_frames_are_counted_not_read, setup, teardown),
    cmocka_unit_test_setup_teardown(a_flood_keeps_the_newest_state_in_bounded_memory, setup, teardown),
    cmocka_unit_test_setup_teardown(bus_off_and_restart_are_reported, setup, teardown),
    cmocka_unit_test_setup_teardown(a_stale_peer_is_never_reported_fresh, setup, teardown),
    cmocka_unit_test_setup_teardown(a_vanished_bus_is_an_error_not_a_crash, setup, teardown),
    cmocka_unit_test_setup_teardown(a_candump_log_replays_through_the_driver, setup, teardown),
    cmocka_unit_test_setup_teardown(a_malformed_log_names_file_and_line, setup, teardown),
    cmocka_unit_test(a_missing_interface_gives_one_clear_message),
    cmocka_unit_test(a_kernel_without_pf_can_gives_one_clear_message),
    cmocka_unit_test(a_bad_configuration_is_named),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
