"""candump log -> range log (tools/finken/can/candump_rangelog.py, tools/candump_to_rangelog.py).

The session log's valid frames (tests/data/can/ranging_session.expected.csv, also checked by the C driver's
replay test) must come out as rows, with true ranges from the poses file: copter 5 at (0, 0, 1) m, copter 9
at (1.5 + 0.2 (t - t0), 0, 1) m, copter 12 at (0, 2.3, 1) m. Motion is linear, so linear interpolation is exact
and the true ranges are checked to 1e-7 m (float64 times near 1.7e9 s are spaced 2.4e-7 s apart: 4.8e-8 m at
0.2 m/s).
"""
import csv
import os
import subprocess
import sys

import numpy as np
import pytest

from finken.can.candump import read_candump
from finken.can.candump_rangelog import ConversionError, convert, positions_at
from finken.rangelog import read_range_log, write_range_log
from finken.run_logs import read_poses

T0_US = 1700000000 * 1000000
TRUTH_TOL_M = 1e-7


def session(repo):
    frames = read_candump(repo / "tests/data/can/ranging_session.log")
    poses = read_poses(repo / "tests/data/can/ranging_session.poses.csv")
    return frames, poses


def expected_rows(repo):
    with open(repo / "tests/data/can/ranging_session.expected.csv") as f:
        return [{k: int(v) for k, v in row.items()} for row in csv.DictReader(f)]


def position(vehicle, time_us):
    return {5: np.array([0.0, 0.0, 1.0]), 9: np.array([1.5 + 0.2 * (time_us - T0_US) / 1e6, 0.0, 1.0]),
            12: np.array([0.0, 2.3, 1.0])}[vehicle]


def test_the_session_becomes_a_range_log_with_true_ranges(repo, tmp_path):
    frames, poses = session(repo)
    log, summary = convert(frames, poses, ifname="can0", path="session")
    rows = expected_rows(repo)
    assert len(log) == len(rows) == summary.written == 26
    for i, row in enumerate(rows):
        assert log.t[i] == pytest.approx(row["time_us"] / 1e6, abs=1e-6)
        assert (log.vehicle[i], log.peer[i]) == (row["node"], row["peer"])
        assert log.sensor[i] == "ranging"
        assert log.measured[i] == pytest.approx(row["range_mm"] / 1000.0, abs=1e-12)
        assert log.ctx["ctx_quality_pct"][i] == row["quality_pct"]
        assert log.extra["seq"][i] == str(row["seq"])
        truth = np.linalg.norm(position(row["node"], row["time_us"]) - position(row["peer"], row["time_us"]))
        assert log.true_range[i] == pytest.approx(truth, abs=TRUTH_TOL_M)
    assert summary.duplicates == 1
    assert summary.other_interfaces == 1
    assert sum(summary.rejected.values()) == 10  # 7 bad data frames (FD, remote, extended among them) + 3 error frames
    # the shared reader accepts what we write: the file follows the spec
    out = tmp_path / "ranging.csv"
    write_range_log(out, log)
    back = read_range_log(out)
    assert np.array_equal(back.true_range, log.true_range)
    assert np.array_equal(back.measured, log.measured)


def test_readings_without_a_pose_are_left_out_and_counted(repo):
    frames, poses = session(repo)
    # tracking of copter 9 lost from t0 + 0.12 s to t0 + 0.28 s
    lost = (poses["vehicle"] == 9) & (poses["t"] > T0_US / 1e6 + 0.12) & (poses["t"] < T0_US / 1e6 + 0.28)
    gap_poses = {k: v[~lost] for k, v in poses.items()}
    log, summary = convert(frames, gap_poses, ifname="can0")
    # readings involving 9 at t0 + 0.15, 0.20, 0.25 (two each: 5->9 and 9->12) have no truth
    assert summary.no_truth == 6
    assert len(log) == 20
    in_gap = (log.t > T0_US / 1e6 + 0.12) & (log.t < T0_US / 1e6 + 0.28)
    assert not np.any(in_gap & ((log.vehicle == 9) | (log.peer == 9)))
    # a copter with no pose at all: its readings go, and the summary names it
    no_12 = {k: v[poses["vehicle"] != 12] for k, v in poses.items()}
    log, summary = convert(frames, no_12, ifname="can0")
    assert summary.untracked == (12,)
    assert not np.any((log.vehicle == 12) | (log.peer == 12))
    assert any("no poses for vehicle 12" in line for line in summary.lines())


