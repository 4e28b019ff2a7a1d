"""Synthetic ground truth for tests: copters wandering in the arena, their sonar and ranging true ranges and
context, as a range log without measurements (the simulator then adds them, hidden.py).

A plain 2-D test fixture, not a sensor model: copters are discs of radius COPTER_RADIUS_M at a fixed
height, moving with an Ornstein-Uhlenbeck velocity kept inside the arena; each carries four horizontal sonars
(front, right, back, left) and one down, and a ranging antenna. True ranges follow the range-log spec: along
the sonar's boresight to the first surface (a wall or another copter), between antennas for ranging. Context:
ctx_target_copter (first hit is a copter), ctx_facing_sonars and ctx_crosstalk_path (other copters' sonars
within each other's beam cone and range, and the distance to the nearest such one), ctx_blocked (a third
copter's disc cuts the line between two antennas), ctx_speed.
"""
import numpy as np

from finken.rangelog import RangeLog

#: FINken arena floor (x east, y north) [m]: the lab report's 3 m x 4 m (finken-environment-report.md 2.4.2).
ARENA_M = (3.0, 4.0)
#: Copter body radius [m] and flight height [m] (report section 2.1: fixed height of 60 cm).
COPTER_RADIUS_M, HEIGHT_M = 0.2, 0.6
#: Sonar beam half-angle [rad] and range [m] used for the facing test (a typical MaxBotix-class cone).
BEAM_HALF_ANGLE_RAD, SONAR_RANGE_M = np.radians(15.0), 3.0
#: Reading rates [Hz]: each sonar, each ranging pair.
SONAR_HZ, RANGING_HZ = 10.0, 10.0
#: Ornstein-Uhlenbeck velocity: stationary speed scale [m/s], correlation time [s]; yaw rate scale [rad/s].
SPEED_MPS, VEL_TAU_S, YAW_RATE = 0.45, 2.0, 0.3
SONARS = (("sonar_front", 0.0), ("sonar_right", -np.pi / 2), ("sonar_back", np.pi), ("sonar_left", np.pi / 2))


def trajectories(n_copters, duration_s, dt_s, rng):
    """Positions (T, N, 2) [m], yaws (T, N) [rad], speeds (T, N) [m/s] at times 0, dt, ..."""
    steps = int(round(duration_s / dt_s)) + 1
    margin = COPTER_RADIUS_M + 0.15
    lo, hi = np.array([margin, margin]), np.array(ARENA_M) - margin
    pos = np.empty((steps, n_copters, 2))
    pos[0] = lo + rng.random((n_copters, 2)) * (hi - lo)
    vel = rng.normal(0, SPEED_MPS / np.sqrt(2), (n_copters, 2))
    yaw = np.empty((steps, n_copters))
    yaw[0] = rng.uniform(-np.pi, np.pi, n_copters)
    speed = np.empty((steps, n_copters))
    a = np.exp(-dt_s / VEL_TAU_S)
    for k in range(steps):
        if k:
            vel = a * vel + np.sqrt(1 - a * a) * rng.normal(0, SPEED_MPS / np.sqrt(2), vel.shape)
            p = pos[k - 1] + vel * dt_s
            for d in range(2):        # reflect at the arena margin
                low, high = p[:, d] < lo[d], p[:, d] > hi[d]
                p[low, d] = 2 * lo[d] - p[low, d]
                p[high, d] = 2 * hi[d] - p[high, d]
                vel[low | high, d] *= -1
            pos[k] = p
            yaw[k] = yaw[k - 1] + rng.normal(0, YAW_RATE * np.sqrt(dt_s), n_copters)
        speed[k] = np.hypot(vel[:, 0], vel[:, 1])
    return pos, yaw, speed


