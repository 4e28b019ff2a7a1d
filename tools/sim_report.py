#!/usr/bin/env python3
"""Report of a `make sim` run: per-sensor errors, wall-detector and swarm metrics, plots.

Reads the detector-on run (--on: readings.csv, poses.csv, walls.csv, detections.csv) and the detector-off run
(--off: the same files) the host wrote, prints the tables and writes, in the --on folder:
  metrics.json       the wall-detector and swarm figures, the targets every run keeps, each sensor's errors
  trajectories.png   top-down trajectories of both runs, with the interior obstacles of the runs' arena (--arena,
                     else the --airframe's NPS_ARENA_FILE; none without either)
  arena.png          the arena at three moments: copters, sonar rays and readings, wall deflection, obstacles

Usage: sim_report.py --on build/sim --off build/sim/detector_off [--airframe conf/airframes/finken_nps.xml]
                     [--arena conf/arena/swarmlab_pillar.xml]
"""
import argparse
import sys
from pathlib import Path

import numpy as np

from finken.conf.airframe import airframe_arena
from finken.rangelog import RangeLogError
from finken.run_logs import read_poses
from finken.sim_report.arena_plot import ArenaPlotError, plot_arena
from finken.sim_report.metrics import sim_metrics


def moments_to_show(walls, count=3):
    """Snapshot times to draw: the one with the largest total wall deflection, and the others evenly spread."""
    times = np.unique(walls["t"])
    deflection = np.array([np.abs(walls["angle_deg"][walls["t"] == t]).sum() for t in times])
    chosen = {float(times[np.argmax(deflection)])}
    for t in times[np.linspace(0, times.size - 1, count + 1).astype(int)[1:]]:
        if len(chosen) < count:
            chosen.add(float(t))
    return sorted(chosen)


def arena_obstacles(arena=None, airframe=None):
    """The interior obstacles (finken.flight.truth.ArenaTruth.obstacles) of the arena file `arena`, else of the
    airframe's NPS_ARENA_FILE; [] without either."""
    path = arena or (airframe and airframe_arena(airframe))
    if not path:
        return []
    from finken.flight.truth import ArenaTruth
    with ArenaTruth(path) as truth:
        return truth.obstacles()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--on", required=True, type=Path, help="folder of the detector-on run")
    parser.add_argument("--off", required=True, type=Path, help="folder of the detector-off run")
    parser.add_argument("--arena", help="the runs' arena XML (its obstacles are drawn)")
    parser.add_argument("--airframe", help="the runs' airframe (its NPS_ARENA_FILE: the arena without --arena)")
    args = parser.parse_args(argv)
    try:
        obstacles = arena_obstacles(args.arena, args.airframe)
        readings, walls = sim_metrics(args.on, args.off, args.on / "trajectories.png", obstacles)
        plot_arena(walls, read_poses(args.on / "poses.csv"), moments_to_show(walls), args.on / "arena.png", readings,
                   obstacles=obstacles)
    except (RangeLogError, ArenaPlotError, ValueError, OSError, RuntimeError) as err:
        # OSError: an output not written; RuntimeError: libfinken_nps not loaded (the arena's obstacles)
        print(f"error: {err}", file=sys.stderr)
        return 1
    for name in ("metrics.json", "trajectories.png", "arena.png", "readings.csv", "poses.csv", "walls.csv",
                 "detections.csv"):
        print(f"  wrote {args.on / name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
