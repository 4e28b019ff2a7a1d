"""What Paparazzi's ground segment sees of the swarm, and commands from it: a step of `make paparazzi-check`.

Four aircraft fly in one world, each NPS process on an Ivy bus of its own (docs/paparazzi.md, "One Ivy bus per
aircraft"), with Paparazzi's `link` (telemetry and uplink over UDP) and `server` (logging) on the ground's bus, as a
Paparazzi Center session starts them. Once every aircraft is in the flight plan's Guided block, a setting change and
a jump to "Land here" go out as the GCS sends them (ground_commands.py). Then, from the server's log (copied to
OUT/ground/):
- every aircraft's telemetry is there, ours included (FINKEN_RANGE_READING and FINKEN_WALL_DECISION of the
  range_recorder module), else the check fails naming the aircraft missing;
- the positions the server received (ROTORCRAFT_FP, in the flight plan's frame, which is the arena's) agree with
  the simulator's truth (poses.csv), within POSITION_TOLERANCE_M at the 95th percentile;
- the uplink of both commands went to each aircraft (the server logs SETTING and BLOCK), each confirmed the setting
  (DL_VALUE) and reached "Land here" or a later block, and landed (its last height below LANDED_M).
With pprzgcs on the PATH, the session's GCS runs too, on a virtual display, with the arena's walls drawn on it, and
its picture of the flying swarm is taken before the commands (OUT/ground/gcs.png; gcs_view.py).
"""
import importlib.util
import os
import shutil
import sys
import time
from contextlib import ExitStack
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from finken.flight.mocap import read_mocap
from finken.flight.server_log import ServerLog
from finken.paparazzi.fleet import Member
from finken.paparazzi.ground import LINK, SERVER, member, session_ground, walls_member
from finken.paparazzi.gcs_view import gcs_env, picture_problem, virtual_display
from finken.paparazzi.ground_ports import udp_port_problem
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.session import GCS
from finken.paparazzi.sim import VARIANTS, fly_and_merge, ivy_bus, run_base_port, simsitl_command
from finken.paparazzi.tree import PaparazziFailed

OURS = ("FINKEN_RANGE_READING", "FINKEN_WALL_DECISION")
EXPECTED = ("ROTORCRAFT_FP", "ROTORCRAFT_NAV_STATUS") + OURS
GUIDED, LAND = "Guided", "Land here"
SETTING = ("nav.climb_vspeed", 0.8)       # a setting each aircraft confirms in DL_VALUE [m/s]
POSITION_TOLERANCE_M = 0.05               # ROTORCRAFT_FP is ins_nps's estimate: the simulator's own position
LANDED_M = 0.1


def ground_problem(tree):
    """Why the ground segment cannot run here (None when it can)."""
    missing = [p for p in (LINK, SERVER) if not (Path(tree) / p).is_file()]
    if missing:
        return (f"the ground segment is not built in the tree ({', '.join(missing)}): build it with "
                "`make -C $PAPARAZZI_HOME tmtc` (setup.sh --ground-segment)")
    if importlib.util.find_spec("ivy") is None:   # ivy-python: the commands go out on the Ivy bus
        return "the Python package ivy-python is missing (make installs it into build/venv)"
    return None


def _numbered(path, tag, key):
    """{name: index} of the elements `tag` of an XML file in document order (Paparazzi numbers blocks and settings
    so)."""
    return {e.get(key): i for i, e in enumerate(etree.parse(str(path)).iter(tag))}


