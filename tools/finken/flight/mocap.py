"""Motion-capture poses of a lab's flight: read, turned into the arena frame, cleaned, interpolated at any time.

The result (Poses) holds, per vehicle id: t (sorted, s), pos (n, 3) [m] in the arena frame (x east, y north, z up)
and quat (n, 4), scalar last (qx, qy, qz, qw), turning the body frame (x forward, y left, z up) into the arena
frame; Poses.at(vehicle, t) interpolates them. Nothing is written.

Formats (fmt="auto" tells them by content; a .log/.data name is Paparazzi's):
- "csv": `t, body, x, y, z, qx, qy, qz, qw` (any order, other columns ignored); body is a name ("finken3") or a
  number. Metres unless `unit`.
- "poses": our simulator's poses.csv, `t, vehicle, x, y, z` and `yaw` [rad, from x toward y] or `qx, qy, qz, qw`
  (the quaternion if both); vehicle is the id itself. Already the arena frame.
- "motive": an OptiTrack Motive CSV export, format version 1.2x-1.3x (finken.flight.motive reads it): its rigid
  bodies' quaternions and positions, in its "Length Units" (`unit` overrides); an empty cell: the body was lost in
  that frame.
- "paparazzi": the positions in Paparazzi's server log pair (.log/.data, finken.flight.server_log.ServerLog): the
  motion capture as it was sent to the copter, EXTERNAL_POSE (enu_x/y/z [m]; body_qi/qx/qy/qz, whose body frame
  sw/airborne/modules/gps/gps_datalink.c reads as x right, y forward, z up: turned here by +90 deg about z into
  ours) or REMOTE_GPS_LOCAL (enu_x/y/z; course [deg] from north, clockwise: level attitude assumed), if the log
  holds them (sent through RAW_DATALINK); else the copter's own estimate ROTORCRAFT_FP (east, north, up and phi,
  theta, psi: integers times their alt_unit_coef in alt_unit, from the .log's definitions; Paparazzi's Euler angles
  of the body x forward, y right, z down in north-east-down, turned here into ours in ENU). `message` picks one.
  Times are the .data's (the server's clock); the vehicle is the aircraft id.

Frames. The motion capture's frame is turned into the arena's by `up` and then `transform`:
- up "y": a y-up frame (Motive's default) becomes z-up by a rotation of +90 deg about x: arena (x, y, z) = (x_m,
  -z_m, y_m); quaternions are turned on both sides (q_c q q_c^-1), so a body frame defined y-up becomes the same
  body's frame z-up (x forward stays x). Default "y" for Motive, "z" for the others (override by `up` or
  transform's `up=`).
- transform (parse_transform "yaw=90,x=1.5,y=2.0,z=0"): arena = R_z(yaw) p + (x, y, z), quaternion q_yaw q.

Bodies to vehicles: `bodies` {body name: vehicle id, or None to leave the body out} (parse_bodies "finken1=1,
wand=-"); else the number at the end of the name ("finken12" -> 12, "Rigid Body 3" -> 3); a body with neither is
refused naming it and its line. Two bodies on one vehicle are refused.

Cleaning, per body, in file order: a time going back is refused (file:line); a repeated time keeps the first
sample (the others counted in `duplicates`); a sample with an empty or non-finite position or a zero or non-finite
quaternion is lost (runs of them in `lost`; quaternions are normalised); a sample farther from the last good one
than max_speed_mps times the time between them plus jump_tolerance_m is a jump: left out and named in `jumps`
(vehicle, body, line, t, distance, speed).

Poses.at(vehicle, t) -> (pos (n, 3), quat (n, 4), valid (n,)): positions interpolated linearly, quaternions by
slerp (shortest arc); valid is False (and pos, quat NaN) where t is outside the vehicle's samples, between two
samples further apart than its max_gap_s, or between two samples with lost ones between them (a time equal to a
sample's is valid). max_gap_s default: max(MIN_GAP_S, GAP_PERIODS x the body's median sample period): 0.1 s for a
motion capture at 100-120 Hz (the copter, at most 1 m/s with about 1 m/s^2, strays about a dt^2/8 = 1 mm from the
chord over 0.1 s), three periods for slower sources such as ROTORCRAFT_FP telemetry.
"""
import csv
import math
import re
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from finken.flight.csv_table import read_table
from finken.flight.errors import FlightInputError
from finken.flight.motive import read_motive
from finken.flight.server_log import ServerLog, field_values
from finken.rangelog_columns import parse_items
from finken.text_numbers import MAX_ID, parse_finite, parse_id

