"""Read the logs of a run beside its range log (readings.csv, finken.rangelog): detections.csv and poses.csv, as
our host and finken_world in Paparazzi's NPS write them, and an arena polygon given as text.

detections.csv is a range log (shared/spec/range-log.md, read with finken.rangelog.read_range_log) with one
row per WALL_DETECTION message, i.e. per horizontal sonar reading, and three more columns:
  t, vehicle, sensor, peer (empty), true_range, measured, ctx_target_copter,
  detector_class, confidence, baseline_class
where measured is the reading [m] (the message's repulsion_distance), true_range and ctx_target_copter are the
ray cast's ground truth of that reading (distance [m] to the first surface on the boresight; 1 if that surface
is a copter, else 0), detector_class and baseline_class are "wall", "copter", "unknown" or "none" (no echo:
reading at the sonar maximum) and confidence is the detector's confidence (0.5-1).
poses.csv: t [s], vehicle, x [m], y [m], z [m], yaw [rad] (the range-log spec's optional second file): finite
numbers and vehicle ids as in a range log (finken.text_numbers); optionally the attitude qx, qy, qz, qw (all four
or none): the unit quaternion, scalar last, of the rotation that turns the copter's body frame (x forward, y left,
z up) into the arena frame ENU, yaw = atan2(2 (qw qz + qx qy), 1 - 2 (qy^2 + qz^2)). Our host and finken_world
write them (the host's flight model turns about z alone: a heading's quaternion); older files have none.
"""
import numpy as np

from finken.rangelog import RangeLogError, read_range_log
from finken.text_numbers import SPACES, ColumnError, parse_column, parse_finite, parse_id

#: Class names in the detections CSV, indexed by the codes of the WALL_DETECTION ABI message.
CLASS_NAMES = ("unknown", "wall", "copter", "none")
DETECTION_COLUMNS = ("detector_class", "confidence", "baseline_class")
POSE_COLUMNS = ("t", "vehicle", "x", "y", "z", "yaw")
#: The attitude columns of poses.csv, optional as a group.
POSE_QUATERNION_COLUMNS = ("qx", "qy", "qz", "qw")
#: How far from 1 the norm of a row's attitude quaternion may be (rounding of a file written with few digits).
POSE_QUATERNION_NORM_TOLERANCE = 1e-2


def read_detections(path):
    """The detections log at `path` as a dict of arrays: t [s], vehicle, sensor, measured [m], true_range [m],
    target_copter (bool), detector_class (str), confidence, baseline_class (str). Raises RangeLogError."""
    log = read_range_log(path)
    if "ctx_target_copter" not in log.ctx:
        raise RangeLogError(path, 1, "ctx_target_copter", "missing column (the ground truth of each reading)")
    for name in DETECTION_COLUMNS:
        if name not in log.extra:
            raise RangeLogError(path, 1, name, "missing column (required: " + ", ".join(DETECTION_COLUMNS) + ")")
    target = log.ctx["ctx_target_copter"]
    bad = ~np.isin(target, (0.0, 1.0))
    _reject_first(path, bad, "ctx_target_copter", lambda i: f"'{target[i]:g}': expected 0 or 1")
    classes = {}
    for name in ("detector_class", "baseline_class"):
        values = np.strings.strip(log.extra[name])
        bad = ~np.isin(values, CLASS_NAMES)
        _reject_first(path, bad, name, lambda i: f"'{values[i]}': expected one of {', '.join(CLASS_NAMES)}")
        classes[name] = values
    confidence_text = np.strings.strip(log.extra["confidence"], SPACES)
    try:
        confidence = parse_column(confidence_text)
    except ColumnError as err:
        raise _row_error(path, err.index, "confidence", err.reason) from None
    _reject_first(path, ~np.isfinite(confidence), "confidence",
                  lambda i: f"'{confidence_text[i]}' is not a finite number")
    return {
        "t": log.t, "vehicle": log.vehicle, "sensor": log.sensor, "measured": log.measured,
        "true_range": log.true_range, "target_copter": target == 1.0,
        "detector_class": classes["detector_class"], "confidence": confidence,
        "baseline_class": classes["baseline_class"],
    }


