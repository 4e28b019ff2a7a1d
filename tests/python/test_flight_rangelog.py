"""A lab's flight to a range log (tools/flight_rangelog.py, finken.flight): true ranges from the motion capture
against hand-computed geometry, the clock offset found, the context of cross-talk from the records' timing, bad
input refused with file:line and nothing written, and our own simulator's flight turned back into its range log."""
import math
import re
import subprocess

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from finken.flight.clock import ClockError, estimate_offset
from finken.flight.flight_log import flight_range_log, parse_offsets
from finken.flight.mocap import read_mocap
from finken.flight.mounts import sonar_mounts, sonar_timing
from finken.flight.records import Records
from finken.flight.truth import ArenaTruth, SonarTiming, range_log
from finken.rangelog import read_range_log

ARENA = "conf/arena/swarmlab.xml"          # 3 m x 4 m, copters 0.2 m in radius, 0.15 m tall, sonars at the centre
AIRFRAME = "conf/airframes/finken_nps.xml"


@pytest.fixture
def arena(repo):
    with ArenaTruth(repo / ARENA) as a:
        yield a


@pytest.fixture
def mounts(repo, arena):
    return sonar_mounts(repo / AIRFRAME, arena.sonar_offset_m)


def write_mocap(path, samples):
    """A plain motion-capture CSV: samples (t, body, x, y, z, rotation)."""
    rows = ["t,body,x,y,z,qx,qy,qz,qw"]
    for t, body, x, y, z, rot in samples:
        qx, qy, qz, qw = rot.as_quat()
        rows.append(f"{t},{body},{x},{y},{z},{qx},{qy},{qz},{qw}")
    path.write_text("\n".join(rows) + "\n")
    return path


def still(t_end, bodies, rate_hz=100.0):
    """Copters held still: bodies {name: (x, y, z, rotation)}, sampled from 0 to t_end."""
    return [(t, name, *pose) for t in np.arange(0.0, t_end + 1e-9, 1.0 / rate_hz) for name, pose in bodies.items()]


def records(rows, path="record.csv"):
    """Records from (t, vehicle, sensor, peer, measured) rows, line i + 2."""
    t, vehicle, sensor, peer, measured = zip(*rows)
    n = len(rows)
    return Records(path, np.array(t, float), np.array(vehicle), np.array(sensor, dtype=object), np.array(peer),
                   np.array(measured, float), np.arange(2, n + 2))


def truth_of(arena, mounts, tmp_path, bodies, rows):
    poses = read_mocap(write_mocap(tmp_path / "mocap.csv", still(1.0, bodies)))
    return range_log(arena, mounts, records(rows), poses)


LEVEL = Rotation.identity()


def test_sonar_rays_follow_the_attitude(arena, mounts, tmp_path):
    """Hand-computed ranges in the 3 m x 4 m arena from (1.5, 2, 0.6): front 1.5 m to the east wall; pitched 10 deg
    nose down 1.5 / cos 10; the downward sonar rolled 20 deg reads 0.6 / cos 20; the left sonar rolled 20 deg
    (left side up) 2 / cos 20 to the north wall, whose curtain is 2 m tall; yawed 90 deg the front looks north."""
    pitched = Rotation.from_euler("y", 10, degrees=True)        # about y (left): x forward turns down
    rolled = Rotation.from_euler("x", 20, degrees=True)         # about x (forward): the left side up
    yawed = Rotation.from_euler("z", 90, degrees=True)
    cases = [(LEVEL, "sonar_front", 1.5), (pitched, "sonar_front", 1.5 / math.cos(math.radians(10))),
             (rolled, "sonar_down", 0.6 / math.cos(math.radians(20))),
             (rolled, "sonar_left", 2.0 / math.cos(math.radians(20))), (yawed, "sonar_front", 2.0),
             (LEVEL, "sonar_back", 1.5), (LEVEL, "sonar_right", 2.0), (LEVEL, "sonar_down", 0.6)]
    for rot, sensor, expected in cases:
        log = truth_of(arena, mounts, tmp_path, {"finken1": (1.5, 2.0, 0.6, rot)}, [(0.5, 1, sensor, -1, 1.0)])
        assert log.true_range[0] == pytest.approx(expected, abs=1e-6), (rot.as_euler("xyz", degrees=True), sensor)
        assert log.ctx["ctx_wall_dist"][0] == pytest.approx(1.5)
        assert log.ctx["ctx_floor"][0] == (1.0 if sensor == "sonar_down" else 0.0)   # the hard floor's code


