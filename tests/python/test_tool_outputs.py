"""Outputs the tools cannot write (finken.atomic_output): one message naming the file, exit status 1, the old
file (or files, for calibrate's report) left as it was, no partial or temporary file. Issue 28:
`gmm_fit.py -o /dev/full` ended in a traceback. A full disk on a regular file is made with a file-size limit
(RLIMIT_FSIZE: a write beyond it fails with EFBIG, "File too large").
"""
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from finken import models
from finken.discrepancy import hidden, synthetic
from finken.rangelog import RangeLog, write_range_log
from run_tool import run_tool

REPO = Path(__file__).resolve().parents[2]
CAN = REPO / "tests" / "data" / "can"
HAS_DEV_FULL = os.path.exists("/dev/full")


@pytest.fixture(scope="module")
def ranging_log(tmp_path_factory):
    """A range log with 300 ranging readings (enough for a 2-component fit)."""
    rng = np.random.default_rng(5)
    n = 300
    true = rng.uniform(0.3, 2.5, n)
    path = tmp_path_factory.mktemp("log") / "log.csv"
    write_range_log(path, RangeLog(str(path), np.arange(n) * 0.1, np.ones(n), np.full(n, "ranging"), np.full(n, 2.0),
                                   true, true + rng.normal(0.0, 0.05, n)))
    return path


@pytest.fixture(scope="module")
def pickled_mixture(tmp_path_factory):
    import joblib
    from sklearn.mixture import GaussianMixture
    path = tmp_path_factory.mktemp("pkl") / "fitted.pkl"
    joblib.dump(GaussianMixture(2, random_state=0).fit(np.random.default_rng(0).normal(size=(200, 2))), path)
    return path


def _assert_only(folder, names):
    assert sorted(os.listdir(folder)) == sorted(names)   # no partial, no temporary file


def _tool_args(name, ranging_log, pickled_mixture, out):
    return {"gmm_fit.py": [ranging_log, "-o", out, "--components", "2"],
            "gmm_import.py": [pickled_mixture, "-o", out],
            "candump_to_rangelog.py": [CAN / "ranging_session.log", "--poses", CAN / "ranging_session.poses.csv",
                                       "-o", out]}[name]


TOOLS = ("gmm_fit.py", "gmm_import.py", "candump_to_rangelog.py")


@pytest.mark.skipif(not HAS_DEV_FULL, reason="no /dev/full")
@pytest.mark.parametrize("name", TOOLS)
def test_a_full_device(name, ranging_log, pickled_mixture):
    done = run_tool(name, *_tool_args(name, ranging_log, pickled_mixture, "/dev/full"))
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.strip().splitlines()[-1] == \
        f"{name[:-3]}: /dev/full: cannot write: No space left on device"
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)


@pytest.mark.parametrize("name", TOOLS)
def test_a_full_disk_keeps_the_old_file(name, ranging_log, pickled_mixture, tmp_path):
    out = tmp_path / "out"
    out.write_text("the old output\n")
    done = run_tool(name, *_tool_args(name, ranging_log, pickled_mixture, out), max_file_bytes=200)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert f"{out}: cannot write: File too large" in done.stderr
    assert out.read_text() == "the old output\n"
    _assert_only(tmp_path, ["out"])


def test_calibrate_keeps_the_whole_old_report(tmp_path):
    base = models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)
    write_range_log(tmp_path / "m.csv", hidden.simulate_measured(synthetic.ground_truth(4, 10.0, seed=22), base, 8))
    out = tmp_path / "out"
    out.mkdir()
    old = {name: f"old {name}\n" for name in ("report.json", "report.html", "model.xml")}
    for name, text in old.items():
        (out / name).write_text(text)
    # model.xml and report.json (~21 kB) fit in 40 kB, report.html (~600 kB) does not
    done = run_tool("calibrate.py", "--measured", tmp_path / "m.csv", "--model", models.GAUSSIAN_ONLY_PATH,
                    "--out", out, "--quiet", "--force", max_file_bytes=40000)
    assert done.returncode == 1 and "Traceback" not in done.stderr
    assert done.stderr.strip() == f"calibrate: {out / 'report.html'}: cannot write: File too large"
    assert {name: (out / name).read_text() for name in old} == old
    _assert_only(out, old)
