"""Build and fly our modules in a real Paparazzi tree, on a scratch copy (the user's tree is never modified).

Steps (each printed; a failure shows Paparazzi's own error lines and the log's path):
  1. copy $PAPARAZZI_HOME to OUT/tree, lay our overlay over it, regenerate its headers (make static_h);
  2. validate the example airframe against Paparazzi's airframe.dtd;
  3. build the example aircraft's NPS simulator with Paparazzi's own make (AIRCRAFT=... nps.compile), which
     runs Paparazzi's generators on our descriptors;
  4. build its autopilot for a Linux board (ap target, BeagleBone Black, arm-linux-gnueabihf) with the sonar
     driver on libgpiod and the ranging driver on SocketCAN;
  5. fly one NPS process DURATION simulated seconds faster than real time, without a GCS, its range log in OUT;
  6. check the range log: every sonar read, the downward sonar sees the hover height, the modelled errors show;
  7. fly 4 aircraft 60 s in one shared world (finken.paparazzi.swarm_check): every pair ranged, copter echoes,
     cross-talk, walls bulging toward copters, and the wall detector scoring within 0.05 of our host's;
  8. close the loop (finken.paparazzi.loop_check): 4 aircraft fly 60 s with a hidden sonar bias; their recorders'
     files and true poses become a range log (make rangelog), whose calibration must name the bias and shrink the
     held-out gap; how well the computed true ranges agree with the simulator's own is printed;
  9. the ground segment (finken.paparazzi.ground_check), when built in the tree: link and server beside 4 aircraft
     for 60 s; every aircraft's telemetry in the server's log (ours included), its positions against the truth, a
     setting change and a jump to "Land here" sent as the GCS sends them and obeyed; with pprzgcs on the PATH,
     PprzGCS on a virtual display and its picture of the swarm in the arena (OUT/ground/gcs.png); "skipped" with
     the reason when the ground segment is not built (the picture alone when PprzGCS or an X tool is missing);
 10. an arena with a pillar (finken.paparazzi.obstacle_check): 4 aircraft 30 s in conf/arena/swarmlab_pillar.xml
     start where our host's copters start, read the pillar with their sonars and never go into it.
Both builds must leave no compiler warning in our files (Paparazzi's flags: -Wshadow, -Wcast-qual, ...).
"""
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from finken.paparazzi.ground_check import check_ground
from finken.paparazzi.loop_check import check_loop
from finken.paparazzi.obstacle_check import check_obstacles
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.swarm_check import check_swarm
from finken.paparazzi.tree import (AIRFRAME, CONF_XML, PaparazziFailed, build, prepare_scratch_tree, run_logged,
                                   tree_problem)
from finken.rangelog import read_range_log

SONARS = ("sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down")


# a failed step (the shared helpers of finken.paparazzi.tree raise it too)
CheckFailed = PaparazziFailed


DRIVER_SYMBOLS = ("sonar_gpiod_request", "ranging_socketcan_open")
#: the file in OUT naming the tree the check was given: make test's tree when PAPARAZZI_HOME is not set
HOME_RECORD = "paparazzi_home"


def check_ap_binary(elf):
    """The autopilot is an ARM Linux executable holding our drivers and linked to libgpiod; its summary."""
    header = subprocess.run(["readelf", "-h", str(elf)], capture_output=True, text=True).stdout
    machine = re.search(r"Machine:\s+(.*)", header)
    dynamic = subprocess.run(["readelf", "-d", str(elf)], capture_output=True, text=True).stdout
    libraries = re.findall(r"Shared library: \[(.*?)\]", dynamic)
    symbols = subprocess.run(["readelf", "-Ws", str(elf)], capture_output=True, text=True).stdout
    missing = [s for s in DRIVER_SYMBOLS if not re.search(rf"\s{s}$", symbols, re.MULTILINE)]
    if not machine or "ARM" not in machine[1] or missing or not any(l.startswith("libgpiod") for l in libraries):
        raise CheckFailed(f"{elf}: expected an ARM executable with {', '.join(DRIVER_SYMBOLS)} linked to libgpiod; "
                          f"machine {machine[1] if machine else '?'}, missing {missing}, libraries {libraries}")
    return f"{machine[1]}, drivers {', '.join(DRIVER_SYMBOLS)}, linked to {', '.join(libraries)}"


def aircraft_names(conf_xml):
    from lxml import etree
    return [a.get("name") for a in etree.parse(str(conf_xml)).getroot().iter("aircraft")]


def check_range_log(path, duration_s, hover_m=0.6, tolerance_m=0.05):
    """The figures of the flight's range log; raises when a sonar is silent or the model shows no error."""
    log = read_range_log(path)
    figures = {"rows": len(log)}
    for name in SONARS:
        rows = log.sensor == name
        if not rows.any():
            raise CheckFailed(f"{path}: no {name} reading in {duration_s:g} s")
        figures[name] = int(rows.sum())
    down = (log.sensor == "sonar_down") & (log.t > duration_s / 2) & np.isfinite(log.measured)
    median_m = float(np.median(log.true_range[down])) if down.any() else float("nan")
    figures["down_true_median_m"] = median_m
    if not abs(median_m - hover_m) <= tolerance_m:
        raise CheckFailed(f"{path}: the downward sonar's true range is {median_m:.3f} m in the second half of the "
                          f"flight, expected the hover height {hover_m} +- {tolerance_m} m")
    horizontal = np.isin(log.sensor, SONARS[:4]) & np.isfinite(log.measured) & (log.true_range < 2.5)
    short = horizontal & (log.measured < log.true_range - 0.05)
    figures["horizontal_echoes"] = int(horizontal.sum())
    figures["short_readings"] = int(short.sum())
    if short.sum() == 0:
        raise CheckFailed(f"{path}: no short horizontal reading among {int(horizontal.sum())} echoes: the sonar "
                          "chain's errors are not applied")
    return figures


