#!/usr/bin/env python3
"""Inertial-sensor errors from a log of the copter at rest, for Paparazzi's NPS gyro and accelerometer models.

    make imu-calibrate LOG=static.csv OUT=build/imu [COLUMNS=t=time,gx=GyroX,...] [GYRO_UNIT=deg/s]
                       [ACCEL_UNIT=g] [TAU_MAX=720] [SIM_RATE=512]
    tools/imu_calibrate.py --log static.csv --out build/imu [--columns ...] [--gyro-unit rad/s|deg/s]
                           [--accel-unit m/s^2|g] [--tau-max S] [--sim-rate HZ] [--bootstrap 30] [--seed 1] [--quiet]

The log: t [s], gx gy gz [rad/s], ax ay az [m/s^2] (finken.imu.imu_log). Writes in OUT: imu_simulator.xml (the
SIMULATOR section defines of the gyro and accelerometer, with a comment naming the log and the fit), allan.png
(the Allan deviations, the fits and Paparazzi's model) and imu_report.json. Exit status 0; 2 for bad input (the
message names the file, line and column) or a bad option; 1 when an output cannot be written.
Method and mapping: finken/imu/noise_fit.py and finken/imu/paparazzi.py; docs/imu-and-floor.md.
"""
import argparse
import sys
import textwrap
from pathlib import Path

from finken.atomic_output import WriteError, write_texts
from finken.cli_types import integer, real
from finken.imu.calibration import BOOTSTRAP_REPS, SIM_RATE_HZ, calibrate
from finken.imu.imu_log import ACCEL_UNITS, GYRO_UNITS, ImuLogError, check_at_rest, parse_imu_columns, read_imu_log
from finken.imu.noise_fit import CONFIDENCE
from finken.imu.plot import plot_calibration
from finken.imu.report import METHOD, UNITS, report_json
from finken.imu.paparazzi import fragment_xml

FRAGMENT, FIGURE, REPORT = "imu_simulator.xml", "allan.png", "imu_report.json"
COMMENT_WIDTH = 110


def _columns(text):
    try:
        return parse_imu_columns(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def comment_lines(cal):
    """The fragment's comment: the log, the fit and every axis's coefficients with their intervals."""
    log = cal.log
    fit = (f"Fit: {METHOD}; up to tau = {cal.tau_max_s:.4g} s; {CONFIDENCE:.0%} intervals from {cal.reps} simulated "
           f"logs (seed {cal.seed}).")
    lines = [f"IMU errors for Paparazzi's NPS, written by tools/imu_calibrate.py from {log.path}",
             f"({len(log.t)} rows at {log.rate_hz:.6g} Hz, {log.t[-1] - log.t[0]:.6g} s at rest).",
             *textwrap.wrap(fit, COMMENT_WIDTH), "N white noise, B bias instability, K rate random walk:"]
    for name, fit in cal.fits.items():
        _, *units = UNITS[name.split()[0]]
        terms = [f"{label} = {t.value:.4g} [{t.low:.3g}, {'unbounded' if t.high is None else f'{t.high:.3g}'}] {unit}"
                 for label, t, unit in zip("NBK", (fit.white, fit.bias_instability, fit.rate_random_walk), units)]
        lines.append(f"  {name}: " + ", ".join(terms))
    lines.append("Paparazzi reads these through NPS_SENSORS_PARAMS=nps_sensors_params_finken.h (sw/simulator/nps),")
    lines.append("which keeps them over its defaults (docs/imu-and-floor.md).")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--log", required=True, help="CSV of the IMU at rest")
    ap.add_argument("--out", required=True, help="folder for the outputs (created)")
    ap.add_argument("--columns", type=_columns, default=None, metavar="SPEC=FILE,...",
                    help="the file's names of t, gx, gy, gz, ax, ay, az, e.g. t=time_s,gx=GyroX")
    ap.add_argument("--gyro-unit", choices=sorted(GYRO_UNITS), default="rad/s")
    ap.add_argument("--accel-unit", choices=sorted(ACCEL_UNITS), default="m/s^2")
    ap.add_argument("--tau-max", type=real(0.0, low_open=True), default=None, metavar="S",
                    help="longest averaging time [s] (default: a tenth of the log)")
    ap.add_argument("--sim-rate", type=real(0.0, low_open=True), default=SIM_RATE_HZ, metavar="HZ",
                    help=f"the rate NPS samples the IMU at (NPS_GYRO_DT = 1/HZ; default {SIM_RATE_HZ:g}, the "
                         "example airframe's PERIODIC_FREQUENCY)")
    ap.add_argument("--bootstrap", type=integer(0, 10000), default=BOOTSTRAP_REPS, metavar="N",
                    help=f"simulated logs for the intervals (default {BOOTSTRAP_REPS}; 0: none)")
    ap.add_argument("--seed", type=integer(0, 2**63 - 1), default=1, help="seed of the bootstrap (default 1)")
    ap.add_argument("--quiet", action="store_true", help="no summary on stdout")
    args = ap.parse_args(argv)

    def progress(axis):
        if not args.quiet:
            print(f"imu_calibrate: fitting {axis}", file=sys.stderr)

    try:
        log = read_imu_log(args.log, args.columns, args.gyro_unit, args.accel_unit)
        check_at_rest(log, args.columns)
        cal = calibrate(log, args.tau_max, args.bootstrap, args.seed, args.sim_rate, progress)
    except ImuLogError as err:
        print(f"imu_calibrate: {err}", file=sys.stderr)
        return 2
    for warning in log.warnings:
        print(f"imu_calibrate: warning: {warning}", file=sys.stderr)
    out = Path(args.out)
    try:
        out.mkdir(parents=True, exist_ok=True)
        plot_calibration(cal, out / FIGURE)
        fragment = fragment_xml(cal.defines, comment_lines(cal))
        write_texts({out / FRAGMENT: fragment, out / REPORT: report_json(cal)})
    except WriteError as err:
        print(f"imu_calibrate: {err}", file=sys.stderr)
        return 1
    except OSError as err:
        print(f"imu_calibrate: {out}: cannot write: {err.strerror}", file=sys.stderr)
        return 1
    if not args.quiet:
        print(fragment, end="")
        print(f"imu_calibrate: wrote {out / FRAGMENT}, {out / FIGURE}, {out / REPORT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
