"""The true range of each reading of a lab's flight, and the context columns our simulator writes, from the copters'
poses (motion capture, on the copters' clock already) and the arena as drawn.

Sonar: a ray from the sonar's mount (finken.flight.mounts) along its boresight, both turned by the copter's attitude
(roll and pitch included, where the simulator keeps the sonars level), against the walls at rest, the other copters
(vertical cylinders at their poses) and the floor: libfinken_nps's own ray casts (nps_flight_truth.h), so the truth
is the simulator's wherever the two see the same scene. Ranging: the distance between the two copters' centres,
where the simulator puts the antennas.

Context columns, as the simulator writes them (../shared/spec/range-log.md):
- ctx_target_copter: the sonar's first hit is a copter; ctx_target_obstacle: an interior obstacle; ctx_wall_dist: the copter's horizontal distance to the
  nearest wall; ctx_floor: the floor's material under a downward sonar (0 on other rows); ctx_speed: the copter's
  speed over the motion capture's samples; ctx_blocked (ranging): a wall or a third copter cuts the line.
- ctx_facing_sonars, ctx_crosstalk_path, ctx_trigger_offset: the other copters' sonars facing this one with a clear
  path (the simulator's cone and range test) whose pulse arrives while this sonar listens,
  0 <= trigger offset + path / c <= listening window (nps_crosstalk_arrives); the trigger offset is the emitter's
  reading of that sonar minus this reading, both in the records (every sonar of the ring reads the same window after
  its trigger); an emitter with no reading of that sonar in the records is counted as heard, offset NaN. The
  nearest heard one gives the path and the offset.
"""
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np
from scipy.spatial.transform import Rotation

from finken import _native
from finken.rangelog import SENSOR_NAMES, RangeLog
from finken.sim_report.arena_plot import read_walls
from finken.sim_report.metrics import arena_polygon

REPO = _native.REPO
NPS = REPO / "sw" / "simulator" / "nps"
HIT_COPTER, HIT_OBSTACLE = 2, 4     # enum nps_hit_kind
SPEED_STEP_S = 0.05     # half the interval of the central difference giving ctx_speed [s]
CTX_COLUMNS = ("ctx_facing_sonars", "ctx_target_copter", "ctx_blocked", "ctx_wall_dist", "ctx_speed",
               "ctx_crosstalk_path", "ctx_trigger_offset", "ctx_floor", "ctx_target_obstacle")


class Obstacle(NamedTuple):
    """An interior obstacle: its footprint (k, 2) [m], counter-clockwise, its height [m] and, for a circle, its
    centre and radius (x, y, r) [m] (None for a polygon)."""
    outline: np.ndarray
    height_m: float
    circle: tuple | None


class ArenaError(ValueError):
    """The arena file cannot be loaded (the loader's message names the file and line)."""


@dataclass
class SonarTiming:
    """When a sonar listens: the listening window after its trigger [s] and the speed of sound [m/s] (airframe
    SONAR_ARRAY_READ_DELAY slots of 1 / (5 SONAR_ARRAY_RATE) s; the module's defaults 2 and 20 Hz: 0.02 s)."""
    window_s: float = 2 / (5 * 20)
    speed_of_sound_mps: float = 343.0


