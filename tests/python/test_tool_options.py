"""Numeric options of the tools (finken.cli_types): a value that means nothing there (negative, NaN, infinite,
out of range, not ASCII decimal) is refused by argparse, exit status 2 and a message naming the option, before
any work; the values that do mean something still run. Issue 28: `calibrate.py --seed -1` and
`gmm_fit.py --max-rows -1` ended in tracebacks; `gmm_fit.py --sensor bogus`, `candump_to_rangelog.py
--max-pose-gap -1` / `nan` and `--time-offset nan` were taken.
"""
from pathlib import Path

import numpy as np
import pytest

import calibrate
import gmm_fit
import gmm_import
from finken import models
from finken.discrepancy import hidden, synthetic
from finken.rangelog import RangeLog, read_range_log, write_range_log
from run_tool import run_tool

REPO = Path(__file__).resolve().parents[2]
GOOD_LOG = REPO / "tests" / "data" / "logs" / "good.csv"
CAN = REPO / "tests" / "data" / "can"
SEED_64 = "'-1' is not an integer from 0 to 18446744073709551615"


def _refused(capsys, main, argv, message):
    with pytest.raises(SystemExit) as done:
        main(argv)
    assert done.value.code == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err


@pytest.mark.parametrize("option, value, message", [
    ("--seed", "-1", "argument --seed: " + SEED_64),
    ("--seed", str(2**64), "argument --seed: '18446744073709551616' is not an integer from 0 to"),
    ("--seed", "1_0", "argument --seed: '1_0' is not an integer"),
])
def test_calibrate(capsys, tmp_path, option, value, message):
    argv = ["--measured", str(GOOD_LOG), "--model", str(models.GAUSSIAN_ONLY_PATH), "--out", str(tmp_path / "out"),
            "--quiet", option, value]
    _refused(capsys, calibrate.main, argv, message)
    assert not (tmp_path / "out").exists()


def test_calibrate_takes_the_largest_seed_the_simulator_takes(tmp_path):
    base = models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)
    write_range_log(tmp_path / "m.csv", hidden.simulate_measured(synthetic.ground_truth(4, 10.0, seed=22), base, 8))
    done = run_tool("calibrate.py", "--measured", tmp_path / "m.csv", "--model", models.GAUSSIAN_ONLY_PATH,
                    "--out", tmp_path / "out", "--quiet", "--seed", 2**64 - 1)
    assert done.returncode == 0, done.stderr
    assert (tmp_path / "out" / "report.json").is_file()


@pytest.mark.parametrize("option, value, message", [
    ("--max-rows", "-1", "argument --max-rows: '-1' is not an integer >= 1"),
    ("--max-rows", "0", "argument --max-rows: '0' is not an integer >= 1"),
    ("--components", "0", "argument --components: '0' is not an integer >= 1"),
    ("--seed", "-1", "argument --seed: '-1' is not an integer from 0 to 4294967295"),
    ("--seed", "4294967296", "argument --seed: '4294967296' is not an integer from 0 to 4294967295"),
    ("--sensor", "bogus", "argument --sensor: invalid choice: 'bogus'"),
])
def test_gmm_fit(capsys, tmp_path, option, value, message):
    _refused(capsys, gmm_fit.main, [str(GOOD_LOG), "-o", str(tmp_path / "m.xml"), option, value], message)
    assert not (tmp_path / "m.xml").exists()


def test_gmm_fit_takes_each_sensor_name_and_a_row_limit(tmp_path):
    rng = np.random.default_rng(4)
    n = 400
    true = rng.uniform(0.3, 2.5, n)
    sensor = np.where(np.arange(n) % 2 == 0, "sonar_left", "sonar_down")
    write_range_log(tmp_path / "log.csv", RangeLog("x", np.arange(n) * 0.05, np.ones(n), sensor, np.full(n, np.nan),
                                                   true, true + rng.normal(0.0, 0.05, n)))
    for sensor_option, rows in (("sonar_left", 150), ("sonar", 150)):
        out = tmp_path / f"{sensor_option}.xml"
        assert gmm_fit.main([str(tmp_path / "log.csv"), "-o", str(out), "--sensor", sensor_option,
                             "--components", "2", "--max-rows", str(rows), "--seed", "4294967295"]) == 0
        assert f"({sensor_option} rows with a reading: {rows})" in out.read_text()


@pytest.mark.parametrize("args, message", [
    (["--true-dim", "-1"], "argument --true-dim: '-1' is not an integer >= 0"),
    (["--measured-dim", "-2"], "argument --measured-dim: '-2' is not an integer >= 0"),
    (["--true-dim", "5"], "fitted.pkl: --true-dim 5: the model has 2 dimensions (0 to 1)"),
    (["--true-dim", "1", "--measured-dim", "1"], "--true-dim and --measured-dim are both 1: they must differ"),
])
def test_gmm_import(capsys, tmp_path, args, message):
    import joblib
    from sklearn.mixture import GaussianMixture
    fitted = GaussianMixture(2, random_state=0).fit(np.random.default_rng(0).normal(size=(200, 2)))
    joblib.dump(fitted, tmp_path / "fitted.pkl")
    _refused(capsys, gmm_import.main, [str(tmp_path / "fitted.pkl"), "-o", str(tmp_path / "m.xml"), *args], message)
    assert not (tmp_path / "m.xml").exists()


@pytest.mark.parametrize("option, value, message", [
    ("--max-pose-gap", "-1", "argument --max-pose-gap: '-1' is not a number >= 0"),
    ("--max-pose-gap", "nan", "argument --max-pose-gap: 'nan' is not a number >= 0"),
    ("--time-offset", "nan", "argument --time-offset: 'nan' is not a finite number"),
    ("--time-offset", "inf", "argument --time-offset: 'inf' is not a finite number"),
    ("--id-base", "-1", "argument --id-base: '-1' is not an integer from 0 to 65535"),
    ("--id-base", "0x3_00", "argument --id-base: '0x3_00' is not an integer from 0 to 65535"),
    ("--nb-nodes", "\uff16\uff14", "argument --nb-nodes: '\uff16\uff14' is not an integer from 0 to 65535"),
    ("--range-max-mm", "70000", "argument --range-max-mm: '70000' is not an integer from 0 to 65535"),
])
def test_candump_to_rangelog(tmp_path, option, value, message):
    done = run_tool("candump_to_rangelog.py", CAN / "ranging_session.log", "--poses", CAN / "ranging_session.poses.csv",
                    "-o", tmp_path / "out.csv", f"{option}={value}")
    assert done.returncode == 2 and message in done.stderr and "Traceback" not in done.stderr
    assert not (tmp_path / "out.csv").exists()


def test_candump_to_rangelog_takes_an_unlimited_pose_gap_and_a_hex_id_base(tmp_path):
    out = tmp_path / "out.csv"
    done = run_tool("candump_to_rangelog.py", CAN / "ranging_session.log", "--poses", CAN / "ranging_session.poses.csv",
                    "-o", out, "--interface", "can0", "--max-pose-gap", "inf", "--id-base", "0x300",
                    "--time-offset", "-0.0")
    assert done.returncode == 0, done.stderr
    assert len(read_range_log(out)) == 26
