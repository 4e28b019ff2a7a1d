"""The host never loses or tears a log: a failed start keeps the previous run's files byte for byte, a signal or a
write error ends the run at a step boundary with complete rows in every log, and runs past 2^32 us keep their times."""
import hashlib
import re
import resource
import signal
import subprocess
import threading

import pytest

from finken.rangelog import read_range_log

LOGS = ("readings.csv", "poses.csv", "walls.csv", "detections.csv")


@pytest.fixture(scope="module")
def host():
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host"], cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    return REPO / "build/host/finken_nps/nps_host"


def run(host, out, *args, **kwargs):
    return subprocess.run([str(host), "--out", str(out), "--quiet", *args], capture_output=True, text=True, **kwargs)


def digests(out):
    return {name: hashlib.sha256((out / name).read_bytes()).hexdigest() for name in LOGS}


def last_times(out):
    """The time of each log's last row; every log must end with a newline."""
    times = {}
    for name in LOGS:
        text = (out / name).read_text()
        assert text.endswith("\n"), name
        times[name] = float(text.rstrip("\n").rsplit("\n", 1)[-1].split(",", 1)[0])
    return times


@pytest.fixture
def previous_run(host, tmp_path):
    out = tmp_path / "out"
    assert run(host, out, "--duration", "2", "--vehicles", "2").returncode == 0
    return out, digests(out)


@pytest.mark.parametrize("args, message", [
    (["--ranging-replay", "/nonexistent.log"], "cannot read /nonexistent.log"),
    (["--arena", "/nonexistent.xml"], "cannot read the arena file"),
    (["--vehicles", "16", "--duration", "100000000"], "this run would write about"),
])
def test_a_failed_start_keeps_the_previous_logs(host, previous_run, args, message):
    out, before = previous_run
    result = run(host, out, *args)
    assert result.returncode == 1 and message in result.stderr
    assert digests(out) == before
    assert sorted(p.name for p in out.iterdir()) == sorted(LOGS)   # no staged file left behind


def test_an_output_that_cannot_be_created_keeps_the_previous_logs(host, previous_run):
    out, before = previous_run
    (out / ".poses.csv.partial").mkdir()   # poses.csv cannot be written
    result = run(host, out, "--duration", "2")
    assert result.returncode == 1 and ".poses.csv.partial" in result.stderr
    assert digests(out) == before


def test_detections_that_cannot_be_written_stop_the_run_with_one_message(host, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / ".detections.csv.partial").mkdir()
    result = run(host, out, "--duration", "20")
    assert result.returncode == 1
    assert result.stderr.count("cannot write") == 1, result.stderr
    assert "the run stops" in result.stderr


def first_progress_s(proc, timeout_s=120):
    """The simulated time of the host's first progress line (on stderr, not a terminal: one every 10% of the run).
    A host that has not said it within timeout_s is killed, and the test fails."""
    said = []
    watchdog = threading.Timer(timeout_s, proc.kill)
    watchdog.start()
    try:
        for line in proc.stderr:
            match = re.match(r"\s*simulated (\S+) of", line)
            if match:
                return float(match[1])
            said.append(line)
    finally:
        watchdog.cancel()
    pytest.fail(f"the host ended or said no progress within {timeout_s} s (status {proc.wait()}):\n{''.join(said)}")


@pytest.mark.parametrize("sig, status", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_ends_every_log_at_one_step(host, tmp_path, sig, status):
    out = tmp_path / "out"
    # 20 s at wall-clock speed: the signal comes when the host says it has simulated 10% (2 s, past the first walls
    # snapshot), however long a loaded machine took to get there; the run is still going then: it never runs ahead
    # of the clock, and 18 of its 20 s are left
    proc = subprocess.Popen([str(host), "--out", str(out), "--realtime", "--duration", "20"],
                            stderr=subprocess.PIPE, text=True)
    assert first_progress_s(proc) > 1.0
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err
    times = last_times(out)
    assert times["readings.csv"] > 1.0   # past the first walls snapshot
    # the run stops at a step that logs poses (10 Hz): every log ends within that step's 0.1 s, the walls (a snapshot
    # per second) within their second
    rows = [times[name] for name in ("readings.csv", "poses.csv", "detections.csv")]
    assert max(rows) - min(rows) <= 0.1 + 1e-9, times
    assert 0.0 <= times["poses.csv"] - times["walls.csv"] < 1.0, times


def test_a_write_error_stops_the_run_with_complete_rows(host, tmp_path):
    """Files may not grow past 256 kB (RLIMIT_FSIZE, as a full disk): the run stops naming the file, exit 1."""
    out = tmp_path / "out"

    def limit_file_size():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)   # a failing write, not a killed process
        resource.setrlimit(resource.RLIMIT_FSIZE, (256 * 1024, 256 * 1024))

    result = run(host, out, "--duration", "600", preexec_fn=limit_file_size)
    assert result.returncode == 1
    assert "failed" in result.stderr and ".partial" in result.stderr and "the run stops" in result.stderr
    for name in LOGS:
        assert (out / name).read_text().endswith("\n"), name   # cut after the last complete row
    read_range_log(out / "readings.csv")


def test_times_run_on_past_2_to_the_32_microseconds(host, tmp_path):
    """Paparazzi's get_sys_time_usec wraps after 4294.97 s: readings and detections went back to 0 there."""
    out = tmp_path / "out"
    assert run(host, out, "--duration", "4400", "--vehicles", "1").returncode == 0
    log = read_range_log(out / "readings.csv")   # rejects times that go back
    assert log.t.max() > 4390.0
    assert last_times(out)["detections.csv"] > 4390.0
