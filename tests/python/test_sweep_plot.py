"""A sweep's plots (finken.sweep.plot): against the swarm size, one line per value of a swept define for each metric
(conf/sweeps/detector_vs_swarm_size.yaml: the wall map and the law before it, detector and baseline); a bool
parameter on the x axis drawn as TRUE / FALSE."""
from finken.sweep.plot import plot_against, series_of
from finken.sweep.spec import load_sweep
from finken.sweep.stats import Interval, PointSummary
from finken.sweep.values import value_text

MAP = "defines.WALL_DETECTOR_MAP"


def summaries_of(sweep):
    """A summary per point of `sweep` with made-up means (the map's recall above the old law's), 10 runs each."""
    result = []
    for point in sweep.points:
        n, on = point.values["vehicles"], point.values[MAP]
        recall = 1.0 - 0.01 * n * (1 if on else 3)
        metrics = {name: Interval(value, value - 0.01, value + 0.01, 10) for name, value in (
            ("detector_wall_recall", recall), ("baseline_wall_recall", 0.9 - 0.05 * n),
            ("detector_copter_as_wall", 0.005), ("baseline_copter_as_wall", 0.1))}
        result.append(PointSummary(point, 10, 0, metrics))
    return result


def test_the_swarm_size_figure_has_a_line_per_law_for_detector_and_baseline(tmp_path):
    sweep = load_sweep("conf/sweeps/detector_vs_swarm_size.yaml")
    assert sweep.swept == ("vehicles", MAP) and len(sweep.runs) == 160
    summaries = summaries_of(sweep)
    series = series_of(summaries, [MAP], True)
    assert list(series) == ["WALL_DETECTOR_MAP=TRUE", "WALL_DETECTOR_MAP=FALSE"]
    assert [[s.point.values["vehicles"] for s in members] for members in series.values()] == \
        [list(range(2, 17, 2))] * 2
    drawn = plot_against(summaries, "vehicles", [MAP], sweep.plots, True, False, sweep.name, tmp_path / "v.png")
    assert (tmp_path / "v.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    (wall_labels, ticks), (copter_labels, _) = drawn
    assert wall_labels == [f"{metric}, WALL_DETECTOR_MAP={law}" for metric in ("detector_wall_recall",
                                                                              "baseline_wall_recall")
                           for law in ("TRUE", "FALSE")]
    assert copter_labels == [label.replace("wall_recall", "copter_as_wall") for label in wall_labels]
    assert ticks == [str(n) for n in range(2, 17, 2)]


def test_a_bool_parameter_is_drawn_as_true_and_false(tmp_path):
    sweep = load_sweep("conf/sweeps/detector_vs_swarm_size.yaml")
    drawn = plot_against(summaries_of(sweep), MAP, ["vehicles"], sweep.plots, True, False, sweep.name,
                         tmp_path / "map.png")
    labels, ticks = drawn[0]
    assert ticks == ["TRUE", "FALSE"]                                      # the sweep file's order
    assert labels[:8] == [f"detector_wall_recall, vehicles={n}" for n in range(2, 17, 2)]
    assert (value_text(True), value_text(False), value_text(0.5), value_text(4)) == ("TRUE", "FALSE", "0.5", "4")
