"""`make sim` end to end on its default seed and duration: both runs, the report, metrics.json with its keys, the
plots, the wall detector in a crowd (8 and 16 copters, detector on), the targets the project keeps, and the
headline figures the documents state for that run (README.md, docs/host.md, docs/wall-detector.md): a regression of
a figure fails here even where no unit test sees it, and a document that no longer tells the truth too."""
import json
import re
import subprocess

import pytest
from conftest import REPO

METRIC_KEYS = ("detector_wall_recall", "detector_copter_as_wall", "baseline_wall_recall", "baseline_copter_as_wall",
               "near_wall_fraction_off", "near_wall_fraction_on", "cohesion_off", "cohesion_on")
#: the crowd's rows in metrics.json, in the order the documents list them
RUNS = ("4_swarmlab", "8_swarmlab", "16_swarmlab_16", "4_swarmlab_l", "8_swarmlab_l", "4_swarmlab_pillar",
        "8_swarmlab_pillar")
FIGURES = ("detector_wall_recall", "baseline_wall_recall", "detector_copter_as_wall", "baseline_copter_as_wall")


@pytest.fixture(scope="module")
def make_sim(tmp_path_factory):
    """(completed make sim with the defaults, its OUT, its metrics.json)."""
    out = tmp_path_factory.mktemp("make_sim") / "sim"
    result = subprocess.run(["make", "--no-print-directory", "sim", f"OUT={out}"], cwd=REPO, capture_output=True,
                            text=True)
    metrics = json.loads((out / "metrics.json").read_text()) if (out / "metrics.json").is_file() else None
    return result, out, metrics


def test_make_sim_writes_logs_metrics_and_plots(make_sim):
    result, out, metrics = make_sim
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-2000:]
    assert "Sensor readings against ground truth" in result.stdout
    for name in ("readings.csv", "poses.csv", "walls.csv", "detections.csv", "arena.png", "trajectories.png",
                 "detector_off/readings.csv", "detector_off/detections.csv"):
        assert (out / name).stat().st_size > 0, name
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
    assert list(crowd) == [*RUNS, "targets"]
    for key in FIGURES:
        assert crowd["4_swarmlab"][key] == metrics[key], key
    assert (crowd["8_swarmlab"]["logs"], crowd["16_swarmlab_16"]["copters"]) == ("crowd_8", 16)


def test_every_target_the_project_keeps_is_met_on_the_default_seed(make_sim):
    result, _, metrics = make_sim
    bounds = {4: ("0.99", "0.02"), 8: ("0.90", "0.05"), 16: ("0.90", "0.05")}
    assert metrics["crowd"]["targets"] == {name: True for n, (recall, as_wall) in bounds.items() for name in (
        f"wall_recall_at_least_{recall}_at_{n}", f"wall_recall_beats_baseline_at_{n}",
        f"copter_as_wall_at_most_{as_wall}_at_{n}", f"copter_as_wall_beats_baseline_at_{n}")} | {
        f"{figure}_at_{n}_{stem}": True for figure in ("wall_recall_beats_baseline", "copter_as_wall_beats_baseline",
                                                       "copter_as_wall_at_most_0.05")
        for stem in ("swarmlab_l", "swarmlab_pillar") for n in (4, 8)}
    assert metrics["targets"] == {"wall_recall_beats_baseline": True, "copter_as_wall_beats_baseline": True,
                                  "cohesion_tighter_with_detector": True}
    assert "Targets the project keeps" in result.stdout and "all 15 targets met" in result.stdout
    assert "issue" not in result.stdout.lower()


def test_the_documents_state_the_figures_make_sim_prints(make_sim, repo):
    _, _, metrics = make_sim
    crowd = metrics["crowd"]
    # docs/host.md: the crowd table of make sim's default run, to the 3 decimals printed
    host_md = (repo / "docs" / "host.md").read_text()
    table = re.findall(r"^\| (\d+) \| [^|]+ \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \|$", host_md, re.M)
    assert [int(row[0]) for row in table] == [4, 8, 16, 4, 8, 4, 8]
    for run, row in zip(RUNS, table):
        assert [f"{crowd[run][key]:.3f}" for key in FIGURES] == list(row[1:]), run
    # docs/wall-detector.md: seed 1 of the 4-copter table, the swarm's figures included
    seed_1 = re.search(r"^\| 1 \| (.*) \|$", (repo / "docs" / "wall-detector.md").read_text(), re.M).group(1)
    assert seed_1 == (f"{metrics['detector_wall_recall']:.3f} ({metrics['baseline_wall_recall']:.3f}) | "
                      f"{metrics['detector_copter_as_wall']:.3f} ({metrics['baseline_copter_as_wall']:.3f}) | "
                      f"{metrics['near_wall_fraction_off']:.3f} / {metrics['near_wall_fraction_on']:.3f} | "
                      f"{metrics['cohesion_off']:.3f} / {metrics['cohesion_on']:.3f}")
    # README.md: the wall recall of the detector and of the single-reading check at 4, 8 and 16 copters, in percent
    readme = " ".join((repo / "README.md").read_text().split())
    detector = re.search(r"the detector labels ([\d.]+) %, ([\d.]+) % and ([\d.]+) % of wall echoes", readme).groups()
    baseline = re.search(r"the single-reading check ([\d.]+) %, ([\d.]+) % and ([\d.]+) %", readme).groups()
    for stated, key in ((detector, "detector_wall_recall"), (baseline, "baseline_wall_recall")):
        decimals = [len(text.partition(".")[2]) for text in stated]
        assert list(stated) == [f"{100 * crowd[run][key]:.{d}f}" for run, d in zip(RUNS, decimals)], key
