/*
 * libFuzzer harness: what a copter makes of the frames on the ranging bus, sw/airborne/modules/ranging/
 * ranging_can_rx.c and ranging_can_frame.c, with any layout, clock and frame (the driver and the replays
 * validate less than this: any length up to 64 bytes, any id and flags).
 *
 * Input (binary; short inputs read as zeros): layout and configuration (id_base, log2 of nb_nodes, range_max_mm,
 * self_id, stale_us), then operations: a frame (clock step, id, length, FD flag and flags, data), a peer
 * query or a stale check. Properties: every frame is counted once by what it was; a ranging frame the decoder
 * accepts passes the kernel filter; a peer is fresh only within stale_us of its stamp.
 */
#include "fuzz_common.h"

#include "modules/ranging/ranging_can_rx.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

static uint32_t counted(const struct ranging_can_rx_stats *s)
{
  uint32_t n = s->readings + s->not_ours + s->duplicates + s->error_frames;
  for (int v = 0; v < RANGING_CAN_FRAME_NB_VERDICTS; v++) {
    n += s->invalid[v];
  }
  return n;
}

static void frame(struct ranging_can_rx *rx, struct fuzz_bytes *in, uint32_t now_us)
{
  struct ranging_can_raw f;
  memset(&f, 0, sizeof(f));
  f.can_id = fuzz_u32(in);
  const uint8_t kind = fuzz_u8(in);
  f.fd = kind & 1U;
  f.fd_flags = (uint8_t)(kind >> 1);
  f.len = (uint8_t)(fuzz_u8(in) % (RANGING_CAN_MAX_DLEN + 1));
  for (unsigned i = 0; i < f.len; i++) {
    f.data[i] = fuzz_u8(in);
  }
  struct ranging_can_reading reading;
  const enum ranging_can_rx_kind got = ranging_can_rx_frame(rx, &f, now_us, &reading);
  fuzz_require(counted(&rx->stats) == rx->stats.frames);
  struct ranging_can_msg msg;
  if (ranging_can_unpack(&rx->cfg.layout, &f, &msg) == RANGING_CAN_FRAME_OK) {
    uint32_t id, mask;
    ranging_can_layout_filter(&rx->cfg.layout, &id, &mask);
    fuzz_require((f.can_id & mask) == (id & mask));
    fuzz_require(got != RANGING_CAN_RX_INVALID && got != RANGING_CAN_RX_ERROR_FRAME);
  }
  if (got == RANGING_CAN_RX_READING) {
    fuzz_require(reading.other_id < rx->cfg.layout.nb_nodes && reading.other_id != rx->cfg.self_id &&
                 reading.stamp_us == now_us);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  struct fuzz_bytes in = { data, size };
  struct ranging_can_rx_config cfg = { .layout = { .id_base = fuzz_u16(&in) } };
  cfg.layout.nb_nodes = (uint16_t)(1U << (fuzz_u8(&in) % 10));   /* 512: one too many */
  cfg.layout.range_max_mm = fuzz_u16(&in);
  cfg.self_id = fuzz_u8(&in);
  cfg.stale_us = fuzz_u32(&in);
  const char *why = NULL;
  if (ranging_can_rx_config_check(&cfg, &why) != 0) {
    fuzz_require(why != NULL);
    return 0;
  }
  static struct ranging_can_rx rx;
  ranging_can_rx_init(&rx, &cfg);
  uint32_t now_us = fuzz_u32(&in);
  while (fuzz_more(&in)) {
    const uint8_t op = fuzz_u8(&in);
    now_us += (uint32_t)fuzz_u16(&in) << (op >> 4);   /* steps up to ~2^31 us: the clock wraps */
    switch (op & 3U) {
      case 0:
      case 1:
        frame(&rx, &in, now_us);
        break;
      case 2: {
        struct ranging_can_reading reading;
        const uint8_t other = fuzz_u8(&in);
        const int fresh = ranging_can_rx_peer(&rx, other, now_us, &reading);
        fuzz_require(fresh >= -1 && fresh <= 1);
        if (fresh == 1) {
          fuzz_require(reading.other_id == other && (int32_t)(now_us - reading.stamp_us) <= (int32_t)cfg.stale_us);
        }
        break;
      }
      default:
        fuzz_require(ranging_can_rx_check_stale(&rx, now_us) <= cfg.layout.nb_nodes);
        break;
    }
  }
  fuzz_require(ranging_can_bus_state_str(rx.bus_state) != NULL);
  return 0;
}
