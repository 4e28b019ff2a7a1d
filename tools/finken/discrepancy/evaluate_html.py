"""evaluate.html: the models side by side, one self-contained page (figures as base64 PNG, as report_html.py).

A summary table (gap, noise floor, gap/floor), the gap per condition of every model (figure and table, the best
of each row marked), and per model the log's rows beyond its range. matplotlib is imported here only.
"""
from pathlib import Path

import numpy as np

from finken.discrepancy.evaluate import SEEDS
from finken.discrepancy.report_html import CSS, GAP_FIGURE_ROWS, esc, finish_gap_axes, fmt, png, table

#: Most bars (conditions x models) in the figure.
MAX_BARS = 120
BEST = " \u2605"   # marks the lowest gap of a row


def _labels(ev):
    """A short label per model: its number and file name (two models may share a file name)."""
    return [f"#{k} {Path(s.name).name}" for k, s in enumerate(ev.scores, start=1)]


def gap_figure(ev):
    """Horizontal grouped bars: each condition's gap per model (largest first), noise floors as ticks."""
    import matplotlib.pyplot as plt
    m = len(ev.scores)
    order = np.argsort([-max(s.conditions[j].gap for s in ev.scores) for j in range(len(ev.scores[0].conditions))],
                       kind="stable")[:max(4, min(GAP_FIGURE_ROWS, MAX_BARS // m))]
    fig, ax = plt.subplots(figsize=(10, (0.12 * m + 0.12) * len(order) + 1.2))
    y, h = np.arange(len(order)), 0.8 / m
    colors = plt.get_cmap("tab10").colors
    for k, (s, label) in enumerate(zip(ev.scores, _labels(ev))):
        yk = y - 0.4 + h * (k + 0.5)
        ax.barh(yk, [s.conditions[j].gap for j in order], h, label=label, color=colors[k % len(colors)])
        ax.plot([s.conditions[j].floor for j in order], yk, "k|", markersize=max(3, 9 / m),
                label="noise floor" if k == 0 else None)
    first = ev.scores[0].conditions
    finish_gap_axes(ax, [f"{first[j].kind}: {first[j].label}" for j in order],
                    "Gap per condition and model, largest first", 7)
    return fig


def _marked(values):
    """Formatted values, the lowest marked (all of them when tied; none for a single model)."""
    low = min(values)
    return [fmt(v) + (BEST if v == low and len(values) > 1 else "") for v in values]


def _beyond_note(score):
    over = [b for b in score.beyond_range if b.true_beyond or b.readings_beyond]
    if not over:
        return "<p>No row of the log lies beyond the model's range.</p>"
    parts = [f"{esc(b.sensor)}: {b.true_beyond} of {b.rows} true ranges and {b.readings_beyond} of {b.readings} "
             f"readings outside [{score.model.chains[b.kind].min_range:g}, {score.model.chains[b.kind].max_range:g}] m"
             for b in over]
    return ("<p>Rows whose true range or reading lies outside the model's range (they are scored all the "
            "same; a gap there may be the range, not a missing effect): " + "; ".join(parts) + ".</p>")


def render_html(ev):
    """The whole page as one HTML string."""
    labels = _labels(ev)
    conds = ev.scores[0].conditions
    ratios = [fmt(s.ratio, 3) for s in ev.scores]
    summary = [[label, s.name, g, s.floor, r] for label, s, g, r in
               zip(labels, ev.scores, _marked([s.gap for s in ev.scores]), ratios)]
    per_condition = [[c.kind, c.label, c.n, *_marked([s.conditions[j].gap for s in ev.scores])]
                     for j, c in enumerate(conds)]
    best = ev.best()
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Model evaluation</title>"
             f"<style>{CSS}</style></head><body>",
             "<h1>Sensor models on a measured log</h1>",
             f"<p class='verdict'>Lowest gap: {esc(', '.join(s.name for s in best))} "
             f"({best[0].gap:.4g} m).</p>",
             table(["", "value"], [
                 ["measured log", ev.measured_path],
                 ["rows (scored) per kind", "; ".join(f"{k}: {n} ({s})" for k, (n, s) in ev.rows.items())],
                 ["simulations per model", SEEDS], ["seed", ev.seed]], left=(0, 1)),
             f"<p><b>Gap:</b> {esc(ev.metric)}. Every model is simulated on the same rows with the same seeds; "
             f"its gap is the mean over {SEEDS} simulations, its noise floor the gap between two of them. "
             f"{BEST.strip()} marks the lowest gap.</p>",
             "<h2>Models</h2>",
             table(["", "model", "gap [m]", "noise floor [m]", "gap / floor"], summary, left=(0, 1)),
             "<h2>Gap per condition</h2>", png(gap_figure(ev)),
             table(["sensor", "condition", "n", *[f"gap [m] {label}" for label in labels]], per_condition,
                    left=(0, 1)),
             "<h2>Rows beyond each model's range</h2>"]
    for label, s in zip(labels, ev.scores):
        parts.append(f"<h3>{esc(label)}: {esc(s.name)}</h3>" + _beyond_note(s))
    parts.append("</body></html>")
    return "\n".join(parts)