__all__ = ["FORMATS", "GAP_PERIODS", "JUMP_TOLERANCE_M", "MAX_SPEED_MPS", "MIN_GAP_S", "Duplicate", "Jump", "Lost",
           "Poses", "Transform", "detect_format", "parse_bodies", "parse_transform", "read_mocap"]

FORMATS = ("csv", "poses", "motive", "paparazzi")
MAX_SPEED_MPS = 5.0       # a jump: faster than this (the FINken flies at most 1 m/s) ...
JUMP_TOLERANCE_M = 0.05   # ... plus this much noise [m]
MIN_GAP_S = 0.1           # max_gap_s is at least this [s] ...
GAP_PERIODS = 3           # ... or this many median sample periods
PAPARAZZI_MESSAGES = (("EXTERNAL_POSE", "datalink"), ("REMOTE_GPS_LOCAL", "datalink"), ("ROTORCRAFT_FP", "telemetry"))
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
TRANSFORM_KEYS = ("yaw", "x", "y", "z", "up")
_Y_UP = np.array([math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)])   # +90 deg about x: y-up to z-up
_Z_90 = np.array([0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5)])   # +90 deg about z
_ENU_OF_NED = np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
_FRD_OF_FLU = np.diag([1.0, -1.0, -1.0])


# ------------------------------------------------------------------ options

@dataclass(frozen=True)
class Transform:
    """The motion capture's frame to the arena's: arena = R_z(yaw_deg) p + offset_m (after `up`, if given)."""
    yaw_deg: float = 0.0
    offset_m: tuple = (0.0, 0.0, 0.0)
    up: str = None   # "y" or "z"; None: the format's default


def _items(text, option, key, what):
    """The `key=what` items of an option's text (rangelog_columns.parse_items), its errors naming the option."""
    try:
        return parse_items(text or "", what, key, key)
    except ValueError as err:
        raise ValueError(f"{option} '{text}': {err}") from None


def parse_transform(text):
    """`yaw=90,x=1.5,y=2.0,z=0,up=y` (degrees about z, metres; any subset, any order) as a Transform; ValueError
    naming an unknown or repeated key or a bad value."""
    values = {}
    for key, value in _items(text, "transform", "key", "value"):
        if key not in TRANSFORM_KEYS:
            raise ValueError(f"transform '{text}': unknown key '{key}' (known: {', '.join(TRANSFORM_KEYS)})")
        if key in values:
            raise ValueError(f"transform '{text}': key '{key}' given twice")
        if key == "up":
            if value not in ("y", "z"):
                raise ValueError(f"transform '{text}': up='{value}': expected y or z")
            values[key] = value
        else:
            try:
                values[key] = parse_finite(value)
            except ValueError as err:
                raise ValueError(f"transform '{text}': {key}: {err}") from None
    return Transform(values.get("yaw", 0.0), (values.get("x", 0.0), values.get("y", 0.0), values.get("z", 0.0)),
                     values.get("up"))


def parse_bodies(text):
    """`finken1=1,finken2=2,wand=-` as {body name: vehicle id, None for '-' (left out)}; ValueError naming a bad
    item."""
    bodies = {}
    for name, value in _items(text, "bodies", "body", "vehicle"):
        if name in bodies:
            raise ValueError(f"bodies '{text}': body '{name}' given twice")
        if value == "-":
            bodies[name] = None
            continue
        try:
            bodies[name] = parse_id(value)
        except ValueError as err:
            raise ValueError(f"bodies '{text}': {name}: {err} (or '-' to leave the body out)") from None
    return bodies


# ------------------------------------------------------------------ the result

@dataclass
class Jump:
    """A sample left out: `distance` [m] from the body's last good sample, at `speed` [m/s]."""
    vehicle: int
    body: str
    line: int
    t: float
    distance: float
    speed: float