def check_ground(tree, env, out, logs, step, vehicles=4, duration_s=60.0, time_factor=2.0):
    """Fly with the ground segment up and check what it saw; returns the GroundView, None when skipped. Raises
    PaparazziFailed naming what is missing."""
    problem = ground_problem(tree)
    if problem:
        print(f"  {step} ground segment: skipped ({problem})", flush=True)
        return None
    taken = udp_port_problem()
    if taken:
        raise PaparazziFailed(f"{step} ground segment: {taken}")
    variant = VARIANTS[0]
    names = variant.aircraft(vehicles)
    ac_dir = tree / "var/aircrafts" / names[0][0]
    blocks = _numbered(ac_dir / "flight_plan.xml", "block", "name")
    settings = _numbered(ac_dir / "settings.xml", "dl_setting", "var")
    shutil.copyfile(tree / variant.conf(), tree / "conf/conf.xml")   # what the server reads
    shutil.rmtree(tree / "var/logs", ignore_errors=True)
    base_port = run_base_port(os.getpid())
    bus = ivy_bus(base_port)
    ids = ",".join(str(ac_id) for _, ac_id in names)
    commands = [sys.executable, "-m", "finken.paparazzi.ground_commands", "--bus", bus, "--aircraft", ids,
                "--after", str(blocks[GUIDED]), "--setting", f"{settings[SETTING[0]]}={SETTING[1]}",
                "--jump", str(blocks[LAND]), "--timeout", f"{duration_s / time_factor:g}"]
    ground = out / "ground"
    picture = ground / "gcs.png"
    no_picture = picture_problem(env)
    picture.unlink(missing_ok=True)
    aircraft = [(name, ac_id, simsitl_command(tree, name, time_factor, ivy_bus(base_port, ac_id)))
                for name, ac_id in names]
    print(f"  {step} ground segment on the Ivy bus {bus}: link, server (logging), "
          + ("PprzGCS, " if no_picture is None else "") + f"commands once all are in \"{GUIDED}\"", flush=True)
    if no_picture:
        print(f"  {step} the GCS's picture: skipped ({no_picture})", flush=True)
    with ExitStack() as stack:
        helpers = _ground_helpers(stack, tree, env, bus, logs, commands, None if no_picture else picture,
                                  ac_dir / "flight_plan.xml", out / "gcs_settings")
        result = fly_and_merge(f"{step} ground", aircraft, env, tree, ground, logs, duration_s, time_factor,
                               world=f"finken-ground-{os.getpid()}", run_id=f"ground-{os.getpid()}-{time.time_ns()}",
                               helpers=helpers)
    copied = _copy_server_log(tree / "var/logs", ground)
    if not result.ok:
        raise PaparazziFailed(f"the ground segment's run did not complete (logs: {logs}, {ground / 'raw'})")
    view = ground_view(copied, [ac_id for _, ac_id in names], blocks[LAND], settings[SETTING[0]], SETTING[1])
    view.positions_m = position_errors(copied, ground / "poses.csv", time_factor)
    if no_picture is None:
        if not picture.is_file():
            raise PaparazziFailed(f"PprzGCS ran but its picture was not taken: see {logs / 'ground_commands.log'} "
                                  f"and {logs / 'pprzgcs.log'}")
        view.picture = picture
    for line in view.lines():
        print(f"        {line}", flush=True)
    problems = view.problems()
    if problems:
        raise PaparazziFailed(f"{copied}: " + "; ".join(problems))
    return view


def _ground_helpers(stack, tree, env, bus, logs, commands, picture, flight_plan, scratch):
    """The fleet's helpers in the ground step: the session's data link and server (the server logs: no -n), as a
    Paparazzi Center session starts them, and the ground commands; with `picture` (a path) also the session's GCS on
    a virtual display (entered in the ExitStack `stack`; its settings in `scratch`) with the arena's walls drawn on
    it (placed by `flight_plan`), and the commands take the picture first."""
    ground_env, gcs_env_ = dict(env, PYTHONPATH=str(REPO_ROOT / "tools")), None
    if picture:
        display = stack.enter_context(virtual_display(logs / "xvfb.log"))
        gcs_env_ = gcs_env(env, display, scratch)
        ground_env["DISPLAY"] = display
        commands = commands + ["--picture", str(picture)]
    helpers = [member(p, bus, logs, gcs_env_ if p.name == GCS else env, tree) for p in session_ground(tree)
               if p.name != GCS or picture]
    if picture:
        helpers.append(walls_member(bus, flight_plan, logs, ground_env, tree))
    return helpers + [Member("commands", commands, logs / "ground_commands.log", ground_env, tree, True)]


def _copy_server_log(log_dir, out):
    """The server's .log and .data copied to out; the .data's path. PaparazziFailed when the server wrote none."""
    data = sorted(Path(log_dir).glob("*.data"))
    if not data:
        raise PaparazziFailed(f"the server wrote no log in {log_dir} (see its output in the logs folder)")
    out.mkdir(parents=True, exist_ok=True)
    for path in sorted(Path(log_dir).glob("*.log")) + data:
        shutil.copy2(path, out / path.name)
    return out / data[-1].name


@dataclass
class GroundView:
    """What the server logged of each aircraft."""
    aircraft: list
    counts: dict          # {message name: {ac_id: lines}}
    obeyed: dict          # {ac_id: {"setting sent", "setting confirmed", "jump sent", "block reached", "landed"}}
    positions_m: dict = None   # {ac_id: (median, p95) distance [m]} between the server's positions and the truth
    picture: Path = None       # PprzGCS's screen with the swarm, when it ran

    def missing(self):
        """{ac_id: [message names it never sent]} of the aircraft missing something."""
        out = {}
        for ac in self.aircraft:
            lacking = [name for name in EXPECTED if self.counts[name].get(ac, 0) == 0]
            if lacking:
                out[ac] = lacking
        return out

    def problems(self):
        found = [f"aircraft {ac} is missing from the server's view: no {', '.join(names)}"
                 for ac, names in self.missing().items()]
        found += [f"aircraft {ac} did not obey: {', '.join(sorted(set(OBEYED) - done))} missing"
                  for ac, done in self.obeyed.items() if set(OBEYED) - done]
        found += [f"aircraft {ac}: the server's positions are {p95:.3f} m from the truth (95th percentile, "
                  f"tolerance {POSITION_TOLERANCE_M} m)" for ac, (_, p95) in (self.positions_m or {}).items()
                  if not p95 <= POSITION_TOLERANCE_M]
        return found

    def lines(self):
        out = ["the server logged, per aircraft: " + "; ".join(
            f"{ac}: " + ", ".join(f"{name} {self.counts[name].get(ac, 0)}" for name in EXPECTED)
            for ac in self.aircraft)]
        out += [f"aircraft {ac}: " + ", ".join(o for o in OBEYED if o in self.obeyed[ac]) for ac in self.aircraft]
        if self.positions_m:
            out.append("server positions against the simulator's truth (median, 95th percentile): " + "; ".join(
                f"{ac}: {med * 1000:.1f} mm, {p95 * 1000:.1f} mm" for ac, (med, p95) in self.positions_m.items()))
        if self.picture:
            out.append(f"the GCS's picture of the swarm: {self.picture}")
        return out


