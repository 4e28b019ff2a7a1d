"""The report of a sweep, from its store, in OUT:

  points.csv           one row per parameter point: every parameter, runs done and failed, and for every metric its
                       mean over the seeds and the bounds of its 95 % interval (<metric>, <metric>.low, .high)
  plots/<param>.png    the sweep's plotted metrics against each swept parameter (finken.sweep.plot)
  summary.html         one page: what was swept, progress, the plots, the points, the failed runs
                       (finken.sweep.summary_page)

Only the runs of the sweep file as it is now are reported; the store may hold more (an earlier version of the file).
"""
import csv

from finken.atomic_output import atomic_output, write_text
from finken.sweep.metrics import metric_names
from finken.sweep.plot import plot_against
from finken.sweep.points import run_key
from finken.sweep.stats import summarize_points
from finken.sweep.summary_page import render
from finken.sweep.values import value_text


def write_report(sweep, store, store_path, out, outcome_note):
    """Write the report files into `out` (a folder); returns their paths and the points' table as text (the plotted
    metrics). WriteError when a file cannot be written."""
    rows = store.rows({run_key(point, seed) for point, seed in sweep.runs})
    summaries = summarize_points(sweep.points, rows, metric_names())
    (out / "plots").mkdir(parents=True, exist_ok=True)
    plots = {}
    for key in sweep.swept:
        plots[key] = out / "plots" / f"{key}.png"
        plot_against(summaries, key, [k for k in sweep.swept if k != key], sweep.plots, sweep.sampling == "grid",
                     key in sweep.log_scale, sweep.name, plots[key])
    _write_points(summaries, out / "points.csv")
    failed = [row for row in rows if row["status"] == "failed"]
    write_text(out / "summary.html", render(sweep, summaries, failed, plots, store_path, outcome_note))
    return [out / "points.csv", *plots.values(), out / "summary.html"], points_table(sweep, summaries)


def points_table(sweep, summaries, max_rows=40):
    """The swept parameters, runs and plotted metrics (mean [95 % interval]) of the first points, as text."""
    metrics = list(dict.fromkeys(m for panel in sweep.plots for m in panel))
    header = [*sweep.swept, "done", "failed", *metrics]
    rows = [[*(value_text(s.point.values[k]) for k in sweep.swept), str(s.done), str(s.failed),
             *(s.metrics[m].text() for m in metrics)] for s in summaries[:max_rows]]
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(header)]
    lines = ["  ".join(text.rjust(w) for text, w in zip(line, widths)) for line in [header, *rows]]
    if len(summaries) > max_rows:
        lines.append(f"... {len(summaries) - max_rows} more points in points.csv")
    return "\n".join(lines)


def _write_points(summaries, path):
    names = metric_names()
    with atomic_output(path, newline="") as f:
        writer = csv.writer(f)
        writer.writerow([*summaries[0].point.values, "runs_done", "runs_failed",
                         *(f"{m}{part}" for m in names for part in ("", ".low", ".high"))])
        for s in summaries:
            writer.writerow([*s.point.values.values(), s.done, s.failed,
                             *(_number(v) for m in names for v in (s.metrics[m].mean, s.metrics[m].low,
                                                                   s.metrics[m].high))])


def _number(value):
    """A value for the CSV: empty when not a number (NaN)."""
    return "" if value != value else f"{value:.6g}"
