"""The fitted noise as the SIMULATOR defines Paparazzi's NPS gyro and accelerometer models read (prefix NPS_;
nps_sensor_gyro.c, nps_sensor_accel.c), and as an airframe fragment.

Paparazzi's models, per axis, every sample period dt (NPS_GYRO_DT, NPS_ACCEL_DT):
  gyro   rate + BIAS_INITIAL + NOISE_STD_DEV n + b,  b += dt (BIAS_RANDOM_WALK_STD_DEV n' - b / 5 s)
  accel  specific force + BIAS + NOISE_STD_DEV n                     (n, n' standard normal)
So: NOISE_STD_DEV = N / sqrt(dt) (white noise of density N sampled every dt). The gyro's b is a first-order Markov
process of fixed correlation time TC = 5 s driven by q = BIAS_RANDOM_WALK_STD_DEV sqrt(dt): a rate random walk of
density q up to a few seconds, bounded beyond; one number cannot give both a bias instability and a rate random
walk, so q is the one that makes the largest ratio between Paparazzi's Allan deviation (white noise and b) and the
fitted one, over the log's averaging times, the smallest (minimax on log adev); that ratio is reported.
BIAS_INITIAL is the log's mean rate (this unit's turn-on bias, plus the Earth's rate, at most 7.3e-5 rad/s).
The accelerometer model has no drift: its B and K are reported, not simulated; its constant bias cannot be told from
a tilt in one static position: BIAS 0 (a multi-position calibration gives it).
"""
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from finken.imu.noise_fit import model_adev

TC_S = 5.0                      # nps_sensor_gyro.c: double_vect3_update_random_walk(..., NPS_GYRO_DT, 5.)
GYRO_AXES = ("P", "Q", "R")     # Paparazzi's names of the gyro axes x, y, z
ACCEL_AXES = ("X", "Y", "Z")
DIGITS = 4                      # significant digits of the written values


@dataclass
class Defines:
    """Ordered (name without the NPS_ prefix, value, comment) triples, and the notes of the fragment."""
    rows: list
    notes: list

    def value(self, name):
        return next(v for n, v, _ in self.rows if n == name)


def markov_adev(q, tau, tc=TC_S):
    """Allan deviation of a first-order Markov process driven by white noise of density q with correlation time tc."""
    tau = np.asarray(tau, dtype=np.float64)
    x = tau / tc
    avar = (q * tc) ** 2 / tau * (1.0 - (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)) / (2.0 * x))
    return np.sqrt(np.maximum(avar, 0.0))


def markov_drive(fitted, tau):
    """(q, largest ratio of the two Allan deviations) for AxisNoise fitted at averaging times tau (module comment)."""
    target = np.log(model_adev(fitted, tau))
    if fitted.bias_instability == 0.0 and fitted.rate_random_walk == 0.0:
        return 0.0, 1.0

    def worst(log_q):
        return float(np.max(np.abs(np.log(paparazzi_adev(True, fitted.white, np.exp(log_q), tau)) - target)))

    scale = np.log(max(fitted.rate_random_walk, fitted.bias_instability / np.sqrt(TC_S)))
    best = minimize_scalar(worst, bounds=(scale - 10.0, scale + 10.0), method="bounded",
                           options={"xatol": 1e-6})
    return float(np.exp(best.x)), float(np.exp(best.fun))


def paparazzi_adev(gyro, white, q, tau):
    """The Allan deviation Paparazzi's model gives: white noise, and the Markov bias for a gyro."""
    tau = np.asarray(tau, dtype=np.float64)
    return np.sqrt(white ** 2 / tau + (markov_adev(q, tau) ** 2 if gyro else 0.0))


def defines(fits, mean, dt):
    """Defines from {axis name: NoiseFit} ("gyro x" ... "accel z", any present) and {axis name: mean value}."""
    rows, notes = [], []
    fmt = f"{{:.{DIGITS}g}}"
    if any(name.startswith("gyro") for name in fits):
        rows.append(("GYRO_DT", f"(1./{1.0 / dt:.6g})", "sample period [s] the standard deviations below are for"))
        for k, axis in enumerate(GYRO_AXES):
            fit = fits[f"gyro {'xyz'[k]}"]
            q, worst = markov_drive(fit.noise(), fit.tau)
            rows.append((f"GYRO_NOISE_STD_DEV_{axis}", fmt.format(fit.white.value / np.sqrt(dt)),
                         f"[rad/s] white N = {fit.white.value:.4g} rad/s/sqrt(Hz)"))
            rows.append((f"GYRO_BIAS_INITIAL_{axis}", fmt.format(mean[f"gyro {'xyz'[k]}"]), "[rad/s] the log's mean"))
            rows.append((f"GYRO_BIAS_RANDOM_WALK_STD_DEV_{axis}", fmt.format(q / np.sqrt(dt)),
                         f"[rad/s^2] Markov drive q = {q:.4g} rad/s^2/sqrt(Hz), Allan deviation within x{worst:.3g} "
                         "of the fit"))
    if any(name.startswith("accel") for name in fits):
        rows.append(("ACCEL_DT", f"(1./{1.0 / dt:.6g})", "sample period [s] the standard deviations below are for"))
        for k, axis in enumerate(ACCEL_AXES):
            fit = fits[f"accel {'xyz'[k]}"]
            rows.append((f"ACCEL_NOISE_STD_DEV_{axis}", fmt.format(fit.white.value / np.sqrt(dt)),
                         f"[m/s^2] white N = {fit.white.value:.4g} m/s^2/sqrt(Hz)"))
            rows.append((f"ACCEL_BIAS_{axis}", "0", "[m/s^2] not told from a tilt in one static position"))
        notes.append("The accelerometer model of Paparazzi has no drift: its bias instability and rate random walk "
                     "are in the report, not simulated.")
    return Defines(rows, notes)


def fragment_xml(defs, comment_lines):
    """An airframe <section name="SIMULATOR" prefix="NPS_"> with the defines, after a comment of comment_lines."""
    width = max(len(name) for name, _, _ in defs.rows)
    text = [f"  {line}".rstrip().replace("--", "- -") for line in comment_lines + defs.notes]   # no -- in a comment
    out = ["<!--"] + text + ["-->"]
    out.append('<section name="SIMULATOR" prefix="NPS_">')
    for name, value, comment in defs.rows:
        out.append(f'  <define name="{name}"{" " * (width - len(name))} value="{value}"/>  <!-- {comment} -->')
    out.append("</section>")
    return "\n".join(out) + "\n"
