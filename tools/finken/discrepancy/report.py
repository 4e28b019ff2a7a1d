"""The workflow's output folder: report.json (schema of shared/spec/discrepancy-report.md), report.html and
model.xml (the updated model, finken.models.SensorModel.save)."""
import json
import math
from pathlib import Path

from finken.atomic_output import WriteError, write_texts
from finken.models import condition_columns

REPORT_FILES = ("report.json", "report.html")
MODEL_FILE = "model.xml"


class OutputExistsError(FileExistsError):
    """The output folder already holds a report and overwriting was not asked for."""


def check_output_dir(out_dir, force, files=REPORT_FILES, what="a report"):
    """Raise OutputExistsError when `out_dir` holds one of `files` (`what` they are) and not `force`; raise
    NotADirectoryError when it is a file. Call before any work."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out}: exists and is not a folder")
    existing = [f for f in files if (out / f).exists()]
    if existing and not force:
        raise OutputExistsError(f"{out}: already holds {what} ({', '.join(existing)}); "
                                "use FORCE=1 (--force) to overwrite it")


def _num(x):
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"non-finite number {x} in the report")
    return x


def report_dict(result):
    """report.json as a dict: the spec's keys with their meaning unchanged, and keys the spec does not name
    (a reader following the spec ignores them): per effect its full condition, 95 % intervals, stability and
    a mixture's summary; the sensors' rows against the model's range, the ranges used, the sensors left out
    and the verdict."""
    return {
        "gap_before": _num(result.gap_before),
        "gap_after": _num(result.gap_after),
        "gap_floor": _num(result.gap_floor),
        "metric": result.metric,
        "effects": [_effect(e) for e in result.effects],
        "conditions": [{"sensor": c.kind, "condition": c.label, "n": int(c.n),
                        "gap_before": _num(c.gap_before), "gap_after": _num(c.gap_after)}
                       for c in result.conditions],
        "sensors": [{"sensor": s.sensor, "kind": s.kind, "rows": s.rows, "readings": s.readings,
                     "true_range_beyond_model": s.true_beyond, "readings_beyond_model": s.readings_beyond}
                    for s in result.sensors],
        "ranges": [{"sensor": k.kind, "min_range_model": _num(k.min_in), "max_range_model": _num(k.max_in),
                    "min_range": _num(k.min_out), "max_range": _num(k.max_out), "source": k.source,
                    "rows_outside_model_range": k.rows_affected} for k in result.ranges.values()],
        "range_gap_reduction": _num(result.range_gap_reduction),
        "notes": list(result.notes),
        "verdict": result.verdict,
    }


def _effect(e):
    """One added effect: the spec's keys (`condition`: the context column it depends on, the first one when
    its condition names two), then the full condition, intervals, stability, a mixture's summary."""
    cand = e.fit.candidate
    out = {"name": cand.name, "sensor": cand.kind,
           "condition": condition_columns(cand.condition)[0] if cand.condition else None,
           "params": {k: _num(v) for k, v in e.fit.params.items()},
           "gap_reduction": _num(e.gap_reduction),
           "condition_expression": cand.condition,
           "ci95": {k: [_num(lo), _num(hi)] for k, (lo, hi) in e.fit.ci.items()}}
    if e.stability is not None:
        out["stability"] = {"share": _num(e.stability.share), "replicates": e.stability.replicates,
                            "rivals": dict(e.stability.rivals)}
    if e.fit.summary:
        out["summary"] = e.fit.summary
    return out


def write_outputs(out_dir, result, force):
    """Write report.json, model.xml and report.html into `out_dir` (created if needed) as a set: the old files
    are replaced only once all three are complete (finken.atomic_output.write_texts); raises WriteError (an
    OSError) naming the file that could not be written."""
    from finken.discrepancy.report_html import render_html
    check_output_dir(out_dir, force)
    out = Path(out_dir)
    return write_folder(out, {out / MODEL_FILE: result.model_out.to_xml(),
                              out / "report.json": json.dumps(report_dict(result), indent=2) + "\n",
                              out / "report.html": render_html(result)})


def write_folder(out, texts):
    """Create the folder `out` if needed and write {path: text} as a set (finken.atomic_output.write_texts);
    raises WriteError naming the folder or file that could not be written. Returns `out`."""
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise WriteError(out, err) from err
    write_texts(texts)
    return out
