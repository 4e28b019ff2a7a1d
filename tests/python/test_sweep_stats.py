"""A sweep's statistics (finken.sweep.stats) and its store (finken.sweep.store), against hand-computed values."""
import math

import pytest

from finken.sweep.points import Point, run_key
from finken.sweep.stats import interval, summarize_points
from finken.sweep.store import RunStore


def test_interval_is_students_by_hand():
    # 1, 2, 3, 4: mean 2.5, s = sqrt(5/3) = 1.29099, t(0.975, 3) = 3.18245, half width 3.18245 x 1.29099 / 2 = 2.05426
    iv = interval([1.0, 2.0, None, 3.0, float("nan"), 4.0])
    assert iv.n == 4 and iv.mean == 2.5
    assert iv.low == pytest.approx(2.5 - 2.05426, abs=1e-5) and iv.high == pytest.approx(2.5 + 2.05426, abs=1e-5)


def test_interval_of_one_value_has_no_bounds_and_of_none_no_mean():
    one = interval([0.7])
    assert one.mean == 0.7 and one.n == 1 and math.isnan(one.low) and math.isnan(one.high)
    assert interval([None, float("nan")]).n == 0 and math.isnan(interval([]).mean)


def test_points_summarize_their_done_runs_and_count_the_failed():
    a, b = Point({"vehicles": 2}), Point({"vehicles": 4})
    rows = [{"point_key": a.key, "status": "done", "m": 1.0}, {"point_key": a.key, "status": "done", "m": 3.0},
            {"point_key": a.key, "status": "failed", "m": None}, {"point_key": "other", "status": "done", "m": 9.0}]
    sa, sb = summarize_points([a, b], rows, ["m"])
    assert (sa.done, sa.failed, sa.metrics["m"].mean, sa.metrics["m"].n) == (2, 1, 2.0, 2)
    assert (sb.done, sb.failed, sb.metrics["m"].n) == (0, 0, 0)


def test_the_store_keeps_each_run_as_recorded_and_a_retry_replaces_its_failure(tmp_path):
    point = Point({"vehicles": 3, "defines.WALL_DETECTOR_WALL_THRESHOLD": 0.5, "arena": "a.xml"})
    store = RunStore(tmp_path / "runs.sqlite")
    store.record(run_key(point, 1), point, 1, 1, error="RunFailed: detector on: nps_host exited with status 1")
    assert store.states() == {run_key(point, 1): ("failed", 1)}
    result = {"started": "2026-01-01T00:00:00+00:00", "wall_s": 0.25, "worker": "h:1",
              "metrics": {"detector_wall_recall": 0.9, "targets.wall_recall_beats_baseline": 0, "cohesion_on": None}}
    store.record(run_key(point, 1), point, 1, 2, result=result)
    store.record(run_key(point, 2), point, 2, 1, result=result)
    store.close()
    reopened = RunStore(tmp_path / "runs.sqlite")                    # what a rerun sees
    assert reopened.states() == {run_key(point, 1): ("done", 2), run_key(point, 2): ("done", 1)}
    row = reopened.rows({run_key(point, 1)})[0]
    assert row["error"] is None and row["detector_wall_recall"] == 0.9 and row["wall_s"] == 0.25
    assert row["defines.WALL_DETECTOR_WALL_THRESHOLD"] == 0.5 and row["vehicles"] == 3 and row["arena"] == "a.xml"
    assert row["targets.wall_recall_beats_baseline"] == 0 and row["cohesion_on"] is None
    reopened.close()
