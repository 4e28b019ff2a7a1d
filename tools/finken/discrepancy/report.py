"""The workflow's output folder: report.json (schema of shared/spec/discrepancy-report.md), report.html and
model.xml (the updated model, finken.models.SensorModel.save)."""
import json
import math
from pathlib import Path

from finken.atomic_output import WriteError, write_texts

REPORT_FILES = ("report.json", "report.html")
MODEL_FILE = "model.xml"


class OutputExistsError(FileExistsError):
    """The output folder already holds a report and overwriting was not asked for."""


def check_output_dir(out_dir, force):
    """Raise OutputExistsError when `out_dir` holds a report and not `force`; raise NotADirectoryError when it
    is a file. Call before any work."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out}: exists and is not a folder")
    existing = [f for f in REPORT_FILES if (out / f).exists()]
    if existing and not force:
        raise OutputExistsError(f"{out}: already holds a report ({', '.join(existing)}); "
                                "use FORCE=1 (--force) to overwrite it")


def _num(x):
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"non-finite number {x} in the report")
    return x


def report_dict(result):
    """report.json as a dict, exactly the spec's keys."""
    return {
        "gap_before": _num(result.gap_before),
        "gap_after": _num(result.gap_after),
        "gap_floor": _num(result.gap_floor),
        "metric": result.metric,
        "effects": [{"name": e.fit.candidate.name, "sensor": e.fit.candidate.kind,
                     "condition": e.fit.candidate.condition,
                     "params": {k: _num(v) for k, v in e.fit.params.items()},
                     "gap_reduction": _num(e.gap_reduction)} for e in result.effects],
        "conditions": [{"sensor": c.kind, "condition": c.label, "n": int(c.n),
                        "gap_before": _num(c.gap_before), "gap_after": _num(c.gap_after)}
                       for c in result.conditions],
    }


def write_outputs(out_dir, result, force):
    """Write report.json, model.xml and report.html into `out_dir` (created if needed) as a set: the old files
    are replaced only once all three are complete (finken.atomic_output.write_texts); raises WriteError (an
    OSError) naming the file that could not be written."""
    from finken.discrepancy.report_html import render_html
    check_output_dir(out_dir, force)
    out = Path(out_dir)
    texts = {out / MODEL_FILE: result.model_out.to_xml(),
             out / "report.json": json.dumps(report_dict(result), indent=2) + "\n",
             out / "report.html": render_html(result)}
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise WriteError(out, err) from err
    write_texts(texts)
    return out
