"""`make evaluate`'s output folder: evaluate.json (below) and evaluate.html (evaluate_html.py), written as a set.

    {"models": [{"model": "<path as given>", "gap": float, "gap_floor": float,
                 "glitch_rate": {"sonar"|"ranging": float},
                 "conditions": [{"sensor": "sonar"|"ranging", "condition": "<label>", "n": int,
                                 "gap": float, "gap_floor": float}]}],
     "glitch_rate": {"sonar"|"ranging": float},      # the log's glitches per row, on the same rows
     "metric": "<gap.METRIC>"}
"""
import json
from pathlib import Path

from finken.discrepancy import report

OUTPUT_FILES = ("evaluate.json", "evaluate.html")


def check_output_dir(out_dir, force):
    """report.check_output_dir for an evaluation."""
    report.check_output_dir(out_dir, force, OUTPUT_FILES, "an evaluation")


def evaluation_dict(ev):
    """evaluate.json as a dict."""
    return {"models": [{"model": s.name, "gap": s.gap, "gap_floor": s.floor, "glitch_rate": s.glitch_rate,
                        "conditions": [{"sensor": c.kind, "condition": c.label, "n": c.n, "gap": c.gap,
                                        "gap_floor": c.floor} for c in s.conditions]} for s in ev.scores],
            "glitch_rate": ev.glitch_rate, "metric": ev.metric}


def write_outputs(out_dir, ev, force):
    """Write evaluate.json and evaluate.html into `out_dir` (created if needed); the old files are replaced only
    once both are complete. Raises WriteError naming the file that could not be written."""
    from finken.discrepancy.evaluate_html import render_html
    check_output_dir(out_dir, force)
    out = Path(out_dir)
    return report.write_folder(out, {
        out / "evaluate.json": json.dumps(evaluation_dict(ev), indent=2, allow_nan=False) + "\n",
        out / "evaluate.html": render_html(ev)})
