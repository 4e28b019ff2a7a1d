"""The discrepancy workflow end to end: the fast subset of the hidden-effect suite, and the command line.

The full suite (>= 20 cases, confusion matrix, parameter recovery) runs in `make validate`; here a few cases on
a 60 s synthetic flight (4 copters, ~15 600 rows), each with fixed seeds, so every outcome is deterministic.
What each case asserts and why it cannot pass by accident:
- no effect: nothing is named and the verdict says so (a false naming needs a Holm-corrected p < 0.01 and a
  candidate beating the current model by the margin);
- one hidden effect: exactly that effect, sensor and condition is named, its 95 % bootstrap interval or, for
  effects fitted on a grid, a 10 % band holds the hidden value, the interval is at most WIDTH_FACTOR = 4 times as
  wide as an efficient estimator's 95 % interval on the same rows (expected_standard_error: formulas, measured
  efficiencies, false-failure probability), and the held-out gap at least halves;
- two hidden effects on different sensors: both are named.
The command line runs on a 30 s flight (~10 000 rows).
"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from finken import models
from finken.discrepancy import hidden, synthetic
from finken.discrepancy.dataset import prepare
from finken.discrepancy.fitting import MLE_ROWS
from finken.discrepancy.validate import run_case
from finken.rangelog import write_range_log

REPO = Path(__file__).resolve().parents[2]
CALIBRATE = REPO / "tools" / "calibrate.py"
LOGS = REPO / "tests" / "data" / "logs"
WORKFLOW_SEED = 2
WIDTH_FACTOR = 4.0


@pytest.fixture(scope="module")
def base():
    return models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)


@pytest.fixture(scope="module")
def truth():
    return synthetic.ground_truth(4, 60.0, seed=21)


def _case(truth, base, effects, seed):
    hid = [hidden.HiddenEffect(kind, models.Effect(name, params, cond)) for kind, name, params, cond in effects]
    return hidden.Case(1, hid, hidden.simulate_measured(truth, hidden.hidden_model(base, hid), seed))


def expected_standard_error(log, base, kind, name, value, condition):
    """The standard error of an efficient estimator of a hidden parameter on the rows the workflow fits it on (its
    training blocks, prepare() with the workflow's seed, under the effect's condition: n rows, true ranges t, true-range
    rates r; the base model's noise sigma0 on that kind). Fisher information / least squares:
      bias b       residual + b:            SE = sigma0 sqrt(2 / n)
      scale k      residual (k - 1) t + k e: SE = k sigma0 sqrt(2 / sum t^2)
      latency tau  residual - tau r (to first order): SE = sigma0 sqrt(2 / sum r^2)
      gaussian s   N(0, sigma0^2 + s^2):    SE = (sigma0^2 + s^2) / (s sqrt(2 n)), n at most MLE_ROWS
    (the factor 2 of the first three: a minimum-gap fit compares with simulated readings of the same noise).
    The workflow's fits are less efficient: with 60 bootstrap replicates their spread was 1.10 (bias), 1.16 (scale),
    1.70 (latency) and 1.51 (gaussian, simulated likelihood) times this SE.
    Bound: width <= WIDTH_FACTOR 2 x 1.96 SE = 15.7 SE, at least 8.4 bootstrap sd even 10 % above those spreads.
    A percentile interval of R replicates is narrower than their range: P(range of 16 normals > 8.4) = 3.6e-7
    (latency; R int phi(x) [(1 - Phi(x))^(R-1) - (Phi(x + w) - Phi(x))^(R-1)] dx), 1e-8 for the gaussian (R = 30,
    w = 9.4), < 1e-15 for bias and scale: about 4e-7 for the four intervals. An interval 4 times too wide (its
    replicates spread 4 times as much) exceeds the bound with probability 0.46, 0.56, 0.96 and 0.99 for these four:
    all four pass with probability 5e-5."""
    kr = prepare(log, base, WORKFLOW_SEED)[kind]
    rows = ~kr.heldout & models.condition_mask(condition, kr.ctx, kr.n)
    n, t, r = int(rows.sum()), kr.true_range[rows], kr.range_rate[rows]
    sigma0 = base.chains[kind].effects[0].params["sigma"]
    if name == "bias":
        return sigma0 * np.sqrt(2 / n)
    if name == "scale":
        return value * sigma0 * np.sqrt(2 / np.sum(t ** 2))
    if name == "latency":
        return sigma0 * np.sqrt(2 / np.sum(r ** 2))
    if name == "gaussian":
        return (sigma0 ** 2 + value ** 2) / (value * np.sqrt(2 * min(n, MLE_ROWS)))
    raise ValueError(f"no standard error for {name}")


@pytest.mark.parametrize("effects", [
    [],
    [("sonar", "bias", {"b": 0.08}, "ctx_target_copter")],
    [("sonar", "latency", {"tau": 0.25}, None)],
    [("ranging", "gaussian", {"sigma": 0.15}, None), ("sonar", "scale", {"k": 1.08}, None)],
], ids=["none", "bias|target_copter", "latency", "gaussian+scale"])
def test_hidden_effects_are_named_and_fitted(truth, base, effects):
    case = _case(truth, base, effects, seed=100 + len(effects))
    outcome = run_case(case, base, seed=WORKFLOW_SEED)
    named = [(k, n, c) for k, n, c, _, _ in outcome.named]
    assert sorted(named) == sorted((k, n, c) for k, n, _, c in effects)
    if not effects:
        assert outcome.gap_after == outcome.gap_before
        return
    assert outcome.gap_after <= 0.5 * outcome.gap_before
    hidden_effects = {f"{k}: {n}": (k, n, c) for k, n, _, c in effects}
    assert len(outcome.recovery) == sum(len(params) for _, _, params, _ in effects)   # the widths below are checked
    for effect, param, value, fitted, lo, hi in outcome.recovery:
        if param == "p_per_m":          # hidden at its bound (0); the interval may sit beside it
            assert abs(fitted) < 0.05
            continue
        inside = lo <= value <= hi
        assert inside or abs(fitted - value) <= 0.1 * abs(value), (effect, param, value, fitted, lo, hi)
        kind, name, condition = hidden_effects[effect]
        se = expected_standard_error(case.log, base, kind, name, value, condition)
        assert hi - lo <= WIDTH_FACTOR * 2 * 1.96 * se, (effect, param, lo, hi, se)


def test_two_effects_on_one_chain_are_named_together_with_the_right_shape(truth, base):
    """Late multipath arrivals on a constant antenna-delay offset (an exponential excess on a negative bias): the
    right-skewed error of a real UWB unit. Fitted one after the other the excess would shrink to sit on the
    offset and a tail of short readings (its mirror) or a mixture would be named; fitted together both are named,
    each within a tolerance of its hidden value (mean 15 %, offset 2 cm: the joint fit's noise on 60 s of flight
    is a few per cent)."""
    effects = [("ranging", "nlos_bias", {"mean": 0.15}, None), ("ranging", "bias", {"b": -0.08}, None)]
    outcome = run_case(_case(truth, base, effects, seed=105), base, seed=WORKFLOW_SEED)
    assert sorted((k, n, c) for k, n, c, _, _ in outcome.named) == [("ranging", "bias", None),
                                                                      ("ranging", "nlos_bias", None)]
    fitted = {n: params for _, n, _, params, _ in outcome.named}
    assert fitted["nlos_bias"]["mean"] == pytest.approx(0.15, rel=0.15)
    assert fitted["bias"]["b"] == pytest.approx(-0.08, abs=0.02)
    assert outcome.gap_after <= 0.25 * outcome.gap_before


def _run(*args):
    return subprocess.run([sys.executable, str(CALIBRATE), *map(str, args), "--quiet"], capture_output=True,
                          text=True, env={"PYTHONPATH": str(REPO / "tools"), "MPLBACKEND": "Agg",
                                          "PATH": "/usr/bin:/bin", **_lib_env()})


def _lib_env():
    import os
    return {k: os.environ[k] for k in ("FINKEN_LIB",) if k in os.environ}


def test_command_line_writes_the_report_the_spec_describes(tmp_path, base):
    short = synthetic.ground_truth(4, 30.0, seed=22)
    case = _case(short, base, [("sonar", "nlos_bias", {"mean": 0.12}, "ctx_target_copter")], seed=7)
    log = tmp_path / "measured.csv"
    write_range_log(log, case.log)
    out = tmp_path / "out"
    proc = _run("--measured", log, "--model", models.GAUSSIAN_ONLY_PATH, "--out", out, "--seed", 3)
    assert proc.returncode == 0, proc.stderr
    report = json.loads((out / "report.json").read_text())
    spec_keys = ["gap_before", "gap_after", "gap_floor", "metric", "effects", "conditions"]
    assert list(report)[:6] == spec_keys          # the spec's keys first, then ours (docs/calibration.md: report.json)
    assert list(report)[6:] == ["glitches", "sensors", "ranges", "range_gap_reduction", "notes", "verdict"]
    assert [(e["name"], e["sensor"], e["condition"]) for e in report["effects"]] == \
        [("nlos_bias", "sonar", "ctx_target_copter")]
    effect = report["effects"][0]
    assert list(effect)[:5] == ["name", "sensor", "condition", "params", "gap_reduction"]
    assert effect["condition_expression"] == "ctx_target_copter" and list(effect["ci95"]) == ["mean"]
    assert effect["stability"]["replicates"] == 10 and 0 <= effect["stability"]["share"] <= 1
    assert list(effect["params"]) == ["mean"] and 0 < effect["gap_reduction"] <= 1
    assert report["gap_after"] < report["gap_before"]
    cond = report["conditions"][0]
    assert list(cond) == ["sensor", "condition", "n", "gap_before", "gap_after", "glitch_rate_measured",
                          "glitch_rate_before", "glitch_rate_after"] and isinstance(cond["n"], int)
    assert {c["sensor"] for c in report["conditions"]} == {"sonar", "ranging"}
    model_out = models.SensorModel.load(out / "model.xml")      # usable as MODEL= for a next run
    assert [e.name for e in model_out.chains["sonar"].effects] == ["gaussian", "nlos_bias"]
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= 3 and "nlos_bias" in html

    again = _run("--measured", log, "--model", models.GAUSSIAN_ONLY_PATH, "--out", out)
    assert again.returncode == 2 and "already holds a report" in again.stderr and "FORCE=1" in again.stderr
    assert json.loads((out / "report.json").read_text()) == report          # untouched
    clean = tmp_path / "clean.csv"                                            # nothing missing: no fitting
    write_range_log(clean, _case(short, base, [], seed=8).log)
    forced = _run("--measured", clean, "--model", models.GAUSSIAN_ONLY_PATH, "--out", out, "--force")
    assert forced.returncode == 0 and "Nothing is missing" in forced.stdout
    assert json.loads((out / "report.json").read_text())["effects"] == []
    assert models.SensorModel.load(out / "model.xml") == base                 # written unchanged


def test_bad_log_is_rejected_with_file_line_and_column(tmp_path):
    proc = _run("--measured", LOGS / "text_in_numeric.csv", "--model", models.GAUSSIAN_ONLY_PATH,
                "--out", tmp_path / "out")
    assert proc.returncode == 2
    assert f"{LOGS / 'text_in_numeric.csv'}:4: column 'measured'" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_bad_model_is_rejected_before_any_work(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<sensor_model>\n  <sonar>\n    <effect name="gaussian" sigma="-1"/>\n  </sonar>\n</sensor_model>\n')
    # the log is read first: the model's conditions may name its columns
    proc = _run("--measured", LOGS / "good.csv", "--model", bad, "--out", tmp_path / "out")
    assert proc.returncode == 2
    assert f"{bad}:3" in proc.stderr
    assert not (tmp_path / "out").exists()


def test_conditions_name_columns_of_the_measured_log(tmp_path, base):
    """A model may be conditioned on a column of the measured log that the simulator does not have (a lab log's
    ctx_quality_pct); a condition on a column the log lacks is refused before any work, naming it."""
    truth = synthetic.ground_truth(4, 10.0, seed=22)
    truth.ctx["ctx_quality_pct"] = np.full(len(truth), 90.0)
    lab_log = tmp_path / "lab.csv"
    write_range_log(lab_log, hidden.simulate_measured(truth, base, 8))
    model = tmp_path / "model.xml"
    quality = models.Effect("bias", {"b": 0.0}, condition="ctx_quality_pct")
    base.for_log(["ctx_quality_pct"]).with_effect("ranging", quality).save(model)
    done = _run("--measured", lab_log, "--model", model, "--out", tmp_path / "out", "--quiet")
    assert done.returncode == 0, done.stderr
    refused = _run("--measured", LOGS / "good.csv", "--model", model, "--out", tmp_path / "out2")
    assert refused.returncode == 2 and not (tmp_path / "out2").exists()
    assert f"{model}:8: condition 'ctx_quality_pct': unknown context column (the simulator has ctx_facing_sonars, " \
           "ctx_target_copter, ctx_blocked, ctx_wall_dist, ctx_speed, ctx_crosstalk_path, ctx_trigger_offset, " \
           "ctx_floor, ctx_target_obstacle, ctx_vehicle; " \
           "the log has ctx_blocked, ctx_speed)" in refused.stderr
    base.with_effect("sonar", models.Effect("bias", {"b": 0.0}, condition="ctx_target_copter")).save(model)
    refused = _run("--measured", LOGS / "good.csv", "--model", model, "--out", tmp_path / "out2")
    assert refused.returncode == 2
    assert f"{LOGS / 'good.csv'}: condition 'ctx_target_copter' of the sonar chain's effect 2 (bias): the log has " \
           "no such column" in refused.stderr


def test_log_with_a_kind_the_model_lacks(tmp_path):
    model = tmp_path / "sonar_only.xml"
    model.write_text('<sensor_model><sonar><effect name="gaussian" sigma="0.02"/></sonar></sensor_model>\n')
    proc = _run("--measured", LOGS / "good.csv", "--model", model, "--out", tmp_path / "out")
    assert proc.returncode == 2 and "no ranging chain" in proc.stderr


def test_make_forwards_the_options(tmp_path):
    proc = subprocess.run(["make", "-n", "-f", "Makefile", "-f", "conf/Makefile.calibrate", "calibrate",
                           "MEASURED=m.csv", "MODEL=x.xml", "OUT=o", "SEED=5", "FORCE=1"], cwd=REPO,
                          capture_output=True, text=True)
    line = [s for s in proc.stdout.replace("\\\n", " ").splitlines() if "tools/calibrate.py" in s]
    assert line and "--measured m.csv --model x.xml --out o" in line[0] and "--seed 5" in line[0]
    assert line[0].rstrip().endswith("--force")