def test_no_ground_truth_at_all_is_an_error(repo):
    frames, poses = session(repo)
    with pytest.raises(ConversionError, match="no reading has a ground truth.*--time-offset"):
        convert(frames, poses, time_offset_s=3600.0, path="session")
    with pytest.raises(ConversionError, match="no valid ranging frame"):
        convert([f for f in frames if f.error], poses, path="session")


def test_the_time_offset_moves_log_times_onto_the_pose_clock(repo):
    frames, poses = session(repo)
    shifted = {k: (v + 10.0 if k == "t" else v) for k, v in poses.items()}
    log, _ = convert(frames, shifted, ifname="can0", time_offset_s=10.0)
    reference, _ = convert(frames, poses, ifname="can0")
    assert np.allclose(log.t, reference.t + 10.0, atol=1e-6)
    assert np.allclose(log.true_range, reference.true_range, atol=TRUTH_TOL_M)


def test_interpolation_at_the_edges_of_the_tracked_span():
    poses = {"t": np.array([1.0, 2.0, 2.5]), "vehicle": np.array([3.0, 3.0, 3.0]),
             "x": np.array([0.0, 1.0, 2.0]), "y": np.zeros(3), "z": np.zeros(3)}
    xyz = positions_at(poses, 3, [0.99, 1.0, 1.5, 2.0, 2.25, 2.5, 2.51], max_pose_gap_s=1.0)
    assert np.isnan(xyz[0]).all() and np.isnan(xyz[6]).all()
    assert np.allclose(xyz[1:6, 0], [0.0, 0.5, 1.0, 1.5, 2.0])
    xyz = positions_at(poses, 3, [1.5, 2.0, 2.25], max_pose_gap_s=0.5)  # 1 s gap too long; on a sample is fine
    assert np.isnan(xyz[0]).all() and xyz[1, 0] == 1.0 and xyz[2, 0] == 1.5
    assert np.isnan(positions_at(poses, 4, [1.5], 1.0)).all()


def run_cli(repo, *args, can_lib=os.environ.get("FINKEN_CAN_LIB")):
    env = {"PYTHONPATH": str(repo / "tools")}
    if can_lib:  # the C codec library the test environment built (finken.can._native)
        env["FINKEN_CAN_LIB"] = str(can_lib)
    return subprocess.run([sys.executable, str(repo / "tools/candump_to_rangelog.py"), *map(str, args)],
                          capture_output=True, text=True, env=env)


def test_the_command_line(repo, tmp_path):
    out = tmp_path / "out.csv"
    log = repo / "tests/data/can/ranging_session.log"
    poses = repo / "tests/data/can/ranging_session.poses.csv"
    done = run_cli(repo, log, "--poses", poses, "-o", out, "--interface", "can0")
    assert done.returncode == 0, done.stderr
    assert "26 rows written" in done.stderr
    assert len(read_range_log(out)) == 26
    # without poses there is no true_range: refused, saying why
    done = run_cli(repo, log, "-o", out)
    assert done.returncode == 2 and "--poses" in done.stderr
    # a malformed log: one message naming the file and line
    done = run_cli(repo, repo / "tests/data/can/malformed.log", "--poses", poses, "-o", out)
    assert done.returncode == 1
    assert done.stderr.strip() == f"candump_to_rangelog: {repo / 'tests/data/can/malformed.log'}:4: data: expected pairs of hex digits"
    done = run_cli(repo, log, "--poses", poses, "-o", out, "--nb-nodes", "48")
    assert done.returncode == 1 and "power of two" in done.stderr
    # the C codec library not built: one message saying how to build it
    done = run_cli(repo, log, "--poses", poses, "-o", out, can_lib=tmp_path / "libfinken_can.so")
    assert done.returncode == 1
    assert done.stderr.strip() == (f"candump_to_rangelog: the CAN codec library {tmp_path / 'libfinken_can.so'} "
                                   f"does not exist: run `make build` in {repo} "
                                   "(or point FINKEN_CAN_LIB at libfinken_can.so)")
