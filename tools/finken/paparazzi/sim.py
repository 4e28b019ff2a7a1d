"""A FINken swarm in Paparazzi's NPS: one simsitl process per aircraft, twice (wall detector on, then off), merged
logs and the report of `make sim` (`make paparazzi-sim`).

Steps (each printed):
  1. copy $PAPARAZZI_HOME to a scratch tree, lay our overlay over it, regenerate its headers (the user's tree is
     never modified);
  2. write two conf files with N aircraft each, ac_id 1..N (FINKEN_<i> on the example airframe with the run's seed,
     FINKEN_OFF_<i> on the same airframe with SWARM_USE_WALL_DETECTOR=FALSE), check the airframes against
     Paparazzi's airframe.dtd, and build every aircraft with Paparazzi's make (one build at a time);
  3. run 1 (detector on, logs in OUT) and run 2 (off, OUT/detector_off), each N simsitl processes in one shared
     world (FINKEN_WORLD, a name unique to the run) for DURATION simulated seconds; progress on one line;
  4. after each run, merge the per-aircraft logs finken_world wrote (OUT/raw) into readings.csv, poses.csv,
     detections.csv and walls.csv (finken.paparazzi.aircraft_logs);
  5. the report of `make sim` (tools/sim_report.py) on both runs.
Ctrl-C (or SIGTERM) stops every process with SIGTERM, merges what they wrote and exits non-zero. A process that
fails is named with the tail of its log; the others fly on.
"""
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from finken.paparazzi.aircraft_logs import KINDS, MergeError, merge_all, newest_time, raw_path
from finken.paparazzi.fleet import Member, run_fleet
from finken.paparazzi.ground import display_problem, ground_members, ground_programs
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.swarm_conf import swarm_airframe, swarm_conf, template_aircraft
from finken.paparazzi.tree import (AIRFRAME, CONF_XML, PaparazziFailed, build, check_airframe, prepare_scratch_tree,
                                   tree_problem)
from finken.progress_line import ProgressLine


@dataclass(frozen=True)
class Variant:
    key: str            # "on" / "off": file names, world names
    title: str          # for the user
    prefix: str         # aircraft names: prefix + ac_id
    subdir: str         # of OUT
    use_wall_detector: bool

    def airframe(self):
        return f"conf/airframes/finken/paparazzi_sim_{self.key}.xml"

    def conf(self):
        return f"conf/userconf/finken/paparazzi_sim_{self.key}.xml"

    def aircraft(self, vehicles):
        return [(f"{self.prefix}{i}", i) for i in range(1, vehicles + 1)]


VARIANTS = (Variant("on", "wall detector on", "FINKEN_", "", True),
            Variant("off", "wall detector off", "FINKEN_OFF_", "detector_off", False))


class Interrupted(Exception):
    """SIGINT or SIGTERM to the launcher."""


def wall_limit_s(duration_s, time_factor):
    """How long a run may take on the wall clock before its processes are stopped."""
    return duration_s / time_factor * 4 + 60


def ivy_bus(base_port, ac_id=0):
    """The Ivy bus of aircraft `ac_id` (1..255, Paparazzi's ids), or of the ground programs (0).
    Each NPS process has a bus of its own: NPS sends on Ivy from one thread while Ivy's loop serves the bus's other
    programs in another, and with several NPS processes on one bus one died in pcre_exec (libivy) in 2 of 27
    four-aircraft runs here (with a bus each, an NPS process has no peer whose bindings it matches: none of 26).
    The ground segment does not need them on its bus: telemetry and uplink go through `link` over UDP."""
    return f"127.255.255.255:{base_port + ac_id}"


def run_base_port(pid):
    """Ports base..base+255 for the buses of one launcher (distinct for launchers side by side)."""
    return 10000 + (pid % 200) * 256


def simsitl_command(tree, aircraft, time_factor, bus):
    return [Path(tree) / "var/aircrafts" / aircraft / "nps/simsitl", "--norc", "--time_factor", f"{time_factor:g}",
            "--ivy_bus", bus]


def world_env(env, world, run_id, aircraft, raw_dir, duration_s, pose_rate_hz=None):
    """The environment of one run's processes: the shared world's name, the run's id, the swarm's size (it sets
    where each aircraft starts), where to log, how long, and, when given, the pose rows per second (else the
    airframe's FINKEN_WORLD_POSES_PERIOD)."""
    run_env = dict(env, FINKEN_WORLD=world, FINKEN_WORLD_RUN=run_id, FINKEN_WORLD_AIRCRAFT=str(aircraft),
                   FINKEN_WORLD_OUT=str(raw_dir), FINKEN_WORLD_DURATION=f"{duration_s:g}")
    if pose_rate_hz is not None:
        run_env["FINKEN_WORLD_POSE_RATE"] = repr(float(pose_rate_hz))
    return run_env


