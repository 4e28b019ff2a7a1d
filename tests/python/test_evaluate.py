"""`make evaluate` / tools/evaluate.py: models scored on a measured log without fitting.

The measured log is simulated from a known model (gaussian_only plus a 0.12 m NLOS bias on sonar readings of
copters, ctx_target_copter) on a 30 s synthetic flight (~9 600 rows), with fixed seeds, so every number is
deterministic. Tolerances: the model that made the log has a gap within 50 % of its own noise floor (its
simulations differ from the log only by their seeds), and the model missing the effect is worse by at least
2 noise floors (measured over 3 logs x 5 seeds: gap/floor 0.90-1.14 for the true model, and 3.8-4.7 floors
between the two).
"""
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from finken import models
from finken.discrepancy import evaluate as evaluate_module
from finken.discrepancy import hidden, synthetic
from finken.discrepancy.evaluate import evaluate
from finken.rangelog import write_range_log
from run_tool import run_tool

REPO = Path(__file__).resolve().parents[2]
EVALUATE = REPO / "tools" / "evaluate.py"
LOGS = REPO / "tests" / "data" / "logs"


@pytest.fixture(scope="module")
def base():
    return models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)


@pytest.fixture(scope="module")
def true_model(base):
    return base.with_effect("sonar", models.Effect("nlos_bias", {"mean": 0.12}, "ctx_target_copter"))


@pytest.fixture(scope="module")
def log(true_model):
    return hidden.simulate_measured(synthetic.ground_truth(4, 30.0, seed=22), true_model, 7)


@pytest.fixture(scope="module")
def files(tmp_path_factory, log, true_model):
    d = tmp_path_factory.mktemp("evaluate")
    write_range_log(d / "measured.csv", log)
    true_model.save(d / "true.xml")
    return d


def test_the_model_that_made_the_log_scores_best(log, base, true_model):
    ev = evaluate(log, [("true", true_model), ("missing nlos_bias", base)], seed=3)
    true, missing = ev.scores
    assert [s.name for s in ev.best()] == ["true"]
    assert true.gap <= 1.5 * true.floor, (true.gap, true.floor)
    assert missing.gap >= true.gap + 2 * true.floor, (missing.gap, true.gap, true.floor)
    worst = max(range(len(true.conditions)), key=lambda j: missing.conditions[j].gap - true.conditions[j].gap)
    assert (missing.conditions[worst].kind, missing.conditions[worst].label) == ("sonar", "ctx_target_copter = 1")


def test_models_get_the_same_rows_and_seeds(log, base, true_model):
    ev = evaluate(log, [("a", base), ("b", true_model), ("c", base)], seed=4)
    a, b, c = ev.scores
    assert (a.gap, a.floor) == (c.gap, c.floor) and a.conditions == c.conditions
    assert [(x.kind, x.label, x.n) for x in a.conditions] == [(x.kind, x.label, x.n) for x in b.conditions]
    # common random numbers: the two models' ranging chains are the same, so are their ranging readings
    same = [(x.gap, y.gap) for x, y in zip(a.conditions, b.conditions) if x.kind == "ranging"]
    assert same and all(x == y for x, y in same)


def test_a_big_log_is_scored_on_whole_time_blocks(log, base, monkeypatch):
    monkeypatch.setattr(evaluate_module, "REPORT_ROWS", 2000)      # as if the log had millions of rows
    ev = evaluate(log, [("a", base), ("b", base)], seed=4)
    assert all(2000 <= scored < rows for rows, scored in ev.rows.values())
    a, b = ev.scores
    assert (a.gap, a.floor) == (b.gap, b.floor) and a.conditions == b.conditions
    assert a.conditions[0].label == "all rows" and a.conditions[0].n == ev.rows["sonar"][1]


def test_deterministic_for_a_seed(log, base):
    def numbers(seed):
        s = evaluate(log, [("m", base)], seed=seed).scores[0]
        return s.gap, s.floor, [(c.gap, c.floor) for c in s.conditions]
    assert numbers(5) == numbers(5)
    assert numbers(5) != numbers(6)


def test_rows_beyond_the_models_range_are_counted(log, base):
    score = evaluate(log, [("m", base)], seed=1).scores[0]
    for b in score.beyond_range:
        rows = log.sensor == b.sensor
        chain = base.chains["ranging" if b.sensor == "ranging" else "sonar"]
        outside = (log.true_range > chain.max_range) | (log.true_range < chain.min_range)
        read_outside = (log.measured > chain.max_range) | (log.measured < chain.min_range)
        assert (b.rows, b.true_beyond, b.readings_beyond) == (rows.sum(), np.sum(rows & outside),
                                                              np.sum(rows & read_outside))
    assert sorted(b.sensor for b in score.beyond_range) == sorted(set(log.sensor))
    assert sum(b.true_beyond for b in score.beyond_range) > 0      # the synthetic arena has walls beyond 3 m


def _run(*args, quiet=True, max_file_bytes=None):
    return run_tool("evaluate.py", *args, *(["--quiet"] if quiet else []), max_file_bytes=max_file_bytes)


