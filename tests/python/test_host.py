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
    (["--vehicles", "0"], "--vehicles '0': expected a whole number in [1, 4096]"),
    (["--vehicles", "1.5"], "--vehicles '1.5': expected a whole number in [1, 4096]"),
    (["--seed", "1e3"], "--seed '1e3': expected a whole number"),
    (["--seed", "1.9"], "--seed '1.9': expected a whole number"),
    (["--seed", "0x10"], "--seed '0x10': expected a whole number"),
    (["--seed", "-1"], "--seed '-1': expected a whole number"),
    (["--seed", "18446744073709551616"], "--seed '18446744073709551616': expected a whole number"),
    (["--threads", "2.0"], "--threads '2.0': expected a whole number"),
    (["--duration", "soon"], "--duration 'soon': expected a number"),
    (["--ins-drift", "-1"], "--ins-drift (SD, m/s) '-1': expected a number in [0, 10]"),
    (["--ins-drift", "abc"], "--ins-drift (SD, m/s) 'abc': expected a number in [0, 10]"),
    (["--ins-drift", "0.02,0"], "--ins-drift (TAU, s) '0': expected a number in [0.001, 1e+06]"),
    (["--ins-drift", "0.02,"], "--ins-drift (TAU, s) '': expected a number in [0.001, 1e+06]"),
    (["--bogus"], "usage:"),
])
def test_bad_options_are_rejected_with_usage(wander_host, tmp_path, args, message):
    result = run_host(wander_host, tmp_path, *args)
    assert result.returncode == 2
    assert message in result.stderr


def test_ins_drift_takes_an_sd_and_optionally_a_correlation_time(wander_host, tmp_path):
    """--ins-drift SD[,TAU] (nps_ins_drift.h): wander circles around the drifted estimate, so the true poses move
    with the drift: each setting its own poses, the same twice."""
    poses = {}
    for name, args in (("none", ()), ("sd", ("--ins-drift", "0.02")), ("sd_tau", ("--ins-drift", "0.02,5")),
                       ("sd_tau_again", ("--ins-drift", "0.02,5"))):
        result = run_host(wander_host, tmp_path / name, "--vehicles", "2", "--duration", "5", *args)
        assert result.returncode == 0, result.stderr
        poses[name] = (tmp_path / name / "poses.csv").read_bytes()
    assert poses["sd"] != poses["none"] and poses["sd_tau"] != poses["sd"]
    assert poses["sd_tau_again"] == poses["sd_tau"]


def test_a_duration_of_2_to_the_32_steps_is_not_0_steps(wander_host, tmp_path):
    """The step count no longer wraps at 2^32 (42949672.96 s at 100 Hz ran 0 steps and exited 0): the banner
    shows the count, then the run is stopped."""
    proc = subprocess.Popen([str(wander_host), "--duration", "42949672.96", "--no-logs", "--out", str(tmp_path)],
                            stderr=subprocess.PIPE, stdout=subprocess.DEVNULL, text=True)
    try:
        banner = proc.stderr.readline()
    finally:
        proc.kill()
        proc.wait()
    hz = float(banner.split(" at ")[1].split(" Hz")[0])
    steps = int(banner.split("(")[1].split(" steps")[0])
    assert steps == round(42949672.96 * hz) and steps > 2**32 - 1