class ArenaTruth:
    """The arena as drawn, loaded through libfinken_nps; `close()` frees it."""

    def __init__(self, path):
        self.ffi, self.lib = _load()
        err = self.ffi.new("char[]", _native.ERR_LEN)
        self.arena = self.lib.nps_arena_load(str(path).encode(), err, _native.ERR_LEN)
        if self.arena == self.ffi.NULL:
            raise ArenaError(self.ffi.string(err).decode())
        geometry = self.ffi.new("double[3]")
        self.lib.nps_flight_truth_sonar_geometry(self.arena, geometry, geometry + 1, geometry + 2)
        self.sonar_offset_m, self.sonar_half_angle_rad, self.sonar_range_m = geometry[0], geometry[1], geometry[2]
        body = self.lib.nps_arena_copter_make(self.arena, 0, 0.0, 0.0, 0.0, 0.0)
        self.copter_radius_m, self.copter_height_m = body.radius_m, body.height_m

    def close(self):
        if self.arena is not None:
            self.lib.nps_arena_free(self.arena)
            self.arena = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def outline(self):
        """The walls at rest as a polygon (n, 2) [m], in the file's order: a snapshot read back as make sim reads
        walls.csv."""
        err = self.ffi.new("char[]", _native.ERR_LEN)
        with tempfile.TemporaryDirectory() as scratch:
            path = Path(scratch) / "walls.csv"
            if self.lib.nps_arena_snapshot_file(self.arena, str(path).encode(), 0, err, _native.ERR_LEN) != 0:
                raise ArenaError(self.ffi.string(err).decode())
            return arena_polygon(read_walls(path))

    def obstacles(self, circle_corners=48):
        """The interior obstacles (Obstacle) in the file's order, a circle's footprint as the regular polygon of
        circle_corners corners."""
        found, height, circle = [], self.ffi.new("double *"), self.ffi.new("double[3]")
        while (is_circle := self.lib.nps_arena_obstacle_circle(self.arena, len(found), circle)) >= 0:
            corners = circle_corners if is_circle else self.lib.nps_arena_obstacle_outline(
                self.arena, len(found), self.ffi.NULL, 0, height)
            xy = self.ffi.new("double[]", 2 * corners)
            self.lib.nps_arena_obstacle_outline(self.arena, len(found), xy, corners, height)
            found.append(Obstacle(np.array(self.ffi.unpack(xy, 2 * corners)).reshape(corners, 2), height[0],
                                  tuple(circle) if is_circle else None))
        return found

    def place(self, ids, pos, yaw):
        """Put the copters `ids` at `pos` (n, 3) with headings `yaw` (n,) [rad] (those with a NaN pose are left out)."""
        present = np.isfinite(pos).all(axis=1) & np.isfinite(yaw)
        copters = self.ffi.new("struct nps_arena_copter[]", max(1, int(present.sum())))
        for k, i in enumerate(np.flatnonzero(present)):
            c = copters[k]
            c.id = int(ids[i])
            c.pos_m = pos[i].tolist()
            c.yaw_rad = float(yaw[i])
            c.radius_m, c.height_m = self.copter_radius_m, self.copter_height_m
        if self.lib.nps_arena_set_copters(self.arena, copters, int(present.sum())) != 0:
            raise ValueError("the arena refused the copters' poses")

    def sonar(self, rx_id, origin, direction):
        """nps_flight_truth_sonar for copter rx_id's ray, the copters placed; the C struct."""
        out = self.ffi.new("struct nps_flight_sonar_truth *")
        if self.lib.nps_flight_truth_sonar(self.arena, int(rx_id), origin.tolist(), direction.tolist(), out) != 0:
            raise ValueError(f"copter {rx_id} is not in the arena")
        return out

    def blocked(self, p_a, p_b, id_a, id_b):
        """ctx_blocked: 1 if a wall or a third copter cuts the line between copters id_a at p_a and id_b at p_b."""
        return self.lib.nps_raycast_line_blocked(self.arena, p_a.tolist(), p_b.tolist(), int(id_a), int(id_b),
                                                 self.ffi.NULL)

    def wall_dist(self, p):
        """ctx_wall_dist: horizontal distance from p to the nearest wall at rest [m]."""
        return self.lib.nps_raycast_wall_dist(self.arena, p.tolist())


_loaded = None


def _load():
    """(ffi, lib) with the arena and flight-truth declarations."""
    global _loaded
    if _loaded is None:
        from cffi import FFI
        path = _native.library_path()
        if not path.is_file():
            raise _native.NativeLibraryError(f"{path} does not exist: run `make build` in {REPO}")
        ffi = FFI()
        ffi.cdef((NPS / "nps_arena.cdef").read_text() + (NPS / "nps_flight_truth.cdef").read_text())
        _loaded = ffi, ffi.dlopen(str(path))
    return _loaded


def yaw_of(quat):
    """Heading [rad] of body-to-arena quaternions (n, 4), scalar last: atan2(2 (w z + x y), 1 - 2 (y^2 + z^2))."""
    x, y, z, w = quat.T
    return np.arctan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


