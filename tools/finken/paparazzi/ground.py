"""Paparazzi's ground segment for watching a simulated swarm (`make paparazzi-sim GCS=1`), as the Paparazzi Center's
simulation session starts it (sw/supervision/python/session_widget.py, start_simulation): the data link on UDP
(the NPS telemetry goes to it), the server (without a log) and the GCS, all on the swarm's Ivy bus. The server
and the GCS read the aircraft of $PAPARAZZI_HOME/conf/conf.xml: `conf` is copied there (in the scratch tree).
"""
import shutil
from pathlib import Path

from finken.paparazzi.fleet import Member
from finken.paparazzi.tree import PaparazziFailed

LINK = "sw/ground_segment/tmtc/link"
SERVER = "sw/ground_segment/tmtc/server"
LEGACY_GCS = "sw/ground_segment/cockpit/gcs"


def display_problem(env):
    """Why no window can be opened (None when one can)."""
    if not env.get("DISPLAY") and not env.get("WAYLAND_DISPLAY"):
        return ("GCS=1 needs a display, and DISPLAY is not set: run it from a desktop session (or ssh -X), "
                "or without GCS=1")
    return None


def ground_programs(tree, env):
    """(link, server, gcs) of the tree (PprzGCS when on PATH, else the tree's legacy GCS). Raises PaparazziFailed
    without a display or when one is missing."""
    problem = display_problem(env)
    if problem:
        raise PaparazziFailed(problem)
    tree = Path(tree)
    programs = (tree / LINK, tree / SERVER, Path(shutil.which("pprzgcs", path=env.get("PATH")) or tree / LEGACY_GCS))
    missing = [str(p) for p in programs if not p.is_file()]
    if missing:
        raise PaparazziFailed(f"GCS=1: {', '.join(missing)} not built (and no pprzgcs on PATH): build the ground "
                              "segment in your tree (make -C $PAPARAZZI_HOME tmtc cockpit) or install PprzGCS")
    return programs


def ground_members(tree, conf, bus, logs, env):
    """Members (helpers) for fleet.run_fleet: link, server and GCS on the Ivy bus `bus`, after copying the conf
    file `conf` to the tree's conf/conf.xml. Raises PaparazziFailed as ground_programs."""
    link, server, gcs = ground_programs(tree, env)
    shutil.copyfile(conf, Path(tree) / "conf/conf.xml")
    return [Member("link", [link, "-udp", "-udp_broadcast", "-b", bus], logs / "link.log", env, tree, True),
            Member("server", [server, "-n", "-b", bus], logs / "server.log", env, tree, True),
            Member("gcs", [gcs, "-b", bus], logs / "gcs.log", env, tree, True)]
