/*
 * libFuzzer harness: what an NPS process reads of another aircraft in a shared world (written by another process,
 * perhaps a stale or broken one), sw/simulator/nps/nps_world_peer.c: the plausibility filter and the pose at a
 * reading's time.
 *
 * Input (binary; short inputs read as zeros): 1 to 8 queries (time, extrapolation limit), then the peer's record as
 * the shared-memory link copies it out: counts (any value), samples and pulses (any bit patterns). Properties:
 * after the filter the counts are within the arrays and every kept sample and pulse is plausible; a pose is found
 * exactly when a sample is left and the time is a number, and its position is finite up to the newest sample's time
 * (with an extrapolation limit of at most 1 s).
 */
#include "fuzz_common.h"

#include <math.h>

#include "nps_raycast.h"
#include "nps_world_peer.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

static void check_sanitized(const struct nps_world_peer *peer)
{
  fuzz_require(peer->n_samples <= NPS_WORLD_SAMPLES && peer->n_pings <= NPS_WORLD_PINGS);
  for (unsigned i = 0; i < peer->n_samples; i++) {
    const struct nps_world_sample *s = &peer->samples[i];
    fuzz_require(isfinite(s->t_s) && (i == 0 || s->t_s > peer->samples[i - 1].t_s) && isfinite(s->yaw_rad));
    fuzz_require(fabs(s->pos_m[0]) <= NPS_WORLD_PEER_MAX_COORD_M && fabs(s->pos_m[1]) <= NPS_WORLD_PEER_MAX_COORD_M &&
                 fabs(s->pos_m[2]) <= NPS_WORLD_PEER_MAX_COORD_M);
    fuzz_require(s->speed_mps >= 0.0 && s->speed_mps <= NPS_WORLD_PEER_MAX_SPEED_MPS);
  }
  for (unsigned i = 0; i < peer->n_pings; i++) {
    fuzz_require(isfinite(peer->pings[i].t_s) && peer->pings[i].sonar < NPS_SONAR_COUNT);
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  struct fuzz_bytes in = { data, size };
  double query[8][2];
  const unsigned queries = 1U + fuzz_u8(&in) % 8U;
  for (unsigned q = 0; q < queries; q++) {
    query[q][0] = fuzz_double(&in);
    query[q][1] = fuzz_double(&in);
  }
  static struct nps_world_peer peer;
  memset(&peer, 0, sizeof(peer));
  peer.n_samples = fuzz_u32(&in);
  peer.n_pings = fuzz_u32(&in);
  for (unsigned i = 0; i < NPS_WORLD_SAMPLES && fuzz_more(&in); i++) {
    struct nps_world_sample *s = &peer.samples[i];
    s->t_s = fuzz_double(&in);
    for (int k = 0; k < 3; k++) {
      s->pos_m[k] = fuzz_double(&in);
    }
    s->yaw_rad = fuzz_double(&in);
    s->speed_mps = fuzz_double(&in);
    if (i < NPS_WORLD_PINGS) {
      peer.pings[i].t_s = fuzz_double(&in);
      peer.pings[i].sonar = fuzz_u32(&in);
    }
  }
  (void)nps_world_peer_sanitize(&peer);
  check_sanitized(&peer);
  for (unsigned q = 0; q < queries; q++) {
    struct nps_world_sample pose;
    double age_s;
    const int rc = nps_world_peer_pose_at(&peer, query[q][0], query[q][1], &pose, &age_s);
    fuzz_require(rc == (peer.n_samples > 0 && !isnan(query[q][0]) ? 0 : -1));
    /* the position, within the samples: a dead-reckoned one is not checked (two samples 5e-324 s apart give it an
     * infinite speed), nor the yaw (a yaw of 1e308 passes the filter, and 1e308 to -1e308 interpolates to NaN) */
    if (rc == 0 && isfinite(query[q][0]) && query[q][0] <= peer.samples[peer.n_samples - 1].t_s &&
        query[q][1] >= 0.0 && query[q][1] <= 1.0) {
      const bool finite = isfinite(pose.pos_m[0]) && isfinite(pose.pos_m[1]) && isfinite(pose.pos_m[2]) &&
                          age_s >= 0.0;
      if (!finite) {
        fprintf(fuzz_report, "at t = %.17g s: pose (%g, %g, %g) yaw %g, age %g s; samples:\n", query[q][0],
                pose.pos_m[0], pose.pos_m[1], pose.pos_m[2], pose.yaw_rad, age_s);
        for (unsigned i = 0; i < peer.n_samples; i++) {
          const struct nps_world_sample *s = &peer.samples[i];
          fprintf(fuzz_report, "  t %.17g s (%g, %g, %g) yaw %g speed %g\n", s->t_s, s->pos_m[0], s->pos_m[1],
                  s->pos_m[2], s->yaw_rad, s->speed_mps);
        }
      }
      fuzz_require(finite);
    }
  }
  return 0;
}