def test_unwritable_output_folder_is_reported(wander_host, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    result = run_host(wander_host, blocker / "sub")
    assert result.returncode == 1
    assert f"cannot create {blocker}/sub" in result.stderr


def test_a_flight_altitude_outside_the_arena_is_refused(tmp_path):
    """FINKEN_ALTITUDE=-1 flew the copters underground: the host refuses an altitude at which a copter does not
    fit between the arena's floor and its wall top, naming the define; so does the build's training run."""
    from conftest import REPO
    airframe = tmp_path / "wander_underground_nps.xml"
    airframe.write_text((REPO / "tests/data/airframes/wander_nps.xml").read_text().replace(
        '<define name="FINKEN_ALTITUDE" value="0.8"/>', '<define name="FINKEN_ALTITUDE" value="-1"/>'))
    message = ("error: the airframe's FINKEN_ALTITUDE (NPS_FINKEN_ALTITUDE) = -1 m: copters 0.15 m tall fly between "
               "the floor and the wall top of conf/arena/swarmlab.xml only above 0.075 m and up to 1.925 m")
    built = subprocess.run(["make", "-s", "--no-print-directory", "host", f"AIRFRAME={airframe}", "HOST_PGO=0",
                            "HOST_VARIANT=_no_pgo"], cwd=REPO, capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    result = run_host(REPO / "build/host/wander_underground_nps_no_pgo/nps_host", tmp_path / "out")
    assert result.returncode == 1
    assert result.stderr.strip() == message
    assert not (tmp_path / "out" / "poses.csv").exists()
    trained = subprocess.run(["make", "-s", "--no-print-directory", "host", f"AIRFRAME={airframe}"], cwd=REPO,
                             capture_output=True, text=True)
    assert trained.returncode != 0 and message in trained.stdout + trained.stderr


@pytest.fixture(scope="module")
def finken_host():
    """The shipped airframe: every module that runs per copter (sonar ring, ranging, wall detector, swarm)."""
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host"], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    return REPO / "build/host/finken_nps/nps_host"


@pytest.mark.parametrize("vehicles, duration_s, thread_counts", [(200, 3, (1, 2, 3, 5)), (6, 20, (1, 2, 4))])
def test_logs_do_not_depend_on_the_thread_count(finken_host, tmp_path, vehicles, duration_s, thread_counts):
    """Copters at the density of the SwarmLab's 4 (cross-talk, ranging peers, contacts): byte-identical logs for
    every thread count. Copters go to the threads in chunks, whichever thread is free: 200 copters on 3 threads
    make uneven chunks; 6 copters make chunks of 3 or 2 (a small swarm's share), one copter's modules still
    reading its sensors while another copter's flight model has moved on."""
    from conftest import REPO
    from finken.bench.arena import write_scaled_arena
    arena = write_scaled_arena(REPO / "conf/arena/swarmlab.xml", tmp_path, vehicles, 20)
    logs = {}
    for threads in thread_counts:
        out = tmp_path / f"t{threads}"
        result = subprocess.run([str(finken_host), "--out", str(out), "--quiet", "--vehicles", str(vehicles),
                                 "--duration", str(duration_s), "--seed", "11", "--arena", str(arena),
                                 "--threads", str(threads)], cwd=REPO, capture_output=True, text=True)
        assert result.returncode == 0, result.stderr
        logs[threads] = {f.name: f.read_bytes() for f in sorted(out.iterdir())}
    assert sorted(logs[1]) == ["detections.csv", "poses.csv", "readings.csv", "walls.csv"]
    readings = logs[1]["readings.csv"].decode().splitlines()
    assert sum(",ranging," in row for row in readings) > 1000   # the copters' phase did write rows
    for threads in thread_counts[1:]:
        assert logs[threads] == logs[1], f"{threads} threads"


def test_the_thread_count_is_checked(finken_host, tmp_path):
    result = run_host(finken_host, tmp_path, "--threads", "0")
    assert result.returncode == 2
    assert "--threads '0': expected a whole number in [1, 64]" in result.stderr


def test_profile_guided_build_writes_the_same_logs(finken_host, tmp_path):
    """The default host is built with profile-guided optimisation (sim/host.mk, HOST_PGO=1); gcc then lays out and
    inlines from the training counts, but computes the same floating-point operations: a host built without it
    (HOST_PGO=0) writes byte-identical logs, here 6 copters for 20 s with every log."""
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host", "HOST_PGO=0", "HOST_VARIANT=_no_pgo"], cwd=REPO,
                   check=True, stdout=subprocess.DEVNULL)
    plain_host = REPO / "build/host/finken_nps_no_pgo/nps_host"
    assert not (REPO / "build/host/finken_nps_no_pgo/train").exists()
    assert (REPO / "build/host/finken_nps/train/profile.stamp").exists()
    for host, name in ((finken_host, "pgo"), (plain_host, "plain")):
        assert run_host(host, tmp_path / name, "--vehicles", "6", "--duration", "20", "--seed", "3").returncode == 0
    logs = sorted(p.name for p in (tmp_path / "pgo").glob("*.csv"))
    assert "readings.csv" in logs and "detections.csv" in logs
    for log in logs:
        assert (tmp_path / "pgo" / log).read_bytes() == (tmp_path / "plain" / log).read_bytes(), log


def test_ins_drift_runs_are_reproducible_and_change_what_the_swarm_does(finken_host, tmp_path):
    """--ins-drift 0.05 on the shipped airframe: poses.csv keeps the truth, but the swarm and the wall detector
    fly on the drifted estimate, so the logs differ from a run without drift; the same seed twice gives
    byte-identical logs."""
    logs = {}
    for name, args in (("drift", ("--ins-drift", "0.05")), ("drift_again", ("--ins-drift", "0.05")), ("none", ())):
        result = run_host(finken_host, tmp_path / name, "--vehicles", "4", "--duration", "30", "--seed", "5", *args)
        assert result.returncode == 0, result.stderr
        logs[name] = {log: (tmp_path / name / log).read_bytes() for log in ("detections.csv", "poses.csv")}
    assert logs["drift_again"] == logs["drift"]
    assert logs["drift"]["detections.csv"] != logs["none"]["detections.csv"]
    assert logs["drift"]["poses.csv"] != logs["none"]["poses.csv"]