@dataclass
class Lost:
    """A run of `samples` consecutive samples where the body was lost, from t_first to t_last [s]; `line` the
    first's."""
    vehicle: int
    body: str
    line: int
    t_first: float
    t_last: float
    samples: int


@dataclass
class Duplicate:
    """A sample at the same time as the body's previous one: left out (the first is kept)."""
    vehicle: int
    body: str
    line: int
    t: float


@dataclass
class Poses:
    """Each vehicle's cleaned poses in the arena frame (dicts keyed by vehicle id) and what the cleaning did."""
    path: str
    format: str                 # csv, poses, motive, or paparazzi:<message>
    t: dict                     # {vehicle: (n,) [s], increasing}
    pos: dict                   # {vehicle: (n, 3) [m], arena frame}
    quat: dict                  # {vehicle: (n, 4) unit, scalar last, body (x fwd, y left, z up) to arena}
    lines: dict                 # {vehicle: (n,) int64, each sample's line in `path`}
    body: dict                  # {vehicle: the body's name in the file}
    max_gap_s: dict             # {vehicle: the longest gap interpolated across [s]}
    lost_after: dict            # {vehicle: (n - 1,) bool: lost samples lie between samples k and k + 1}
    jumps: list = field(default_factory=list)        # [Jump]
    lost: list = field(default_factory=list)        # [Lost]
    duplicates: list = field(default_factory=list)  # [Duplicate]
    up: str = "z"
    transform: Transform = Transform()
    unit: str = "m"
    notes: list = field(default_factory=list)       # what the reader assumed, in words

    @property
    def vehicles(self):
        return sorted(self.t)

    def at(self, vehicle, t):
        """(pos (n, 3) [m], quat (n, 4), valid (n,) bool) of `vehicle` at times t [s]: linear interpolation of
        the position and slerp of the quaternion between the samples around each time; NaN and valid False outside
        the samples, across a gap longer than max_gap_s[vehicle] or lost samples (all False for a vehicle without
        poses)."""
        t = np.atleast_1d(np.asarray(t, dtype=np.float64))
        n = len(t)
        pos, quat, valid = np.full((n, 3), np.nan), np.full((n, 4), np.nan), np.zeros(n, dtype=bool)
        key = int(vehicle)
        if key not in self.t or len(self.t[key]) == 0 or n == 0:
            return pos, quat, valid
        ts, ps, qs = self.t[key], self.pos[key], self.quat[key]
        if len(ts) == 1:
            valid = t == ts[0]
            pos[valid], quat[valid] = ps[0], qs[0]
            return pos, quat, valid
        i1 = np.clip(np.searchsorted(ts, t, side="right"), 1, len(ts) - 1)
        i0 = i1 - 1
        dt = ts[i1] - ts[i0]
        on_sample = (t == ts[i0]) | (t == ts[i1])
        valid = (t >= ts[0]) & (t <= ts[-1]) & (on_sample | ((dt <= self.max_gap_s[key]) & ~self.lost_after[key][i0]))
        i0, i1 = i0[valid], i1[valid]
        u = ((t[valid] - ts[i0]) / (ts[i1] - ts[i0]))[:, None]
        pos[valid] = ps[i0] + u * (ps[i1] - ps[i0])
        quat[valid] = slerp(qs[i0], qs[i1], u[:, 0])
        return pos, quat, valid

    def report_lines(self):
        """What was read and left out, in words (one line each)."""
        out = [f"{self.path}: {self.format}, {len(self.t)} vehicles: " + ", ".join(
            f"{v} ({self.body[v]}, {len(self.t[v])} poses, gaps up to {self.max_gap_s[v]:g} s)" for v in self.vehicles)]
        for v in self.vehicles:
            jumps = [j for j in self.jumps if j.vehicle == v]
            lost = [k for k in self.lost if k.vehicle == v]
            duplicates = [d for d in self.duplicates if d.vehicle == v]
            if jumps:
                worst = max(jumps, key=lambda j: j.distance)
                out.append(f"vehicle {v}: {len(jumps)} jumps left out (largest {worst.distance:.3f} m at "
                           f"t = {worst.t:.3f} s, line {worst.line})")
            if lost:
                out.append(f"vehicle {v}: {sum(k.samples for k in lost)} samples lost in {len(lost)} runs (the "
                           f"first at t = {lost[0].t_first:.3f} s, line {lost[0].line})")
            if duplicates:
                out.append(f"vehicle {v}: {len(duplicates)} samples at a repeated time left out")
        return out + list(self.notes)