@dataclass
class FlightPoses:
    """Every copter's pose at every reading's time: ids (m,), pos (m, n, 3), quat (m, n, 4), valid (m, n), speed (m, n)."""
    ids: np.ndarray
    pos: np.ndarray
    quat: np.ndarray
    valid: np.ndarray
    speed: np.ndarray


def poses_at(poses, ids, t, with_speed=True):
    """The poses of copters `ids` at times t (the motion capture's clock), from finken.flight.mocap.Poses, and with
    `with_speed` their speeds; a copter lost or not yet seen at a time has valid False there."""
    m, n = len(ids), len(t)
    pos, quat = np.full((m, n, 3), np.nan), np.full((m, n, 4), np.nan)
    valid, speed = np.zeros((m, n), bool), np.full((m, n), np.nan)
    for k, v in enumerate(ids):
        pos[k], quat[k], valid[k] = poses.at(v, t)
        if not with_speed:
            continue
        ahead, _, ok_ahead = poses.at(v, t + SPEED_STEP_S)
        behind, _, ok_behind = poses.at(v, t - SPEED_STEP_S)
        ok = ok_ahead & ok_behind
        speed[k, ok] = np.linalg.norm(ahead[ok] - behind[ok], axis=1) / (2 * SPEED_STEP_S)
        speed[k, ~ok & valid[k]] = 0.0   # at the edge of the samples: no central difference
    return FlightPoses(np.asarray(ids), pos, quat, valid, speed)


def range_log(arena, mounts, readings, poses, timing=SonarTiming(), context=True, progress=None):
    """The range log of `readings` (finken.flight.records.Records, t on the motion capture's clock): a RangeLog with
    true ranges and, with `context`, the context columns, rows in the readings' order. Every body of the motion
    capture is in the arena, whether it recorded or not; a row whose copter or peer the motion capture did not see
    then gets no true range (NaN: the caller leaves such rows out, clock.seen_by_mocap)."""
    t = np.asarray(readings.t, float)
    vehicle, sensor = readings.vehicle, readings.sensor
    peer = np.where(readings.peer >= 0, readings.peer, np.nan)   # the range log's empty peer on sonar rows
    ids = np.unique(np.concatenate([list(poses.vehicles), vehicle, readings.peer[readings.peer >= 0]])).astype(int)
    at = poses_at(poses, ids, t, with_speed=context)
    row_of = {v: k for k, v in enumerate(ids)}
    own = np.array([row_of[v] for v in vehicle], dtype=int)
    cols = np.arange(len(t))
    n = len(t)
    true_range = np.full(n, np.nan)
    ctx = {name: np.zeros(n) for name in CTX_COLUMNS}
    ctx["ctx_speed"] = at.speed[own, cols]
    facing = _Facing(n)
    yaw = yaw_of(at.quat.reshape(-1, 4)).reshape(at.valid.shape)
    own_quat = at.quat[own, cols]
    own_pos = at.pos[own, cols]
    is_ranging = sensor == "ranging"
    origin, direction = _sonar_rays(mounts, sensor, own_pos, own_quat, ~is_ranging)
    placed_at = None
    for done, i in enumerate(np.argsort(t, kind="stable")):   # in time order: the copters placed once per time
        if not at.valid[own[i], i] or (is_ranging[i] and not at.valid[row_of[int(peer[i])], i]):
            continue
        if t[i] != placed_at:
            arena.place(at.ids, at.pos[:, i], np.where(at.valid[:, i], yaw[:, i], np.nan))
            placed_at = t[i]
        if is_ranging[i]:
            q = row_of[int(peer[i])]
            true_range[i] = np.linalg.norm(at.pos[q, i] - own_pos[i])
            if not context:
                continue
            ctx["ctx_blocked"][i] = arena.blocked(own_pos[i], at.pos[q, i], vehicle[i], peer[i])
            ctx["ctx_wall_dist"][i] = arena.wall_dist(own_pos[i])
        else:
            hit = arena.sonar(vehicle[i], origin[i], direction[i])
            true_range[i] = hit.true_range_m
            if not context:
                continue
            ctx["ctx_target_copter"][i] = hit.hit_kind == HIT_COPTER
            ctx["ctx_target_obstacle"][i] = hit.hit_kind == HIT_OBSTACLE
            ctx["ctx_wall_dist"][i] = hit.wall_dist_m
            ctx["ctx_floor"][i] = hit.floor if sensor[i] == "sonar_down" else 0.0
            facing.add(i, hit)
        if progress is not None and done % 4096 == 0:
            progress(done, n)
    if context:
        facing.heard(t, vehicle, sensor, timing, ctx)
    return RangeLog(readings.path, t, vehicle.astype(float), sensor, peer, true_range, readings.measured,
                    ctx if context else {}, {}, readings.line)


