"""The whole calibration of a static log: every axis's Allan deviation and fit, and the Paparazzi defines.

Averaging times run from one sample to tau_max (default: the log's span / TAU_FRACTION). A longer tau_max is
refused: the log would hold fewer than TAU_FRACTION stretches of it, and the Allan deviation there is too rough to
fit.
"""
from dataclasses import dataclass

import numpy as np

from finken.imu.imu_log import ImuLogError
from finken.imu.noise_fit import fit_axis
from finken.imu.paparazzi import defines

TAU_FRACTION = 10        # the longest averaging time is at most the log's span / TAU_FRACTION
BOOTSTRAP_REPS = 30
SIM_RATE_HZ = 512.0      # the example airframe's PERIODIC_FREQUENCY: NPS samples its IMU at it


@dataclass
class Calibration:
    log: object          # ImuLog
    tau_max_s: float
    fits: dict           # axis name -> NoiseFit
    curves: dict         # axis name -> AllanCurve
    means: dict          # axis name -> mean value
    defines: object      # paparazzi.Defines
    dt_s: float
    reps: int
    seed: int


def longest_tau(log, tau_max_s=None):
    """The longest averaging time [s]: tau_max_s, checked against the log's span, or span / TAU_FRACTION."""
    span = float(log.t[-1] - log.t[0]) + 1.0 / log.rate_hz
    if tau_max_s is None:
        return span / TAU_FRACTION
    if tau_max_s * TAU_FRACTION > span:
        raise ImuLogError(log.path, None, "t", f"{span:.6g} s of data ({len(log.t)} rows) are too short for "
                          f"--tau-max {tau_max_s:g} s: an Allan deviation at tau needs {TAU_FRACTION} tau of data "
                          f"({TAU_FRACTION * tau_max_s:g} s); record longer or ask for at most "
                          f"{span / TAU_FRACTION:.4g} s")
    return tau_max_s


def calibrate(log, tau_max_s=None, reps=BOOTSTRAP_REPS, seed=1, sim_rate_hz=SIM_RATE_HZ, progress=None):
    """Calibration of an ImuLog (at rest: imu_log.check_at_rest first). progress(axis name) before each axis."""
    tau_max_s = longest_tau(log, tau_max_s)
    rng = np.random.default_rng(seed)
    fits, curves, means = {}, {}, {}
    for name, column, samples in log.axes():
        if progress:
            progress(name)
        try:
            fits[name], curves[name] = fit_axis(samples, log.rate_hz, tau_max_s, reps, rng)
        except ValueError as err:
            raise ImuLogError(log.path, None, column, f"{err} (the log is too short or too coarse: {len(log.t)} "
                              f"rows at {log.rate_hz:.4g} Hz up to {tau_max_s:.4g} s)") from None
        means[name] = float(np.mean(samples))
    dt_s = 1.0 / sim_rate_hz
    return Calibration(log, tau_max_s, fits, curves, means, defines(fits, means, dt_s), dt_s, reps, seed)