def test_a_copter_ahead_is_the_target_and_ranging_sees_through_nothing(arena, mounts, tmp_path):
    """Copter 2 at 1.0 m ahead of copter 1: the front sonar hits its body (radius 0.2 m) at 0.8 m; ranging reads the
    centres' distance, 1.0 m; a third copter between them blocks the line (ctx_blocked)."""
    bodies = {"finken1": (0.5, 2.0, 0.6, LEVEL), "finken2": (1.5, 2.0, 0.6, LEVEL)}
    rows = [(0.5, 1, "sonar_front", -1, 0.8), (0.5, 1, "ranging", 2, 1.0)]
    log = truth_of(arena, mounts, tmp_path, bodies, rows)
    assert log.true_range[0] == pytest.approx(0.8, abs=1e-9) and log.ctx["ctx_target_copter"][0] == 1
    assert log.true_range[1] == pytest.approx(1.0, abs=1e-9) and log.ctx["ctx_blocked"][1] == 0
    assert np.isnan(log.peer[0]) and log.peer[1] == 2
    bodies["finken3"] = (1.0, 2.0, 0.6, LEVEL)
    log = truth_of(arena, mounts, tmp_path, bodies, rows)
    assert log.ctx["ctx_blocked"][1] == 1 and log.true_range[0] == pytest.approx(0.3, abs=1e-9)


def test_a_facing_sonar_is_heard_only_when_its_pulse_arrives_while_this_one_listens(arena, mounts, tmp_path):
    """Copters 1 and 2 face each other 1.0 m apart (front to front: 2 yawed 180 deg). The pulse of 2's front sonar
    travels 1.0 / 343 s = 2.9 ms; copter 1 listens for 20 ms before its reading: heard when 2's reading (its own
    trigger + 20 ms) comes -2.9 ms to +17.1 ms after 1's."""
    bodies = {"finken1": (1.0, 2.0, 0.6, LEVEL), "finken2": (2.0, 2.0, 0.6, Rotation.from_euler("z", 180, degrees=True))}
    travel = 1.0 / 343.0
    for offset, heard in ((0.005, True), (-0.002, True), (-0.004, False), (0.0165, True), (0.018, False)):
        rows = [(0.5, 1, "sonar_front", -1, 0.6), (0.5 + offset, 2, "sonar_front", -1, 0.6)]
        log = truth_of(arena, mounts, tmp_path, bodies, rows)
        assert log.ctx["ctx_facing_sonars"][0] == heard, offset
        if heard:
            assert log.ctx["ctx_trigger_offset"][0] == pytest.approx(offset)
            assert log.ctx["ctx_crosstalk_path"][0] == pytest.approx(1.0, abs=1e-9)
        assert 0 <= offset + travel <= 0.02 if heard else not 0 <= offset + travel <= 0.02
    # an emitter whose readings are not in the records is counted: it may be heard
    log = truth_of(arena, mounts, tmp_path, bodies, [(0.5, 1, "sonar_front", -1, 0.6)])
    assert log.ctx["ctx_facing_sonars"][0] == 1 and np.isnan(log.ctx["ctx_trigger_offset"][0])


def test_the_airframe_gives_the_mounts_and_the_listening_window(tmp_path, repo):
    frame = tmp_path / "af.xml"
    frame.write_text('<airframe name="x"><firmware name="rotorcraft"><target name="ap" board="pc"/>'
                     '<module name="sonar_array"><define name="SONAR_ARRAY_RATE" value="10"/></module></firmware>'
                     '<section name="SONAR_ARRAY" prefix="SONAR_ARRAY_"><define name="MOUNT_OFFSET" value="0.05"/>'
                     '<define name="DOWN_MOUNT_Z" value="-0.02"/><define name="READ_DELAY" value="3"/></section>'
                     '</airframe>')
    m = sonar_mounts(frame, 0.0)
    assert m.position["sonar_left"].tolist() == [0.0, 0.05, 0.0]
    assert m.position["sonar_down"].tolist() == [0.0, 0.0, -0.02] and "af.xml" in m.source
    assert sonar_timing(frame).window_s == pytest.approx(3 / (5 * 10))
    assert sonar_timing(repo / AIRFRAME) == SonarTiming(0.02, 343.0)
    frame.write_text(frame.read_text().replace('value="0.05"', 'value="5 cm"'))
    with pytest.raises(ValueError, match=r"af.xml:1: SONAR_ARRAY_MOUNT_OFFSET: '5 cm' is not a number"):
        sonar_mounts(frame, 0.0)


