"""finken.rangelog reading a lab's own CSV as is: `columns` (file column -> spec column), `unit`, `fill`,
`group` (recordings), and the command-line text forms parse_column_map / parse_fill.

Exact tests on small hand-written files.
"""
import numpy as np
import pytest

from finken.rangelog import RangeLogError, parse_column_map, parse_fill, read_range_log, stream_ids

LAB = ["rec,time,id,other,kind,real_rng,rng,NLOS,operator",
       "A,0.0,1,2,ranging,1500,1480,0,kim",
       "A,0.5,1,2,ranging,1600,,1,kim",
       "B,0.0,1,2,ranging,1700,1710,0,lee",
       "",
       "B,0.2,1,2,ranging,1800,1850,1,lee"]
LAB_COLUMNS = {"t": "time", "vehicle": "id", "peer": "other", "sensor": "kind", "true_range": "real_rng",
               "measured": "rng", "ctx_nlos": "NLOS"}


def _write(tmp_path, lines, name="lab.csv"):
    path = tmp_path / name
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _error(path, **options):
    with pytest.raises(RangeLogError) as info:
        read_range_log(path, **options)
    return info.value


def test_lab_columns_in_mm_with_a_ctx_mapping_and_recordings(tmp_path):
    log = read_range_log(_write(tmp_path, LAB), columns=LAB_COLUMNS, unit="mm", group="rec")
    np.testing.assert_array_equal(log.t, [0.0, 0.5, 0.0, 0.2])            # t unchanged
    np.testing.assert_array_equal(log.true_range, [1.5, 1.6, 1.7, 1.8])   # divided by 1000
    np.testing.assert_array_equal(log.measured, [1.48, np.nan, 1.71, 1.85])
    assert list(log.ctx) == ["ctx_nlos"]
    np.testing.assert_array_equal(log.ctx["ctx_nlos"], [0, 1, 0, 1])       # ctx_ unchanged
    assert sorted(log.extra) == ["operator", "rec"] and log.extra["operator"].tolist() == ["kim"] * 2 + ["lee"] * 2
    assert log.line.tolist() == [2, 3, 4, 6]
    assert log.group.dtype == np.int64 and log.group.tolist() == [0, 0, 1, 1]
    assert log.group_names.tolist() == ["A", "B"]
    assert stream_ids(log).tolist() == [0, 0, 1, 1]   # one stream per recording
    sub = log.select([3, 0])
    assert sub.group.tolist() == [1, 0] and sub.group_names.tolist() == ["A", "B"] and sub.line.tolist() == [6, 2]


def test_cm_divides_by_100_and_negative_ranges_are_named_in_the_files_unit(tmp_path):
    log = read_range_log(_write(tmp_path, LAB), columns=LAB_COLUMNS, unit="cm", group="rec")
    np.testing.assert_array_equal(log.true_range, [15.0, 16.0, 17.0, 18.0])
    lines = LAB[:3] + ["B,0.0,1,2,ranging,-20,1710,0,lee"]
    err = _error(_write(tmp_path, lines), columns=LAB_COLUMNS, unit="cm")
    assert (err.line, err.column) == (4, "true_range") and "negative range -20 cm" in str(err)


def test_without_group_a_recording_starting_again_at_zero_goes_back_in_time(tmp_path):
    err = _error(_write(tmp_path, LAB), columns=LAB_COLUMNS, unit="mm")
    assert (err.line, err.column) == (4, "t") and "from t = 0.5 s on line 3" in str(err)
    lines = LAB + ["B,0.1,1,2,ranging,1800,1850,1,lee"]   # back in time within recording B
    err = _error(_write(tmp_path, lines), columns=LAB_COLUMNS, unit="mm", group="rec", chunk_bytes=5)
    assert (err.line, err.column) == (7, "t")
    assert "from t = 0.2 s on line 6 of the same stream (vehicle 1, sensor ranging, peer 2, rec 'B')" in str(err)


def test_the_group_column_may_be_any_column_and_its_values_are_stripped(tmp_path):
    lines = [LAB[0]] + [" A ,0.0,1,2,ranging,1,1,0,kim", "A,0.0,1,2,ranging,1,1,0,kim", "B,0.0,1,2,ranging,1,1,0,lee"]
    log = read_range_log(_write(tmp_path, lines), columns=LAB_COLUMNS, group="operator")
    assert log.group.tolist() == [0, 0, 1] and log.group_names.tolist() == ["kim", "lee"]
    err = _error(_write(tmp_path, lines), columns=LAB_COLUMNS, group="recording")
    assert (err.line, err.column) == (1, "recording") and "group option" in str(err)


def test_fill_gives_required_columns_the_file_lacks(tmp_path):
    lines = ["time,real_rng,rng", "0.0,1.0,1.1", "0.1,1.2,"]
    columns = {"t": "time", "true_range": "real_rng", "measured": "rng"}
    log = read_range_log(_write(tmp_path, lines), columns=columns,
                         fill=parse_fill("sensor=ranging,vehicle=1,peer=2,ctx_site=3"))
    assert log.sensor.tolist() == ["ranging", "ranging"]
    np.testing.assert_array_equal(log.vehicle, [1, 1])
    np.testing.assert_array_equal(log.peer, [2, 2])
    np.testing.assert_array_equal(log.measured, [1.1, np.nan])
    np.testing.assert_array_equal(log.ctx["ctx_site"], [3, 3])
    sonar = read_range_log(_write(tmp_path, lines), columns=columns,
                           fill={"sensor": "sonar_down", "vehicle": "4", "peer": ""})
    assert np.isnan(sonar.peer).all() and sonar.sensor.tolist() == ["sonar_down"] * 2


