/*
 * libFuzzer harness: candump logs replayed into the ranging driver, sw/airborne/arch/linux/modules/ranging/
 * ranging_can_replay.c (lines of a file, written as frames to a SOCK_SEQPACKET socketpair) read by ranging_can.c.
 * The replay is asked for the frames up to time 0, then for all; the driver reads whenever the socket is full
 * (the replay pauses) and at the end.
 * Properties: the replay ends (or stops on a malformed line with file:line), and the driver reads every frame the
 * replay wrote, as a frame.
 */
#include "fuzz_common.h"

#include <sys/socket.h>

#include "modules/ranging/ranging_can.h"
#include "modules/ranging/ranging_can_replay.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

/** Read until the driver has taken `written` frames; false if it stopped taking any. */
static bool drain(struct ranging_can *rc, uint32_t written)
{
  struct ranging_can_stats st;
  uint32_t previous = UINT32_MAX;
  for (;;) {
    ranging_can_stats(rc, &st);
    fuzz_require(st.malformed == 0 && st.read_errors == 0 && st.rx.frames <= written);
    if (st.rx.frames == written) {
      return true;
    }
    if (st.rx.frames == previous) {
      return false;
    }
    previous = st.rx.frames;
    fuzz_require(ranging_can_event(rc, 0, NULL, NULL) >= 0);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, sv) != 0) {
    abort();
  }
  const struct ranging_can_config cfg = {
    .rx = { .layout = RANGING_CAN_LAYOUT_DEFAULT, .self_id = 5, .stale_us = RANGING_CAN_STALE_MS * 1000U },
    .max_frames_per_event = RANGING_CAN_MAX_FRAMES_PER_EVENT,
  };
  char err[512];
  struct ranging_can *rc = ranging_can_open_fd(sv[0], &cfg, err, sizeof(err));
  struct ranging_can_replay *r = ranging_can_replay_open(fuzz_file(data, size), size % 2 ? "can0" : NULL, sv[1],
                                                         err, sizeof(err));
  fuzz_require(rc != NULL && r != NULL);
  /* the frames logged at time 0 (usually none: the first frame waits), then all */
  err[0] = '\0';
  int rc_replay = ranging_can_replay_until(r, 0, err, sizeof(err));
  fuzz_require(drain(rc, ranging_can_replay_count(r)));
  while (rc_replay == 1) {
    rc_replay = ranging_can_replay_until(r, UINT64_MAX, err, sizeof(err));
    fuzz_require(drain(rc, ranging_can_replay_count(r)));
  }
  fuzz_require(rc_replay == 0 || (rc_replay == -1 && strchr(err, ':') != NULL));
  ranging_can_replay_close(r);
  ranging_can_close(rc);
  close(sv[1]);
  return 0;
}
