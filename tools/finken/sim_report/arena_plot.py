"""Top-down pictures of the arena: curtain walls deflected by the copters, copters and their sonar rays.

Inputs (all CSV with a header row):
- walls.csv, written by the simulator (sw/simulator/nps/nps_arena_snapshot.h), one row per wall segment and
  snapshot: t [s], wall, segment, x0, y0, x1, y1 (rest endpoints [m]), nx, ny (unit normal into the arena),
  angle_deg (hinge angle), disp_flight_m (inward displacement of the plate at flight height [m]),
  disp_bottom_m (of its bottom edge [m]), target_deg, driven (0/1);
- poses.csv: t [s], vehicle, x [m], y [m], z [m], yaw [rad] (finken.run_logs.read_poses);
- optionally readings.csv, a range log (shared/spec/range-log.md, finken.rangelog.read_range_log).

Pure selection functions (snapshot_at, poses_at, readings_at, displaced_segments) are separate from the
drawing (plot_arena, matplotlib imported there) and the command line (main):

    python -m finken.sim_report.arena_plot --walls walls.csv --poses poses.csv [--readings readings.csv] \
        --times 10,60,120 -o arena.png
"""
import argparse
import csv
import math
import sys

import numpy as np

from finken.atomic_output import WriteError, atomic_output
from finken.cli_types import real
from finken.rangelog import RangeLogError, read_range_log
from finken.run_logs import read_poses
from finken.text_numbers import parse_finite, parse_id

WALL_COLUMNS = ("t", "wall", "segment", "x0", "y0", "x1", "y1", "nx", "ny", "angle_deg", "disp_flight_m",
                "disp_bottom_m", "target_deg", "driven")
WALL_ID_COLUMNS = ("wall", "segment")
# FINken sonar headings in the body frame [rad] (front, right, back, left); sonar_down is not drawn
SONAR_HEADING_RAD = {"sonar_front": 0.0, "sonar_right": -math.pi / 2, "sonar_back": math.pi,
                     "sonar_left": math.pi / 2}
AUTO_DRAWN_FRACTION = 0.08   # automatic exaggeration: the largest displacement drawn as 8 % of the arena span
AUTO_MAX_EXAGGERATION = 10.0
DEFAULT_RADIUS_M = 0.2
DEFAULT_WINDOW_S = 0.5
DEFAULT_RAY_M = 0.4


class ArenaPlotError(ValueError):
    """An input that cannot be plotted: `file:line: column 'x': reason` (line 1 is the header)."""


def read_walls(path):
    """walls.csv as a dict of float arrays, one per column of WALL_COLUMNS: finite numbers, wall and segment ids
    (finken.text_numbers). Raises ArenaPlotError."""
    path = str(path)
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError) as err:
        raise ArenaPlotError(f"{path}: cannot read: {err}") from None
    numbered = [(n + 1, r) for n, r in enumerate(rows) if any(field.strip() for field in r)]
    if not numbered:
        raise ArenaPlotError(f"{path}: empty file: expected the header {','.join(WALL_COLUMNS)}")
    header = [h.strip().lstrip("\ufeff") for h in numbered[0][1]]
    for name in WALL_COLUMNS:
        if name not in header:
            raise ArenaPlotError(f"{path}:1: column '{name}': missing (required: {', '.join(WALL_COLUMNS)})")
    index = [header.index(name) for name in WALL_COLUMNS]
    values = np.empty((len(numbered) - 1, len(WALL_COLUMNS)))
    for row, (line, fields) in enumerate(numbered[1:]):
        if len(fields) != len(header):
            raise ArenaPlotError(f"{path}:{line}: expected {len(header)} fields as in the header, found {len(fields)}")
        for j, k in enumerate(index):
            name = WALL_COLUMNS[j]
            try:
                values[row, j] = parse_id(fields[k]) if name in WALL_ID_COLUMNS else parse_finite(fields[k])
            except ValueError as err:
                raise ArenaPlotError(f"{path}:{line}: column '{name}': {err}") from None
    return {name: values[:, j] for j, name in enumerate(WALL_COLUMNS)}


def snapshot_at(walls, t):
    """Rows (a dict of arrays) of the last wall snapshot at or before t [s] (the first one if all are later)."""
    times = np.unique(walls["t"])
    if times.size == 0:
        raise ArenaPlotError("the walls file holds no snapshot")
    earlier = times[times <= t]
    chosen = earlier[-1] if earlier.size else times[0]
    rows = walls["t"] == chosen
    return {name: column[rows] for name, column in walls.items()}


def auto_exaggeration(walls):
    """Factor for the drawn deflection: the largest displacement drawn as AUTO_DRAWN_FRACTION of the arena
    span, but never less than true scale (1) nor more than AUTO_MAX_EXAGGERATION."""
    span = max(np.ptp(np.concatenate([walls["x0"], walls["x1"]])), np.ptp(np.concatenate([walls["y0"], walls["y1"]])))
    largest = float(np.max(np.abs(walls["disp_flight_m"]))) if walls["disp_flight_m"].size else 0.0
    if largest <= 0.0:
        return 1.0
    return float(np.clip(AUTO_DRAWN_FRACTION * span / largest, 1.0, AUTO_MAX_EXAGGERATION))


