"""Seeded synthetic IMU noise and static logs of known parameters (numpy only).

One axis (noise): white noise of density N (per-sample standard deviation N sqrt(rate)), flicker noise of bias
instability B (one-sided PSD B^2 / (pi f) from 1/T to the Nyquist frequency, shaped in the frequency domain: the
IEEE 952 flicker law whose Allan deviation is sqrt(2 ln 2 / pi) B = 0.664 B), and a rate random walk of density K
(increments K sqrt(dt)). Its Allan deviation is sqrt(N^2/tau + (2 ln 2/pi) B^2 + K^2 tau/3) for averaging times
well inside (1/rate, T).

    python -m finken.imu.synthetic -o build/imu/mpu9250_static.csv [--preset mpu9250] [--seed 1]
                                   [--duration 7200] [--rate 100]

writes a log of the copter at rest (level: the accelerometer reads -g on z) in imu_log's columns.
"""
import argparse
import sys
from dataclasses import dataclass

import numpy as np

from finken.atomic_output import WriteError, atomic_output
from finken.cli_types import integer, real
from finken.imu.imu_log import ACCEL_COLUMNS, GYRO_COLUMNS, STANDARD_GRAVITY

DEG = np.pi / 180.0


@dataclass(frozen=True)
class AxisNoise:
    """Noise of one axis: white N [unit/sqrt(Hz)], bias instability B [unit], rate random walk K [unit*sqrt(Hz)]."""
    white: float
    bias_instability: float
    rate_random_walk: float


@dataclass(frozen=True)
class ImuPreset:
    """A sensor's noise (the same on its three axes) and turn-on gyro bias [rad/s], with where they come from."""
    gyro: AxisNoise
    accel: AxisNoise
    gyro_bias: tuple
    source: str


# MPU-9250 (the example airframe's IMU, conf/airframes/finken/finken_quad.xml): datasheet (InvenSense PS-MPU-9250A-01
# rev. 1.1) rate noise spectral density 0.01 deg/s/sqrt(Hz), accelerometer noise power spectral density
# 300 ug/sqrt(Hz), taken as the white densities N. It specifies no bias instability nor rate random walk: those and
# the turn-on gyro bias (within its initial ZRO tolerance of +-5 deg/s) are ASSUMED, of the order of consumer MEMS.
MPU9250 = ImuPreset(
    gyro=AxisNoise(white=0.01 * DEG, bias_instability=10.0 * DEG / 3600.0, rate_random_walk=5e-6),
    accel=AxisNoise(white=300e-6 * STANDARD_GRAVITY, bias_instability=5e-4, rate_random_walk=2e-5),
    gyro_bias=(0.012, -0.008, 0.004),
    source="MPU-9250 datasheet noise densities (gyro 0.01 deg/s/sqrt(Hz), accel 300 ug/sqrt(Hz)); bias instability "
           "(gyro 10 deg/h, accel 0.5 mm/s^2), rate random walk (gyro 5e-6 rad/s^2/sqrt(Hz), accel 2e-5 "
           "m/s^3/sqrt(Hz)) and turn-on gyro bias ASSUMED",
)
PRESETS = {"mpu9250": MPU9250}


def noise(axis, rate_hz, n, rng):
    """n samples at rate_hz of one axis's noise (AxisNoise) from the numpy Generator rng."""
    white = axis.white * np.sqrt(rate_hz) * rng.standard_normal(n)
    f = np.fft.rfftfreq(n, 1.0 / rate_hz)
    psd = np.zeros_like(f)
    psd[1:] = axis.bias_instability ** 2 / (np.pi * f[1:])          # one-sided [unit^2/Hz]
    spectrum = np.sqrt(psd * n * rate_hz) / 2.0 * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    if n % 2 == 0:
        spectrum[-1] = spectrum[-1].real * np.sqrt(2.0)                # the Nyquist term is real
    flicker = np.fft.irfft(spectrum, n)
    walk = np.cumsum(axis.rate_random_walk * np.sqrt(1.0 / rate_hz) * rng.standard_normal(n))
    return white + flicker + walk


def static_log(preset, rate_hz, duration_s, seed):
    """{column: samples} of a copter at rest, level, for duration_s at rate_hz (seeded)."""
    rng = np.random.default_rng(seed)
    n = int(round(rate_hz * duration_s))
    columns = {"t": np.arange(n) / rate_hz}
    for k, name in enumerate(GYRO_COLUMNS):
        columns[name] = preset.gyro_bias[k] + noise(preset.gyro, rate_hz, n, rng)
    for k, name in enumerate(ACCEL_COLUMNS):
        columns[name] = (-STANDARD_GRAVITY if name == "az" else 0.0) + noise(preset.accel, rate_hz, n, rng)
    return columns


def write_log(path, columns):
    """Write {column: samples} as a CSV (t with 6 decimals, values with 9 significant digits)."""
    names = list(columns)
    table = np.column_stack([columns[name] for name in names])
    with atomic_output(path, newline="") as f:
        f.write(",".join(names) + "\n")
        np.savetxt(f, table, fmt=["%.6f"] + ["%.9g"] * (len(names) - 1), delimiter=",")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", required=True, help="CSV to write")
    ap.add_argument("--preset", choices=sorted(PRESETS), default="mpu9250")
    ap.add_argument("--seed", type=integer(0, 2**63 - 1), default=1)
    ap.add_argument("--duration", type=real(1.0), default=7200.0, help="seconds (default 7200)")
    ap.add_argument("--rate", type=real(1.0), default=100.0, help="samples per second (default 100)")
    args = ap.parse_args(argv)
    try:
        write_log(args.out, static_log(PRESETS[args.preset], args.rate, args.duration, args.seed))
    except WriteError as err:
        print(f"synthetic: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