def tree_for_tests(out, environ=os.environ):
    """(tree, None): the Paparazzi tree make test checks against: PAPARAZZI_HOME when it is set, else the tree the
    last make paparazzi-check with this `out` was given (recorded there as HOME_RECORD) while it is still a
    prepared tree; (None, why not) when there is none."""
    if environ.get("PAPARAZZI_HOME"):
        return environ["PAPARAZZI_HOME"], None
    record = Path(out) / HOME_RECORD
    if not record.is_file():
        return None, f"PAPARAZZI_HOME is not set and {record} does not exist (make paparazzi-check writes it)"
    home = record.read_text().strip()
    problem = tree_problem(home)
    if problem:
        return None, f"PAPARAZZI_HOME is not set and the tree {record} names is no longer usable: {problem}"
    return home, None


def check(home, out, duration_s=60.0, time_factor=10.0, jobs=2):
    problem = tree_problem(home)
    if problem:
        raise CheckFailed(problem)
    out = Path(out).resolve()
    tree = out / "tree"
    logs = out / "logs"
    print(f"paparazzi-check: {home} -> scratch copy {tree}", flush=True)
    shutil.rmtree(out, ignore_errors=True)
    logs.mkdir(parents=True)
    (out / HOME_RECORD).write_text(str(Path(home).resolve()) + "\n")
    env = prepare_scratch_tree(home, tree, logs / "static_h.log", "[1/10] headers")
    run_logged("[2/10] airframe.dtd", ["xmllint", "--noout", "--valid", str(tree / AIRFRAME)],
               logs / "airframe_dtd.log", env)
    aircraft = aircraft_names(tree / CONF_XML)[0]
    build(f"[3/10] build {aircraft} nps", tree, CONF_XML, aircraft, "nps", logs / "nps_compile.log", env, jobs)
    build(f"[4/10] build {aircraft} ap (Linux board)", tree, CONF_XML, aircraft, "ap", logs / "ap_compile.log", env,
          jobs)
    elf = tree / "var/aircrafts" / aircraft / "ap/ap.elf"
    print(f"        {elf}: {check_ap_binary(elf)}", flush=True)
    simsitl = tree / "var/aircrafts" / aircraft / "nps/simsitl"
    flight = out / "flight"
    flight.mkdir()
    env_fly = dict(env, FINKEN_WORLD_OUT=str(flight), FINKEN_WORLD_DURATION=f"{duration_s:g}")
    started = time.monotonic()
    run_logged(f"[5/10] fly {duration_s:g} s at x{time_factor:g}",
               [str(simsitl), "--norc", "--time_factor", f"{time_factor:g}", "--ivy_bus", "127.255.255.255:2010"],
               logs / "simsitl.log", env_fly, cwd=tree, timeout=duration_s / time_factor * 4 + 60)
    print(f"        {duration_s:g} s simulated in {time.monotonic() - started:.1f} s", flush=True)
    readings = sorted(flight.glob("readings_*.csv"))
    if not readings:
        raise CheckFailed(f"no range log in {flight}: the finken_world module did not run")
    figures = check_range_log(readings[0], duration_s)
    print(f"  [6/10] range log {readings[0]}: " + ", ".join(f"{k} {v:.3g}" if isinstance(v, float) else f"{k} {v}"
                                                             for k, v in figures.items()))
    check_swarm(tree, env, out, logs, "[7/10]", jobs=jobs)
    check_loop(tree, env, out, logs, "[8/10]")
    check_ground(tree, env, out, logs, "[9/10]")
    check_obstacles(tree, env, out, logs, "[10/10]", jobs=jobs)
    return figures


def main(argv=None):
    import argparse
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(REPO_ROOT / "build/paparazzi"))
    parser.add_argument("--duration", type=float, default=60.0)
    parser.add_argument("--time-factor", type=float, default=10.0)
    parser.add_argument("--find-tree", action="store_true",
                        help="print the tree make test checks against (PAPARAZZI_HOME, else the one the last check "
                             "in --out was given) and exit 0, or why there is none and exit 1; nothing is built")
    args = parser.parse_args(argv)
    if args.find_tree:
        home, why_not = tree_for_tests(args.out)
        print(home or why_not)
        return 0 if home else 1
    try:
        check(os.environ.get("PAPARAZZI_HOME", ""), args.out, args.duration, args.time_factor)
    except (CheckFailed, OSError, subprocess.SubprocessError) as err:
        print(f"paparazzi-check: FAILED: {err}", file=sys.stderr)
        return 1
    print("paparazzi-check: passed")
    return 0
