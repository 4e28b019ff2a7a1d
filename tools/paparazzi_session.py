#!/usr/bin/env python3
"""Run a Paparazzi Center session without the Center: by default "FINken swarm" of
conf/userconf/finken/finken_control_panel.xml (four FINken in NPS in one arena, the data link, the server and the
GCS), in $PAPARAZZI_HOME, each program as the Center starts it (tools/finken/paparazzi/session.py). Without a
display the GCS runs under Xvfb (xvfb-run). Ctrl-C stops every program; so does a program that fails (named, with
the last lines of its output), and nothing is left running.

Usage: PAPARAZZI_HOME=<tree> tools/paparazzi_session.py [--session NAME] [--control-panel FILE] [--duration S]
       [--logs DIR]
"""
import argparse
import os
import sys
from pathlib import Path

from finken.paparazzi.fleet import Member, run_fleet
from finken.paparazzi.ground import (LEGACY_GCS, conf_flight_plan, display_problem, gcs_available, on_display,
                                     walls_member)
from finken.paparazzi.ground_ports import ivy_bus_problem, udp_port_problem
from finken.paparazzi.session import GCS, SESSION, SESSION_FILE, SIMULATOR, describe, read_session
from finken.xml_errors import XmlInputError


DEFAULT_BUS = "127.255.255.255:2010"   # Paparazzi's programs without -b


class ProgramFailed(Exception):
    pass


def _ports_problem(programs):
    """A taken data-link UDP port, or another agent on the ground programs' Ivy bus (None when both are free)."""
    ground = [p for p in programs if p.name != SIMULATOR]
    if any(p.name == "Data Link" for p in ground) and udp_port_problem():
        return udp_port_problem()
    buses = {p.arg("-b") or DEFAULT_BUS for p in ground}
    return next((problem for problem in map(ivy_bus_problem, sorted(buses)) if problem), None)


def _gcs_problem(programs, home, env):
    """Why the session's GCS cannot start (None when it can, or the session has none)."""
    if not any(p.name == GCS for p in programs):
        return None
    if gcs_available(home, env):
        return display_problem(env)
    return ("the GCS cannot start: no pprzgcs on the PATH and no legacy GCS built in the tree "
            f"({Path(home) / LEGACY_GCS}); install PprzGCS (docs/paparazzi.md)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--session", default=SESSION)
    ap.add_argument("--control-panel", default=SESSION_FILE, help="relative to $PAPARAZZI_HOME")
    ap.add_argument("--duration", type=float, help="simulated seconds of each aircraft (default: until Ctrl-C)")
    ap.add_argument("--logs", type=Path, default=Path("build/paparazzi-session/logs"))
    args = ap.parse_args(argv)
    home = os.environ.get("PAPARAZZI_HOME")
    if not home:
        print("paparazzi-session: PAPARAZZI_HOME is not set", file=sys.stderr)
        return 2
    try:
        programs = read_session(home, args.control_panel, args.session)
    except XmlInputError as err:
        print(f"paparazzi-session: {err}", file=sys.stderr)
        return 2
    env = dict(os.environ, PAPARAZZI_SRC=os.environ.get("PAPARAZZI_SRC", home))
    if args.duration:
        env["FINKEN_WORLD_DURATION"] = f"{args.duration:g}"
    problem = _gcs_problem(programs, home, env) or _ports_problem(programs)
    if problem:
        print(f"paparazzi-session: {problem}", file=sys.stderr)
        return 2
    args.logs.mkdir(parents=True, exist_ok=True)
    members = []
    for n, p in enumerate(programs):
        command = on_display(p, p.command, env)
        label = f"{p.name}_{p.arg('-a')}" if p.name == SIMULATOR else p.name.replace(" ", "_")
        members.append(Member(label, command, args.logs / f"{n:02d}_{label}.log", env, Path(home),
                              helper=p.name != SIMULATOR))
    gcs = [p for p in programs if p.name == GCS]
    if gcs:   # the arena's walls drawn on the GCS
        first = next(p.arg("-a") for p in programs if p.name == SIMULATOR)
        members.append(walls_member(gcs[0].arg("-b") or DEFAULT_BUS,
                                    conf_flight_plan(home, Path(home) / "conf/conf.xml", first), args.logs, env,
                                    Path(home)))
    for line in describe(programs):
        print(f"  {line}", flush=True)

    def failed(ended):
        raise ProgramFailed(f"{ended.name} ended ({ended.how}); its last lines:\n    " + "\n    ".join(ended.log_tail))

    try:
        outcome = run_fleet(members, float("inf"), on_failure=failed)
    except ProgramFailed as err:
        print(f"paparazzi-session: {err}\n  every program of the session was stopped (logs: {args.logs})",
              file=sys.stderr)
        return 1
    print(f"paparazzi-session: ended after {outcome.wall_s:.0f} s" +
          (f" ({outcome.interrupted})" if outcome.interrupted else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
