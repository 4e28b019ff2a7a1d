"""The figures of `make sim` from the logs of its two runs (wall detector on and off): each sensor's error against
the ground truth and the wall detector's and swarm's metrics, printed as tables and written as metrics.json.

Shared by tools/sim_report.py (make sim) and the sweeps' workers (finken.sweep.worker), so that a sweep's run has
the figures of make sim.
"""
from pathlib import Path

import numpy as np

from finken.rangelog import read_range_log
from finken.sim_report.arena_plot import read_walls
from finken.sim_report.detector_report import write_report
from finken.sim_report.sensor_errors import format_table, sensor_error_stats


def arena_polygon(walls):
    """The wall polygon at rest, from the first snapshot of walls.csv: each wall's first segment starts a wall."""
    first = walls["t"] == walls["t"][0]
    starts = first & (walls["segment"] == 0)
    order = np.argsort(walls["wall"][starts])
    return np.column_stack([walls["x0"][starts][order], walls["y0"][starts][order]])


def sim_metrics(on_dir, off_dir, trajectories_png=None, obstacles=()):
    """Print the tables of the runs in on_dir and off_dir (readings.csv, walls.csv, detections.csv, poses.csv) and
    write on_dir/metrics.json (and the trajectory plot, with the arena's `obstacles`, when a path is given).
    Returns the detector-on run's readings (a RangeLog) and wall snapshots. Raises RangeLogError, ArenaPlotError or
    ValueError on bad logs, WriteError when an output cannot be written."""
    on_dir, off_dir = Path(on_dir), Path(off_dir)
    readings = read_range_log(on_dir / "readings.csv")
    walls = read_walls(on_dir / "walls.csv")
    errors = sensor_error_stats(readings)
    print("\nSensor readings against ground truth (detector-on run)")
    print(format_table(errors))
    print("\nWall detector and swarm")
    write_report(off_dir, on_dir, arena_polygon(walls), on_dir / "metrics.json", trajectories_png,
                 extra={"sensor_errors": errors}, obstacles=obstacles)
    return readings, walls