def _sonar_rays(mounts, sensor, pos, quat, is_sonar):
    """Origins and unit directions (n, 3) of the sonar rows' rays in the arena frame (NaN on other rows)."""
    origin, direction = np.full(pos.shape, np.nan), np.full(pos.shape, np.nan)
    rows = np.flatnonzero(is_sonar & np.isfinite(quat).all(axis=1))
    if len(rows):
        turn = Rotation.from_quat(quat[rows])   # scipy's quaternions are scalar last, as the motion capture's
        mount = np.array([mounts.position[s] for s in sensor[rows]])
        bore = np.array([mounts.boresight[s] for s in sensor[rows]])
        origin[rows] = pos[rows] + turn.apply(mount)
        direction[rows] = turn.apply(bore)
    return origin, direction


class _Facing:
    """The facing sonars of every sonar reading, kept for the timing test once all readings are known."""

    def __init__(self, n):
        self.rows, self.copter, self.sonar, self.path_m, self.unlisted = [], [], [], [], np.zeros(n)

    def add(self, i, hit):
        for k in range(hit.listed):
            self.rows.append(i)
            self.copter.append(hit.facing_copter[k])
            self.sonar.append(hit.facing_sonar[k])
            self.path_m.append(hit.facing_path_m[k])
        self.unlisted[i] = hit.facing - hit.listed

    def heard(self, t, vehicle, sensor, timing, ctx):
        """Fill ctx_facing_sonars, ctx_crosstalk_path and ctx_trigger_offset (see the module docstring)."""
        rows, path_m = np.asarray(self.rows, int), np.asarray(self.path_m, float)
        copter, sonar = np.asarray(self.copter, int), np.asarray(self.sonar, int)
        offset = np.full(len(rows), np.nan)
        unrecorded = np.zeros(len(rows), bool)   # the emitter recorded nothing of that sonar: counted as heard
        for c, s in set(zip(self.copter, self.sonar)):
            pick = (copter == c) & (sonar == s)
            times = np.sort(t[(vehicle == c) & (sensor == SENSOR_NAMES[s])])   # enum nps_sonar's order
            if len(times):
                offset[pick] = _heard_offset(times, t[rows[pick]], path_m[pick], timing)
            else:
                unrecorded[pick] = True
        heard = ~np.isnan(offset) | unrecorded
        count, path, trigger = ctx["ctx_facing_sonars"], ctx["ctx_crosstalk_path"], ctx["ctx_trigger_offset"]
        count += self.unlisted
        for i, L, dt in zip(rows[heard][::-1], path_m[heard][::-1], offset[heard][::-1]):  # nearest written last
            count[i] += 1
            path[i], trigger[i] = L, dt


def _heard_offset(emitter_times, t, path_m, timing):
    """For receivers reading at t, the trigger offset (emitter reading minus this reading) of the emitter's pulse
    that arrives in the window, 0 <= offset + path / c <= window (the nearer of its two readings around t), else
    NaN."""
    travel = path_m / timing.speed_of_sound_mps
    k = np.searchsorted(emitter_times, t)
    result = np.full(len(t), np.nan)
    for j in (k, k - 1):   # the emitter's readings just after and just before
        ok = (j >= 0) & (j < len(emitter_times))
        dt = np.where(ok, emitter_times[np.clip(j, 0, len(emitter_times) - 1)] - t, np.nan)
        arrival = dt + travel
        take = ok & (arrival >= 0.0) & (arrival <= timing.window_s) & np.isnan(result)
        result[take] = dt[take]
    return result
