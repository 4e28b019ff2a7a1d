"""Top-down trajectory plot of the swarm runs side by side (matplotlib, imported when called)."""
import numpy as np

from finken.atomic_output import atomic_output


def plot_trajectories(runs, polygon, path, near_wall_m=0.5, obstacles=()):
    """Write a PNG with one top-down panel per run.

    runs: list of (title, poses) with poses a dict of arrays t [s], vehicle, x [m], y [m].
    polygon: arena corners (k x 2) [m]. near_wall_m: the near-wall distance, drawn as a dotted margin [m].
    obstacles: the interior obstacles (finken.flight.truth.Obstacle: their footprints), drawn filled grey.
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
        for k, outline in enumerate(o.outline for o in obstacles):
            ax.fill(outline[:, 0], outline[:, 1], color="grey", label=None if k else "obstacle")
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


def _near_wall_margin(ax, closed, margin_m, cells=400):
    """A dotted line margin_m inside the walls of the closed polygon `closed`, convex or not (rounded around a
    reentrant corner): the level margin_m of the distance to the walls inside, on a grid of cells x cells."""
    from matplotlib.path import Path
    x, y = np.meshgrid(*np.linspace(closed.min(axis=0), closed.max(axis=0), cells).T)
    p = np.column_stack([x.ravel(), y.ravel()])[:, None]
    a, ab = closed[:-1], np.diff(closed, axis=0)
    along = np.clip(np.sum((p - a) * ab, axis=2) / np.sum(ab * ab, axis=1), 0.0, 1.0)
    dist = np.linalg.norm(p - (a + along[..., None] * ab), axis=2).min(axis=1)
    inside = Path(closed).contains_points(p[:, 0])
    ax.contour(x, y, np.where(inside, dist, -dist).reshape(x.shape), levels=[margin_m], colors="grey",
               linestyles="dotted", linewidths=1)
