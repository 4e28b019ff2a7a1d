"""The NPS-style host end to end: built from an airframe, lock-step, deterministic, logs in the spec's format."""
import subprocess

import numpy as np
import pytest


@pytest.fixture(scope="module")
def wander_host():
    from conftest import REPO
    airframe = "tests/data/airframes/wander_nps.xml"
    subprocess.run(["make", "-s", "--no-print-directory", "host", f"AIRFRAME={airframe}"], cwd=REPO, check=True,
                   stdout=subprocess.DEVNULL)
    return REPO / "build/host/wander_nps/nps_host"


def run_host(host, out, *args):
    return subprocess.run([str(host), "--out", str(out), "--quiet", *args], capture_output=True, text=True)


def read_poses(out):
    return np.genfromtxt(out / "poses.csv", delimiter=",", names=True)


def test_runs_n_copters_and_writes_poses(wander_host, tmp_path):
    result = run_host(wander_host, tmp_path / "a", "--vehicles", "3", "--duration", "5")
    assert result.returncode == 0, result.stderr
    poses = read_poses(tmp_path / "a")
    assert sorted(set(poses["vehicle"].astype(int))) == [1, 2, 3]
    assert len(poses) == 3 * 50                             # 10 Hz pose log for 5 s
    assert np.allclose(poses["z"][-3:], 0.8, atol=1e-3)     # the airframe's section define reached the host


def test_same_seed_same_output(wander_host, tmp_path):
    for name in ("a", "b"):
        assert run_host(wander_host, tmp_path / name, "--seed", "7", "--duration", "3").returncode == 0
    assert (tmp_path / "a/poses.csv").read_bytes() == (tmp_path / "b/poses.csv").read_bytes()


def test_copters_follow_their_guided_commands(wander_host, tmp_path):
    """wander flies circles of radius 1 m around the arena centre (1.5, 2): after settling, every copter is near it."""
    assert run_host(wander_host, tmp_path / "c", "--duration", "30").returncode == 0
    poses = read_poses(tmp_path / "c")
    late = poses[poses["t"] > 25]
    assert np.allclose(np.hypot(late["x"] - 1.5, late["y"] - 2.0), 1.0, atol=0.15)


@pytest.mark.parametrize("args, message", [
    (["--vehicles", "0"], "--vehicles '0': expected a number in [1, 4096]"),
    (["--duration", "soon"], "--duration 'soon': expected a number"),
    (["--bogus"], "usage:"),
])
def test_bad_options_are_rejected_with_usage(wander_host, tmp_path, args, message):
    result = run_host(wander_host, tmp_path, *args)
    assert result.returncode == 2
    assert message in result.stderr


def test_unwritable_output_folder_is_reported(wander_host, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    result = run_host(wander_host, blocker / "sub")
    assert result.returncode == 1
    assert f"cannot create {blocker}/sub" in result.stderr
