"""Whole-simulation runs of the NPS-style host for `make bench`: speed, cost per copter-step, peak memory.

Each run is `nps_host --vehicles N --duration D --arena FILE --out TMP --quiet`, into a temporary folder deleted
after the run, of two kinds:
  batch   `--no-logs`: every sensor and every module of the airframe on, nothing written (a Monte-Carlo batch
          run that keeps what the modules compute); the headline figures sim_rtf_N, copter_step_us_N,
          peak_rss_mb_N
  logged  every log on (readings.csv, poses.csv, walls.csv, detections.csv): sim_rtf_logged_N, ...
Wall-clock time and the run's own peak resident memory come from wait4 in the small launcher
tests/bench/bench_spawn.c (forked from Python, a child would count the driver's memory in its peak).
D is chosen from a short pilot run so each timed run takes about `run_s` seconds, but at most
SWARM_MAX_DURATION_S for a large swarm (its swarm law contracts it later).

Derived figures per configuration and kind (median over the repetitions):
  real-time factor  D / wall time  [simulated s per wall-clock s]
  copter-step cost  wall time / (N x D x step rate)  [us]
  peak RSS          [MB]
and, for the batch runs, the clock the processor really ran at (tests/bench/bench_clock.c; /proc/cpuinfo of a
virtual machine may show only a nominal one): measured just before and just after each run, averaged;
and, from the first logged repetition's poses.csv, how crowded the swarm is: the median number of other copters
within the radio horizon (5 m) at the first and the last pose snapshot, against what a uniform layout at the
arena's density would give (so a layout far denser than intended shows in the table).
"""
import json
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

from finken.bench.arena import REFERENCE_COPTERS, arena_size_m
from finken.bench.programs import BenchProgramError, run_program
from finken.run_logs import read_poses

#: distance within which peers are measured by the ranging simulation: 2 x the ranging chain's 2.5 m
RADIO_HORIZON_M = 5.0
#: host step rate [Hz] (example airframe: PERIODIC_FREQUENCY 100)
STEP_RATE_HZ = 100.0
#: shortest and longest simulated time of a timed run [s]
MIN_DURATION_S, MAX_DURATION_S = 0.1, 100000.0
#: a pilot run shorter than this [s] is repeated with a longer simulated time
PILOT_MIN_WALL_S = 0.3
#: from this many copters on, a timed run lasts at most SWARM_MAX_DURATION_S of simulated time
LARGE_SWARM = 1000
#: longest simulated time [s] of a large swarm's run: the example airframe's swarm law then contracts the swarm
#: (1000 copters: 7.6 peers within 2.5 m at the start, 10 at 20 s, 14 at 30 s, 33 at 50 s), so a longer run no
#: longer measures the arena's density, which the issue sets (docs/performance.md, "What bounds each figure")
SWARM_MAX_DURATION_S = 20.0


class HostRunError(RuntimeError):
    """The host exited with an error."""


@dataclass
class HostRun:
    """One host run: simulated duration [s], wall-clock time [s], peak resident memory [MB]."""
    duration_s: float
    wall_s: float
    peak_rss_mb: float


def run_host(spawn: Path, host: Path, vehicles: int, duration_s: float, arena: Path,
             keep_poses: Path | None = None, logs: bool = True) -> HostRun:
    """Run the host once, through the bench_spawn launcher, with every log into a temporary folder (deleted
    after the run; poses.csv copied to keep_poses), or with no log at all (logs=False: a batch run)."""
    out = Path(tempfile.mkdtemp(prefix="finken_bench_"))
    try:
        cmd = [str(host), "--vehicles", str(vehicles), "--duration", f"{duration_s:.2f}", "--arena", str(arena),
               "--out", str(out), "--quiet"] + ([] if logs else ["--no-logs"])
        with open(out / "host.stderr", "w") as err:
            subprocess.run([str(spawn), str(out / "spawn.json"), *cmd], stdout=subprocess.DEVNULL, stderr=err,
                           check=False)
        try:
            spawned = json.loads((out / "spawn.json").read_text())
        except (OSError, json.JSONDecodeError):
            spawned = {"exit_status": -1}
        if spawned["exit_status"] != 0:
            raise HostRunError(f"{' '.join(cmd)}: exit status {spawned['exit_status']}: "
                               f"{(out / 'host.stderr').read_text().strip()}")
        if keep_poses is not None:
            shutil.copyfile(out / "poses.csv", keep_poses)
        return HostRun(duration_s, spawned["wall_s"], spawned["peak_rss_kb"] / 1024.0)   # ru_maxrss: KiB
    finally:
        shutil.rmtree(out, ignore_errors=True)


def clock_ghz(clock: Path) -> float:
    """The processor's effective clock now [GHz]: one short repetition of the bench_clock program."""
    figures = run_program(clock, ["--reps", 1])
    if len(figures) != 1 or figures[0]["name"] != "clock_ghz":
        raise BenchProgramError(f"{clock}: expected the one figure clock_ghz, got {figures}")
    return float(figures[0]["value"])


def max_duration_s(vehicles: int) -> float:
    """Longest simulated time [s] of a timed run: SWARM_MAX_DURATION_S for a large swarm. Smaller swarms are not
    cut: at 16 copters the radio horizon covers the whole arena anyway, and a 20 s run of 16 or 100 copters would
    be mostly start-up."""
    return SWARM_MAX_DURATION_S if vehicles >= LARGE_SWARM else MAX_DURATION_S


