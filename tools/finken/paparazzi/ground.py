"""Paparazzi's ground segment beside a simulated swarm (`make paparazzi-sim GCS=1`): the ground programs of the
session "FINken swarm" (conf/userconf/finken/finken_control_panel.xml, read by session.py as the Paparazzi Center
reads it): the data link on UDP (the NPS telemetry goes to it), the server and the GCS, on the ground's Ivy bus. The
server and the GCS read the aircraft of $PAPARAZZI_HOME/conf/conf.xml: the run's conf is copied there (in the scratch
tree). Without a display the GCS runs under Xvfb (xvfb-run). The arena's walls are drawn on the GCS
(arena_shapes.py).
"""
import shutil
import sys
from pathlib import Path

from lxml import etree

from finken.paparazzi.fleet import Member
from finken.paparazzi.ground_ports import udp_port_problem
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.session import GCS, SESSION_FILE, SIMULATOR, read_session, with_bus
from finken.paparazzi.tree import PaparazziFailed
from finken.xml_errors import XmlInputError

LINK = "sw/ground_segment/tmtc/link"
SERVER = "sw/ground_segment/tmtc/server"
LEGACY_GCS = "sw/ground_segment/cockpit/gcs"
ARENA = "conf/arena/swarmlab.xml"       # the example airframe's FINKEN_WORLD_ARENA
XVFB = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24"]


def headless(env):
    return not env.get("DISPLAY") and not env.get("WAYLAND_DISPLAY")


def display_problem(env):
    """Why no window can be opened, not even on Xvfb (None when one can)."""
    if headless(env) and not shutil.which("xvfb-run", path=env.get("PATH")):
        return ("GCS=1 needs a display or Xvfb: DISPLAY is not set and xvfb-run is missing (apt-get install xvfb), "
                "or run without GCS=1")
    return None


def gcs_available(tree, env):
    """Whether Paparazzi's gcs_launch.py finds a GCS: `pprzgcs` on the PATH, else the tree's legacy GCS (it exits 0
    even when it finds neither)."""
    return bool(shutil.which("pprzgcs", path=env.get("PATH"))) or (Path(tree) / LEGACY_GCS).is_file()


def ground_programs(tree, env):
    """The session's programs but its simulators (session.Program, commands in the tree `tree`). Raises
    PaparazziFailed without a display or Xvfb, when the link or the server is not built, when the GCS cannot start
    (no pprzgcs on the PATH and no legacy GCS built: Paparazzi's gcs_launch.py runs one or the other), or when the
    data link's UDP port is taken (the ground's Ivy bus is the launcher's own: ivy_bus)."""
    problem = display_problem(env)
    if problem:
        raise PaparazziFailed(problem)
    tree = Path(tree)
    missing = [str(tree / p) for p in (LINK, SERVER) if not (tree / p).is_file()]
    if not gcs_available(tree, env):
        missing.append(f"{tree / LEGACY_GCS} (and no pprzgcs on PATH)")
    if missing:
        raise PaparazziFailed(f"GCS=1: {', '.join(missing)} not built: build the ground segment in your tree "
                              "(make -C $PAPARAZZI_HOME tmtc) and install PprzGCS (docs/paparazzi.md)")
    taken = udp_port_problem()
    if taken:
        raise PaparazziFailed(f"GCS=1: {taken}")
    return session_ground(tree)


def session_ground(tree):
    """The programs of the session "FINken swarm" but its simulators (the data link, the server, the GCS), their
    commands in the tree `tree`; PaparazziFailed naming the session file's fault."""
    try:
        programs = read_session(tree, REPO_ROOT / SESSION_FILE, conf=None)
    except XmlInputError as err:
        raise PaparazziFailed(f"the ground segment: {err}") from err
    return [p for p in programs if p.name != SIMULATOR]


def on_display(program, command, env):
    """The program's command as it is run: the GCS's under Xvfb when there is no display."""
    return XVFB + command if program.name == GCS and headless(env) else command


def member(program, bus, logs, env, tree):
    """The fleet Member (a helper) running a ground program on the Ivy bus `bus`, the GCS under Xvfb without a
    display; its log logs/<name>.log."""
    command = on_display(program, with_bus(program, bus), env)
    name = program.name.lower().replace(" ", "_")
    return Member(name, command, Path(logs) / f"{name}.log", env, tree, True)


def walls_member(bus, flight_plan, logs, env, tree, arena=REPO_ROOT / ARENA):
    """The fleet Member (a helper) drawing the arena's walls on the GCS (arena_shapes.py), placed by the flight plan
    `flight_plan`; its log logs/arena_shapes.log."""
    command = [sys.executable, "-m", "finken.paparazzi.arena_shapes", "--bus", bus, "--arena", str(arena),
               "--flight-plan", str(flight_plan)]
    return Member("arena_shapes", command, Path(logs) / "arena_shapes.log",
                  dict(env, PYTHONPATH=str(REPO_ROOT / "tools")), tree, True)


def ground_members(tree, conf, bus, logs, env):
    """Members (helpers) for fleet.run_fleet: the session's ground programs on the Ivy bus `bus`, the GCS under Xvfb
    when there is no display, and the arena's walls drawn on it, after copying the conf file `conf` to the tree's
    conf/conf.xml. Raises PaparazziFailed as ground_programs."""
    programs = ground_programs(tree, env)
    shutil.copyfile(conf, Path(tree) / "conf/conf.xml")
    return [member(p, bus, logs, env, tree) for p in programs] + [
        walls_member(bus, conf_flight_plan(tree, conf), logs, env, tree)]


def conf_flight_plan(tree, conf, aircraft=None):
    """The flight plan (a path in the tree) of the aircraft named `aircraft` in the conf file `conf`, or of its first
    aircraft."""
    found = [a for a in etree.parse(str(conf)).iter("aircraft") if aircraft in (None, a.get("name"))]
    return Path(tree) / "conf" / found[0].get("flight_plan")