@pytest.mark.parametrize("fill, column, words", [
    ({"sensor": "sonar_top", "vehicle": "1", "peer": "2"}, "sensor", "fill option sensor='sonar_top': unknown sensor"),
    ({"sensor": "ranging", "vehicle": "1.5", "peer": "2"}, "vehicle",
     "fill option vehicle='1.5': '1.5' is not an integer id"),
    ({"sensor": "ranging", "vehicle": "", "peer": "2"}, "vehicle",
     "fill option vehicle='': empty: a number is required"),
    ({"sensor": "ranging", "vehicle": "1", "peer": "x"}, "peer", "fill option peer='x': 'x' is not a number"),
    ({"sensor": "ranging", "vehicle": "1", "peer": ""}, "peer", "fill option sensor='ranging', peer='': no value"),
    ({"sensor": "ranging", "vehicle": "2", "peer": "2"}, "peer", "vehicle='2', peer='2': 2 is the row's own vehicle"),
])
def test_a_bad_fill_value_is_named_by_its_option_not_a_line(tmp_path, fill, column, words):
    path = _write(tmp_path, ["t,true_range,measured", "0.0,1.0,1.1"])
    err = _error(path, fill=fill)
    assert (err.line, err.column) == (None, column) and words in str(err)
    assert str(err).startswith(f"{path}: column '{column}': fill option ")


def test_a_filled_value_breaking_a_rule_with_a_file_column_names_the_row(tmp_path):
    path = _write(tmp_path, ["t,vehicle,true_range,measured", "0.0,1,1.0,1.1", "0.0,2,1.0,1.1"])
    err = _error(path, fill={"sensor": "ranging", "peer": "2"})
    assert (err.line, err.column) == (3, "peer") and "2 is the row's own vehicle" in str(err)
    err = _error(path, fill={"sensor": "ranging", "peer": "3", "true_range": "-1"})   # checked before the file
    assert (err.line, err.column) == (None, "true_range") and "true_range='-1': negative range -1 m" in str(err)


@pytest.mark.parametrize("options, line, column, words", [
    ({"columns": {"measured": "range_mm"}}, 1, "range_mm",
     "not in the header (given for 'measured' by the columns option)"),
    ({"columns": {"ctx_x": "measured"}}, 1, "measured", "missing required column"),
    ({"columns": {"measured": "note"}}, 1, "measured",
     "is in the header and also given by the columns option (as column 'note')"),
    ({"fill": {"sensor": "ranging"}}, 1, "sensor", "is in the file and given by the fill option too"),
    ({"columns": {"measured": "note", "true_range": "note"}}, None, None,
     "file column 'note' is given for both 'measured' and 'true_range'"),
    ({"columns": {"range": "note"}}, None, None, "columns: unknown column 'range'"),
    ({"fill": {"colour": "red"}}, None, None, "fill: unknown column 'colour'"),
    ({"unit": "km"}, None, None, "unit: 'km' is not one of m, cm, mm"),
])
def test_options_that_do_not_fit_the_file_are_errors(tmp_path, options, line, column, words):
    path = _write(tmp_path, ["t,vehicle,sensor,peer,true_range,measured,note", "0.0,1,sonar_front,,1.0,1.1,5"])
    err = _error(path, **options)
    assert (err.line, err.column) == (line, column) and words in str(err)


def test_a_ctx_mapping_makes_any_column_a_context_column_and_keeps_the_rest(tmp_path):
    path = _write(tmp_path, ["t,vehicle,sensor,peer,true_range,measured,note,ctx_speed",
                             "0.0,1,sonar_front,,1.0,1.1,5,0.3"])
    log = read_range_log(path, columns={"ctx_note": "note"})
    assert list(log.ctx) == ["ctx_note", "ctx_speed"] and log.extra == {}
    np.testing.assert_array_equal(log.ctx["ctx_note"], [5])
    path = _write(tmp_path, ["t,vehicle,sensor,peer,true_range,measured,note", "0.0,1,sonar_front,,1.0,1.1,n/a"])
    err = _error(path, columns={"ctx_note": "note"})
    assert (err.line, err.column) == (2, "ctx_note") and "'n/a' is not a number" in str(err)


def test_parse_column_map_and_parse_fill():
    assert parse_column_map("measured=rng, true_range = real_rng,ctx_nlos=NLOS") == {
        "measured": "rng", "true_range": "real_rng", "ctx_nlos": "NLOS"}
    assert parse_column_map("") == {} and parse_fill(" ") == {}
    assert parse_fill("sensor=ranging,vehicle=1,peer=") == {"sensor": "ranging", "vehicle": "1", "peer": ""}
    for text, words in (("distance=rng", "unknown column 'distance'"), ("ctx_=rng", "unknown column 'ctx_'"),
                        ("=rng", "empty column name"), ("measured", "expected spec_name=file_column"),
                        ("measured=", "empty file column name for 'measured'"),
                        ("measured=a,measured=b", "'measured' is given twice"),
                        ("measured=a,true_range=a", "file column 'a' is given for both"),
                        ("measured=a,", "an empty item")):
        with pytest.raises(ValueError, match=words):
            parse_column_map(text)
    for text, words in (("colour=red", "unknown column 'colour'"), ("=1", "empty column name"),
                        ("vehicle=1,vehicle=2", "'vehicle' is given twice"), ("vehicle", "expected spec_name=value")):
        with pytest.raises(ValueError, match=words):
            parse_fill(text)