def pick_duration(spawn: Path, host: Path, vehicles: int, arena: Path, run_s: float, logs: bool = True) -> float:
    """Simulated time [s] for a run of about run_s wall-clock seconds (at most max_duration_s), from pilot runs."""
    duration_s = MIN_DURATION_S
    while True:
        pilot = run_host(spawn, host, vehicles, duration_s, arena, logs=logs)
        if pilot.wall_s >= PILOT_MIN_WALL_S or duration_s >= MAX_DURATION_S:
            break
        duration_s = min(MAX_DURATION_S, duration_s * min(20.0, 2.0 * PILOT_MIN_WALL_S / max(pilot.wall_s, 1e-3)))
    wanted = duration_s * run_s / pilot.wall_s
    return float(np.clip(round(wanted, 2), MIN_DURATION_S, max_duration_s(vehicles)))


def uniform_peers(width_m: float, depth_m: float, vehicles: int, r_m: float = RADIO_HORIZON_M) -> float:
    """Mean number of other copters within r_m of a copter when all are uniform in a width x depth rectangle.

    Two uniform points in a W x D rectangle are within r <= min(W, D) of each other with probability
    (pi r^2 W D - 4/3 r^3 (W + D) + r^4 / 2) / (W D)^2 (the border term removes what lies outside); every pair
    is within r when r reaches the diagonal. NaN in between (not needed here).
    """
    if r_m >= np.hypot(width_m, depth_m):
        return vehicles - 1.0
    if r_m > min(width_m, depth_m):
        return float("nan")
    area = width_m * depth_m
    p = (np.pi * r_m ** 2 * area - 4.0 / 3.0 * r_m ** 3 * (width_m + depth_m) + r_m ** 4 / 2.0) / area ** 2
    return (vehicles - 1.0) * p


def crowding(poses_csv: Path, arena: Path, vehicles: int) -> dict:
    """Median number of other copters within RADIO_HORIZON_M at the first and last snapshot of poses.csv, and
    the mean a uniform layout over the arena's bounding box would give (uniform_peers)."""
    data = read_poses(poses_csv)
    width_m, depth_m = arena_size_m(arena)
    r = RADIO_HORIZON_M
    expected = uniform_peers(width_m, depth_m, vehicles)
    medians = []
    for t in (data["t"].min(), data["t"].max()):
        at = data["t"] == t
        xy = np.column_stack([data["x"][at], data["y"][at]])
        counts = np.array([len(n) - 1 for n in cKDTree(xy).query_ball_point(xy, r)])
        medians.append(float(np.median(counts)))
    return {"peers_start": medians[0], "peers_end": medians[1], "peers_uniform": float(expected)}


def timed_runs(spawn: Path, host: Path, vehicles: int, arena: Path, label: str, reps: int, run_s: float,
               logs: bool, keep_poses: Path | None = None, clock: Path | None = None) -> list[dict]:
    """sim_rtf, copter_step_us and peak_rss_mb of `reps` runs of one kind (names: <figure>[_logged]_<label>);
    poses.csv of the first run is copied to keep_poses. With the bench_clock program `clock`, also clock_ghz
    (the effective clock around each run: the mean of one measurement just before and one just after)."""
    duration_s = pick_duration(spawn, host, vehicles, arena, run_s, logs=logs)
    runs, clocks = [], []
    for k in range(reps):
        before = clock_ghz(clock) if clock else None
        runs.append(run_host(spawn, host, vehicles, duration_s, arena, keep_poses=keep_poses if k == 0 else None,
                             logs=logs))
        if clock:
            clocks.append(0.5 * (before + clock_ghz(clock)))
    steps = duration_s * STEP_RATE_HZ
    kind = "_logged" if logs else ""

    def result(name, values, unit):
        values = sorted(values)
        return {"name": f"{name}{kind}_{label}", "value": float(np.median(values)), "unit": unit, "reps": reps,
                "min": values[0], "max": values[-1]}

    return [
        result("sim_rtf", [r.duration_s / r.wall_s for r in runs], "x"),
        result("copter_step_us", [1e6 * r.wall_s / (vehicles * steps) for r in runs], "us"),
        result("peak_rss_mb", [r.peak_rss_mb for r in runs], "MB"),
        {"name": f"sim_seconds{kind}_{label}", "value": duration_s, "unit": "s", "reps": 1},
    ] + ([result("clock_ghz", clocks, "GHz")] if clocks else [])


def host_figures(spawn: Path, host: Path, vehicles: int, arena: Path, label: str, reps: int, run_s: float,
                 work: Path, logged: bool = True, clock: Path | None = None) -> list[dict]:
    """Bench results of one configuration (names end in label): the batch runs (with the machine's clock around
    each, given the bench_clock program) and, when `logged`, the logged runs and the crowding of the swarm."""
    results = timed_runs(spawn, host, vehicles, arena, label, reps, run_s, logs=False, clock=clock)
    if not logged:
        return results
    poses = work / f"poses_{label}.csv"
    results += timed_runs(spawn, host, vehicles, arena, label, reps, run_s, logs=True, keep_poses=poses)
    crowd = crowding(poses, arena, vehicles)
    poses.unlink()
    return results + [
        {"name": f"peers_5m_start_{label}", "value": crowd["peers_start"], "unit": "copters", "reps": 1},
        {"name": f"peers_5m_end_{label}", "value": crowd["peers_end"], "unit": "copters", "reps": 1},
        {"name": f"peers_5m_uniform_{label}", "value": crowd["peers_uniform"], "unit": "copters", "reps": 1},
    ]


def startup_figure(spawn: Path, host: Path, arena: Path, reps: int) -> dict:
    """Wall-clock time [ms] of a 4-copter run of zero simulated seconds: load, set-up, tear-down."""
    times = sorted(1e3 * run_host(spawn, host, REFERENCE_COPTERS, 0.0, arena).wall_s for _ in range(reps))
    return {"name": "host_startup_ms", "value": float(np.median(times)), "unit": "ms", "reps": reps,
            "min": times[0], "max": times[-1]}
