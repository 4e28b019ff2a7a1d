"""The swarm part of `make paparazzi-check`: several NPS processes of the example airframe in one shared world
(issue 27). It checks that the arena is shared (every pair ranged, copter echoes, cross-talk between facing sonars,
walls bulging toward passing copters) and that the wall detector scores as in our host on the same scenario
(same swarm size, seed and duration; scores after take-off, within a tolerance).
"""
import os
import subprocess
import time
from pathlib import Path

from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.sim import (VARIANTS, build_aircraft, fly_and_merge, ivy_bus, run_base_port, simsitl_command,
                                  write_variant)
from finken.paparazzi.tree import PaparazziFailed
from finken.sim_report.swarm_figures import compare_detectors, problems, swarm_figures

HOST = REPO_ROOT / "build/host/finken_nps/nps_host"
# the detector's scores are compared from here on [s]: the NPS aircraft take off first (about 15 s to GUIDED),
# our host's copters start in the air
SCORES_FROM_S = 20.0
TOLERANCE = 0.05


def _summary(figures):
    d = figures.detector
    return (f"copter echoes {figures.copter_echoes}, cross-talk {figures.crosstalk_readings}, bulges toward a copter "
            f"{figures.bulges_toward_a_copter} of {figures.bulges}, wall recall {d['wall_recall']:.3f}, copter as "
            f"wall {d['copter_as_wall']:.3f}")


def check_swarm(tree, env, out, logs, step, vehicles=4, duration_s=60.0, time_factor=5.0, seed=1, jobs=2):
    """Build and fly `vehicles` aircraft in one world, check their merged logs against our host's run. Returns the
    figures of both; raises PaparazziFailed naming what is missing."""
    variant = VARIANTS[0]
    write_variant(tree, variant, vehicles, seed, env, logs, step)
    build_aircraft(tree, [(variant, name) for name, _ in variant.aircraft(vehicles)], env, logs, jobs, step)
    base_port = run_base_port(os.getpid())
    aircraft = [(name, ac_id, simsitl_command(tree, name, time_factor, ivy_bus(base_port, ac_id)))
                for name, ac_id in variant.aircraft(vehicles)]
    run_out = Path(out) / "swarm"
    result = fly_and_merge(f"{step} swarm", aircraft, env, tree, run_out, logs, duration_s, time_factor,
                           world=f"finken-check-{os.getpid()}", run_id=f"check-{os.getpid()}-{time.time_ns()}")
    if not result.ok:
        raise PaparazziFailed(f"the swarm's run did not complete (logs: {logs}, {run_out / 'raw'})")
    ours = swarm_figures(run_out, from_s=SCORES_FROM_S)
    print(f"        Paparazzi's NPS: {_summary(ours)}", flush=True)
    missing = problems(ours)
    if missing:
        raise PaparazziFailed(f"{run_out}: the arena is not shared: " + "; ".join(missing))
    host_out = Path(out) / "swarm_host"
    subprocess.run([str(HOST), "--vehicles", str(vehicles), "--seed", str(seed), "--duration", f"{duration_s:g}",
                    "--out", str(host_out), "--quiet"], check=True)
    host = swarm_figures(host_out, from_s=SCORES_FROM_S)
    print(f"        our host:        {_summary(host)}", flush=True)
    apart = compare_detectors(ours, host, TOLERANCE)
    if apart:
        raise PaparazziFailed("the wall detector scores differently from our host's on the same scenario (after "
                              f"{SCORES_FROM_S:g} s, tolerance {TOLERANCE}): " +
                              ", ".join(f"{k} {a:.3f} against {b:.3f}" for k, (a, b) in apart.items()))
    return ours, host
