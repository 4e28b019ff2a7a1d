"""finken.sim_report.swarm_figures on small hand-made runs: each figure counts what it names, and a run lacking a shared
arena's signs is told so."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
from finken.sim_report.swarm_figures import compare_detectors, problems, swarm_figures  # noqa: E402

READINGS_HEADER = "t,vehicle,sensor,peer,true_range,measured,ctx_facing_sonars,ctx_target_copter\n"
WALLS_HEADER = "t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven\n"
DETECTIONS_HEADER = ("t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,detector_class,confidence,"
                     "baseline_class\n")


def write_run(run, ranging_pairs=((1, 2), (2, 1)), crosstalk=True, copter_x=2.8, labels=("wall", "copter")):
    """Two aircraft; aircraft 2 at (copter_x, 2) beside the east wall's plate at x = 3; one wall echo and one copter
    echo judged as `labels`."""
    run.mkdir(parents=True, exist_ok=True)
    rows = [f"{0.1 * k:.1f},{a},ranging,{b},1.0,1.0,,\n" for k, (a, b) in enumerate(ranging_pairs)]
    rows.append(f"1.0,1,sonar_front,,1.0,0.5,{1 if crosstalk else 0},1\n")
    rows.append("1.1,1,sonar_back,,1.5,1.5,0,0\n")
    (run / "readings.csv").write_text(READINGS_HEADER + "".join(rows))
    (run / "poses.csv").write_text(f"t,vehicle,x,y,z,yaw\n1.0,1,1.5,2.0,0.6,0\n1.0,2,{copter_x},2.0,0.6,3.14\n")
    (run / "walls.csv").write_text(WALLS_HEADER + "1.0,1,3,3.0,1.8,3.0,2.2,-1,0,12.0,0.1,0.1,12.0,1\n"
                                   "1.0,1,9,3.0,3.8,3.0,4.0,-1,0,0.0,0.0,0.0,0.0,0\n")
    (run / "detections.csv").write_text(
        DETECTIONS_HEADER + f"2.0,1,sonar_back,,1.5,1.5,0,{labels[0]},0.9,wall\n"
        f"2.0,1,sonar_front,,1.0,1.0,1,{labels[1]},0.9,wall\n")
    return run


def test_a_shared_arena_shows_every_sign(tmp_path):
    figures = swarm_figures(write_run(tmp_path / "run"))
    assert figures.aircraft == [1, 2]
    assert figures.pairs_not_ranged == []
    assert (figures.copter_echoes, figures.crosstalk_readings) == (1, 1)
    assert (figures.bulges, figures.bulges_toward_a_copter) == (1, 1)
    assert figures.detector["wall_recall"] == 1.0 and figures.detector["copter_as_wall"] == 0.0
    assert problems(figures) == []


def test_what_is_missing_is_named(tmp_path):
    figures = swarm_figures(write_run(tmp_path / "run", ranging_pairs=((1, 2),), crosstalk=False, copter_x=1.0))
    assert figures.pairs_not_ranged == [(2, 1)]
    found = " / ".join(problems(figures))
    assert "pairs never ranged: [(2, 1)]" in found
    assert "cross-talk" in found
    assert "no plate bulged" in found   # the bulge has no copter within 1 m


def test_detector_scores_are_compared_within_the_tolerance(tmp_path):
    good = swarm_figures(write_run(tmp_path / "good"))
    fooled = swarm_figures(write_run(tmp_path / "fooled", labels=("wall", "wall")))
    assert compare_detectors(good, good) == {}
    assert compare_detectors(fooled, good) == {"copter_as_wall": (1.0, 0.0)}


def test_detections_before_from_s_are_left_out(tmp_path):
    figures = swarm_figures(write_run(tmp_path / "run", labels=("wall", "wall")), from_s=3.0)
    assert figures.detector["walls"] == 0 and figures.detector["copters"] == 0
