"""Wall-detector metrics (finken.sim_report.detector_metrics), their log readers (finken.run_logs), the command line
(finken.sim_report.detector_report) and the trajectory plot (finken.sim_report.swarm_plot), against hand-computed
values."""
import json
import math
import os

import numpy as np
import pytest

from finken.rangelog import RangeLogError
from finken.run_logs import parse_polygon, read_detections, read_poses
from finken.sim_report import detector_report
from finken.sim_report.detector_metrics import (classification_scores, cohesion, distance_to_polygon,
                                                near_wall_fraction, run_classification, summarize, targets_met)
from finken.sim_report.swarm_plot import plot_trajectories

SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])
DETECTIONS_HEADER = ("t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,"
                     "detector_class,confidence,baseline_class\n")


def test_classification_scores_by_hand():
    # truth: 4 walls, 2 copters
    truth = np.array([0, 0, 0, 0, 1, 1], dtype=bool)
    labels = np.array(["wall", "wall", "wall", "copter", "wall", "unknown"])
    s = classification_scores(truth, labels)
    assert s["wall_recall"] == pytest.approx(3 / 4)
    assert s["wall_precision"] == pytest.approx(3 / 4)   # 3 of the 4 "wall" labels are walls
    assert s["copter_recall"] == 0.0
    assert s["copter_precision"] == 0.0                  # the one "copter" label is a wall
    assert s["copter_as_wall"] == pytest.approx(1 / 2)
    assert s["undecided"] == pytest.approx(1 / 6)
    assert (s["walls"], s["copters"]) == (4, 2)


def test_scores_without_a_class_are_nan_not_an_error():
    s = classification_scores(np.zeros(3, dtype=bool), np.array(["wall", "wall", "unknown"]))
    assert math.isnan(s["copter_recall"]) and math.isnan(s["copter_as_wall"]) and math.isnan(s["copter_precision"])


def test_distance_to_polygon_edges_and_corners():
    points = np.array([[2.0, 2.0], [0.3, 2.0], [3.9, 0.1], [5.0, 5.0], [2.0, 4.0]])
    expected = [2.0, 0.3, 0.1, math.sqrt(2.0), 0.0]
    assert distance_to_polygon(points, SQUARE) == pytest.approx(expected)
    closed = np.vstack([SQUARE, SQUARE[:1]])
    assert distance_to_polygon(points, closed) == pytest.approx(expected)


def test_near_wall_fraction_is_time_weighted():
    # vehicle 1: near the wall (0.3 m) for 1 s of its 3 s; vehicle 2 sampled twice as often, near for 1 s of 3 s
    t = np.array([0.0, 1.0, 2.0, 3.0] + [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0])
    vehicle = np.array([1] * 4 + [2] * 7)
    xy = np.array([[0.3, 2.0], [2.0, 2.0], [2.0, 2.0], [2.0, 2.0]] +
                  [[2.0, 2.0], [2.0, 2.0], [2.0, 2.0], [2.0, 2.0], [2.0, 3.8], [2.0, 3.8], [2.0, 2.0]])
    # weights: vehicle 1 1 s each (last: median 1 s) -> near 1 of 4 s; vehicle 2 0.5 s each -> near 1 of 3.5 s
    assert near_wall_fraction(t, vehicle, xy, SQUARE) == pytest.approx((1.0 + 1.0) / (4.0 + 3.5))


def test_cohesion_is_the_mean_distance_to_the_centroid():
    # two copters 2 m apart, then 4 m apart: 1 m then 2 m from the centroid; a time with one copter is skipped
    t = np.array([0.0, 0.0, 1.0, 1.0, 2.0])
    vehicle = np.array([1, 2, 1, 2, 1])
    xy = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 0.0], [0.0, 4.0], [9.0, 9.0]])
    assert cohesion(t, vehicle, xy) == pytest.approx(1.5)