def flying(t_end, rate_hz=50.0):
    """Two copters flying figure-of-eights at 0.4-0.5 m/s, with a yaw that turns: mocap samples."""
    samples = []
    for t in np.arange(0.0, t_end + 1e-9, 1.0 / rate_hz):
        for body, phase in (("finken1", 0.0), ("finken2", 2.0)):
            x = 1.5 + 0.9 * math.sin(0.41 * t + phase)     # frequencies without a common period
            y = 2.0 + 1.2 * math.sin(0.87 * t + phase)
            samples.append((t, body, x, y, 0.6, Rotation.from_euler("z", 0.23 * t + phase)))
    return samples


def flight_records(arena, mounts, poses, offset_s, t_end, rng, glitches=0):
    """What the copters would have recorded: every sonar at 20 Hz and ranging at 10 Hz on clocks offset_s behind the
    motion capture, each reading the truth plus 2 cm of noise, some glitches."""
    rows = []
    for v in (1, 2):
        for t in np.arange(1.0, t_end - 1.0, 0.05):
            rows += [(t, v, s, -1, 0.0) for s in ("sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down")]
            if round(t / 0.05) % 2 == 0:
                rows.append((t, v, "ranging", 3 - v, 0.0))
    rec = records(rows)
    truth = range_log(arena, mounts, rec, poses, context=False)
    rec.measured[:] = truth.true_range + rng.normal(0.0, 0.02, len(rec))
    rec.measured[rng.choice(len(rec), glitches, replace=False)] = -12.84
    rec.t[:] -= np.where(rec.vehicle == 1, offset_s[0], offset_s[1])
    return rec


def test_the_clock_offset_is_found_per_copter_despite_glitches(arena, mounts, tmp_path):
    poses = read_mocap(write_mocap(tmp_path / "mocap.csv", flying(60.0)))
    rec = flight_records(arena, mounts, poses, (3.217, -41.5), 60.0, np.random.default_rng(1), glitches=40)
    for v, expected in ((1, 3.217), (2, -41.5)):
        found = estimate_offset(arena, mounts, rec, poses, v, where="record.csv:2")
        assert found.offset_s == pytest.approx(expected, abs=0.005)
        assert found.agreeing > 0.95


def test_a_hovering_copter_has_no_offset_to_find(arena, mounts, tmp_path):
    poses = read_mocap(write_mocap(tmp_path / "mocap.csv", still(60.0, {"finken1": (1.0, 1.0, 0.6, LEVEL),
                                                                          "finken2": (2.0, 3.0, 0.6, LEVEL)}, 20)))
    rec = flight_records(arena, mounts, poses, (1.0, 1.0), 60.0, np.random.default_rng(2))
    with pytest.raises(ClockError, match=r"record.csv:2: vehicle 1: the clock offset is ambiguous: tried offsets "
                                         r"from -600 s to \+600 s"):
        estimate_offset(arena, mounts, rec, poses, 1, where="record.csv:2")


def test_the_offset_is_stated_or_refused_with_the_reason():
    assert parse_offsets("0.25") == {None: 0.25}
    assert parse_offsets("1=0.25, 2=-1.5") == {1: 0.25, 2: -1.5}
    for bad in ("one=2", "1=abc", "nan"):
        with pytest.raises(ValueError, match="clock offset"):
            parse_offsets(bad)


def test_readings_where_the_motion_capture_lost_a_copter_are_left_out_and_counted(arena, mounts, tmp_path):
    samples = [s for s in flying(40.0) if not (s[1] == "finken2" and 20.0 < s[0] < 25.0)]
    poses = read_mocap(write_mocap(tmp_path / "mocap.csv", samples))
    rec = flight_records(arena, mounts, poses, (0.0, 0.0), 40.0, np.random.default_rng(3))
    log, report = flight_range_log(arena, mounts, rec, poses, offsets={None: 0.0})
    lost = (rec.t > 20.0) & (rec.t < 25.0) & ((rec.vehicle == 2) | (rec.peer == 2))
    assert report.vehicles[1].left_out == int(((rec.vehicle == 2) & lost).sum()) > 0
    assert report.written == len(rec) - int(lost.sum())
    assert np.allclose(log.true_range, rec.measured[~lost], atol=0.1)


