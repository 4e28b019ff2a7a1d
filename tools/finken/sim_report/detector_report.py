"""Wall-detector and swarm metrics of a detector-off and a detector-on simulation run (thin CLI).

Usage:
  python -m finken.sim_report.detector_report --off build/sim/off --on build/sim/on \\
      --arena-polygon "-1.5,-2 1.5,-2 1.5,2 -1.5,2" [--json build/sim/metrics.json] [--plot build/sim/trajectories.png]

Each run folder holds detections.csv and poses.csv (formats in finken.run_logs). The detector judges
readings in both runs (only the swarm's use of its verdicts differs); the classification keys come from the
detector-on run, the detector-off run's figures are reported beside them
(finken.sim_report.detector_metrics.summarize). Prints the table, writes the JSON (the keys, the _off_run keys, the
full score sets and the targets every run keeps: detector_metrics.targets_met) and the trajectory plot. Exit status
0 whether or not the targets are met, 1 on bad input.
"""
import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from finken.atomic_output import atomic_output
from finken.rangelog import RangeLogError
from finken.run_logs import parse_polygon, read_detections, read_poses
from finken.sim_report.detector_metrics import format_table, summarize, targets_met


def json_safe(value):
    """NaN -> None (JSON has no NaN), recursively; numpy scalars -> Python."""
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (float, np.floating)):
        return None if math.isnan(value) else float(value)
    return value


def write_report(off_dir, on_dir, polygon, json_path=None, plot_path=None, extra=None, obstacles=()):
    """Metrics of the detector-off and -on runs in off_dir and on_dir (folders with detections.csv and poses.csv):
    printed as a table, written as JSON (with `extra` entries added) and as a trajectory plot (with the arena's
    `obstacles`, swarm_plot.plot_trajectories) when paths are given. Returns the metrics; raises RangeLogError or
    ValueError on bad input, WriteError (an OSError) when an output cannot be written."""
    runs = {name: {"detections": read_detections(Path(folder) / "detections.csv"),
                   "poses": read_poses(Path(folder) / "poses.csv")}
            for name, folder in (("off", off_dir), ("on", on_dir))}
    metrics = summarize(runs, polygon)
    print(format_table(metrics))
    if json_path:
        Path(json_path).parent.mkdir(parents=True, exist_ok=True)
        with atomic_output(json_path) as f:
            json.dump(json_safe({**metrics, "targets": targets_met(metrics), **(extra or {})}), f, indent=2)
    if plot_path:
        from finken.sim_report.swarm_plot import plot_trajectories
        Path(plot_path).parent.mkdir(parents=True, exist_ok=True)
        plot_trajectories([("wall detector off", runs["off"]["poses"]), ("wall detector on", runs["on"]["poses"])],
                          polygon, plot_path, obstacles=obstacles)
    return metrics


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--off", required=True, type=Path, help="folder of the detector-off run")
    parser.add_argument("--on", required=True, type=Path, help="folder of the detector-on run")
    parser.add_argument("--arena-polygon", required=True, help="arena corners 'x,y x,y ...' [m]")
    parser.add_argument("--json", type=Path, help="write the metrics here (e.g. build/sim/metrics.json)")
    parser.add_argument("--plot", type=Path, help="write the trajectory plot here (PNG)")
    args = parser.parse_args(argv)
    try:
        write_report(args.off, args.on, parse_polygon(args.arena_polygon), args.json, args.plot)
    except (RangeLogError, ValueError, OSError) as err:
        print(f"error: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