def slerp(q0, q1, u):
    """Spherical linear interpolation between unit quaternions q0 and q1 ((n, 4), scalar last) at fractions u
    (n,), along the shorter arc; unit quaternions."""
    q0, q1, u = np.asarray(q0, float), np.asarray(q1, float), np.asarray(u, float)
    dot = np.sum(q0 * q1, axis=-1)
    q1 = np.where((dot < 0)[..., None], -q1, q1)
    dot = np.clip(np.abs(dot), 0.0, 1.0)
    theta = np.arccos(dot)
    sin_theta = np.sin(theta)
    near = sin_theta < 1e-9
    safe = np.where(near, 1.0, sin_theta)
    w0 = np.where(near, 1.0 - u, np.sin((1.0 - u) * theta) / safe)
    w1 = np.where(near, u, np.sin(u * theta) / safe)
    q = w0[..., None] * q0 + w1[..., None] * q1
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def quat_mul(a, b):
    """Hamilton product a b of quaternions, scalar last (broadcast over leading axes)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    x1, y1, z1, w1 = np.moveaxis(a, -1, 0)
    x2, y2, z2, w2 = np.moveaxis(b, -1, 0)
    return np.stack([w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
                     w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2], axis=-1)


def quat_of_yaw(yaw):
    """Quaternions (n, 4) of rotations by yaw [rad] about z."""
    yaw = np.asarray(yaw, float)
    zero = np.zeros_like(yaw)
    return np.stack([zero, zero, np.sin(yaw / 2), np.cos(yaw / 2)], axis=-1)


# ------------------------------------------------------------------ reading

@dataclass
class _Body:
    """One body's samples as read, in file order, in the file's frame and metres (NaN: lost)."""
    name: str
    t: np.ndarray
    pos: np.ndarray
    quat: np.ndarray
    line: np.ndarray
    name_line: int            # where the body is named (for an error about it)
    vehicle: int = None       # the vehicle the format gives directly


def detect_format(path):
    """The format of the file at `path` (one of FORMATS), by name and content; FlightInputError if none fits."""
    path = str(path)
    if path.endswith((".log", ".data", ".data.gz", ".data.bz2")):
        return "paparazzi"
    number, first = _first_text_line(path)
    if first is None:
        raise FlightInputError(path, None, "empty file: no motion-capture data")
    if first.startswith("Format Version"):
        return "motive"
    if ServerLog.is_server_log(path):
        return "paparazzi"
    header = [cell.strip() for cell in next(csv.reader([first]))]
    if "body" in header:
        return "csv"
    if "vehicle" in header:
        return "poses"
    raise FlightInputError(path, number, "cannot tell the motion-capture format: expected a CSV with a 'body' "
                           "column (t, body, x, y, z, qx, qy, qz, qw), our poses.csv (t, vehicle, x, y, z, yaw), "
                           "a Motive export (first line 'Format Version,...') or a Paparazzi .log/.data")


def read_mocap(path, fmt="auto", bodies=None, transform=None, up=None, unit=None, max_speed_mps=MAX_SPEED_MPS,
               jump_tolerance_m=JUMP_TOLERANCE_M, max_gap_s=None, message=None):
    """Poses of the motion-capture file at `path`.

    fmt: "auto" or one of FORMATS; bodies: {body name: vehicle id or None} (or its text, parse_bodies);
    transform: a Transform (or its text, parse_transform); up: "y" or "z", the file's up axis (default "y" for
    Motive, "z" otherwise); unit: "m", "cm" or "mm", the file's length unit (Motive: its "Length Units");
    max_speed_mps, jump_tolerance_m: what makes a jump; max_gap_s: the longest gap interpolated across [s] (None:
    max(MIN_GAP_S, GAP_PERIODS median periods) per body); message: the Paparazzi message to read (EXTERNAL_POSE,
    REMOTE_GPS_LOCAL or ROTORCRAFT_FP; None: the first of these the log holds).
    Raises FlightInputError for a file it cannot use, ValueError for a bad option."""
    path = str(path)
    bodies = parse_bodies(bodies) if isinstance(bodies, str) else dict(bodies or {})
    transform = parse_transform(transform) if isinstance(transform, str) else (transform or Transform())
    if fmt == "auto":
        fmt = detect_format(path)
    if fmt not in FORMATS:
        raise ValueError(f"format '{fmt}': expected auto or one of {', '.join(FORMATS)}")
    if unit is not None and unit not in UNITS:
        raise ValueError(f"unit '{unit}': expected one of {', '.join(UNITS)}")
    if up is not None and up not in ("y", "z"):
        raise ValueError(f"up '{up}': expected y or z")
    if up is not None and transform.up is not None and up != transform.up:
        raise ValueError(f"up '{up}' and the transform's up '{transform.up}' disagree")
    for name, value in (("max_speed_mps", max_speed_mps), ("jump_tolerance_m", jump_tolerance_m)):
        if not (value >= 0 and math.isfinite(value)):
            raise ValueError(f"{name} {value}: expected a finite number >= 0")
    if max_gap_s is not None and not max_gap_s > 0:
        raise ValueError(f"max_gap_s {max_gap_s}: expected a number > 0")
    notes = []
    if fmt == "csv":
        raw, file_unit, default_up = _read_plain_csv(path), "m", "z"
    elif fmt == "poses":
        raw, file_unit, default_up = _read_poses_csv(path), "m", "z"
    elif fmt == "motive":
        export = read_motive(path, unit)
        raw = [_Body(name, export.t, pos, quat, export.line, export.name_line)
               for name, (pos, quat) in export.bodies.items()]
        file_unit, default_up = export.unit, "y"
    else:
        raw, fmt, notes, path = _read_paparazzi(path, message)
        file_unit, default_up = "m", "z"
    unit = unit or file_unit
    up = up or transform.up or default_up
    scale = UNITS[unit]
    poses = Poses(path, fmt, {}, {}, {}, {}, {}, {}, {}, up=up, transform=transform, unit=unit, notes=notes)
    seen = {}
    for body in raw:
        vehicle = _vehicle_of(path, body, bodies)
        if vehicle is None:
            continue
        if vehicle in seen:
            raise FlightInputError(path, body.name_line, f"body '{body.name}' and body '{seen[vehicle]}' are both "
                                   f"vehicle {vehicle}: map one elsewhere (bodies='{body.name}=<id>' or "
                                   f"'{body.name}=-')")
        seen[vehicle] = body.name
        _add_track(poses, path, vehicle, body, scale, up, transform, max_speed_mps, jump_tolerance_m, max_gap_s)
    absent = [name for name in bodies if name not in {body.name for body in raw}]
    if absent:
        poses.notes.append("bodies given but not in the file: " + ", ".join(absent))
    if not poses.t:
        raise FlightInputError(path, None, "no body with a vehicle: nothing to read")
    return poses


def _vehicle_of(path, body, bodies):
    if body.name in bodies:
        return bodies[body.name]
    if body.vehicle is not None:
        return body.vehicle
    number = re.search(r"([0-9]+)\s*$", body.name)
    if number and int(number.group(1)) <= MAX_ID:
        return int(number.group(1))
    raise FlightInputError(path, body.name_line, f"body '{body.name}' has no vehicle: no number at the end of its "
                           f"name and none given (bodies='{body.name}=<id>', or '{body.name}=-' to leave it out)")


def _add_track(poses, path, vehicle, body, scale, up, transform, max_speed, tolerance, max_gap):
    """Check, turn and clean one body's samples and add them to `poses` as `vehicle`."""
    t, line = body.t, body.line
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        k = int(back[0])
        raise FlightInputError(path, int(line[k + 1]), f"t = {t[k + 1]:g} s goes back in time from t = {t[k]:g} s "
                               f"on line {line[k]} of the same body '{body.name}'", None)
    repeated = np.concatenate(([False], np.diff(t) == 0))
    for k in np.flatnonzero(repeated):
        poses.duplicates.append(Duplicate(vehicle, body.name, int(line[k]), float(t[k])))
    keep = ~repeated
    t, line, pos, quat = t[keep], line[keep], body.pos[keep] * scale, body.quat[keep]
    norm = np.linalg.norm(quat, axis=1)
    lost = ~(np.isfinite(pos).all(axis=1) & np.isfinite(norm) & (norm > 1e-9))
    good = ~lost
    quat = np.where(good[:, None], quat / np.where(good, norm, 1.0)[:, None], np.nan)
    pos = np.where(good[:, None], pos, np.nan)
    pos, quat = _to_arena(pos, quat, up, transform)
    _report_lost(poses, vehicle, body.name, t, line, lost)
    g = np.flatnonzero(good)
    jumped = _jumps(t[g], pos[g], max_speed, tolerance)
    for k in np.flatnonzero(jumped):
        i, last = g[k], g[_last_kept(jumped, k)]
        distance = float(np.linalg.norm(pos[i] - pos[last]))
        poses.jumps.append(Jump(vehicle, body.name, int(line[i]), float(t[i]), distance,
                                distance / float(t[i] - t[last])))
    kept = g[~jumped]
    lost_count = np.cumsum(lost)
    poses.t[vehicle], poses.pos[vehicle], poses.quat[vehicle] = t[kept], pos[kept], quat[kept]
    poses.lines[vehicle], poses.body[vehicle] = line[kept], body.name
    poses.lost_after[vehicle] = lost_count[kept][1:] > lost_count[kept][:-1]
    if max_gap is None:
        period = float(np.median(np.diff(t[kept]))) if len(kept) > 1 else 0.0
        max_gap = max(MIN_GAP_S, GAP_PERIODS * period)
    poses.max_gap_s[vehicle] = float(max_gap)