def _ray_to_walls(p, d):
    """Distance from points p (M, 2) along unit directions d (M, 2) to the arena walls [m]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(d[:, 0] > 0, (ARENA_M[0] - p[:, 0]) / d[:, 0], np.where(d[:, 0] < 0, -p[:, 0] / d[:, 0], np.inf))
        ty = np.where(d[:, 1] > 0, (ARENA_M[1] - p[:, 1]) / d[:, 1], np.where(d[:, 1] < 0, -p[:, 1] / d[:, 1], np.inf))
    return np.minimum(tx, ty)


def _ray_to_disc(p, d, c, r):
    """Distance along rays (p, d) to discs (centres c, radius r) [m], inf when missed or behind."""
    m = c - p
    along = np.sum(m * d, axis=1)
    miss2 = np.sum(m * m, axis=1) - along ** 2
    half = np.sqrt(np.maximum(r * r - miss2, 0.0))
    hit = (miss2 <= r * r) & (along - half > 0)
    return np.where(hit, along - half, np.inf)


def ground_truth(n_copters=4, duration_s=120.0, seed=0):
    """A RangeLog of true ranges and context (measured all NaN) for `n_copters` over `duration_s`."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / (SONAR_HZ * len(SONARS))        # the ring fires its sonars in turn
    pos, yaw, speed = trajectories(n_copters, duration_s, dt, rng)
    cols = {k: [] for k in ("t", "vehicle", "sensor", "peer", "true_range", "ctx_target_copter",
                            "ctx_facing_sonars", "ctx_crosstalk_path", "ctx_blocked", "ctx_speed")}

    def add(t, vehicle, sensor, peer, rng_m, target=0.0, facing=0.0, path=0.0, blocked=0.0, spd=0.0):
        n = len(t)
        for key, v in (("t", t), ("vehicle", vehicle), ("peer", peer), ("true_range", rng_m),
                       ("ctx_target_copter", target), ("ctx_facing_sonars", facing), ("ctx_crosstalk_path", path),
                       ("ctx_blocked", blocked), ("ctx_speed", spd)):
            cols[key].append(np.broadcast_to(np.asarray(v, dtype=float), (n,)))
        cols["sensor"].append(np.full(n, sensor))

    steps = pos.shape[0]
    times = np.arange(steps) * dt
    for i in range(n_copters):
        for s, (name, ang) in enumerate(SONARS):
            k = np.arange(s, steps, len(SONARS))
            p, heading = pos[k, i], yaw[k, i] + ang
            d = np.column_stack([np.cos(heading), np.sin(heading)])
            wall = _ray_to_walls(p, d)
            copter = np.full(len(k), np.inf)
            facing = np.zeros(len(k))
            path = np.zeros(len(k))
            for j in range(n_copters):
                if j == i:
                    continue
                copter = np.minimum(copter, _ray_to_disc(p, d, pos[k, j], COPTER_RADIUS_M))
                m = pos[k, j] - p
                dist = np.hypot(m[:, 0], m[:, 1])
                bearing = np.arctan2(m[:, 1], m[:, 0])
                for _, ang_j in SONARS:   # j's sonar pointing back at i, i's pointing at j, within range
                    back = yaw[k, j] + ang_j
                    ok = ((np.abs(_wrap(bearing - heading)) < BEAM_HALF_ANGLE_RAD)
                          & (np.abs(_wrap(bearing + np.pi - back)) < BEAM_HALF_ANGLE_RAD) & (dist <= SONAR_RANGE_M))
                    path = np.where(ok & ((path == 0) | (dist < path)), dist, path)
                    facing += ok
            add(times[k], i + 1, name, np.nan, np.minimum(wall, copter), (copter < wall).astype(float),
                facing, path, 0.0, speed[k, i])
        k = np.arange(len(SONARS) - 1, steps, len(SONARS))
        add(times[k], i + 1, "sonar_down", np.nan, HEIGHT_M + 0.03 * np.sin(0.5 * times[k] + i), spd=speed[k, i])
        step = int(round(1.0 / (RANGING_HZ * dt)))
        k = np.arange(i, steps, step)
        for j in range(n_copters):
            if j == i:
                continue
            a, b = pos[k, i], pos[k, j]
            blocked = np.zeros(len(k))
            for m in range(n_copters):
                if m not in (i, j):
                    blocked = np.maximum(blocked, _segment_blocked(a, b, pos[k, m]))
            add(times[k], i + 1, "ranging", j + 1, np.hypot(*(b - a).T), blocked=blocked, spd=speed[k, i])
    data = {key: np.concatenate(v) for key, v in cols.items()}
    order = np.argsort(data["t"], kind="stable")
    data = {key: v[order] for key, v in data.items()}
    ctx = {key: data[key] for key in data if key.startswith("ctx_")}
    return RangeLog("<synthetic>", data["t"], data["vehicle"], data["sensor"].astype(str), data["peer"],
                    data["true_range"], np.full(len(order), np.nan), ctx, {})


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def _segment_blocked(a, b, c):
    """1 where disc c (radius COPTER_RADIUS_M) cuts the open segment a-b, else 0."""
    ab = b - a
    length2 = np.maximum(np.sum(ab * ab, axis=1), 1e-12)
    u = np.clip(np.sum((c - a) * ab, axis=1) / length2, 0, 1)
    closest = a + u[:, None] * ab
    dist = np.hypot(*(c - closest).T)
    return ((dist < COPTER_RADIUS_M) & (u > 0) & (u < 1)).astype(float)
