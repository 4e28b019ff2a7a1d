/*
 * libFuzzer harness: the messages the ranging driver reads off its CAN socket, through its seam
 * (sw/airborne/arch/linux/modules/ranging/ranging_can.c and ranging_socketcan.c on a SOCK_SEQPACKET socketpair):
 * struct can_frame / canfd_frame messages with any content, and messages of any other size.
 *
 * Input (binary; short inputs read as zeros): this copter's node id and frames per event, then operations: a
 * message (a classical frame, an FD frame, or 0 to 79 bytes; its bytes follow) or an event call (clock step).
 * Properties: every message is counted once (a frame or a malformed message), an event call returns the number of
 * distances it handed to the callback, and each is about another copter.
 */
#include "fuzz_common.h"

#include <linux/can.h>
#include <sys/socket.h>

#include "modules/ranging/ranging_can.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

struct seen {
  uint8_t self_id;
  unsigned readings;
};

static void on_reading(void *user, const struct ranging_can_reading *reading)
{
  struct seen *seen = user;
  fuzz_require(reading->other_id != seen->self_id && reading->other_id < RANGING_CAN_NB_NODES);
  seen->readings++;
}

/** One message of the size op chooses, its bytes from the input; whether it was sent. */
static bool send_message(int fd, uint8_t op, struct fuzz_bytes *in)
{
  uint8_t msg[CANFD_MTU + 8];
  const size_t size = op & 4U ? (op & 8U ? CANFD_MTU : CAN_MTU) : (size_t)(op >> 4) * 5U;
  for (size_t i = 0; i < size; i++) {
    msg[i] = fuzz_u8(in);
  }
  return send(fd, msg, size, MSG_DONTWAIT) == (ssize_t)size;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  struct fuzz_bytes in = { data, size };
  struct seen seen = { .self_id = (uint8_t)(fuzz_u8(&in) % RANGING_CAN_NB_NODES) };
  const struct ranging_can_config cfg = {
    .rx = { .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = seen.self_id, .stale_us = RANGING_CAN_STALE_MS * 1000U },
    .max_frames_per_event = 1U + fuzz_u8(&in) % 16U,
  };
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) != 0) {
    abort();
  }
  char err[256];
  struct ranging_can *rc = ranging_can_open_fd(sv[0], &cfg, err, sizeof(err));
  fuzz_require(rc != NULL);
  uint32_t now_us = 0, sent = 0;
  while (fuzz_more(&in)) {
    const uint8_t op = fuzz_u8(&in);
    if (op & 3U) {
      sent += send_message(sv[1], op, &in);
      continue;
    }
    now_us += (uint32_t)fuzz_u16(&in) << (op >> 4);
    const unsigned before = seen.readings;
    const int got = ranging_can_event(rc, now_us, on_reading, &seen);
    /* -1: a read failed (a 0-byte message reads as a closed socket), after the distances read before it */
    fuzz_require(got == -1 || seen.readings - before == (unsigned)got);
  }
  /* drain: unless a read failed (a 0-byte message reads as a closed socket), every message is counted once */
  struct ranging_can_stats st;
  uint32_t counted = 0, previous = UINT32_MAX;
  for (;;) {
    ranging_can_stats(rc, &st);
    counted = st.rx.frames + st.malformed;
    if (ranging_can_fd(rc) < 0 || counted >= sent || counted == previous) {
      break;
    }
    previous = counted;
    fuzz_require(ranging_can_event(rc, now_us, on_reading, &seen) >= -1);
  }
  fuzz_require(counted <= sent && (ranging_can_fd(rc) < 0 || counted == sent));
  ranging_can_close(rc);
  close(sv[1]);
  return 0;
}
