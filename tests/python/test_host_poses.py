"""poses.csv of the host: rows at --pose-rate (make sim's POSE_RATE), each with the attitude quaternion qx, qy, qz,
qw beside the yaw; a rate the step rate cannot log is refused before the run starts and the previous run's logs are
kept; the rate changes no other log. finken.run_logs.read_poses reads files with and without the quaternion, and
the launcher of Paparazzi's NPS passes the rate on to finken_world."""
import hashlib
import math
import subprocess

import numpy as np
import pytest

from finken.rangelog import RangeLogError
from finken.run_logs import read_poses

STEP_HZ = 100.0   # the example airframe's PERIODIC_FREQUENCY
HEADER = "t,vehicle,x,y,z,yaw,qx,qy,qz,qw"


@pytest.fixture(scope="module")
def host():
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host"], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    return REPO / "build/host/finken_nps/nps_host"


def run(host, out, *args):
    return subprocess.run([str(host), "--out", str(out), "--quiet", *args], capture_output=True, text=True)


def quaternion_yaw(p):
    return np.arctan2(2 * (p["qw"] * p["qz"] + p["qx"] * p["qy"]), 1 - 2 * (p["qy"] ** 2 + p["qz"] ** 2))


def digest(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("rate, every", [(None, 10), ("10", 10), ("50", 2), ("100", 1), ("2.5", 40),
                                         (repr(100 / 3), 3)])
def test_rows_come_at_the_requested_rate(host, tmp_path, rate, every):
    copters, duration_s = 3, 6.0
    out = tmp_path / "out"
    result = run(host, out, "--vehicles", str(copters), "--duration", f"{duration_s:g}",
                 *(["--pose-rate", rate] if rate is not None else []))
    assert result.returncode == 0, result.stderr
    assert (out / "poses.csv").read_text().split("\n", 1)[0] == HEADER
    poses = read_poses(out / "poses.csv")
    rows_per_copter = math.ceil(duration_s * STEP_HZ / every)   # a row every `every` steps from the first
    assert len(poses["t"]) == copters * rows_per_copter
    assert len(poses["t"]) == pytest.approx(duration_s * (float(rate or 10)) * copters, abs=copters)
    for v in range(1, copters + 1):
        t = poses["t"][poses["vehicle"] == v]
        assert len(t) == rows_per_copter
        assert np.allclose(np.diff(t), every / STEP_HZ, atol=1.5e-4)


def test_the_attitude_is_a_unit_quaternion_with_the_rows_yaw(host, tmp_path):
    out = tmp_path / "out"
    assert run(host, out, "--vehicles", "4", "--duration", "30", "--pose-rate", "20").returncode == 0
    poses = read_poses(out / "poses.csv")
    norm = np.sqrt(poses["qx"] ** 2 + poses["qy"] ** 2 + poses["qz"] ** 2 + poses["qw"] ** 2)
    assert np.allclose(norm, 1.0, atol=1e-8)
    assert np.all(poses["qw"] >= 0.0)
    # yaw is written with 4 decimals
    assert np.allclose(np.remainder(quaternion_yaw(poses) - poses["yaw"] + np.pi, 2 * np.pi) - np.pi, 0.0, atol=1e-4)
    assert np.ptp(poses["yaw"]) > 3.0    # the copters turned: the comparison is not of one heading
    # the host's flight model hovers level (docs/host.md): a heading's quaternion, no roll or pitch
    assert np.all(poses["qx"] == 0.0) and np.all(poses["qy"] == 0.0)


def test_the_rate_changes_no_other_log(host, tmp_path):
    for name, extra in (("default", []), ("fast", ["--pose-rate", "100"])):
        assert run(host, tmp_path / name, "--vehicles", "4", "--duration", "20", *extra).returncode == 0
    for log in ("readings.csv", "walls.csv", "detections.csv"):
        assert digest(tmp_path / "default" / log) == digest(tmp_path / "fast" / log), log
    fast = read_poses(tmp_path / "fast/poses.csv")
    default = read_poses(tmp_path / "default/poses.csv")
    # every 10th step of the fast log is the default's row
    rows = np.isin(np.round(fast["t"], 4), np.round(default["t"], 4))
    for name in ("t", "vehicle", "x", "y", "z", "yaw", "qx", "qy", "qz", "qw"):
        assert np.array_equal(fast[name][rows], default[name]), name


@pytest.mark.parametrize("rate, status, message", [
    ("200", 1, "--pose-rate 200 Hz is above the step rate of 100 Hz (the airframe's PERIODIC_FREQUENCY)"),
    ("100.5", 1, "is above the step rate of 100 Hz"),
    ("30", 1, "--pose-rate 30 Hz: pose rows are logged a whole number of steps apart and the host steps at 100 Hz "
              "(the airframe's PERIODIC_FREQUENCY), so 30 Hz is 3.33333 steps apart; the nearest rates it can log "
              "are 25 Hz (every 4 steps) and 33.3333 Hz (every 3 steps)"),
    ("7", 1, "the nearest rates it can log are 6.66667 Hz (every 15 steps) and 7.14286 Hz (every 14 steps)"),
    ("0", 2, "--pose-rate '0': expected a number in [0.001, 1e+06]"),
    ("-10", 2, "--pose-rate '-10': expected a number"),
    ("fast", 2, "--pose-rate 'fast': expected a number"),
])
def test_a_rate_the_host_cannot_log_is_refused_and_the_previous_logs_kept(host, tmp_path, rate, status, message):
    out = tmp_path / "out"
    assert run(host, out, "--vehicles", "2", "--duration", "1").returncode == 0
    before = {p.name: digest(p) for p in out.iterdir()}
    result = run(host, out, "--pose-rate", rate)
    assert result.returncode == status and message in result.stderr, result.stderr
    assert {p.name: digest(p) for p in out.iterdir()} == before   # nothing written, no staged file left


def test_make_sim_passes_pose_rate_to_every_host_run(repo):
    def sim_args(*variables):
        return subprocess.run(["make", "-s", "--no-print-directory", "--eval", "print-sim-args: ; @echo $(SIM_ARGS)",
                               "print-sim-args", *variables], cwd=repo, check=True, capture_output=True,
                              text=True).stdout.split()
    assert "--pose-rate" not in sim_args()
    args = sim_args("POSE_RATE=50")
    assert args[args.index("--pose-rate") + 1] == "50"


def write(path, text):
    path.write_text(text)
    return path


def test_read_poses_returns_the_quaternion_when_the_file_has_it(tmp_path):
    p = read_poses(write(tmp_path / "p.csv", HEADER + "\n0.1000,1,1.0,2.0,0.6,1.5708,0,0,0.707106781,0.707106781\n"))
    assert p["qz"] == pytest.approx([0.707106781]) and p["qw"] == pytest.approx([0.707106781])
    assert p["yaw"] == pytest.approx([1.5708])


def test_read_poses_reads_files_without_the_quaternion(tmp_path):
    p = read_poses(write(tmp_path / "old.csv", "t,vehicle,x,y,z,yaw\n0.1,1,1.0,2.0,0.6,0.5\n"))
    assert sorted(p) == sorted(["t", "vehicle", "x", "y", "z", "yaw"])
    assert p["yaw"] == pytest.approx([0.5])


def test_read_poses_wants_all_four_quaternion_columns_or_none(tmp_path):
    path = write(tmp_path / "p.csv", "t,vehicle,x,y,z,yaw,qx,qy,qz\n0.1,1,1.0,2.0,0.6,0.0,0,0,0\n")
    with pytest.raises(RangeLogError, match=r"p.csv:1: column 'qw': missing column \(the attitude is qx, qy, qz, qw"):
        read_poses(path)


@pytest.mark.parametrize("quaternion, message", [
    ("0,0,0,0", "has norm 0: expected 1 within 0.01"),
    ("0,0,0.6,0.6", "has norm 0.848528"),
    ("0,0,0,nan", "'nan' is not a finite number"),
])
def test_read_poses_refuses_a_row_without_an_attitude(tmp_path, quaternion, message):
    path = write(tmp_path / "p.csv", HEADER + "\n0.1,1,1.0,2.0,0.6,0.0,0,0,0,1\n"
                 f"0.2,1,1.0,2.0,0.6,0.0,{quaternion}\n")
    with pytest.raises(RangeLogError, match=rf"p.csv:3: column 'qw': .*{message}"):
        read_poses(path)


def test_the_paparazzi_launcher_passes_the_rate_to_finken_world(tmp_path):
    from finken.paparazzi.sim import world_env
    env = world_env({}, "w", "r", 4, tmp_path, 60.0, pose_rate_hz=50)
    assert float(env["FINKEN_WORLD_POSE_RATE"]) == 50.0
    assert "FINKEN_WORLD_POSE_RATE" not in world_env({}, "w", "r", 4, tmp_path, 60.0)
