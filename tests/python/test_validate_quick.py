"""make validate's reduced run (`--quick`: the first 5 cases of its hidden-effect suite, seed 1; ~80 s) passes by the
suite's own rule: every case named right with its condition, nothing named without an effect, both effects named
where two were hidden, the held-out gap halved wherever an effect was hidden (finken.discrepancy.validate). A
regression of the workflow on any of these fails the suite; `make validate` runs the whole of it."""
import json
import subprocess
import sys

from conftest import REPO


def test_the_reduced_validation_passes_by_its_own_rule(tmp_path):
    done = subprocess.run([sys.executable, "-m", "finken.discrepancy.validate", "--quick", "--out", str(tmp_path)],
                          cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert done.stdout.splitlines()[-2] == "VALIDATION PASSED"
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["cases"] == 5 and summary["named_correctly"] == 1.0
    assert summary["two_effect_cases"] >= 1 and summary["two_effect_cases_both_named"] == summary["two_effect_cases"]
