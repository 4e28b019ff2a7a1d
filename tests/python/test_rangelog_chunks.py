"""finken.rangelog read in chunks: chunk boundaries change nothing (values, line numbers, which error is
reported and where), progress reports, the `line` of each row.

Exact tests on small hand-written files read with tiny `chunk_bytes` (down to 1 byte: every line, and every
CRLF pair, split across chunks).
"""
from pathlib import Path

import numpy as np
import pytest

from finken.rangelog import CHUNK_BYTES, RangeLog, RangeLogError, read_range_log, write_range_log
from finken.text_numbers import ColumnError, parse_column

LOGS = Path(__file__).resolve().parents[1] / "data" / "logs"
HEAD = "t,vehicle,sensor,peer,true_range,measured"
CHUNKS = (1, 2, 3, 7, 16, 61, CHUNK_BYTES)


def _rows(n):
    """n good rows: vehicle 1's sonar_front every 0.1 s, interleaved with its ranging to copter 2."""
    return [f"{i * 0.1:.1f},1,{'ranging' if i % 2 else 'sonar_front'},{2 if i % 2 else ''},1.5,1.4" for i in range(n)]


def _write(tmp_path, lines, end="\n", name="log.csv"):
    path = tmp_path / name
    path.write_bytes(end.join(lines).encode() + end.encode())
    return path


def _error(path, chunk_bytes):
    with pytest.raises(RangeLogError) as info:
        read_range_log(path, chunk_bytes=chunk_bytes)
    return info.value


@pytest.mark.parametrize("end", ["\n", "\r\n", "\r"])
def test_chunk_boundaries_do_not_shift_line_numbers(tmp_path, end):
    # blank lines (empty, spaces, a tab) before the header and between rows; a byte-order mark
    lines = ["", "  ", HEAD] + _rows(3) + ["", "\t"] + _rows(6)[3:] + [""]
    path = tmp_path / "log.csv"
    path.write_bytes(b"\xef\xbb\xbf" + end.join(lines).encode())
    expected = [4, 5, 6, 9, 10, 11]   # the header is line 3; line 1 is the first line, blank or not
    whole = read_range_log(path)
    for chunk_bytes in CHUNKS:
        log = read_range_log(path, chunk_bytes=chunk_bytes)
        assert log.line.dtype == np.int64 and log.line.tolist() == expected, chunk_bytes
        np.testing.assert_array_equal(log.t, whole.t)
        assert log.sensor.tolist() == whole.sensor.tolist()
        np.testing.assert_array_equal(log.peer, whole.peer)


def test_quoted_fields_over_several_lines_and_chunks_keep_line_numbers(tmp_path):
    lines = [HEAD + ",note", "0.0,1,sonar_front,,1.5,1.4,\"two\nlines\"", "", "0.1,1,sonar_front,,1.5,1.4,plain",
             "0.2,1,sonar_front,,1.5,1.4,\"a, b\"", "0.3,1,sonar_front,,1.5,oops,\"x\""]
    path = _write(tmp_path, lines[:-1])
    bad = _write(tmp_path, lines, name="bad.csv")
    for chunk_bytes in CHUNKS:
        log = read_range_log(path, chunk_bytes=chunk_bytes)
        assert log.line.tolist() == [2, 5, 6]
        assert log.extra["note"].tolist() == ["two\nlines", "plain", "a, b"]
        err = _error(bad, chunk_bytes)
        assert (err.line, err.column) == (7, "measured") and "'oops' is not a number" in str(err)


@pytest.mark.parametrize("row, column, words", [
    ("0.9,1,sonar_front,,1.5", "measured", "expected 6 fields as in the header, found 5"),
    ("0.9,1,sonar_front,,1.5,1.4,7", None, "expected 6 fields as in the header, found 7"),
    ("0.9,1,sonar_front,,1_5,1.4", "true_range", "'1_5' is not a number"),
    ("0.9,1,sonar_top,,1.5,1.4", "sensor", "unknown sensor 'sonar_top'"),
    ("0.9,1,ranging,,1.5,1.4", "peer", "a ranging row needs the id of the other copter"),
    ("0.9,1,sonar_front,2,1.5,1.4", "peer", "2 on a sonar_front row"),
    ("0.9,1,ranging,1,1.5,1.4", "peer", "1 is the row's own vehicle"),
    ("0.9,1,sonar_front,,-0.1,1.5", "true_range", "negative range -0.1 m"),
    ("0.9,1.5,sonar_front,,1.5,1.4", "vehicle", "'1.5' is not an integer id"),
])
def test_each_error_names_its_line_whatever_the_chunks(tmp_path, row, column, words):
    path = _write(tmp_path, [HEAD] + _rows(12) + ["", row] + _rows(20)[14:])
    for chunk_bytes in CHUNKS:
        err = _error(path, chunk_bytes)
        assert (err.line, err.column) == (15, column), chunk_bytes
        assert str(err).startswith(f"{path}:15: ") and words in str(err)