def _last_kept(jumped, k):
    """Index of the last sample before k that is not a jump (there is one: the first sample never is)."""
    j = k - 1
    while jumped[j]:
        j -= 1
    return j


def _jumps(t, pos, max_speed, tolerance):
    """Which samples are jumps: farther from the last good sample than max_speed x the time between + tolerance.
    Steps between neighbours are checked at once; only from a failing step on is the last good sample followed
    one sample at a time."""
    m = len(t)
    jumped = np.zeros(m, dtype=bool)
    if m < 2:
        return jumped
    failing = np.flatnonzero(np.linalg.norm(np.diff(pos, axis=0), axis=1) > max_speed * np.diff(t) + tolerance) + 1
    start = 0
    while True:
        k = np.searchsorted(failing, start)
        if k == len(failing):
            return jumped
        i = int(failing[k])
        last = i - 1
        while i < m and np.linalg.norm(pos[i] - pos[last]) > max_speed * (t[i] - t[last]) + tolerance:
            jumped[i] = True
            i += 1
        start = i + 1


def _report_lost(poses, vehicle, name, t, line, lost):
    if not lost.any():
        return
    edges = np.diff(np.concatenate(([0], lost.astype(np.int8), [0])))
    for first, end in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)):
        poses.lost.append(Lost(vehicle, name, int(line[first]), float(t[first]), float(t[end - 1]),
                               int(end - first)))


