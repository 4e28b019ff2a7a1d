"""Read a static IMU log: a CSV with a time column and gyro and accelerometer axes, checked and in SI units.

Columns (any order; another name with --columns gx=GyroX,...): t [s], gx gy gz [rad/s], ax ay az [m/s^2]; other
columns are ignored. Units: --gyro-unit rad/s|deg/s, --accel-unit m/s^2|g. Numbers follow finken.text_numbers.
A sensor whose three columns are all absent is left out with a warning (the other is calibrated); a sensor with
one or two of its columns is refused, naming the missing column. Rejected with ImuLogError ("file:line: column
'x': reason"): a missing t, an empty, non-numeric or infinite value, a time that does not increase, fewer rows
than MIN_ROWS. Warned: gaps in the time steps (the Allan deviation treats samples as evenly spaced), an
accelerometer whose mean norm is far from 1 g (a unit?).
The copter must be at rest (check_at_rest): its accelerometer's 1-s means may not jump by more than the larger of
REST_JUMP_MPS2 and REST_JUMP_SIGMAS times their own noise; otherwise ImuLogError names the column, the line and
the time of the largest jump.
"""
import csv
import math
from dataclasses import dataclass, field

import numpy as np

from finken.rangelog import RangeLogError
from finken.rangelog_columns import parse_items
from finken.text_numbers import SPACES, ColumnError, parse_column

GYRO_COLUMNS = ("gx", "gy", "gz")
ACCEL_COLUMNS = ("ax", "ay", "az")
SPEC_COLUMNS = ("t",) + GYRO_COLUMNS + ACCEL_COLUMNS
STANDARD_GRAVITY = 9.80665                                  # [m/s^2]
GYRO_UNITS = {"rad/s": 1.0, "deg/s": math.pi / 180.0}       # what a file value is multiplied by
ACCEL_UNITS = {"m/s^2": 1.0, "g": STANDARD_GRAVITY}
MIN_ROWS = 100
GAP_FACTOR = 1.5            # a time step longer than this many median steps is a gap
GRAVITY_TOLERANCE = 0.1     # warn when the mean |a| is more than 10 % away from 1 g
REST_WINDOW_S = 1.0         # the at-rest check compares means over windows this long
REST_JUMP_MPS2 = 0.1        # ... which may jump by this much (a tilt of 0.6 deg, a light knock) ...
REST_JUMP_SIGMAS = 8.0      # ... or this many standard deviations of their jumps, if larger (noisy sensors)


class ImuLogError(RangeLogError):
    """A log that cannot be calibrated: `file:line: column 'x': reason` (line 1 is the header), written as the
    range-log reader writes its errors."""


@dataclass
class ImuLog:
    """A static IMU log in SI units; gyro and accel are n x 3 arrays (x, y, z) or None when absent."""
    path: str
    t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    line: np.ndarray                       # file line of each row (1 = header)
    rate_hz: float                         # 1 / the median time step
    warnings: list = field(default_factory=list)

    def axes(self):
        """(name, column, samples) of every axis present: gyro x, y, z, then accel x, y, z."""
        out = []
        for sensor, columns, data in (("gyro", GYRO_COLUMNS, self.gyro), ("accel", ACCEL_COLUMNS, self.accel)):
            if data is not None:
                out += [(f"{sensor} {'xyz'[k]}", columns[k], data[:, k]) for k in range(3)]
        return out


def parse_imu_columns(text):
    """`gx=GyroX,t=time_s` -> {"gx": "GyroX", "t": "time_s"}; ValueError for an unknown or repeated name."""
    result = {}
    for spec, column in parse_items(text, "file_column"):
        if spec not in SPEC_COLUMNS:
            raise ValueError(f"columns: unknown column '{spec}' (expected {', '.join(SPEC_COLUMNS)})")
        if spec in result:
            raise ValueError(f"columns: '{spec}' is given twice")
        if not column:
            raise ValueError(f"columns: empty file column name for '{spec}'")
        if column in result.values():
            raise ValueError(f"columns: file column '{column}' is given twice")
        result[spec] = column
    return result


