"""The interior obstacles' part of `make paparazzi-check`: 4 aircraft of the example airframe in
conf/arena/swarmlab_pillar.xml (SwarmLab and a pillar), one build flown as every aircraft (FINKEN_WORLD_AC_ID).
It checks that Paparazzi's NPS has the obstacle as our host has it: the aircraft start where our host's copters
start, sonars read the pillar (ctx_target_obstacle), and no body goes into it (the contacts push them out).
"""
import math
import os
import subprocess
import time
from pathlib import Path

import numpy as np

from finken.flight.truth import ArenaTruth
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.sim import build_aircraft, fly_and_merge, ivy_bus, run_base_port, simsitl_command, Variant
from finken.paparazzi.swarm_conf import swarm_airframe, swarm_conf, template_aircraft
from finken.paparazzi.tree import AIRFRAME, CONF_XML, PaparazziFailed, check_airframe
from finken.rangelog import read_range_log
from finken.run_logs import read_poses

ARENA = "conf/arena/swarmlab_pillar.xml"
HOST = REPO_ROOT / "build/host/finken_nps/nps_host"
VARIANT = Variant("pillar", "an arena with a pillar", "FINKEN_PILLAR_", "pillar", True)
#: how far a body may reach into an obstacle [m]: the flight model takes the contacts' push at the processes'
#: meetings, every 8th step (docs/paparazzi-world.md): a copter at 1 m/s goes 1.6 cm in before it is pushed back
CONTACT_TOLERANCE_M = 0.02
#: how far an aircraft's first pose may be from our host's start [m] (the logs' 4 decimals)
START_TOLERANCE_M = 1e-3


def starts_of(poses):
    """The first (x, y) of each vehicle in a poses log, by vehicle id."""
    vehicles, first = np.unique(poses["vehicle"], return_index=True)
    return {int(v): (poses["x"][i], poses["y"][i]) for v, i in zip(vehicles, first)}


def deepest_reach_m(poses, obstacles, body_radius_m):
    """How far any body of the poses log reached into an obstacle's footprint (negative: it stayed clear) [m]."""
    xy = np.column_stack([poses["x"], poses["y"]])
    reach = -np.inf
    for obstacle in obstacles:
        if obstacle.circle is None:
            raise ValueError("only round obstacles are checked here")
        x, y, radius_m = obstacle.circle
        reach = max(reach, float(np.max(radius_m + body_radius_m - np.hypot(xy[:, 0] - x, xy[:, 1] - y))))
    return reach


def check_obstacles(tree, env, out, logs, step, vehicles=4, duration_s=30.0, time_factor=5.0, seed=1, jobs=2):
    """Build and fly the pillar arena's swarm; returns its figures; raises PaparazziFailed naming what is wrong."""
    (tree / VARIANT.airframe()).write_text(swarm_airframe(tree / AIRFRAME, seed, True, arena=ARENA))
    (tree / VARIANT.conf()).write_text(swarm_conf(template_aircraft(tree / CONF_XML),
                                                  VARIANT.airframe().removeprefix("conf/"), VARIANT.prefix, 1))
    check_airframe(step, tree, VARIANT.airframe(), logs / "airframe_dtd_pillar.log", env)
    name = VARIANT.aircraft(1)[0][0]
    build_aircraft(tree, [(VARIANT, name)], env, logs, jobs, step)
    base_port = run_base_port(os.getpid())
    command = [simsitl_command(tree, name, time_factor, ivy_bus(base_port, k)) for k in range(1, vehicles + 1)]
    aircraft = [(f"{name}_as_{k}", k, ["env", f"FINKEN_WORLD_AC_ID={k}", *command[k - 1]])
                for k in range(1, vehicles + 1)]
    run_out = Path(out) / "pillar"
    result = fly_and_merge(f"{step} {VARIANT.title}", aircraft, env, tree, run_out, logs, duration_s, time_factor,
                           world=f"finken-pillar-{os.getpid()}", run_id=f"pillar-{os.getpid()}-{time.time_ns()}")
    if not result.ok:
        raise PaparazziFailed(f"the pillar arena's run did not complete (logs: {logs}, {run_out / 'raw'})")
    host_out = Path(out) / "pillar_host"
    subprocess.run([str(HOST), "--vehicles", str(vehicles), "--seed", str(seed), "--duration", "0.1", "--arena",
                    str(REPO_ROOT / ARENA), "--out", str(host_out), "--quiet"], check=True)
    poses = read_poses(run_out / "poses.csv")
    ours, host = starts_of(poses), starts_of(read_poses(host_out / "poses.csv"))
    start_gap_m = max(math.dist(ours[v], host[v]) for v in host)
    readings = read_range_log(run_out / "readings.csv")
    pillar_echoes = int(np.sum(readings.ctx.get("ctx_target_obstacle", np.zeros(1)) == 1.0))
    with ArenaTruth(REPO_ROOT / ARENA) as arena:
        reach_m = deepest_reach_m(poses, arena.obstacles(), arena.copter_radius_m)
    print(f"        starts {start_gap_m * 1000:.1f} mm from our host's; {pillar_echoes} sonar readings of the pillar; "
          f"deepest a body reached into it {reach_m * 1000:.1f} mm (tolerance {CONTACT_TOLERANCE_M * 1000:g} mm)",
          flush=True)
    wrong = [what for what, bad in (
        (f"the aircraft start up to {start_gap_m:.3f} m from our host's copters", start_gap_m > START_TOLERANCE_M),
        ("no sonar reading has the pillar as its first hit", pillar_echoes == 0),
        (f"a body reached {reach_m:.3f} m into the pillar", reach_m > CONTACT_TOLERANCE_M)) if bad]
    if wrong:
        raise PaparazziFailed(f"{run_out}: " + "; ".join(wrong))
    return {"start_gap_m": start_gap_m, "pillar_echoes": pillar_echoes, "deepest_reach_m": reach_m}