def test_command_line_writes_json_and_html(files, tmp_path):
    out = tmp_path / "out"
    true, base = files / "true.xml", models.GAUSSIAN_ONLY_PATH
    proc = _run("--measured", files / "measured.csv", "--model", true, "--model", base, "--out", out, "--seed", 3)
    assert proc.returncode == 0, proc.stderr
    report = json.loads((out / "evaluate.json").read_text())
    assert list(report) == ["models", "glitch_rate", "metric"]
    # the log's glitches: the ranging readings the chain clamped to 0 (zero is no range two copters can be at)
    ranging = np.loadtxt(files / "measured.csv", delimiter=",", skiprows=1, usecols=5, dtype=str)
    sensors = np.loadtxt(files / "measured.csv", delimiter=",", skiprows=1, usecols=2, dtype=str)
    zeros = [m for m, s in zip(ranging, sensors) if s == "ranging" and m and float(m) <= 0]
    assert report["glitch_rate"] == {"sonar": 0.0, "ranging": len(zeros) / np.sum(sensors == "ranging")}
    assert [m["model"] for m in report["models"]] == [str(true), str(base)]
    for m in report["models"]:
        assert list(m) == ["model", "gap", "gap_floor", "glitch_rate", "conditions"]
        assert set(m["glitch_rate"]) == set(report["glitch_rate"])
        assert isinstance(m["gap"], float) and isinstance(m["gap_floor"], float)
        for c in m["conditions"]:
            assert list(c) == ["sensor", "condition", "n", "gap", "gap_floor"]
            assert c["sensor"] in ("sonar", "ranging") and isinstance(c["n"], int) and c["n"] > 0
    assert report["models"][0]["gap"] < report["models"][1]["gap"]
    lines = proc.stdout.splitlines()
    assert lines[0].startswith(f"{true}: gap ") and "noise floor" in lines[0]
    assert lines[1].startswith(f"{base}: gap ") and lines[2] == f"best: {true}"
    html = (out / "evaluate.html").read_text()
    assert html.count("data:image/png;base64,") == 1 and "gaussian_only.xml" in html and "beyond" in html

    again = _run("--measured", files / "measured.csv", "--model", base, "--out", out)
    assert again.returncode == 2 and "already holds an evaluation" in again.stderr and "FORCE=1" in again.stderr
    assert json.loads((out / "evaluate.json").read_text()) == report          # untouched
    forced = _run("--measured", files / "measured.csv", "--model", base, "--out", out, "--force", quiet=False)
    assert forced.returncode == 0 and "simulating" in forced.stderr, forced.stderr     # the progress display
    assert [m["model"] for m in json.loads((out / "evaluate.json").read_text())["models"]] == [str(base)]


@pytest.mark.parametrize("case", ["bad log line", "missing model", "model without a chain", "out is a file"])
def test_command_line_refuses_bad_input(files, tmp_path, case):
    log, model, out = files / "measured.csv", models.GAUSSIAN_ONLY_PATH, tmp_path / "out"
    if case == "bad log line":
        log, expected = LOGS / "text_in_numeric.csv", f"{LOGS / 'text_in_numeric.csv'}:4: column 'measured'"
    elif case == "missing model":
        model = tmp_path / "absent.xml"
        expected = f"{model}:0: cannot read"
    elif case == "model without a chain":
        model = tmp_path / "sonar_only.xml"
        model.write_text('<sensor_model><sonar><effect name="gaussian" sigma="0.02"/></sonar></sensor_model>\n')
        expected = f"but the model has no ranging chain (model {model})"
    else:
        out.write_text("")
        expected = "exists and is not a folder"
    proc = _run("--measured", log, "--model", models.GAUSSIAN_ONLY_PATH, "--model", model, "--out", out)
    assert proc.returncode == 2 and expected in proc.stderr, proc.stderr
    assert not (out / "evaluate.json").exists()
    if case == "bad log line":
        assert not out.exists()


def test_a_write_error_exits_1_and_keeps_the_old_pair(files, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    old = {name: f"old {name}\n" for name in ("evaluate.json", "evaluate.html")}
    for name, text in old.items():
        (out / name).write_text(text)
    # evaluate.json (~10 kB) fits in 20 kB, evaluate.html (~100 kB) does not
    proc = _run("--measured", files / "measured.csv", "--model", models.GAUSSIAN_ONLY_PATH, "--out", out, "--force",
                max_file_bytes=20000)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.strip() == f"evaluate: {out / 'evaluate.html'}: cannot write: File too large"
    assert {p.name: p.read_text() for p in out.iterdir()} == old


def test_make_forwards_every_model():
    proc = subprocess.run(["make", "-n", "evaluate", "MEASURED=m.csv", "MODEL=a.xml", "MODEL2=b.xml",
                           "MODEL9=i.xml", "OUT=o", "SEED=5", "FORCE=1"], cwd=REPO, capture_output=True, text=True)
    line = [s for s in proc.stdout.replace("\\\n", " ").splitlines() if "tools/evaluate.py" in s]
    assert line and "--measured m.csv --model a.xml --model b.xml --model i.xml" in line[0]
    assert "--out o" in line[0] and "--seed 5" in line[0] and line[0].rstrip().endswith("--force")