OBEYED = ("setting sent", "setting confirmed", "jump sent", "block reached", "landed")


def ground_view(data_path, aircraft, land_block, setting_index, setting_value):
    """The GroundView of a server log (.data beside its .log)."""
    log = ServerLog.open(str(data_path))
    wanted = {name: "telemetry" for name in EXPECTED + ("DL_VALUE",)}
    wanted.update(SETTING="datalink", BLOCK="datalink")
    msgs = log.messages(wanted)
    counts = {name: {int(a): int(n) for a, n in zip(*np.unique(msgs[name].ac, return_counts=True))}
              for name in EXPECTED}
    obeyed = {}
    for ac in aircraft:
        done = set()
        setting = msgs["SETTING"]
        sent = (setting.ac == ac) & (setting.numbers("index") == setting_index)
        if sent.any():
            done.add("setting sent")
            t_sent = setting.t_log[sent][0]
            value = msgs["DL_VALUE"]
            after = (value.ac == ac) & (value.t_log >= t_sent) & (value.numbers("index") == setting_index)
            if np.any(np.isclose(value.numbers("value")[after], setting_value, atol=1e-6)):
                done.add("setting confirmed")
        block = msgs["BLOCK"]
        jumped = (block.ac == ac) & (block.numbers("block_id") == land_block)
        if jumped.any():
            done.add("jump sent")
            nav = msgs["ROTORCRAFT_NAV_STATUS"]
            after = (nav.ac == ac) & (nav.t_log >= block.t_log[jumped][0])
            if np.any(nav.numbers("cur_block")[after] >= land_block):
                done.add("block reached")
        fp = msgs["ROTORCRAFT_FP"]
        mine = fp.ac == ac
        if mine.any() and fp.numbers("up")[mine][-1] * fp.field("up").si_scale("ROTORCRAFT_FP") < LANDED_M:
            done.add("landed")
        obeyed[ac] = done
    return GroundView(list(aircraft), counts, obeyed)


def position_errors(data_path, poses_path, time_factor):
    """{ac_id: (median, 95th percentile)} of the horizontal distance [m] between the positions the server logged
    (ROTORCRAFT_FP, in the flight plan's frame: the arena's, finken_world.h) and the simulator's truth at the same
    time. The server's clock is the wall clock, the simulator's runs at about time_factor times it: the samples are
    matched in windows of WINDOW_S of world time, each with the offset that brings them closest (the least mean
    distance, on a grid of 10 ms within 2 s of the whole run's best, itself on a grid of 50 ms over +-5 s of wall
    time), so that a drift of the two clocks over a long run does not count as a distance."""
    server, truth = read_mocap(str(data_path)), read_mocap(str(poses_path))
    out = {}
    for ac in server.vehicles:
        if ac not in truth.vehicles:
            continue
        xy = server.pos[ac][:, :2]
        world_t = time_factor * server.t[ac]
        start = truth.t[ac][0] - world_t[0]
        run = _best_offset(truth, ac, world_t, xy, start + np.arange(-5.0, 5.0, 0.05) * time_factor)
        if run is None:
            continue
        distances = []
        for first in np.arange(world_t[0], world_t[-1], WINDOW_S):
            rows = (world_t >= first) & (world_t < first + WINDOW_S)
            best = _best_offset(truth, ac, world_t[rows], xy[rows], run[1] + np.arange(-2.0, 2.0, 0.01))
            if best is not None:
                distances.append(best[2])
        if distances:
            d = np.concatenate(distances)
            out[ac] = (float(np.median(d)), float(np.percentile(d, 95)))
    return out


WINDOW_S = 60.0


def _best_offset(truth, ac, world_t, xy, offsets):
    """(mean distance, offset, distances) of the offset bringing the server's positions xy at world_t + offset
    closest to the truth, among those whose truth covers 80 % of the samples; None if none does."""
    best = None
    for offset in offsets:
        pos, _, ok = truth.at(ac, world_t + offset)
        if ok.sum() < 0.8 * len(ok) or not ok.any():
            continue
        d = np.linalg.norm(pos[ok, :2] - xy[ok], axis=1)
        if best is None or d.mean() < best[0]:
            best = (float(d.mean()), float(offset), d)
    return best