def max_aircraft(world_header=REPO_ROOT / "sw/simulator/nps/nps_world_link.h"):
    """How many aircraft a shared world holds (NPS_WORLD_MAX_AIRCRAFT of the simulator's header)."""
    match = re.search(r"#define\s+NPS_WORLD_MAX_AIRCRAFT\s+(\d+)", Path(world_header).read_text())
    if not match:
        raise PaparazziFailed(f"{world_header}: no NPS_WORLD_MAX_AIRCRAFT")
    return int(match[1])


def _logged_until(raw_dir, ac_id):
    """The newest row time among an aircraft's logs so far (None before any row reached a file; the logs are
    buffered, the poses log by a few seconds, the readings by up to 1 MiB)."""
    times = [t for t in (newest_time(raw_path(raw_dir, kind, ac_id)) for kind in KINDS) if t is not None]
    return max(times, default=None)


def _progress_text(title, aircraft, flying, raw_dir, duration_s, time_factor, elapsed_s):
    """`title: 12.0/20 s simulated (by the clock; logs of the slowest at 9.8 s), 2/2 aircraft flying, 3 s wall`:
    the wall clock times the time factor, and how far the logs of the flying aircraft have got."""
    done = min(elapsed_s * time_factor, duration_s)
    logged = [_logged_until(raw_dir, ac_id) for name, ac_id in aircraft if name in flying]
    logs = f"; logs of the slowest at {min(logged):.1f} s" if logged and None not in logged else ""
    return (f"  {title}: {done:6.1f}/{duration_s:g} s simulated (by the clock{logs}), {len(flying)}/{len(aircraft)} "
            f"aircraft flying, {elapsed_s:.0f} s wall")


def report_failure(ended):
    print(f"  {ended.name} ended with {ended.how}" + (f" ({ended.stopped})" if ended.stopped else "") +
          "; the last lines of its log:", flush=True)
    for line in ended.log_tail:
        print(f"      {line}")


def _report_merge(outcome, raw_dir, ids):
    """Print what each merge gave; returns the kinds merged completely (a file from every aircraft)."""
    for kind in KINDS:
        result = outcome[kind]
        if isinstance(result, MergeError):
            print(f"  {kind}.csv: NOT merged ({result}); an earlier {kind}.csv there is left as it was")
            continue
        if result.written:
            print(f"  {kind}.csv: {result.rows} rows from {len(ids) - len(result.missing) - len(result.empty)} of "
                  f"{len(ids)} aircraft -> {result.path}")
        elif len(result.missing) == len(ids):
            hint = " (a finken_world without the shared world writes only readings_ and walls_)" \
                if kind in ("poses", "detections") else ""
            print(f"  {kind}.csv: not written: no aircraft wrote {kind}_<id>.csv in {raw_dir}{hint}")
        else:
            print(f"  {kind}.csv: not written: no {kind}_<id>.csv in {raw_dir} has a header line")
        if result.missing and len(result.missing) < len(ids):
            print(f"      missing: {', '.join(p.name for p in result.missing)}")
        if result.empty:
            print(f"      empty, not even a header (the process ended before its first write reached the file): "
                  f"{', '.join(p.name for p in result.empty)}")
        for warning in result.warnings:
            print(f"      warning: {warning}")
    return [kind for kind in KINDS if not isinstance(outcome[kind], MergeError) and outcome[kind].complete]


@dataclass
class RunResult:
    fleet: object           # fleet.FleetOutcome
    complete_kinds: list    # kinds merged from every aircraft

    @property
    def ok(self):
        return (not self.fleet.failures() and not self.fleet.interrupted and not self.fleet.timed_out
                and len(self.complete_kinds) == len(KINDS))