def read_imu_log(path, columns=None, gyro_unit="rad/s", accel_unit="m/s^2"):
    """The log at `path` as an ImuLog (see the module comment); raises ImuLogError."""
    path = str(path)
    header, header_line, rows, lines = _read_rows(path)
    names = {spec: (columns or {}).get(spec, spec) for spec in SPEC_COLUMNS}
    index = {spec: header.index(name) for spec, name in names.items() if name in header}
    if "t" not in index:
        raise ImuLogError(path, header_line, names["t"], f"missing (the file has {', '.join(header)})")
    warnings = []
    data = {}
    for sensor, group, unit in (("gyroscope", GYRO_COLUMNS, GYRO_UNITS[gyro_unit]),
                                ("accelerometer", ACCEL_COLUMNS, ACCEL_UNITS[accel_unit])):
        present = [spec for spec in group if spec in index]
        if not present:
            warnings.append(f"{path}: no {sensor} columns ({', '.join(names[s] for s in group)}): only the "
                            f"{'accelerometer' if sensor == 'gyroscope' else 'gyroscope'} is calibrated")
            data[group] = None
            continue
        for spec in group:
            if spec not in index:
                raise ImuLogError(path, header_line, names[spec], f"missing: the {sensor} needs "
                                  f"{', '.join(names[s] for s in group)} (the file has {', '.join(header)}; "
                                  f"name yours with --columns {spec}=<column>)")
        data[group] = np.column_stack([_numbers(path, rows, lines, index[s], names[s]) for s in group]) * unit
    if data[GYRO_COLUMNS] is None and data[ACCEL_COLUMNS] is None:
        raise ImuLogError(path, header_line, None, "neither gyroscope nor accelerometer columns: expected gx, gy, gz "
                          "and/or ax, ay, az (or --columns)")
    t = _numbers(path, rows, lines, index["t"], names["t"])
    if len(t) < MIN_ROWS:
        raise ImuLogError(path, None, None, f"{len(t)} rows: too few for an Allan deviation (at least {MIN_ROWS})")
    rate_hz = _check_time(path, t, lines, names["t"], warnings)
    log = ImuLog(path, t, data[GYRO_COLUMNS], data[ACCEL_COLUMNS], lines, rate_hz, warnings)
    if log.accel is not None:
        norm = float(np.linalg.norm(log.accel.mean(axis=0)))
        if abs(norm / STANDARD_GRAVITY - 1.0) > GRAVITY_TOLERANCE:
            warnings.append(f"{path}: the accelerometer's mean norm is {norm:.4g} m/s^2, not about "
                            f"{STANDARD_GRAVITY} m/s^2: check --accel-unit (g or m/s^2)")
    return log


def check_at_rest(log, columns=None):
    """Raise ImuLogError when the copter moved (see the module comment); a warning when there is no accelerometer."""
    if log.accel is None:
        log.warnings.append(f"{log.path}: no accelerometer: whether the copter was at rest is not checked")
        return
    per_window = max(1, int(round(REST_WINDOW_S * log.rate_hz)))
    windows = len(log.t) // per_window
    if windows < 3:
        return
    means = log.accel[:windows * per_window].reshape(windows, per_window, 3).mean(axis=1)
    jumps = np.abs(np.diff(means, axis=0))
    noise = 1.4826 * np.median(np.abs(jumps - np.median(jumps, axis=0)), axis=0)   # MAD: jumps of a move don't count
    limit = np.maximum(REST_JUMP_MPS2, REST_JUMP_SIGMAS * noise)
    excess = jumps / limit
    w, k = np.unravel_index(int(np.argmax(excess)), excess.shape)
    if excess[w, k] > 1.0:
        first = (w + 1) * per_window
        name = (columns or {}).get(ACCEL_COLUMNS[k], ACCEL_COLUMNS[k])
        raise ImuLogError(log.path, int(log.line[first]), name,
                          f"the copter moved: the {REST_WINDOW_S:g}-s mean jumped by {jumps[w, k]:.3g} m/s^2 at "
                          f"t = {log.t[first]:.6g} s (at rest: under {limit[k]:.3g} m/s^2); record the copter at "
                          f"rest, or cut the log to the time it lay still")


def _read_rows(path):
    """(header names, the header's line, rows as lists of str, file line of each row) of a CSV; blank lines
    skipped."""
    try:
        with open(path, encoding="utf-8-sig", newline="") as f:
            reader = csv.reader(f)
            header, rows, lines = None, [], []
            for record in reader:
                if not any(field.strip(SPACES) for field in record):
                    continue
                if header is None:
                    header = [name.strip(SPACES) for name in record]
                    header_line = reader.line_num
                    continue
                if len(record) != len(header):
                    raise ImuLogError(path, reader.line_num, None,
                                      f"expected {len(header)} fields as in the header, found {len(record)}")
                rows.append(record)
                lines.append(reader.line_num)
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise ImuLogError(path, None, None, f"cannot read: {err}") from None
    if header is None:
        raise ImuLogError(path, None, None, "empty file: expected a header with t, gx, gy, gz, ax, ay, az")
    return header, header_line, rows, np.asarray(lines, dtype=np.int64)


def _numbers(path, rows, lines, column, name):
    """Column `column` of the rows as finite floats; ImuLogError naming the line of the first bad field."""
    texts = np.array([row[column].strip(SPACES) for row in rows], dtype=str)
    try:
        values = parse_column(texts)
    except ColumnError as err:
        raise ImuLogError(path, int(lines[err.index]), name, err.reason) from None
    bad = ~np.isfinite(values)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ImuLogError(path, int(lines[i]), name,
                          "no value (the Allan deviation needs every sample)" if texts[i] == "" or
                          math.isnan(values[i]) else f"'{texts[i]}' is not a finite number")
    return values


def _check_time(path, t, lines, name, warnings):
    """The sample rate [Hz] from the median step; ImuLogError where time does not increase; gaps warned."""
    step = np.diff(t)
    bad = step <= 0
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0]) + 1
        raise ImuLogError(path, int(lines[i]), name, f"time {t[i]:.9g} s does not increase (previous row "
                          f"{t[i - 1]:.9g} s)")
    median = float(np.median(step))
    gaps = np.flatnonzero(step > GAP_FACTOR * median)
    if gaps.size:
        largest = int(gaps[np.argmax(step[gaps])])
        warnings.append(f"{path}:{int(lines[largest + 1])}: column '{name}': {gaps.size} gap(s) in time, the "
                        f"largest {step[largest]:.3g} s here (median step {median:.3g} s): the Allan deviation "
                        f"treats the samples as evenly spaced")
    return 1.0 / median
