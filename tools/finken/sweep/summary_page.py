"""summary.html: a sweep on one self-contained page (plots inline as base64 PNG).

What was swept and how many runs are done and failed, the plots, a table of every point (its swept parameters,
runs, and the mean and 95 % interval of each plotted metric), the failed runs with their errors, and where the
full results are.
"""
import base64
import html
from datetime import datetime, timezone

from finken.sweep.values import value_text

#: failed runs listed (the store has them all)
MAX_FAILED_SHOWN = 20
CSS = """body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}
table{border-collapse:collapse;margin:1em 0;font-size:0.85em}td,th{border:1px solid #ccc;padding:3px 6px}
th{background:#eee}td.n{text-align:right}img{max-width:100%}.failed{color:#a00}"""


def render(sweep, summaries, failed_rows, plot_files, store_path, outcome_note):
    """The page as text. summaries: finken.sweep.stats.PointSummary per point; failed_rows: stored rows of the
    runs that failed; plot_files: {swept parameter: PNG path}; outcome_note: one line on this invocation."""
    metrics = list(dict.fromkeys(m for panel in sweep.plots for m in panel))
    done = sum(s.done for s in summaries)
    facts = [("sweep file", sweep.path), ("description", sweep.description), ("airframe", sweep.airframe),
             ("sampling", sweep.sampling), ("parameter points", len(summaries)),
             ("swept", ", ".join(sweep.swept) or "nothing (seeds only)"),
             ("seeds per point", len(sweep.seeds)), ("runs done", f"{done} of {len(sweep.runs)}"),
             ("runs failed", len(failed_rows)), ("this invocation", outcome_note),
             ("results, one row per run", f"{store_path} (SQLite, table runs)"),
             ("written", datetime.now(timezone.utc).isoformat(timespec="seconds"))]
    parts = [f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>Sweep {_e(sweep.name)}</title>"
             f"<style>{CSS}</style></head><body><h1>Sweep {_e(sweep.name)}</h1>",
             _table(None, facts, numeric=False)]
    for key, path in plot_files.items():
        data = base64.b64encode(path.read_bytes()).decode()
        parts.append(f"<h2>Against {_e(key)}</h2><img alt='{_e(key)}' src='data:image/png;base64,{data}'/>")
    parts.append("<h2>Points: mean over seeds [95 % interval]</h2>")
    rows = [[*(value_text(s.point.values[k]) for k in sweep.swept), s.done, s.failed,
             *(s.metrics[m].text() for m in metrics)] for s in summaries]
    parts.append(_table([*sweep.swept, "runs done", "failed", *metrics], rows))
    if failed_rows:
        parts.append(f"<h2 class='failed'>Failed runs ({len(failed_rows)}; the first {MAX_FAILED_SHOWN} shown)</h2>")
        parts.append(_table(["run", "seed", "tries", "error"],
                            [[r["run_key"], r["seed"], r["attempts"], r["error"]]
                             for r in failed_rows[:MAX_FAILED_SHOWN]], numeric=False))
    parts.append("<p>Every metric of every point (mean and interval) is in points.csv beside this page.</p>"
                 "</body></html>")
    return "\n".join(parts)


def _table(header, rows, numeric=True):
    cell = "<td class='n'>" if numeric else "<td>"
    lines = ["<table>"] + (["<tr>" + "".join(f"<th>{_e(h)}</th>" for h in header) + "</tr>"] if header else [])
    lines += ["<tr>" + "".join(f"{cell}{_e(c)}</td>" for c in row) + "</tr>" for row in rows]
    return "\n".join(lines + ["</table>"])


def _e(value):
    return html.escape(str(value))