def fly_and_merge(title, aircraft, env, cwd, out, logs, duration_s, time_factor, world, run_id, helpers=(),
                  pose_rate_hz=None):
    """Run one swarm: `aircraft` is a list of (name, ac_id, command); each process gets the shared world's
    variables (world_env, with pose_rate_hz) and logs to logs/<name>.log; `helpers` (fleet.Member) run beside
    them. Then merge the per-aircraft logs of out/raw into out. Returns a RunResult (printing as it goes)."""
    out, raw = Path(out), Path(out) / "raw"
    shutil.rmtree(raw, ignore_errors=True)
    raw.mkdir(parents=True)
    run_env = world_env(env, world, run_id, len(aircraft), raw, duration_s, pose_rate_hz)
    members = [Member(name, command, Path(logs) / f"{name}.log", run_env, cwd) for name, _, command in aircraft]
    names, ids = [(name, ac_id) for name, ac_id, _ in aircraft], [ac_id for _, ac_id, _ in aircraft]
    limit = wall_limit_s(duration_s, time_factor)
    print(f"  {title}: {len(aircraft)} processes, world {world}, logs {raw}, wall-time limit {limit:.0f} s",
          flush=True)
    progress = ProgressLine()

    def tick(flying, elapsed):
        progress.show(_progress_text(title, names, flying, raw, duration_s, time_factor, elapsed))

    def failure(ended):
        progress.done()
        report_failure(ended)

    fleet = run_fleet(members + list(helpers), limit, on_tick=tick, on_failure=failure)
    progress.done()
    for ended in fleet.ended:
        if ended.stopped and not ended.ok:   # those that failed by themselves were reported as they did
            report_failure(ended)
    ok = sum(1 for e in fleet.ended if not e.helper and e.ok)
    print(f"  {title}: {ok} of {len(aircraft)} aircraft ended with exit 0 after {fleet.wall_s:.1f} s wall", flush=True)
    if fleet.interrupted:
        print(f"  {title}: INTERRUPTED ({fleet.interrupted}): every process was sent SIGTERM; merging what they wrote")
    if fleet.timed_out:
        print(f"  {title}: the wall-time limit ({limit:.0f} s) passed: the processes were stopped")
    return RunResult(fleet, _report_merge(merge_all(raw, ids, out), raw, ids))


def prepare(home, tree, out, vehicles, seed, jobs):
    """The scratch tree with both variants' airframes and conf files, every aircraft built. Returns the env."""
    logs = out / "logs"
    print(f"paparazzi-sim: {home} -> scratch copy {tree}", flush=True)
    env = prepare_scratch_tree(home, tree, logs / "static_h.log", "[1/3] headers")
    for v in VARIANTS:
        write_variant(tree, v, vehicles, seed, env, logs, "[2/3]")
    build_aircraft(tree, [(v, name) for v in VARIANTS for name, _ in v.aircraft(vehicles)], env, logs, jobs, "[3/3]")
    return env


def write_variant(tree, variant, vehicles, seed, env, logs, step):
    """The variant's airframe (checked against airframe.dtd) and its conf file of `vehicles` aircraft."""
    template = template_aircraft(tree / CONF_XML)
    (tree / variant.airframe()).write_text(swarm_airframe(tree / AIRFRAME, seed, variant.use_wall_detector))
    (tree / variant.conf()).write_text(swarm_conf(template, variant.airframe().removeprefix("conf/"), variant.prefix,
                                                  vehicles))
    check_airframe(step, tree, variant.airframe(), logs / f"airframe_dtd_{variant.key}.log", env)


def build_aircraft(tree, builds, env, logs, jobs, step):
    """Paparazzi's make of each (variant, aircraft name), one at a time."""
    for n, (v, name) in enumerate(builds, 1):
        started = time.monotonic()
        build(f"{step} build {n}/{len(builds)} {name}", tree, v.conf(), name, "nps", logs / f"build_{name}.log", env,
              jobs)
        print(f"        built in {time.monotonic() - started:.0f} s", flush=True)


def run_report(out):
    """tools/sim_report.py on both runs (as `make sim` does); its output goes to ours. Returns its exit status."""
    env = dict(os.environ, PYTHONPATH=str(REPO_ROOT / "tools"))
    env.setdefault("MPLBACKEND", "Agg")
    cmd = [sys.executable, str(REPO_ROOT / "tools/sim_report.py"), "--on", str(out), "--off",
           str(out / VARIANTS[1].subdir)]
    print(f"== Report: {' '.join(cmd[1:])}", flush=True)
    return subprocess.run(cmd, env=env).returncode