def _run(detector, baseline, truth, poses_xy):
    n = len(truth)
    poses = {"t": np.repeat(np.arange(len(poses_xy) // 2, dtype=float), 2),
             "vehicle": np.tile([1.0, 2.0], len(poses_xy) // 2),
             "x": np.array([p[0] for p in poses_xy]), "y": np.array([p[1] for p in poses_xy])}
    return {"detections": {"target_copter": np.asarray(truth, dtype=bool), "detector_class": np.array(detector),
                           "baseline_class": np.array(baseline), "t": np.arange(n, dtype=float)},
            "poses": poses}


def test_summary_keys_and_which_run_they_come_from():
    on = _run(["wall", "wall", "copter", "none"], ["wall", "copter", "wall", "none"], [0, 0, 1, 0],
              [(2, 2), (2, 3)] * 2)
    off = _run(["copter", "wall"], ["copter", "copter"], [0, 1], [(0.2, 2), (2, 2)] * 2)
    m = summarize({"off": off, "on": on}, SQUARE)
    for key in ("detector_wall_recall", "detector_copter_as_wall", "baseline_wall_recall", "baseline_copter_as_wall",
                "near_wall_fraction_off", "near_wall_fraction_on", "cohesion_off", "cohesion_on"):
        assert key in m
    # on run, echoes only (the "none" row is no echo): walls 2 (both wall), copter 1 (copter)
    assert m["detector_wall_recall"] == 1.0 and m["detector_copter_as_wall"] == 0.0
    assert m["baseline_wall_recall"] == 0.5 and m["baseline_copter_as_wall"] == 1.0
    # off run: its wall labelled copter, its copter labelled wall
    assert m["detector_wall_recall_off_run"] == 0.0 and m["detector_copter_as_wall_off_run"] == 1.0
    assert m["near_wall_fraction_off"] == pytest.approx(0.5) and m["near_wall_fraction_on"] == 0.0
    assert m["cohesion_off"] == pytest.approx(0.9) and m["cohesion_on"] == pytest.approx(0.5)
    assert m["classification"]["on"] == run_classification(on["detections"])
    assert targets_met(m) == {"wall_recall_beats_baseline": True, "copter_as_wall_beats_baseline": True,
                              "cohesion_tighter_with_detector": True}


@pytest.mark.parametrize("change, missed", [
    ({}, set()),
    ({"detector_wall_recall": 0.5}, {"wall_recall_beats_baseline"}),                  # a tie is not beating it
    ({"detector_copter_as_wall": 0.5}, {"copter_as_wall_beats_baseline"}),
    ({"cohesion_on": 0.9}, {"cohesion_tighter_with_detector"}),
    ({"detector_wall_recall": float("nan")}, {"wall_recall_beats_baseline"}),        # nothing to compute it from
])
def test_targets_every_run_keeps_fail_where_the_detector_does_not_beat_its_baseline(change, missed):
    m = {"detector_wall_recall": 0.9, "baseline_wall_recall": 0.5, "detector_copter_as_wall": 0.1,
         "baseline_copter_as_wall": 0.5, "cohesion_on": 0.5, "cohesion_off": 0.9, **change}
    assert {name for name, met in targets_met(m).items() if not met} == missed


def write_detections(path, rows):
    with open(path, "w") as f:
        f.write(DETECTIONS_HEADER)
        for row in rows:
            f.write(",".join(str(v) for v in row) + "\n")
    return path


def write_poses(path, rows):
    with open(path, "w") as f:
        f.write("t,vehicle,x,y,z,yaw\n")
        for row in rows:
            f.write(",".join(str(v) for v in row) + "\n")
    return path


def test_read_detections_round_trip(tmp_path):
    path = write_detections(tmp_path / "d.csv", [(0.05, 11, "sonar_front", "", 1.2, 1.15, 0, "wall", 0.99, "copter"),
                                                 (0.10, 11, "sonar_front", "", 3.4, 3.0, 0, "none", 1.0, "none")])
    d = read_detections(path)
    assert d["detector_class"].tolist() == ["wall", "none"]
    assert d["baseline_class"].tolist() == ["copter", "none"]
    assert d["target_copter"].tolist() == [False, False]
    assert d["confidence"] == pytest.approx([0.99, 1.0])
    assert d["measured"] == pytest.approx([1.15, 3.0])


@pytest.mark.parametrize("column, value, message", [
    ("detector_class", "door", "detector_class': data row 1: 'door': expected one of"),
    ("ctx_target_copter", "2", "ctx_target_copter': data row 1: '2': expected 0 or 1"),
    ("confidence", "high", "confidence': data row 1: 'high' is not a number"),
])
def test_read_detections_names_the_bad_field(tmp_path, column, value, message):
    row = {"t": 0.05, "vehicle": 11, "sensor": "sonar_front", "peer": "", "true_range": 1.2, "measured": 1.1,
           "ctx_target_copter": 0, "detector_class": "wall", "confidence": 0.9, "baseline_class": "wall"}
    row[column] = value
    path = write_detections(tmp_path / "d.csv", [tuple(row.values())])
    with pytest.raises(RangeLogError, match=message):
        read_detections(path)


def test_read_detections_needs_the_detector_columns(tmp_path):
    path = tmp_path / "d.csv"
    path.write_text("t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,detector_class\n"
                    "0.05,11,sonar_front,,1.2,1.1,0,wall\n")
    with pytest.raises(RangeLogError, match=r"d.csv:1: column 'confidence': missing column"):
        read_detections(path)


def test_read_poses_names_file_line_and_column(tmp_path):
    good = read_poses(write_poses(tmp_path / "p.csv", [(0.0, 1, 1.0, 2.0, 0.6, 0.0), (0.1, 1, 1.1, 2.0, 0.6, 0.0)]))
    assert good["x"] == pytest.approx([1.0, 1.1])
    bad = write_poses(tmp_path / "bad.csv", [(0.0, 1, 1.0, 2.0, 0.6, 0.0), (0.1, 1, "x", 2.0, 0.6, 0.0)])
    with pytest.raises(RangeLogError, match=r"bad.csv:3: column 'x': 'x' is not a finite number"):
        read_poses(bad)
    (tmp_path / "short.csv").write_text("t,vehicle,x,y,z\n0,1,1,1,1\n")
    with pytest.raises(RangeLogError, match=r"short.csv:1: column 'yaw': missing column"):
        read_poses(tmp_path / "short.csv")


@pytest.mark.parametrize("column, value, message", [
    ("t", "1_0", "'1_0' is not a finite number"),
    ("x", "\u0661", "'\u0661' is not a finite number"),
    ("vehicle", "-1", "'-1' is not an integer from 0 to 2147483647"),
    ("vehicle", "1e300", "'1e300' is not an integer from 0"),
    ("vehicle", "1.5", "'1.5' is not an integer from 0"),
])
def test_read_poses_numbers_and_ids_as_in_a_range_log(tmp_path, column, value, message):
    row = dict(zip(("t", "vehicle", "x", "y", "z", "yaw"), (0.1, 1, 1.1, 2.0, 0.6, 0.0)))
    row[column] = value
    path = write_poses(tmp_path / "p.csv", [(0.0, 1, 1.0, 2.0, 0.6, 0.0), tuple(row.values())])
    with pytest.raises(RangeLogError, match=rf"p.csv:3: column '{column}': {message}"):
        read_poses(path)


@pytest.mark.parametrize("value, message", [("0_9", "'0_9' is not a number"), ("nan", "'nan' is not a finite number")])
def test_read_detections_confidence_is_an_ascii_finite_number(tmp_path, value, message):
    path = write_detections(tmp_path / "d.csv", [(0.05, 11, "sonar_front", "", 1.2, 1.1, 0, "wall", value, "wall")])
    with pytest.raises(RangeLogError, match=f"column 'confidence': data row 1: {message}"):
        read_detections(path)


def test_parse_polygon():
    assert parse_polygon("0,0 3,0 3,4 0,4").tolist() == [[0, 0], [3, 0], [3, 4], [0, 4]]
    for bad in ("0,0 3,0", "0,0 3,x 3,4", "0,0,1 3,0 3,4", "0,0 3,0 3,4_0", "0,0 3,0 3,nan"):
        with pytest.raises(ValueError, match="arena polygon"):
            parse_polygon(bad)


def _write_run(folder, near_wall):
    folder.mkdir()
    write_detections(folder / "detections.csv", [
        (0.05, 1, "sonar_front", "", 1.2, 1.15, 0, "wall", 0.99, "copter"),
        (0.05, 2, "sonar_front", "", 1.0, 0.98, 1, "copter", 0.95, "copter"),
        (0.10, 1, "sonar_front", "", 3.4, 3.0, 0, "none", 1.0, "none"),
    ])
    x = 0.2 if near_wall else 1.5
    write_poses(folder / "poses.csv", [(0.0, 1, x, 2.0, 0.6, 0.0), (0.0, 2, 1.5, 1.0, 0.6, 0.0),
                                       (0.1, 1, x, 2.0, 0.6, 0.0), (0.1, 2, 1.5, 1.0, 0.6, 0.0)])


def test_command_line_writes_json_table_and_plot(tmp_path, capsys):
    _write_run(tmp_path / "off", near_wall=True)
    _write_run(tmp_path / "on", near_wall=False)
    out_json, out_png = tmp_path / "sim" / "metrics.json", tmp_path / "sim" / "trajectories.png"
    rc = detector_report.main(["--off", str(tmp_path / "off"), "--on", str(tmp_path / "on"),
                            "--arena-polygon", "0,0 3,0 3,4 0,4", "--json", str(out_json), "--plot", str(out_png)])
    assert rc == 0
    metrics = json.loads(out_json.read_text())
    assert metrics["detector_wall_recall"] == 1.0 and metrics["baseline_wall_recall"] == 0.0
    assert metrics["near_wall_fraction_off"] == pytest.approx(0.5) and metrics["near_wall_fraction_on"] == 0.0
    # the baseline labels no copter echo wall either: a tie, not beaten
    assert metrics["targets"] == {"wall_recall_beats_baseline": True, "copter_as_wall_beats_baseline": False,
                                  "cohesion_tighter_with_detector": True}
    assert out_png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "wall recall" in capsys.readouterr().out


def test_command_line_reports_bad_input(tmp_path, capsys):
    _write_run(tmp_path / "off", near_wall=True)
    rc = detector_report.main(["--off", str(tmp_path / "off"), "--on", str(tmp_path / "missing"),
                            "--arena-polygon", "0,0 3,0 3,4 0,4"])
    assert rc == 1
    assert "missing/detections.csv" in capsys.readouterr().err


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
@pytest.mark.parametrize("option", ["--json", "--plot"])
def test_command_line_reports_an_output_it_cannot_write(tmp_path, capsys, option):
    _write_run(tmp_path / "off", near_wall=True)
    _write_run(tmp_path / "on", near_wall=False)
    rc = detector_report.main(["--off", str(tmp_path / "off"), "--on", str(tmp_path / "on"),
                            "--arena-polygon", "0,0 3,0 3,4 0,4", option, "/dev/full"])
    assert rc == 1
    assert capsys.readouterr().err.strip() == "error: /dev/full: cannot write: No space left on device"


def test_trajectory_plot_has_one_panel_per_run(tmp_path):
    poses = {"t": np.array([0.0, 1.0, 0.0, 1.0]), "vehicle": np.array([1.0, 1.0, 2.0, 2.0]),
             "x": np.array([1.0, 1.5, 2.0, 2.0]), "y": np.array([1.0, 1.0, 3.0, 2.5])}
    path = tmp_path / "t.png"
    plot_trajectories([("off", poses), ("on", poses)], SQUARE, path)
    from matplotlib.image import imread
    height, width = imread(path).shape[:2]
    assert width > 1.5 * height   # two panels side by side
