"""`make sim` end to end: both runs, the report, metrics.json with its keys, the plots, the wall detector in a crowd
(8 and 16 copters, detector on), the targets."""
import json
import subprocess

METRIC_KEYS = ("detector_wall_recall", "detector_copter_as_wall", "baseline_wall_recall", "baseline_copter_as_wall",
               "near_wall_fraction_off", "near_wall_fraction_on", "cohesion_off", "cohesion_on")


def test_make_sim_writes_logs_metrics_and_plots(repo, tmp_path):
    out = tmp_path / "sim"
    result = subprocess.run(["make", "--no-print-directory", "sim", f"OUT={out}", "DURATION=30", "SEED=2"], cwd=repo,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    assert "Sensor readings against ground truth" in result.stdout
    for name in ("readings.csv", "poses.csv", "walls.csv", "detections.csv", "arena.png", "trajectories.png",
                 "detector_off/readings.csv", "detector_off/detections.csv"):
        assert (out / name).stat().st_size > 0, name
    metrics = json.loads((out / "metrics.json").read_text())
    for key in METRIC_KEYS:
        value = metrics[key]
        assert value is not None and value >= 0.0, key
        if not key.startswith("cohesion"):
            assert value <= 1.0, key
    assert set(metrics["sensor_errors"]) == {"sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down",
                                             "ranging"}
    # the wall detector in a crowd: the main run's figures, 8 copters in SwarmLab, 16 in SwarmLab scaled
    assert "== The wall detector in a crowd" in result.stdout
    for name in ("crowd_8/detections.csv", "crowd_16/detections.csv", "crowd_16/poses.csv"):
        assert (out / name).stat().st_size > 0, name
    crowd = metrics["crowd"]
    assert list(crowd) == ["4_swarmlab", "8_swarmlab", "16_swarmlab_16", "targets"]
    for key in ("detector_wall_recall", "detector_copter_as_wall", "baseline_wall_recall", "baseline_copter_as_wall"):
        assert crowd["4_swarmlab"][key] == metrics[key], key
        assert 0.0 <= crowd["8_swarmlab"][key] <= 1.0 and 0.0 <= crowd["16_swarmlab_16"][key] <= 1.0, key
    assert (crowd["8_swarmlab"]["logs"], crowd["16_swarmlab_16"]["copters"]) == ("crowd_8", 16)
    bounds = {4: ("0.99", "0.02"), 8: ("0.90", "0.05"), 16: ("0.90", "0.05")}
    assert set(crowd["targets"]) == {name for n, (recall, as_wall) in bounds.items() for name in (
        f"wall_recall_at_least_{recall}_at_{n}", f"copter_as_wall_at_most_{as_wall}_at_{n}",
        f"wall_recall_beats_baseline_at_{n}", f"copter_as_wall_beats_baseline_at_{n}")}
    assert "Targets the project keeps" in result.stdout and "issue" not in result.stdout
