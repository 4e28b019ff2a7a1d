"""make sweep end to end (tools/sweep.py): a tiny sweep on a 2-worker LocalCluster with a point made to fail (an
arena too low for the airframe's flight altitude: the host refuses to start), its rerun on an existing cluster's
scheduler, Ctrl-C in the middle of a sweep, an unreachable scheduler and a bad sweep file."""
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time

import pytest

TOOL = ["tools/sweep.py"]


@pytest.fixture
def env(repo):
    return dict(os.environ, PYTHONPATH=str(repo / "tools"), MPLBACKEND="Agg")


def sweep(repo, env, *args):
    return subprocess.run([sys.executable, *TOOL, *map(str, args)], cwd=repo, env=env, capture_output=True, text=True)


def low_arena(repo, tmp_path):
    """SwarmLab with walls 0.6 m high: the example airframe's copters (0.15 m tall at 0.6 m) do not fit under it."""
    text = (repo / "conf/arena/swarmlab.xml").read_text()
    for name, value in (("wallHeight", "0.6"), ("hingeHeight", "0.5"), ("flightHeight", "0.5")):
        text = re.sub(rf'{name}="[^"]*"', f'{name}="{value}"', text)
    path = tmp_path / "low.xml"
    path.write_text(text)
    return path


def rows(out):
    db = sqlite3.connect(out / "runs.sqlite")
    db.row_factory = sqlite3.Row
    try:
        return [dict(r) for r in db.execute("SELECT * FROM runs ORDER BY run_key")]
    finally:
        db.close()


def stored_count(out):
    """Runs stored so far (0 while the store is being created)."""
    try:
        return len(rows(out)) if (out / "runs.sqlite").exists() else 0
    except sqlite3.OperationalError:
        return 0


def test_a_sweep_stores_every_run_retries_a_failure_once_and_a_rerun_skips_the_finished(repo, env, tmp_path):
    spec = tmp_path / "tiny.yaml"
    spec.write_text(f"airframe: conf/airframes/finken_nps.xml\nvehicles: 2\nduration: 5\nseeds: 2\nkeep_logs: true\n"
                    f"arena: [conf/arena/swarmlab.xml, {low_arena(repo, tmp_path)}]\n")
    out = tmp_path / "out"
    first = sweep(repo, env, spec, "--out", out, "--workers", 2, "--quiet")
    assert first.returncode == 1, first.stdout + first.stderr          # some runs failed
    assert "on 2 Dask workers" in first.stdout
    assert "2 runs done, 2 failed after a second try, 2 tried again" in first.stdout
    stored = rows(out)
    done = [r for r in stored if r["status"] == "done"]
    failed = [r for r in stored if r["status"] == "failed"]
    assert len(done) == 2 and len(failed) == 2
    for r in done:
        assert r["arena"] == "conf/arena/swarmlab.xml" and r["attempts"] == 1 and r["error"] is None
        assert 0.0 <= r["detector_wall_recall"] <= 1.0 and r["sensor_errors.ranging.readings"] > 0
        assert r["wall_s"] > 0 and r["started"] and r["worker"]
        logs = out / "logs" / r["run_key"]                                 # make sim's layout
        for name in ("metrics.json", "report.txt", "readings.csv", "detections.csv", "detector_off/poses.csv"):
            assert (logs / name).stat().st_size > 0, name
    for r in failed:
        assert r["attempts"] == 2 and r["detector_wall_recall"] is None
        assert "RunFailed: detector on: nps_host exited with status 1" in r["error"]
        assert "FINKEN_ALTITUDE" in r["error"]
    for name in ("points.csv", "summary.html", "plots/arena.png"):
        assert (out / name).stat().st_size > 0, name
    assert "Failed runs (2" in (out / "summary.html").read_text()
    assert len((out / "points.csv").read_text().splitlines()) == 3

    from distributed import LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None, silence_logs=50) as cluster:
        again = sweep(repo, env, spec, "--out", out, "--scheduler", cluster.scheduler_address, "--quiet")
    assert again.returncode == 1, again.stdout + again.stderr
    assert "2 done before, 2 to fly" in again.stdout
    stored_again = {r["run_key"]: r for r in rows(out)}
    for r in done:
        assert stored_again[r["run_key"]] == r                             # skipped: the row as it was
    for r in failed:
        assert stored_again[r["run_key"]]["attempts"] == 4                  # tried twice more


def test_ctrl_c_keeps_every_finished_run_and_the_same_command_goes_on(repo, env, tmp_path):
    spec = tmp_path / "longer.yaml"
    spec.write_text("airframe: conf/airframes/finken_nps.xml\nvehicles: 4\nduration: 30\nseeds: 14\n")
    out = tmp_path / "out"
    command = [sys.executable, *TOOL, str(spec), "--out", str(out), "--workers", "2", "--quiet"]
    # its own process group, as a terminal's, with Ctrl-C's default action: a shell that runs make test in the
    # background (cmd &) hands its children SIGINT ignored, and Python then raises no KeyboardInterrupt
    proc = subprocess.Popen(command, cwd=repo, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    # Ctrl-C as soon as the store holds 2 finished runs, however long a loaded machine takes to fly them (not all
    # 14: the 2 workers can finish at most 2 more meanwhile); the 900 s bound only ends a sweep that is stuck
    deadline = time.monotonic() + 900
    while stored_count(out) < 2:
        if proc.poll() is not None:
            pytest.fail(f"the sweep ended (status {proc.returncode}) before it had stored 2 runs:\n"
                        f"{proc.communicate()[1]}")
        if time.monotonic() > deadline:
            os.killpg(proc.pid, signal.SIGKILL)
            pytest.fail(f"the sweep stored {stored_count(out)} runs in 900 s:\n{proc.communicate()[1]}")
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)                                   # Ctrl-C
    _, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 130, stderr
    assert "interrupted; every finished run is in" in stderr
    kept = rows(out)
    assert 2 <= len(kept) < 14 and all(r["status"] == "done" for r in kept)
    resumed = sweep(repo, env, spec, "--out", out, "--workers", 2, "--quiet")
    assert resumed.returncode == 0, resumed.stderr
    assert f"{len(kept)} done before, {14 - len(kept)} to fly" in resumed.stdout
    assert len(rows(out)) == 14


def test_an_unreachable_scheduler_is_named_and_nothing_starts(repo, env, tmp_path):
    out = tmp_path / "out"
    result = sweep(repo, env, "conf/sweeps/sonar_noise.yaml", "--out", out, "--scheduler", "tcp://127.0.0.1:9",
                   "--connect-timeout", 0.5)
    assert result.returncode == 1
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9 within 0.5 s" in result.stderr
    assert not out.exists()


def test_a_bad_sweep_file_is_refused_before_anything_runs(repo, env, tmp_path):
    spec = tmp_path / "bad.yaml"
    spec.write_text("airframe: conf/airframes/finken_nps.xml\nvehicles: {from: 8, to: 2, step: 2}\n")
    result = sweep(repo, env, spec, "--out", tmp_path / "out")
    assert result.returncode == 2
    assert f"{spec}:2: vehicles: empty range: from 8 is above to 2" in result.stderr
    assert not (tmp_path / "out").exists()
