"""The workflow's output folder: report.json (schema of shared/spec/discrepancy-report.md), report.html and
model.xml (the updated model, finken.models.SensorModel.save)."""
import json
import math
from pathlib import Path

from finken.atomic_output import WriteError, write_texts
from finken.discrepancy.glitches import RULE
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
        "effects": [_effect(e) for e in result.effects] + [_glitch_effect(t) for t in result.glitch_tests
                                                           if t.changed and t.effect is not None],
        "conditions": [{"sensor": c.kind, "condition": c.label, "n": int(c.n),
                        "gap_before": _num(c.gap_before), "gap_after": _num(c.gap_after),
                        **({f"glitch_rate_{k}": _num(v) for k, v in c.glitch_rates.items()} if c.glitch_rates else {})}
                       for c in result.conditions],
        "glitches": _glitches(result),
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


def _glitches(result):
    """report.json's "glitches": the rule, the counts per kind (with the rates of the input and output models on
    the held-out rows and the test of the rates), per sensor and per stream that has a glitch."""
    overall = {c.kind: c.glitch_rates for c in result.conditions if c.view == "all" and c.glitch_rates}
    tests = {t.kind: t for t in result.glitch_tests}
    kinds = []
    for c in result.glitch_counts.get("kinds", []):
        entry = c.to_dict()
        if c.label in tests:
            t = tests[c.label]
            entry.update(model_rate_before=_num(t.model_rate), test_p=_num(t.p), effect_set=t.changed)
        if c.label in overall:
            entry.update(heldout_rate_measured=_num(overall[c.label]["measured"]),
                         heldout_rate_before=_num(overall[c.label]["before"]),
                         heldout_rate_after=_num(overall[c.label]["after"]))
        kinds.append(entry)
    streams = result.glitch_counts.get("streams", [])
    return {"rule": RULE, "kinds": kinds,
            "sensors": [c.to_dict() for c in result.glitch_counts.get("sensors", [])],
            "streams": [c.to_dict() for c in streams if c.glitches],
            "streams_without_glitches": sum(not c.glitches for c in streams)}


def _glitch_effect(test):
    """The glitch effect the workflow set on a kind, as an entry of "effects" (it leaves the continuous gap as
    it is: gap_reduction 0); an infinite glitch value is written "inf" or "-inf" (JSON has no infinity)."""
    e = test.effect
    return {"name": "glitch", "sensor": test.kind, "condition": None, "params": {"p": _num(e.params["p"])},
            "gap_reduction": 0.0, "condition_expression": None, "ci95": {},
            "values": [float(v) if math.isfinite(v) else ("inf" if v > 0 else "-inf") for v in e.values]}


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
    if e.undecided is not None:
        out["undecided_with"] = {"name": e.undecided.candidate.name, "condition": e.undecided.candidate.condition,
                                 "params": {k: _num(v) for k, v in e.undecided.params.items()}}
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