def displaced_segments(snapshot, exaggeration):
    """Segment end points [m] moved inward by exaggeration x disp_flight_m: an (n, 2, 2) array."""
    shift = exaggeration * snapshot["disp_flight_m"]
    x0 = snapshot["x0"] + shift * snapshot["nx"]
    y0 = snapshot["y0"] + shift * snapshot["ny"]
    x1 = snapshot["x1"] + shift * snapshot["nx"]
    y1 = snapshot["y1"] + shift * snapshot["ny"]
    return np.stack([np.stack([x0, y0], axis=1), np.stack([x1, y1], axis=1)], axis=1)


def poses_at(poses, t):
    """{vehicle: (x, y, z, yaw)} with each vehicle's last pose at or before t [s] (its first if all later)."""
    result = {}
    for vehicle in np.unique(poses["vehicle"]):
        rows = np.flatnonzero(poses["vehicle"] == vehicle)
        before = rows[poses["t"][rows] <= t]
        i = before[np.argmax(poses["t"][before])] if before.size else rows[np.argmin(poses["t"][rows])]
        result[int(vehicle)] = (poses["x"][i], poses["y"][i], poses["z"][i], poses["yaw"][i])
    return result


def readings_at(log, t, window_s=DEFAULT_WINDOW_S):
    """{(vehicle, sensor): (true_range, measured)} of the last horizontal sonar reading in [t - window_s, t]."""
    result = {}
    if log is None:
        return result
    recent = np.flatnonzero((log.t <= t) & (log.t >= t - window_s) & np.isin(log.sensor, list(SONAR_HEADING_RAD)))
    for i in recent[np.argsort(log.t[recent], kind="stable")]:
        result[(int(log.vehicle[i]), str(log.sensor[i]))] = (log.true_range[i], log.measured[i])
    return result


def plot_arena(walls, poses, times, path, readings=None, exaggeration=None,
               radius_m=DEFAULT_RADIUS_M, window_s=DEFAULT_WINDOW_S, ray_m=DEFAULT_RAY_M, obstacles=()):
    """Write a PNG with one top-down panel per time [s] in `times`.

    walls: read_walls(); poses: read_poses(); readings: a RangeLog or None. Plates are drawn where they are at
    flight height, their displacement multiplied by `exaggeration` (None: auto_exaggeration; said in the
    legend) and coloured by hinge angle; copters as circles of radius_m [m] with their sonar rays (true range solid, reading as a cross; or
    ray_m-long dashed headings when there are no readings within window_s [s]); the interior obstacles
    (finken.flight.truth.Obstacle) filled grey.
    """
    import matplotlib
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    from matplotlib.lines import Line2D
    from matplotlib.patches import Circle

    if exaggeration is None:
        exaggeration = auto_exaggeration(walls)
    snapshots = [snapshot_at(walls, t) for t in times]
    max_angle = max(1.0, max(float(np.max(s["angle_deg"])) for s in snapshots))
    norm = matplotlib.colors.Normalize(vmin=0.0, vmax=max_angle)
    cmap = matplotlib.colormaps["plasma"]
    cols = min(3, len(times))
    rows = math.ceil(len(times) / cols)
    lo = np.min([walls["x0"].min(), walls["x1"].min()]), np.min([walls["y0"].min(), walls["y1"].min()])
    hi = np.max([walls["x0"].max(), walls["x1"].max()]), np.max([walls["y0"].max(), walls["y1"].max()])
    span = max(hi[0] - lo[0], hi[1] - lo[1])
    margin = 0.06 * span
    panel_w = 4.2 * (hi[0] - lo[0] + 2 * margin) / (hi[1] - lo[1] + 2 * margin)
    fig, axes = plt.subplots(rows, cols, figsize=(max(3.0, panel_w) * cols + 1.4, 4.6 * rows + 0.9),
                             squeeze=False, constrained_layout=True)
    for k, ax in enumerate(axes.flat):
        if k >= len(times):
            ax.set_visible(False)
            continue
        t, snap = times[k], snapshots[k]
        rest = np.stack([np.stack([snap["x0"], snap["y0"]], 1), np.stack([snap["x1"], snap["y1"]], 1)], 1)
        ax.add_collection(LineCollection(rest, colors="0.75", linewidths=1.0, linestyles="--", zorder=1))
        ax.add_collection(LineCollection(displaced_segments(snap, exaggeration), colors=cmap(norm(snap["angle_deg"])),
                                         linewidths=3.0, capstyle="butt", zorder=2))
        for obstacle in obstacles:
            ax.fill(obstacle.outline[:, 0], obstacle.outline[:, 1], color="0.6", zorder=2)
        shown = readings_at(readings, t, window_s)
        for vehicle, (x, y, _z, yaw) in sorted(poses_at(poses, t).items()):
            ax.add_patch(Circle((x, y), radius_m, facecolor="#cfe3f5", edgecolor="#1f4e79", lw=1.2, zorder=4))
            ax.text(x + 0.8 * radius_m, y + 0.8 * radius_m, str(vehicle), ha="left", va="bottom", fontsize=8,
                    color="#1f4e79", fontweight="bold", zorder=5)
            for sensor, heading in SONAR_HEADING_RAD.items():
                ux, uy = math.cos(yaw + heading), math.sin(yaw + heading)
                if (vehicle, sensor) in shown:
                    true_range, measured = shown[(vehicle, sensor)]
                    ax.plot([x, x + true_range * ux], [y, y + true_range * uy], color="#2a9d8f", lw=0.9, zorder=3)
                    if np.isfinite(measured):
                        ax.plot(x + measured * ux, y + measured * uy, marker="x", color="#e63946", ms=6, mew=1.6,
                                zorder=6)
                elif readings is None:
                    ax.plot([x, x + ray_m * ux], [y, y + ray_m * uy], color="#2a9d8f", lw=0.9, ls=":", zorder=3)
            ax.plot([x, x + radius_m * math.cos(yaw)], [y, y + radius_m * math.sin(yaw)], color="#1f4e79", lw=1.6,
                    zorder=5)
        ax.set_xlim(lo[0] - margin, hi[0] + margin)
        ax.set_ylim(lo[1] - margin, hi[1] + margin)
        ax.set_aspect("equal")
        ax.set_title(f"t = {t:g} s (walls at {snap['t'][0]:g} s)", fontsize=10)
        ax.set_xlabel("x east [m]")
        ax.set_ylabel("y north [m]")
        ax.grid(True, color="0.92", lw=0.6)
    handles = [
        Line2D([], [], color="0.75", ls="--", label="wall at rest"),
        Line2D([], [], color=cmap(0.8), lw=3, label="plate at flight height, deflection " +
               ("true scale" if exaggeration == 1.0 else f"exaggerated x{exaggeration:.3g}")),
        Line2D([], [], color="#2a9d8f", lw=0.9, label="sonar ray (true range)" if readings is not None
               else f"sonar heading ({ray_m:g} m)"),
        Line2D([], [], marker="o", ls="", mfc="#cfe3f5", mec="#1f4e79", label=f"copter (r = {radius_m:g} m), id"),
    ]
    if readings is not None:
        handles.append(Line2D([], [], marker="x", ls="", color="#e63946", mew=1.6, label="sonar reading"))
    if obstacles:
        handles.append(Line2D([], [], marker="s", ls="", color="0.6", label="obstacle"))
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 3), fontsize=8, frameon=False)
    fig.colorbar(matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap), ax=axes.ravel().tolist(), shrink=0.8,
                 label="hinge angle [deg]")
    try:
        with atomic_output(path, "wb") as f:
            fig.savefig(f, format="png", dpi=130)
    finally:
        plt.close(fig)