def simulate(home, out, tree, vehicles=4, duration_s=180.0, time_factor=1.0, seed=1, gcs=False, jobs=2,
             pose_rate_hz=None, sensor_model=None):
    """Everything `make paparazzi-sim` does; returns the exit status (0: both runs complete and reported).
    pose_rate_hz: rows of poses.csv per aircraft and second (None: the airframe's FINKEN_WORLD_POSES_PERIOD);
    sensor_model: a sensor model file every aircraft flies instead of the airframe's (FINKEN_WORLD_SENSOR_MODEL)."""
    problem = (gcs and display_problem(os.environ)) or tree_problem(home)
    if problem:
        raise PaparazziFailed(problem)
    if pose_rate_hz is not None and not (0 < pose_rate_hz < float("inf")):
        raise PaparazziFailed(f"POSE_RATE={pose_rate_hz:g}: expected a positive number of pose rows per second")
    if not 1 <= vehicles <= max_aircraft() or not duration_s > 0 or not time_factor > 0:
        raise PaparazziFailed(f"VEHICLES={vehicles}, DURATION={duration_s:g}, TIME_FACTOR={time_factor:g}: VEHICLES "
                              f"must be 1..{max_aircraft()} (a shared world's aircraft), DURATION and TIME_FACTOR "
                              "positive")
    if sensor_model is not None and not Path(sensor_model).is_file():
        raise PaparazziFailed(f"MODEL={sensor_model}: no such sensor model file")
    if gcs:
        ground_programs(home, os.environ)   # a display and the programs, before anything is built
    out, tree = Path(out).resolve(), Path(tree).resolve()
    (out / "logs").mkdir(parents=True, exist_ok=True)
    env = prepare(home, tree, out, vehicles, seed, jobs)
    if sensor_model is not None:
        env = dict(env, FINKEN_WORLD_SENSOR_MODEL=str(Path(sensor_model).resolve()))
    base_port = run_base_port(os.getpid())
    results = []
    for n, v in enumerate(VARIANTS, 1):
        run_out = out / v.subdir
        print(f"== Run {n}/{len(VARIANTS)}: {v.title}, {vehicles} aircraft, {duration_s:g} s at x{time_factor:g}, "
              f"seed {seed} -> {run_out}", flush=True)
        aircraft = [(name, ac_id, simsitl_command(tree, name, time_factor, ivy_bus(base_port, ac_id)))
                    for name, ac_id in v.aircraft(vehicles)]
        helpers = ground_members(tree, tree / v.conf(), ivy_bus(base_port), out / "logs", env) if gcs else ()
        if gcs:
            print(f"  ground segment (link, server, GCS) on the Ivy bus {ivy_bus(base_port)}", flush=True)
        result = fly_and_merge(v.title, aircraft, env, tree, run_out, out / "logs", duration_s, time_factor,
                               world=f"finken-{os.getpid()}-{v.key}", run_id=f"{os.getpid()}-{time.time_ns()}-{v.key}",
                               helpers=helpers, pose_rate_hz=pose_rate_hz)
        results.append(result)
        if result.fleet.interrupted:
            raise Interrupted(result.fleet.interrupted)
    incomplete = {v.title: [k for k in KINDS if k not in r.complete_kinds] for v, r in zip(VARIANTS, results)}
    incomplete = {title: kinds for title, kinds in incomplete.items() if kinds}
    if incomplete:
        print("paparazzi-sim: report skipped: it needs every log from every aircraft of both runs; incomplete: " +
              "; ".join(f"{title}: {', '.join(kinds)}" for title, kinds in incomplete.items()))
        return 1
    report_rc = run_report(out)
    return 0 if report_rc == 0 and all(r.ok for r in results) else 1


def _interrupt(signum, _frame):
    raise Interrupted(signal.Signals(signum).name)


def main(argv=None):
    import argparse
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=REPO_ROOT / "build/paparazzi-sim")
    parser.add_argument("--tree", type=Path, default=REPO_ROOT / "build/paparazzi-sim/tree",
                        help="where the scratch copy of $PAPARAZZI_HOME goes (replaced)")
    parser.add_argument("--vehicles", type=int, default=4)
    parser.add_argument("--duration", type=float, default=180.0, help="simulated seconds of each run")
    parser.add_argument("--time-factor", type=float, default=1.0, help="simulated seconds per wall second")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--gcs", action="store_true", help="also start Paparazzi's link, server and GCS")
    parser.add_argument("--jobs", type=int, default=2, help="make -j of each Paparazzi build")
    parser.add_argument("--pose-rate", type=float, default=None,
                        help="rows of poses.csv per aircraft and second (default: the airframe's "
                             "FINKEN_WORLD_POSES_PERIOD, 0.1 s)")
    parser.add_argument("--sensor-model", default=None,
                        help="a sensor model every aircraft flies instead of the airframe's (a calibrated model.xml)")
    args = parser.parse_args(argv)
    previous = signal.signal(signal.SIGTERM, _interrupt)
    try:
        rc = simulate(os.environ.get("PAPARAZZI_HOME", ""), args.out, args.tree, args.vehicles, args.duration,
                      args.time_factor, args.seed, args.gcs, args.jobs, args.pose_rate, args.sensor_model)
    except (KeyboardInterrupt, Interrupted) as why:
        name = str(why) or "SIGINT"
        print(f"\npaparazzi-sim: INTERRUPTED ({name}); the logs of a run that started are merged in {args.out}",
              file=sys.stderr)
        return 130 if name == "SIGINT" else 143
    except (PaparazziFailed, OSError, ValueError, subprocess.SubprocessError) as err:
        print(f"paparazzi-sim: FAILED: {err}", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)
    print("paparazzi-sim: " + ("done" if rc == 0 else "finished with problems (see above)"))
    return rc
