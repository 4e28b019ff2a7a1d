"""A candump log of the ranging units fed to the host's copters (--ranging-replay): each frame reaches both
copters it is about, at its logged time, through the Linux driver's own decoding (tests/data/can)."""
import collections
import csv
import subprocess

import pytest


def build(repo, airframe):
    subprocess.run(["make", "-s", "--no-print-directory", "host", f"AIRFRAME={airframe}"], cwd=repo, check=True,
                   stdout=subprocess.DEVNULL)


def test_every_valid_frame_reaches_both_copters_at_its_time(repo, tmp_path):
    build(repo, "tests/data/airframes/sensors_nps.xml")
    host = repo / "build/host/sensors_nps/nps_host"
    log = repo / "tests/data/can/ranging_session.log"
    result = subprocess.run([str(host), "--vehicles", "12", "--duration", "3", "--quiet", "--out", str(tmp_path),
                             "--ranging-replay", str(log)], cwd=repo, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    with open(repo / "tests/data/can/ranging_session.expected.csv") as f:
        expected = list(csv.DictReader(f))
    with open(tmp_path / "ranging_replay.csv") as f:
        delivered = {(row["t"], int(row["vehicle"]), int(row["peer"]), row["distance"]) for row in csv.DictReader(f)}
    first_us = int(expected[0]["time_us"])
    want = set()
    for row in expected:
        t = f"{(int(row['time_us']) - first_us) / 1e6:.4f}"
        d = f"{int(row['range_mm']) / 1000:.4f}"
        node, peer = int(row["node"]), int(row["peer"])
        want |= {(t, node, peer, d), (t, peer, node, d)}
    assert delivered == want
    # the simulated ranging is off while the log is replayed
    with open(tmp_path / "readings.csv") as f:
        rows = list(csv.DictReader(f))
    assert not [row for row in rows if row["sensor"] == "ranging"]
    # every copter's modules run on its own state: each copter reads one sonar in every step, also in the steps where
    # a replayed frame reached some copters only (the replay selects those copters in turn)
    sonar_vehicles = collections.defaultdict(list)
    for row in rows:
        sonar_vehicles[row["t"]].append(int(row["vehicle"]))
    assert len(sonar_vehicles) > 250
    assert all(sorted(vehicles) == list(range(1, 13)) for vehicles in sonar_vehicles.values())


@pytest.mark.parametrize("airframe, log, message", [
    ("tests/data/airframes/wander_nps.xml", "tests/data/can/ranging_session.log",
     "--ranging-replay needs the virtual_ranging module in the airframe"),
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can/malformed.log", "tests/data/can/malformed.log:"),
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can/missing.log", "cannot read tests/data/can/missing.log"),
    # a frame stamped before the previous one stopped every later delivery, silently
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can/time_goes_back.log",
     "tests/data/can/time_goes_back.log:4: time stamp before the previous frame's"),
    # a line over 511 characters was split into frames; a NUL byte ended the line
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can/long_line.log",
     "tests/data/can/long_line.log:3: line longer than 511 characters"),
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can/nul_byte.log", "tests/data/can/nul_byte.log:3: a NUL byte"),
    # a directory read as a log of 0 lines
    ("tests/data/airframes/sensors_nps.xml", "tests/data/can", "cannot read tests/data/can: Is a directory"),
])
def test_bad_replays_are_reported(repo, tmp_path, airframe, log, message):
    build(repo, airframe)
    host = repo / "build/host" / airframe.split("/")[-1].replace(".xml", "") / "nps_host"
    result = subprocess.run([str(host), "--vehicles", "12", "--duration", "3", "--quiet", "--out", str(tmp_path),
                             "--ranging-replay", log], cwd=repo, capture_output=True, text=True)
    assert result.returncode == 1
    assert message in result.stderr