def read_poses(path):
    """poses.csv as a dict of float arrays t, vehicle, x, y, z, yaw, and qx, qy, qz, qw when the file has them
    (files without them are read as before; a quaternion's norm must be 1 within POSE_QUATERNION_NORM_TOLERANCE).
    Raises RangeLogError naming the line."""
    path = str(path)
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().lstrip("\ufeff").splitlines()
    except (OSError, UnicodeDecodeError) as err:
        raise RangeLogError(path, None, None, f"cannot read: {err}")
    numbered = [(n + 1, line) for n, line in enumerate(lines) if line.strip()]
    if not numbered:
        raise RangeLogError(path, None, None, "empty file: expected the header " + ",".join(POSE_COLUMNS))
    header = [h.strip() for h in numbered[0][1].split(",")]
    for name in POSE_COLUMNS:
        if name not in header:
            raise RangeLogError(path, 1, name, "missing column (required: " + ", ".join(POSE_COLUMNS) + ")")
    quaternion = [name for name in POSE_QUATERNION_COLUMNS if name in header]
    if quaternion and len(quaternion) < len(POSE_QUATERNION_COLUMNS):
        missing = next(name for name in POSE_QUATERNION_COLUMNS if name not in header)
        raise RangeLogError(path, 1, missing, "missing column (the attitude is " +
                            ", ".join(POSE_QUATERNION_COLUMNS) + ", all four or none)")
    names = POSE_COLUMNS + tuple(quaternion)
    columns = {name: np.empty(len(numbered) - 1) for name in names}
    for row, (line_no, line) in enumerate(numbered[1:]):
        fields = line.split(",")
        if len(fields) != len(header):
            raise RangeLogError(path, line_no, None,
                                f"expected {len(header)} fields as in the header, found {len(fields)}")
        for name in names:
            text = fields[header.index(name)]
            try:
                columns[name][row] = parse_id(text) if name == "vehicle" else parse_finite(text)
            except ValueError as err:
                raise RangeLogError(path, line_no, name, str(err)) from None
    if quaternion:
        norm = np.sqrt(sum(columns[name] ** 2 for name in POSE_QUATERNION_COLUMNS))
        bad = np.flatnonzero(~(np.abs(norm - 1.0) <= POSE_QUATERNION_NORM_TOLERANCE))
        if bad.size:
            raise RangeLogError(path, numbered[1 + int(bad[0])][0], "qw",
                                f"the attitude quaternion (qx, qy, qz, qw) has norm {norm[bad[0]]:.6g}: expected 1 "
                                f"within {POSE_QUATERNION_NORM_TOLERANCE:g}")
    return columns


def parse_polygon(text):
    """Arena corners from "x,y x,y ..." (metres, arena frame; at least 3 corners) as a k x 2 array."""
    try:
        corners = np.array([[parse_finite(v) for v in pair.split(",")] for pair in text.split()], dtype=float)
    except ValueError:
        raise ValueError(f"arena polygon '{text}': expected corners as 'x,y x,y ...' in metres") from None
    if corners.ndim != 2 or corners.shape[1] != 2 or corners.shape[0] < 3:
        raise ValueError(f"arena polygon '{text}': expected at least 3 finite corners 'x,y'")
    return corners


def _reject_first(path, bad, column, reason):
    """Raise _row_error for the first True row of `bad`, with reason(row index)."""
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise _row_error(path, i, column, reason(i))


def _row_error(path, i, column, reason):
    """RangeLogError for data row i (0-based), named by its data row (1 = first after the header)."""
    return RangeLogError(path, None, column, f"data row {i + 1}: {reason}")