def test_time_going_back_names_both_lines_across_chunks(tmp_path):
    rows = _rows(40)
    rows[30] = "0.5,1,sonar_front,,1.5,1.4"   # line 32; its stream was last at t = 2.8 on line 30
    path = _write(tmp_path, [HEAD] + rows)
    for chunk_bytes in CHUNKS:
        err = _error(path, chunk_bytes)
        assert (err.line, err.column) == (32, "t")
        assert "t = 0.5 s goes back in time from t = 2.8 s on line 30 of the same stream" in str(err)
        assert "(vehicle 1, sensor sonar_front)" in str(err)


def test_of_several_faults_the_first_check_is_reported_as_for_the_whole_file(tmp_path):
    rows = _rows(40)
    rows[2] = "0.2,x,sonar_front,,1.5,1.4"      # line 4: vehicle
    rows[30] = "y,1,sonar_front,,1.5,1.4"       # line 32: t, checked before vehicle
    rows[35] = "3.5,1,sonar_front,,1.5"         # line 37: field count, checked before any value
    path = _write(tmp_path, [HEAD] + rows)
    no_count = _write(tmp_path, [HEAD] + rows[:35] + rows[36:], name="two.csv")
    for chunk_bytes in CHUNKS:
        assert (_error(path, chunk_bytes).line, _error(path, chunk_bytes).column) == (37, "measured")
        assert (_error(no_count, chunk_bytes).line, _error(no_count, chunk_bytes).column) == (32, "t")


def test_bad_utf8_names_its_byte_in_any_chunk(tmp_path):
    path = tmp_path / "log.csv"
    text = ("\n".join([HEAD] + _rows(10)) + "\n").encode()
    path.write_bytes(text[:200] + b"\xc3(" + text[200:])
    for chunk_bytes in CHUNKS:
        assert str(_error(path, chunk_bytes)) == f"{path}: not UTF-8 text: invalid continuation byte at byte 200"


def test_progress_reports_bytes_after_each_chunk(tmp_path):
    path = _write(tmp_path, [HEAD] + _rows(50))
    total = path.stat().st_size
    calls = []
    read_range_log(path, progress=lambda done, of: calls.append((done, of)), chunk_bytes=256)
    assert len(calls) >= total // 256 and all(of == total for _, of in calls)
    done = [d for d, _ in calls]
    assert done == sorted(done) and done[-1] == total
    calls.clear()
    read_range_log(path, progress=lambda done, of: calls.append((done, of)))
    assert calls == [(total, total)]


def test_a_line_longer_than_a_chunk(tmp_path):
    path = _write(tmp_path, [HEAD + ",note", "0.0,1,sonar_front,,1.5,1.4," + "x" * 5000])
    log = read_range_log(path, chunk_bytes=100)
    assert log.line.tolist() == [2] and len(log.extra["note"][0]) == 5000


def test_a_large_log_reads_the_same_in_small_chunks(tmp_path):
    rng = np.random.default_rng(5)
    n = 5000
    sensors = np.array(["sonar_front", "sonar_down", "ranging"])[rng.integers(0, 3, n)]
    log = RangeLog("x", np.sort(rng.uniform(0, 100, n)), rng.integers(1, 4, n).astype(float), sensors,
                   np.where(sensors == "ranging", 4.0, np.nan), rng.uniform(0, 4, n),
                   np.where(rng.random(n) < 0.1, np.nan, rng.uniform(0, 4, n)),
                   {"ctx_speed": rng.normal(size=n)}, {"note": np.full(n, 'say "hi"')})
    for note in ('say "hi"', "plain"):   # the csv-module path and the str-method path
        log.extra["note"] = np.full(n, note)
        write_range_log(tmp_path / "log.csv", log)
        a, b = read_range_log(tmp_path / "log.csv"), read_range_log(tmp_path / "log.csv", chunk_bytes=999)
        for name in ("t", "vehicle", "peer", "true_range", "measured", "line"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
            np.testing.assert_array_equal(getattr(a, name), getattr(log, name) if name != "line" else np.arange(n) + 2)
        assert a.sensor.tolist() == b.sensor.tolist() == sensors.tolist()
        assert b.extra["note"].tolist() == [note] * n


def test_line_is_kept_by_select_and_optional_when_building_a_log():
    log = read_range_log(LOGS / "good.csv")
    assert log.line.tolist() == [2, 3, 4, 5, 6, 7, 8]
    sub = log.select(log.sensor == "ranging")
    assert sub.line.tolist() == [3, 6, 7] and sub.group is None and sub.group_names is None
    built = RangeLog("x", log.t, log.vehicle, log.sensor, log.peer, log.true_range, log.measured)
    assert built.line is None and built.select([0, 1]).line is None and len(built.select([0, 1])) == 2


def test_numbers_outside_ascii_are_refused_even_when_case_folding_would_match(tmp_path):
    # the dotless i folds to i without re.ASCII: 'ınf' passed the grammar, then float() failed
    with pytest.raises(ColumnError):
        parse_column(["1", "\u0131nf"])
    path = _write(tmp_path, [HEAD, "0.0,1,sonar_front,,1.5,\u0131nf"])
    err = _error(path, CHUNK_BYTES)
    assert (err.line, err.column) == (2, "measured") and "is not a number" in str(err)
