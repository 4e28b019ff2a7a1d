"""A stand-in for a lab's first real log: UWB two-way ranging between a tag and an anchor, recorded in many
short static recordings, with a LOS/NLOS label and the received signal strength.

Written after what public UWB ranging data sets show (and what issue 29 met on one): true ranges 0.4-12.8 m,
far beyond the 2.5 m of the FINken ranging model; in line of sight a small bias and centimetre noise; out of
line of sight (an obstacle on the direct path) a positive excess path of tens of centimetres whose
distribution is skewed but not exactly exponential (here a gamma law of shape NLOS_SHAPE, so that no library
effect fits it exactly, as on real data); the signal strength falls with range (free-space path loss,
20 log10 d) and by several dB out of line of sight.

The readings are drawn here with numpy, not by the sensor model: this is "the world", which the workflow has
to learn, not a model of ours.
"""
import numpy as np

from finken.rangelog import RangeLog

#: Recordings and readings per recording (10 Hz, a few seconds each).
RECORDINGS, READINGS_PER_RECORDING, RATE_HZ = 300, 50, 10.0
#: True range of a recording [m]: uniform over this interval.
RANGE_M = (0.4, 12.8)
#: Share of the recordings out of line of sight.
NLOS_SHARE = 0.35
#: Line of sight: bias [m] and noise [m].
LOS_BIAS_M, LOS_SIGMA_M = 0.02, 0.05
#: Excess path out of line of sight: gamma law of this shape and mean [m].
NLOS_SHAPE, NLOS_MEAN_M = 1.6, 0.4
#: Signal strength [dBm]: at 1 m, loss out of line of sight [dB], noise [dB].
RSSI_1M_DBM, NLOS_LOSS_DB, RSSI_SIGMA_DB = -60.0, 8.0, 2.0


def uwb_log(seed=0, recordings=RECORDINGS, readings=READINGS_PER_RECORDING, restart_time=False):
    """A RangeLog of `recordings` x `readings` ranging rows between copter 1 and copter 2, with ctx_nlos (0/1),
    ctx_rssi [dBm] and a `recording` column (extra). With restart_time every recording starts at t = 0 (as
    many loggers write it); otherwise recordings follow each other 1 s apart."""
    rng = np.random.default_rng(seed)
    rec = np.repeat(np.arange(recordings), readings)
    true_rec = rng.uniform(*RANGE_M, recordings)
    nlos_rec = (rng.random(recordings) < NLOS_SHARE).astype(float)
    k = np.tile(np.arange(readings), recordings)
    t = k / RATE_HZ + (0.0 if restart_time else rec * (readings / RATE_HZ + 1.0))
    true_range = true_rec[rec] + rng.normal(0.0, 0.005, rec.size)      # a tag held by hand moves a little
    nlos = nlos_rec[rec]
    excess = rng.gamma(NLOS_SHAPE, NLOS_MEAN_M / NLOS_SHAPE, rec.size) * nlos
    measured = true_range + LOS_BIAS_M + rng.normal(0.0, LOS_SIGMA_M, rec.size) + excess
    rssi = (RSSI_1M_DBM - 20.0 * np.log10(true_range) - NLOS_LOSS_DB * nlos
            + rng.normal(0.0, RSSI_SIGMA_DB, rec.size))
    n = rec.size
    return RangeLog("<uwb-like>", t, np.ones(n), np.full(n, "ranging"), np.full(n, 2.0), true_range,
                    np.maximum(measured, 0.0), {"ctx_nlos": nlos, "ctx_rssi": rssi},
                    {"recording": np.char.add("rec", rec.astype(str))})