def rangelog(repo, tmp_path, *args):
    cmd = ["build/venv/bin/python", "tools/flight_rangelog.py", "--arena", ARENA, "--quiet", *map(str, args)]
    return subprocess.run(cmd, cwd=repo, capture_output=True, text=True)


def record_csv(path, rows):
    path.write_text("t,vehicle,sensor,peer,measured\n" + "".join(f"{t},{v},{s},{p},{m}\n" for t, v, s, p, m in rows))
    return path


def test_bad_input_is_refused_with_file_line_and_nothing_written(repo, tmp_path):
    mocap = write_mocap(tmp_path / "mocap.csv", still(30.0, {"finken1": (1.0, 1.0, 0.6, LEVEL),
                                                             "finken2": (2.0, 3.0, 0.6, LEVEL)}, 10))
    out = tmp_path / "log.csv"
    cases = [
        ([(1.0, 1, "sonar_front", "", 2.0), (1.05, 3, "sonar_front", "", 2.0)], [],
         r"record.csv:3: vehicle 3 has no body in the motion capture"),
        ([(1.0, 1, "ranging", 5, 2.0)], [], r"record.csv:2: ranging peer 5 has no body"),
        ([(1.0, 1, "sonar_top", "", 2.0)], [], r"record.csv:2: column 'sensor': unknown sensor 'sonar_top'"),
        ([(5000.0, 1, "sonar_front", "", 2.0)], [],
         r"record.csv:2: vehicle 1: no clock offset from -600 s to \+600 s puts 10% of its readings inside the "
         r"motion capture's time: the files do not overlap"),
        ([(t, 1, "sonar_front", "", x) for t, x in zip(np.arange(1.0, 20.0, 0.05),
                                                       np.random.default_rng(4).uniform(0.2, 3.0, 380))], [],
         r"record.csv:2: vehicle 1: no clock offset makes its readings agree with the motion capture: tried"),
        ([(1.0, 1, "sonar_front", "", 2.0)], ["--clock-offset", "x"], r"clock offset 'x' is not a number"),
    ]
    for rows, extra, message in cases:
        result = rangelog(repo, tmp_path, "--readings", record_csv(tmp_path / "record.csv", rows), "--mocap", mocap,
                          "--out", out, *extra)
        assert result.returncode == 2, result.stdout + result.stderr
        assert re.search(message, result.stderr), result.stderr
        assert not out.exists()
    out.write_text("kept\n")
    result = rangelog(repo, tmp_path, "--readings", tmp_path / "record.csv", "--mocap", mocap, "--out", out)
    assert result.returncode == 2 and "exists" in result.stderr and out.read_text() == "kept\n"


def test_a_body_that_jumps_is_named_and_its_samples_left_out(repo, tmp_path):
    samples = flying(30.0)
    k = next(i for i, s in enumerate(samples) if s[1] == "finken1" and s[0] >= 10.0)
    samples[k] = (samples[k][0], "finken1", 0.2, 0.2, 0.6, LEVEL)   # a marker swap: 1.5 m in 20 ms
    mocap = write_mocap(tmp_path / "mocap.csv", samples)
    rows = [(t, 1, "sonar_down", "", 0.6) for t in np.arange(1.0, 29.0, 0.05)]
    result = rangelog(repo, tmp_path, "--readings", record_csv(tmp_path / "record.csv", rows), "--mocap", mocap,
                      "--out", tmp_path / "log.csv", "--clock-offset", "0")
    assert result.returncode == 0, result.stderr
    assert re.search(rf"vehicle 1: 1 jumps left out \(largest [0-9.]+ m at t = 10\.000 s, line {k + 2}\)",
                     result.stdout), result.stdout
    log = read_range_log(tmp_path / "log.csv")
    assert np.allclose(log.true_range, 0.6) and len(log) == len(rows)


@pytest.fixture(scope="module")
def simulated_flight(tmp_path_factory):
    """Our host's flight of 4 copters for 40 s with poses at 50 Hz and full attitude."""
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host"], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    out = tmp_path_factory.mktemp("flight")
    subprocess.run([str(REPO / "build/host/finken_nps/nps_host"), "--out", str(out), "--quiet", "--duration", "40",
                    "--vehicles", "4", "--seed", "3", "--pose-rate", "50"], check=True)
    return out