def _to_arena(pos, quat, up, transform):
    """The file's frame to the arena's: y-up to z-up if `up` is "y", then the transform (rows of NaN stay NaN)."""
    if up == "y":
        pos = np.stack([pos[:, 0], -pos[:, 2], pos[:, 1]], axis=1)
        inverse = _Y_UP * np.array([-1.0, -1.0, -1.0, 1.0])
        quat = quat_mul(quat_mul(_Y_UP, quat), inverse)
    yaw = math.radians(transform.yaw_deg)
    if yaw != 0.0:
        c, s = math.cos(yaw), math.sin(yaw)
        pos = pos @ np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]).T
        quat = quat_mul(quat_of_yaw(yaw), quat)
    return pos + np.asarray(transform.offset_m, dtype=float), quat


# ------------------------------------------------------------------ the formats

def _first_text_line(path):
    """(line number, the first non-blank line stripped) of a text file, or (None, None)."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as f:
            for number, text in enumerate(f, 1):
                if text.strip():
                    return number, text.strip()
    except OSError as err:
        raise FlightInputError(path, None, f"cannot read: {err.strerror or err}") from None
    return None, None


def _split_bodies(table, t, names, pos, quat, vehicle=None):
    """[_Body] of the rows of each body name, bodies in order of first appearance."""
    out = []
    order = {}
    for i, name in enumerate(names):
        order.setdefault(name, []).append(i)
    for name, rows in order.items():
        rows = np.asarray(rows)
        out.append(_Body(name, t[rows], pos[rows], quat[rows], table.line[rows], int(table.line[rows[0]]),
                         None if vehicle is None else int(vehicle[rows[0]])))
    return out


def _read_plain_csv(path):
    table = read_table(path, ("t", "body", "x", "y", "z", "qx", "qy", "qz", "qw"))
    names = table.columns["body"]
    for i, name in enumerate(names):
        if not name:
            table.fail(i, "body", "empty: every row names its body")
    t = table.numbers("t", finite=True)
    pos = np.column_stack([table.numbers(c, finite=False) for c in ("x", "y", "z")])
    quat = np.column_stack([table.numbers(c, finite=False) for c in ("qx", "qy", "qz", "qw")])
    return _split_bodies(table, t, names, pos, quat)


def _read_poses_csv(path):
    table = read_table(path, ("t", "vehicle", "x", "y", "z"), ("yaw", "qx", "qy", "qz", "qw"))
    has_quat = all(c in table.columns for c in ("qx", "qy", "qz", "qw"))
    if not has_quat and "yaw" not in table.columns:
        raise FlightInputError(path, table.header_line, "missing column: poses need yaw [rad] or qx, qy, qz, qw",
                               "yaw")
    t = table.numbers("t", finite=True)
    vehicle = table.ids("vehicle")
    pos = np.column_stack([table.numbers(c, finite=False) for c in ("x", "y", "z")])
    if has_quat:
        quat = np.column_stack([table.numbers(c, finite=False) for c in ("qx", "qy", "qz", "qw")])
    else:
        quat = quat_of_yaw(table.numbers("yaw", finite=False))
    return _split_bodies(table, t, [str(v) for v in vehicle], pos, quat, vehicle)


def _read_paparazzi(path, message):
    """([_Body], format name, notes, the .data's path) of the positions in a Paparazzi server log."""
    log = ServerLog.open(path)
    known = dict(PAPARAZZI_MESSAGES)
    if message is not None and message not in known:
        raise ValueError(f"message '{message}': expected one of {', '.join(known)}")
    wanted = {message: known[message]} if message else known
    found = log.messages(wanted)
    name = message or next((n for n, _ in PAPARAZZI_MESSAGES if len(found[n])), None)
    if name is None or len(found[name]) == 0:
        raise FlightInputError(log.data_path, None, "no " + (name or " or ".join(known)) + " message: no positions")
    m = found[name]
    notes = [log.definitions_note([name])] if name in log.builtin_used else []
    pos = np.column_stack([field_values(m, f) for f in ("east", "north", "up")] if name == "ROTORCRAFT_FP" else
                          [field_values(m, f) for f in ("enu_x", "enu_y", "enu_z")])
    vehicle = m.ac
    if name == "ROTORCRAFT_FP":
        euler = np.column_stack([field_values(m, f) for f in ("psi", "theta", "phi")])
        ned_of_frd = Rotation.from_euler("ZYX", euler).as_matrix()
        quat = Rotation.from_matrix(_ENU_OF_NED @ ned_of_frd @ _FRD_OF_FLU).as_quat()
        notes.append("ROTORCRAFT_FP: the copter's own position estimate, not the motion capture")
    elif name == "EXTERNAL_POSE":
        vehicle = m.integers("ac_id", "ac_id")
        q = np.column_stack([m.numbers(f) for f in ("body_qx", "body_qy", "body_qz", "body_qi")])
        quat = quat_mul(q, _Z_90)
    else:
        vehicle = m.integers("ac_id", "ac_id")
        quat = quat_of_yaw(math.pi / 2 - field_values(m, "course"))
        notes.append("REMOTE_GPS_LOCAL: heading only, level attitude assumed")
    bodies = []
    for v in np.unique(vehicle):
        rows = np.flatnonzero(vehicle == v)
        bodies.append(_Body(str(int(v)), m.t_log[rows], pos[rows], quat[rows], m.line[rows], int(m.line[rows[0]]),
                            int(v)))
    return bodies, f"paparazzi:{name}", notes, log.data_path