def parse_times(text):
    """'10,60,120' as a list of floats [s]."""
    try:
        times = [parse_finite(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ArenaPlotError(f"--times '{text}': expected comma-separated times in seconds") from None
    if not times:
        raise ArenaPlotError(f"--times '{text}': expected comma-separated times in seconds")
    return times


def main(argv=None):
    """Command line; returns the exit status (0; 2 on bad input, 1 when the PNG cannot be written; the error on
    stderr)."""
    parser = argparse.ArgumentParser(prog="python -m finken.sim_report.arena_plot",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--walls", required=True, help="walls.csv written by the simulator")
    parser.add_argument("--poses", required=True, help="poses.csv: t,vehicle,x,y,z,yaw")
    parser.add_argument("--readings", help="a range log (optional): draws each sonar's true range and reading")
    parser.add_argument("--times", help="panel times [s], e.g. 10,60,120 (default: start, middle, end)")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--exaggerate", type=real(0, low_open=True), default=None,
                        help="multiply the drawn deflection (default: largest drawn as "
                             f"{AUTO_DRAWN_FRACTION:.0%} of the arena, x1 to x{AUTO_MAX_EXAGGERATION:g})")
    parser.add_argument("--radius", type=real(0, low_open=True), default=DEFAULT_RADIUS_M,
                        help=f"copter body radius [m] (default {DEFAULT_RADIUS_M:g})")
    args = parser.parse_args(argv)
    try:
        walls = read_walls(args.walls)
        poses = read_poses(args.poses)
        readings = read_range_log(args.readings) if args.readings else None
        if args.times:
            times = parse_times(args.times)
        else:
            span = np.unique(walls["t"])
            times = [float(span[0]), float(span[len(span) // 2]), float(span[-1])] if span.size else [0.0]
        plot_arena(walls, poses, times, args.output, readings, args.exaggerate, args.radius)
    except (ArenaPlotError, RangeLogError) as err:
        print(f"arena_plot: {err}", file=sys.stderr)
        return 2
    except WriteError as err:
        print(f"arena_plot: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