def test_our_simulators_flight_gives_back_its_own_true_ranges(repo, tmp_path, simulated_flight):
    """The host's readings (true ranges dropped, clocks moved 2.5 s and -7.25 s) and its poses as the motion capture:
    the offsets are found within 30 ms (less than the sonar's 50 ms period; where the copters fly slowly the
    readings hardly tell nearby offsets apart) and the true ranges come back. They differ where the host's curtains bulged toward a copter
    (the arena file holds them at rest) and where the pose samples (50 Hz) cut a turn short."""
    sim = read_range_log(simulated_flight / "readings.csv")
    shift = np.where(sim.vehicle % 2 == 1, 2.5, -7.25)
    rows = zip(sim.t - shift, sim.vehicle.astype(int), sim.sensor,
               ["" if np.isnan(p) else int(p) for p in sim.peer], sim.measured)
    record = record_csv(tmp_path / "record.csv", [(f"{t:.4f}", v, s, p, "" if np.isnan(m) else m)
                                                  for t, v, s, p, m in rows])
    out = tmp_path / "log.csv"
    result = rangelog(repo, tmp_path, "--readings", record, "--mocap", simulated_flight / "poses.csv", "--out", out)
    assert result.returncode == 0, result.stderr
    found = {v: float(re.search(rf"vehicle {v}: \d+ readings, clock offset ([-+0-9.]+) s", result.stdout).group(1))
             for v in (1, 2, 3, 4)}
    for v, offset in found.items():
        assert offset == pytest.approx(2.5 if v % 2 else -7.25, abs=0.03), result.stdout
    log = read_range_log(out)
    sonar = log.sensor != "ranging"
    # each row of ours is the host's row at time t - (found offset) + (the shift made)
    host_t = log.t - np.vectorize(found.get)(log.vehicle.astype(int)) + np.where(log.vehicle % 2 == 1, 2.5, -7.25)
    host_row = np.full(len(log), -1)
    for (v, name) in set(zip(log.vehicle[sonar], log.sensor[sonar])):
        ours = np.flatnonzero((log.vehicle == v) & (log.sensor == name))
        theirs = np.flatnonzero((sim.vehicle == v) & (sim.sensor == name))
        k = np.clip(np.searchsorted(sim.t[theirs], host_t[ours] - 1e-3), 0, len(theirs) - 1)
        host_row[ours] = theirs[k]
    assert np.all(np.abs(sim.t[host_row[sonar]] - host_t[sonar]) < 2e-3)
    ours, theirs = np.flatnonzero(sonar), host_row[sonar]
    error = np.abs(log.true_range[ours] - sim.true_range[theirs])
    assert np.mean(error < 0.01) > 0.97
    assert np.mean(log.ctx["ctx_target_copter"][ours] == sim.ctx["ctx_target_copter"][theirs]) > 0.99


def test_the_cdef_mirrors_the_header(repo):
    nps = repo / "sw/simulator/nps"
    headers = " ".join((nps / h).read_text() for h in ("nps_flight_truth.h", "nps_raycast.h", "nps_arena.h"))
    headers = re.sub(r"\s+", " ", re.sub(r"/\*.*?\*/", " ", headers, flags=re.S))
    squeeze = lambda text: re.sub(r"\s*([(),;*\[\]])\s*", r"\1", text)  # noqa: E731
    cdef = re.sub(r"/\*.*?\*/", " ", (nps / "nps_flight_truth.cdef").read_text(), flags=re.S)
    functions = [line.strip() for line in cdef.splitlines() if line.strip().endswith(");")]
    assert len(functions) == 5
    for declaration in functions:
        assert squeeze(declaration) in squeeze(headers), declaration
    struct = re.search(r"struct nps_flight_sonar_truth \{(.*?)\};", headers).group(1)
    struct = re.sub(r"///<.*?$|/\*\*<.*?\*/", "", struct).replace("NPS_FLIGHT_TRUTH_MAX_FACING", "8")
    assert re.sub(r"\s+", "", struct) == re.sub(r"\s+", "", re.search(r"struct nps_flight_sonar_truth \{(.*?)\};",
                                                                       cdef, re.S).group(1))
