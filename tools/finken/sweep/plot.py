"""Plots of a sweep: metrics against one swept parameter, with the 95 % interval of each point's mean.

One figure per swept parameter; one panel per group of metrics (the sweep file's plots); in a grid, one line per
combination of the other swept parameters (a swept define such as WALL_DETECTOR_MAP: one line per value); in a
random sample, the points alone. A parameter that is a file or a bool is drawn at evenly spaced positions named by
the file or TRUE / FALSE; one given as a log range on a log scale. matplotlib is imported here only.
"""
from pathlib import Path

import numpy as np

from finken.atomic_output import atomic_output
from finken.sweep.values import value_text

#: metrics of a panel are told apart by colour, the other parameters' combinations by marker and line style
MARKERS = "osD^vP*X"
STYLES = ("-", "--", ":", "-.")
#: up to this many values of the parameter, each has its tick
MAX_TICKS = 12


def plot_against(summaries, x_key, others, panels, connect, log_x, title, path):
    """Write the figure of the metrics of `panels` (tuples of metric names) against the parameter `x_key` to
    `path` (PNG; WriteError when it cannot be written). summaries: finken.sweep.stats.PointSummary; others: the
    keys of the other swept parameters; connect: draw lines between the points of a series (a grid); log_x: a log
    scale for the parameter. Returns, per panel, the legend's labels and the parameter's tick labels."""
    import matplotlib.pyplot as plt
    xs = [s.point.values[x_key] for s in summaries]
    numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in xs)
    positions = None if numeric else {x: k for k, x in enumerate(dict.fromkeys(xs))}     # in the sweep's order
    series = series_of(summaries, others, connect)
    legend_lines = len(series) * max(map(len, panels))
    fig, axes = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 3.4 + 0.2 * legend_lines), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        for m, metric in enumerate(panel):
            for k, (label, members) in enumerate(series.items()):
                members = sorted(members, key=lambda s: positions[s.point.values[x_key]] if positions else
                                 s.point.values[x_key])
                x = [positions[s.point.values[x_key]] if positions else s.point.values[x_key] for s in members]
                iv = [s.metrics[metric] for s in members]
                mean = np.array([i.mean for i in iv])
                error = np.array([[i.mean - i.low for i in iv], [i.high - i.mean for i in iv]])
                ax.errorbar(x, mean, yerr=np.where(np.isfinite(error), error, 0.0), capsize=3,
                            color=f"C{m}", marker=MARKERS[k % len(MARKERS)], markersize=4,
                            linestyle=STYLES[k % len(STYLES)] if connect else "none",
                            label=", ".join(filter(None, (metric, label))))
        ax.set_xlabel(x_key)
        ax.set_title(" / ".join(panel), fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.18))
        if positions:
            ax.set_xticks(list(positions.values()), [Path(x).name if isinstance(x, str) else value_text(x)
                                                     for x in positions], fontsize=7)
            continue
        if log_x:
            ax.set_xscale("log")
        if len(set(xs)) <= MAX_TICKS:
            ax.set_xticks(sorted(set(xs)), [f"{x:.3g}" for x in sorted(set(xs))], fontsize=7)
            ax.minorticks_off()
    fig.suptitle(f"{title}: mean over seeds, 95 % interval", fontsize=10)
    fig.tight_layout()
    with atomic_output(path, "wb") as f:
        fig.savefig(f, format="png", dpi=100)
    drawn = [(ax.get_legend_handles_labels()[1], [t.get_text() for t in ax.get_xticklabels()]) for ax in axes[0]]
    plt.close(fig)
    return drawn


def series_of(summaries, others, connect):
    """{legend label: the points of one line}: in a grid (connect), one line per combination of the values of the
    other swept parameters `others`, labelled 'NAME=value, ...'; else one series of every point, without label."""
    series = {}
    for summary in summaries:
        label = ", ".join(f"{_short(k)}={value_text(summary.point.values[k])}" for k in others)
        series.setdefault(label if connect else "", []).append(summary)
    return series


def _short(key):
    """A parameter's key without the defines. or model_parameters. before it (for legends)."""
    return key.split(".", 1)[1] if key.startswith(("defines.", "model_parameters.")) else key
