"""finken.rangelog: reading, validating and writing range logs (shared/spec/range-log.md).

Exact tests (no statistics): values read from small hand-written files, errors naming file, line and column,
round trips through write_range_log.
"""
from pathlib import Path

import numpy as np
import pytest

from finken.rangelog import RangeLog, RangeLogError, read_range_log, stream_ids, write_range_log

LOGS = Path(__file__).resolve().parents[1] / "data" / "logs"


def test_reads_every_column_of_a_good_log():
    log = read_range_log(LOGS / "good.csv")
    assert len(log) == 7
    assert log.path == str(LOGS / "good.csv")
    np.testing.assert_array_equal(log.t, [0.0, 0.0, 0.05, 0.10, 0.10, 0.10, 0.15])
    np.testing.assert_array_equal(log.vehicle, [1, 1, 2, 1, 1, 2, 1])
    assert log.sensor.tolist() == ["sonar_front", "ranging", "sonar_front", "sonar_front", "ranging", "ranging",
                                   "sonar_front"]
    np.testing.assert_array_equal(log.peer, [np.nan, 2, np.nan, np.nan, 2, 1, np.nan])
    np.testing.assert_array_equal(log.true_range, [1.20, 0.80, 2.50, 1.18, 0.82, 0.82, 3.40])
    np.testing.assert_array_equal(log.measured, [1.21, np.nan, 2.47, 1.19, 0.85, 0.80, 3.0])
    assert list(log.ctx) == ["ctx_blocked", "ctx_speed"]
    np.testing.assert_array_equal(log.ctx["ctx_blocked"], [0, 1, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(log.ctx["ctx_speed"], [0.3, 0.3, 0.1, 0.3, np.nan, 0.1, 0.3])
    assert log.extra["note"].tolist() == ["takeoff", "", "", "", "hover, stable", "", "beyond max"]


def test_messy_file_bom_crlf_spaces_blank_lines_and_nan():
    log = read_range_log(LOGS / "messy.csv")
    assert len(log) == 4
    assert log.sensor.tolist() == ["sonar_left"] * 3 + ["ranging"]
    np.testing.assert_array_equal(log.measured, [1.49, np.nan, np.nan, 2.5])
    np.testing.assert_array_equal(log.ctx["ctx_facing_sonars"], [0, np.nan, 2, 1])
    np.testing.assert_array_equal(log.t, [0.0, 0.1, 0.1, 0.2])   # equal times in one stream are accepted


@pytest.mark.parametrize("name, line, column, words", [
    ("missing_column.csv", 1, "true_range", "missing required column"),
    ("text_in_numeric.csv", 4, "measured", "'n/a' is not a number"),
    ("negative_range.csv", 3, "true_range", "negative range -0.5"),
    ("unsorted_stream.csv", 5, "t", "goes back in time"),
    ("quoted_multiline.csv", 4, "measured", "'oops' is not a number"),
])
def test_bad_logs_are_rejected_with_file_line_and_column(name, line, column, words):
    path = LOGS / name
    with pytest.raises(RangeLogError) as info:
        read_range_log(path)
    err = info.value
    assert (err.path, err.line, err.column) == (str(path), line, column)
    assert str(err).startswith(f"{path}:{line}: column '{column}': ")
    assert words in str(err)


def _write(tmp_path, text):
    path = tmp_path / "log.csv"
    path.write_text(text)
    return path


HEAD = "t,vehicle,sensor,peer,true_range,measured\n"


@pytest.mark.parametrize("row, column, words", [
    ("0.0,1,sonar_top,,1.0,1.0", "sensor", "unknown sensor 'sonar_top'"),
    ("0.0,1.5,sonar_front,,1.0,1.0", "vehicle", "not an integer id"),
    ("0.0,1,ranging,2.5,1.0,1.0", "peer", "not an integer id"),
    ("0.0,1,sonar_front,,inf,1.0", "true_range", "not a finite number"),
    (",1,sonar_front,,1.0,1.0", "t", "empty"),
    ("0.0,1,sonar_front,,NaN,1.0", "true_range", "'NaN'"),
    ("0.0,1,sonar_front,,-0.01,1.0", "true_range", "negative range -0.01"),
    ("0.0,1,sonar_front,,-inf,1.0", "true_range", "not a finite number"),
    ("0.0,1,sonar_front,,1.0", "measured", "expected 6 fields"),
    ("0.0,1,sonar_front,,1.0,1.0,7", None, "expected 6 fields"),
])
def test_each_rule_of_the_spec(tmp_path, row, column, words):
    path = _write(tmp_path, HEAD + "0.0,1,sonar_front,,1.0,1.0\n" + row + "\n")
    with pytest.raises(RangeLogError) as info:
        read_range_log(path)
    assert (info.value.line, info.value.column) == (3, column)
    assert words in str(info.value)


def test_a_sensors_glitches_are_readings_kept_as_they_are(tmp_path):
    """Negative, zero, infinite and absurd readings are what real sensors report now and then (shared/spec/
    range-log.md): data, never a reason to refuse the file."""
    rows = ["-12.84", "0", "inf", "-inf", "1e5", "270.1", "", "1.0"]
    path = _write(tmp_path, HEAD + "".join(f"{0.1 * i:.1f},1,ranging,2,1.0,{m}\n" for i, m in enumerate(rows)))
    np.testing.assert_array_equal(read_range_log(path).measured,
                                  [-12.84, 0.0, np.inf, -np.inf, 1e5, 270.1, np.nan, 1.0])
    mm = _write(tmp_path, HEAD + "0.0,1,ranging,2,1000,-12840\n0.1,1,ranging,2,1000,inf\n")
    np.testing.assert_array_equal(read_range_log(mm, unit="mm").measured, [-12.84, np.inf])


@pytest.mark.parametrize("row, column, words", [
    # numbers: ASCII decimal only (Python's float() reads 1_5 as 15 and accepts digits of other scripts)
    ("1_0,1,sonar_front,,1.0,1.0", "t", "'1_0' is not a number"),
    ("0.0,1_5,sonar_front,,1.0,1.0", "vehicle", "'1_5' is not a number"),
    ("0.0,\u0661\u0665,sonar_front,,1.0,1.0", "vehicle", "is not a number"),
    ("0.0,1,sonar_front,,1_5,1.0", "true_range", "'1_5' is not a number"),
    ("0.0,1,sonar_front,,1.0,\uff11", "measured", "is not a number"),
    ("0.0,1,sonar_front,,1.0,1.0\u00a0", "measured", "is not a number"),
    # ids: whole numbers from 0 to 2**31 - 1
    ("0.0,1e300,sonar_front,,1.0,1.0", "vehicle", "'1e300' is not an integer id from 0 to 2147483647"),
    ("0.0,-1,sonar_front,,1.0,1.0", "vehicle", "'-1' is not an integer id"),
    ("0.0,2147483648,sonar_front,,1.0,1.0", "vehicle", "not an integer id"),
    ("0.0,1,ranging,-7,1.0,1.0", "peer", "'-7' is not an integer id"),
    # peer: the other copter on a ranging row, nothing on a sonar row
    ("0.0,1,ranging,1,1.0,1.0", "peer", "1 is the row's own vehicle"),
    ("0.0,1,sonar_front,2,1.0,1.0", "peer", "2 on a sonar_front row: sonar rows have no peer"),
    ("0.0,1,ranging,,1.0,1.0", "peer", "a ranging row needs the id of the other copter"),
])
def test_numbers_ids_and_peers_follow_the_spec_strictly(tmp_path, row, column, words):
    path = tmp_path / "log.csv"
    path.write_text(HEAD + "0.0,1,sonar_front,,1.0,1.0\n" + row + "\n", encoding="utf-8")
    with pytest.raises(RangeLogError) as info:
        read_range_log(path)
    assert (info.value.line, info.value.column) == (3, column)
    assert str(info.value).startswith(f"{path}:3: column '{column}': ") and words in str(info.value)


def test_ids_written_as_decimals_and_nan_for_no_peer_are_read(tmp_path):
    log = read_range_log(_write(tmp_path, HEAD + "0.0,2.0,ranging,3e0,1.0,1.0\n0.0,2,sonar_down,NaN,0.6,0.6\n"))
    np.testing.assert_array_equal(log.vehicle, [2, 2])
    np.testing.assert_array_equal(log.peer, [3, np.nan])


def test_duplicated_column_and_empty_file(tmp_path):
    with pytest.raises(RangeLogError, match="duplicated column"):
        read_range_log(_write(tmp_path, "t,t,vehicle,sensor,peer,true_range,measured\n"))
    with pytest.raises(RangeLogError, match="empty file"):
        read_range_log(_write(tmp_path, "\n\n"))
    with pytest.raises(RangeLogError, match="cannot read"):
        read_range_log(tmp_path / "absent.csv")


def test_header_only_gives_an_empty_log(tmp_path):
    log = read_range_log(_write(tmp_path, HEAD + "\n"))
    assert len(log) == 0 and log.t.dtype == np.float64


def test_round_trip_keeps_values_nan_ctx_and_extra(tmp_path):
    log = read_range_log(LOGS / "good.csv")
    out = tmp_path / "copy.csv"
    write_range_log(out, log)
    again = read_range_log(out)
    for name in ("t", "vehicle", "peer", "true_range", "measured"):
        np.testing.assert_array_equal(getattr(again, name), getattr(log, name))
    assert again.sensor.tolist() == log.sensor.tolist()
    for k in log.ctx:
        np.testing.assert_array_equal(again.ctx[k], log.ctx[k])
    assert again.extra["note"].tolist() == log.extra["note"].tolist()   # "hover, stable" quoted and back


def test_fast_and_quoted_paths_agree_on_a_large_interleaved_log(tmp_path):
    rng = np.random.default_rng(3)
    n = 20000
    sensors = np.array(["sonar_front", "sonar_down", "ranging"])[rng.integers(0, 3, n)]
    log = RangeLog("x", np.sort(rng.uniform(0, 100, n)), rng.integers(1, 4, n).astype(float), sensors,
                   np.where(sensors == "ranging", 4.0, np.nan), rng.uniform(0, 4, n),
                   np.where(rng.random(n) < 0.1, np.nan, rng.uniform(0, 4, n)),
                   {"ctx_speed": rng.normal(size=n)}, {"note": np.full(n, "x")})
    plain, quoted = tmp_path / "plain.csv", tmp_path / "quoted.csv"
    write_range_log(plain, log)
    log.extra["note"] = np.full(n, 'say "hi"')      # forces quotes, hence the csv-module path
    write_range_log(quoted, log)
    a, b = read_range_log(plain), read_range_log(quoted)
    np.testing.assert_array_equal(a.measured, b.measured)
    np.testing.assert_array_equal(a.ctx["ctx_speed"], log.ctx["ctx_speed"])
    assert b.extra["note"][0] == 'say "hi"'


def test_stream_ids_group_vehicle_sensor_and_peer():
    log = read_range_log(LOGS / "good.csv")
    ids = stream_ids(log)
    # streams: (1, sonar_front), (1, ranging, 2), (2, sonar_front), (2, ranging, 1)
    assert len(set(ids.tolist())) == 4
    assert ids[0] == ids[3] == ids[6] and ids[1] == ids[4] and ids[1] != ids[5]


def test_select_keeps_columns_together():
    log = read_range_log(LOGS / "good.csv")
    sub = log.select(log.sensor == "ranging")
    assert len(sub) == 3 and sub.extra["note"].tolist() == ["", "hover, stable", ""]
    np.testing.assert_array_equal(sub.ctx["ctx_blocked"], [1, 0, 0])
