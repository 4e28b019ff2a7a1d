/*
 * libFuzzer harness: candump logs given to the NPS host (--ranging-replay), sim/nps_host_ranging_replay.c: lines
 * read with their limits (length, NUL bytes, time order, the bus of the first frame), each frame decoded by every
 * copter (ranging_can_rx.c) and the distances about it handed to its virtual_ranging module (here a stand-in that
 * checks them), in steps of growing log time. Properties: a distance goes to the copter it is about, from another
 * copter, finite and within the frame layout's range.
 */
#include "fuzz_common.h"

#include <math.h>

#include "modules/ranging/ranging_can_frame.h"
#include "modules/ranging/virtual_ranging.h"
#include "nps_host_ranging_replay.h"
#include "pprz_host_vehicle.h"

#define VEHICLES 8

void virtual_ranging_report(uint16_t peer_id, float distance_m, uint32_t stamp_us)
{
  (void)stamp_us;
  fuzz_require(peer_id < RANGING_CAN_NB_NODES && peer_id != pprz_vehicle_ac_id());
  fuzz_require(distance_m >= 0.0f && distance_m <= RANGING_CAN_RANGE_MAX_MM * 1e-3f);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  pprz_vehicles_setup(VEHICLES, NULL);
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static const double step_s[] = { 0.0, 0.001, 0.05, 0.1, 0.5, 2.0, 60.0, 3600.0, 1e6, 1e9, 1e13 };
  if (nps_host_ranging_replay_open(fuzz_file(data, size), "/dev/null", VEHICLES) != 0) {
    return 0;
  }
  for (size_t i = 0; i < sizeof(step_s) / sizeof(step_s[0]); i++) {
    if (nps_host_ranging_replay_step(step_s[i]) != 0) {
      break;
    }
  }
  fuzz_require(nps_host_ranging_replay_write_error() == NULL);
  fuzz_require(nps_host_ranging_replay_close() == 0);
  return 0;
}
