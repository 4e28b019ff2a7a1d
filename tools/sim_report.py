#!/usr/bin/env python3
"""Report of a `make sim` run: per-sensor errors, wall-detector and swarm metrics, plots.

Reads the detector-on run (--on: readings.csv, poses.csv, walls.csv, detections.csv) and the detector-off run
(--off: the same files) the host wrote, prints the tables and writes, in the --on folder:
  metrics.json       the wall-detector and swarm figures, the targets every run keeps, each sensor's errors
  trajectories.png   top-down trajectories of both runs
  arena.png          the arena at three moments: copters, sonar rays and readings, wall deflection

Usage: sim_report.py --on build/sim --off build/sim/detector_off
"""
import argparse
import sys
from pathlib import Path

import numpy as np

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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--on", required=True, type=Path, help="folder of the detector-on run")
    parser.add_argument("--off", required=True, type=Path, help="folder of the detector-off run")
    args = parser.parse_args(argv)
    try:
        readings, walls = sim_metrics(args.on, args.off, args.on / "trajectories.png")
        plot_arena(walls, read_poses(args.on / "poses.csv"), moments_to_show(walls), args.on / "arena.png", readings)
    except (RangeLogError, ArenaPlotError, ValueError, OSError) as err:   # OSError: an output not written
        print(f"error: {err}", file=sys.stderr)
        return 1
    for name in ("metrics.json", "trajectories.png", "arena.png", "readings.csv", "poses.csv", "walls.csv",
                 "detections.csv"):
        print(f"  wrote {args.on / name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
