"""Top-down trajectory plot of the swarm runs side by side (matplotlib, imported when called)."""
import numpy as np

from finken.atomic_output import atomic_output


def plot_trajectories(runs, polygon, path, near_wall_m=0.5):
    """Write a PNG with one top-down panel per run.

    runs: list of (title, poses) with poses a dict of arrays t [s], vehicle, x [m], y [m].
    polygon: arena corners (k x 2) [m]. near_wall_m: the near-wall distance, drawn as a dotted margin [m].
    Each vehicle's path is one coloured line, with a circle at its start and a cross at its end.
    """
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    corners = np.asarray(polygon, dtype=float).reshape(-1, 2)
    closed = corners if np.allclose(corners[0], corners[-1]) else np.vstack([corners, corners[:1]])
    fig, axes = plt.subplots(1, len(runs), figsize=(5.5 * len(runs), 6), squeeze=False)
    for ax, (title, poses) in zip(axes[0], runs):
        ax.plot(closed[:, 0], closed[:, 1], color="black", linewidth=2, label="wall")
        _near_wall_margin(ax, closed, near_wall_m)
        t, vehicle = np.asarray(poses["t"]), np.asarray(poses["vehicle"])
        for k, v in enumerate(np.unique(vehicle)):
            rows = np.flatnonzero(vehicle == v)
            rows = rows[np.argsort(t[rows], kind="stable")]
            x, y = np.asarray(poses["x"])[rows], np.asarray(poses["y"])[rows]
            color = f"C{k % 10}"
            ax.plot(x, y, color=color, linewidth=0.8, alpha=0.8, label=f"copter {v:g}")
            ax.plot(x[:1], y[:1], "o", color=color)
            ax.plot(x[-1:], y[-1:], "x", color=color, markersize=8)
        ax.set_title(title)
        ax.set_xlabel("x (east) [m]")
        ax.set_ylabel("y (north) [m]")
        ax.set_aspect("equal")
        ax.grid(True, linewidth=0.3)
    axes[0][0].legend(loc="upper left", fontsize="small")
    fig.suptitle(f"Trajectories (o start, x end; dotted: {near_wall_m:g} m from the walls)")
    fig.tight_layout()
    try:
        with atomic_output(path, "wb") as f:
            fig.savefig(f, format="png", dpi=120)
    finally:
        plt.close(fig)


def _near_wall_margin(ax, closed, margin_m):
    """Dotted lines margin_m inside each wall (parallel to it), for a convex counter- or clockwise polygon."""
    area2 = np.sum(closed[:-1, 0] * closed[1:, 1] - closed[1:, 0] * closed[:-1, 1])
    for a, b in zip(closed[:-1], closed[1:]):
        tangent = (b - a) / np.linalg.norm(b - a)
        inward = np.array([-tangent[1], tangent[0]]) * np.sign(area2)
        ends = np.vstack([a, b]) + margin_m * inward
        ax.plot(ends[:, 0], ends[:, 1], color="grey", linestyle=":", linewidth=1)
