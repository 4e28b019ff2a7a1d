"""make sim's "wall detector in a crowd" (finken.sim_report.crowd, tools/sim_crowd.py) with a stand-in host: which runs
are flown with which options, the figures from detections.csv, the targets at their bounds
(finken.sim_report.targets), metrics.json's other keys kept. tests/python/test_make_sim.py runs it end to end with
the real host."""
import json
import stat
import sys

import pytest
from run_tool import run_tool

from finken.sim_report.crowd import (add_to_metrics, fly_crowd, format_crowd_table, row_from_detections,
                                     row_from_metrics, split_host_args)
from finken.sim_report.targets import cohesion_target, detector_targets, format_targets

HEADER = "t,vehicle,sensor,peer,true_range,measured,ctx_target_copter,detector_class,confidence,baseline_class\n"

#: a stand-in for nps_host: records its options, writes a detections.csv of 10 wall echoes (9 labelled wall by the
#: detector, 2 by the baseline), 20 copter echoes (1 labelled wall by the detector, 4 by the baseline) and a reading
#: without echo; exits 3 when asked for 16 copters and FAIL16 is in its folder's name; with LOW in its folder's name
#: the detector labels every echo wall
FAKE_HOST = """#!{python}
import os, sys
args = sys.argv[1:]
out = args[args.index("--out") + 1]
with open({log!r}, "a") as f:
    f.write(" ".join(args) + "\\n")
if args[args.index("--vehicles") + 1] == "16" and "FAIL16" in out:
    print("arena refused", file=sys.stderr)
    sys.exit(3)
os.makedirs(out, exist_ok=True)
rows = [(0, "wall" if k < 9 else "copter", "wall" if k < 2 else "copter") for k in range(10)]
rows += [(1, "wall" if k < 1 else "copter", "wall" if k < 4 else "copter") for k in range(20)]
if "LOW" in out:
    rows = [(truth, "wall", baseline) for truth, _, baseline in rows]
with open(os.path.join(out, "detections.csv"), "w") as f:
    f.write({header!r})
    for k, (truth, detector, baseline) in enumerate(rows):
        f.write(f"{{0.05 * k:.2f}},1,sonar_front,,1.0,1.0,{{truth}},{{detector}},0.9,{{baseline}}\\n")
    f.write("2.00,1,sonar_front,,3.0,3.0,0,none,0.5,none\\n")
"""

MAIN = {"detector_wall_recall": 0.5, "near_wall_fraction_on": 0.25, "sensor_errors": {"ranging": {"rmse_m": 0.1}},
        "cohesion_on": 0.4, "cohesion_off": 0.6, "targets": {"cohesion_tighter_with_detector": True},
        "classification": {"on": {
            "detector": {"wall_recall": 0.99, "copter_as_wall": 0.01, "walls": 100, "copters": 50},
            "baseline": {"wall_recall": 0.5, "copter_as_wall": 0.125, "walls": 100, "copters": 50}}}}


@pytest.fixture
def fake(tmp_path):
    """(host path, out folder with the main run's metrics.json, log of the host's command lines)."""
    log = tmp_path / "host_calls.txt"
    host = tmp_path / "nps_host"
    host.write_text(FAKE_HOST.format(python=sys.executable, log=str(log), header=HEADER))
    host.chmod(host.stat().st_mode | stat.S_IXUSR)
    out = tmp_path / "sim"
    out.mkdir()
    (out / "metrics.json").write_text(json.dumps(MAIN, indent=2))
    return host, out, log


def test_split_host_args_takes_out_size_and_arena_and_keeps_the_rest():
    args = split_host_args(["--vehicles", "4", "--seed", "2", "--duration", "30", "--arena=a.xml",
                            "--ins-drift", "0.02,10", "--sensor-model", "m.xml"])
    assert (args.vehicles, args.arena) == (4, "a.xml")
    assert args.rest == ["--seed", "2", "--duration", "30", "--ins-drift", "0.02,10", "--sensor-model", "m.xml"]
    assert split_host_args(["--seed", "1"]).vehicles == 4 and split_host_args([]).arena is None
    with pytest.raises(ValueError, match="--arena without a value"):
        split_host_args(["--vehicles", "4", "--arena"])
    with pytest.raises(ValueError, match="--vehicles four"):
        split_host_args(["--vehicles", "four"])


def test_the_main_run_of_4_and_both_crowd_runs(fake, capsys):
    host, out, log = fake
    host_args = split_host_args(["--vehicles", "4", "--seed", "2", "--duration", "30", "--ins-drift", "0.02"])
    rows = fly_crowd(host, out, host_args, "conf/arena/swarmlab.xml")
    calls = log.read_text().splitlines()
    examples = [(n, f"conf/arena/{stem}.xml", f"crowd_{n}_{stem}") for stem in ("swarmlab_l", "swarmlab_pillar")
                for n in (4, 8)]
    assert calls == [f"--seed 2 --duration 30 --ins-drift 0.02 --vehicles 8 --arena conf/arena/swarmlab.xml --quiet "
                     f"--out {out / 'crowd_8'}",
                     f"--seed 2 --duration 30 --ins-drift 0.02 --vehicles 16 --arena conf/arena/swarmlab_16.xml "
                     f"--quiet --out {out / 'crowd_16'}"] + [
        f"--seed 2 --duration 30 --ins-drift 0.02 --vehicles {n} --arena {arena} --quiet --out {out / folder}"
        for n, arena, folder in examples]
    assert [(r["copters"], r["arena"], r["logs"]) for r in rows] == [
        (4, "conf/arena/swarmlab.xml", "."), (8, "conf/arena/swarmlab.xml", "crowd_8"),
        (16, "conf/arena/swarmlab_16.xml", "crowd_16")] + examples
    assert rows[0]["detector_wall_recall"] == 0.99 and rows[0]["baseline_copter_as_wall"] == 0.125
    crowd = rows[1]
    assert (crowd["detector_wall_recall"], crowd["baseline_wall_recall"]) == (0.9, 0.2)
    assert (crowd["detector_copter_as_wall"], crowd["baseline_copter_as_wall"]) == (0.05, 0.2)
    assert (crowd["wall_echoes"], crowd["copter_echoes"]) == (10, 20)        # the reading without echo left out
    assert crowd == row_from_detections(8, "conf/arena/swarmlab.xml", "crowd_8", out / "crowd_8" / "detections.csv")
    assert "8 copters in conf/arena/swarmlab.xml ->" in capsys.readouterr().out


def test_a_crowd_run_that_is_the_main_run_is_not_flown_again(fake, repo, capsys, monkeypatch):
    host, out, log = fake
    monkeypatch.chdir(repo)                      # the crowd's arenas are relative to the repository, as in make sim
    rows = fly_crowd(host, out, split_host_args(["--vehicles", "8"]), str(repo / "conf" / "arena" / "swarmlab.xml"))
    assert [line.split(" --arena")[0] for line in log.read_text().splitlines()] == ["--vehicles 16"] + [
        f"--vehicles {n}" for n in (4, 8, 4, 8)]
    assert [(r["copters"], r["logs"]) for r in rows][:2] == [(8, "."), (16, "crowd_16")]
    assert "8 copters in conf/arena/swarmlab.xml: the main run" in capsys.readouterr().out
    assert detector_targets(rows[0])[0].checks == {"wall_recall_at_least_0.90_at_8": True,
                                                   "wall_recall_beats_baseline_at_8": True}


def test_a_failed_crowd_run_is_an_error_with_the_hosts_words(fake):
    host, out, _ = fake
    out = out.rename(out.with_name("FAIL16"))
    with pytest.raises(RuntimeError, match="exit status 3: arena refused"):
        fly_crowd(host, out, split_host_args(["--vehicles", "4"]), "conf/arena/swarmlab.xml")


@pytest.mark.parametrize("copters, arena, recall_bound, as_wall_bound", [
    (4, "conf/arena/swarmlab.xml", 0.99, 0.02), (8, "conf/arena/swarmlab.xml", 0.90, 0.05),
    (16, "conf/arena/swarmlab_16.xml", 0.90, 0.05)])
def test_detector_targets_at_their_bounds(copters, arena, recall_bound, as_wall_bound):
    row = {"copters": copters, "arena": arena, "logs": ".", "detector_wall_recall": recall_bound,
           "detector_copter_as_wall": as_wall_bound, "baseline_wall_recall": 0.1, "baseline_copter_as_wall": 0.06}
    at_bounds = detector_targets(row)
    assert [t.met for t in at_bounds] == [True, True]
    assert at_bounds[0].goal == f">= {recall_bound:.2f}, above baseline"
    assert at_bounds[1].checks == {f"copter_as_wall_at_most_{as_wall_bound:.2f}_at_{copters}": True,
                                   f"copter_as_wall_beats_baseline_at_{copters}": True}
    beyond = detector_targets({**row, "detector_wall_recall": recall_bound - 1e-4,
                               "detector_copter_as_wall": as_wall_bound + 1e-4})
    assert [t.met for t in beyond] == [False, False]
    assert [t.checks[f"{key}_beats_baseline_at_{copters}"] for t, key in
            zip(beyond, ("wall_recall", "copter_as_wall"))] == [True, True]      # missed by the bound alone


def test_targets_of_another_arena_are_named_by_size_and_arena():
    row = {"copters": 4, "arena": "conf/arena/swarmlab_l.xml", "logs": "crowd_4_swarmlab_l", "detector_wall_recall": 0.8,
           "detector_copter_as_wall": 0.0, "baseline_wall_recall": 0.4, "baseline_copter_as_wall": 0.1}
    assert [t.checks for t in detector_targets(row)] == [{"wall_recall_beats_baseline_at_4_swarmlab_l": True},
                                                         {"copter_as_wall_at_most_0.05_at_4_swarmlab_l": True,
                                                          "copter_as_wall_beats_baseline_at_4_swarmlab_l": True}]


@pytest.mark.parametrize("arena", ["swarmlab_l", "swarmlab_pillar"])
@pytest.mark.parametrize("copters", [4, 8])
def test_the_example_arenas_keep_the_bound_on_copter_echoes_but_none_on_wall_recall(copters, arena):
    row = {"copters": copters, "arena": f"conf/arena/{arena}.xml", "logs": ".", "detector_wall_recall": 0.7,
           "detector_copter_as_wall": 0.05 + 1e-4, "baseline_wall_recall": 0.4, "baseline_copter_as_wall": 0.1}
    recall, as_wall = detector_targets(row)
    assert (recall.goal, recall.met) == ("above baseline", True)
    assert (as_wall.goal, as_wall.met) == ("<= 0.05, below baseline", False)
    assert detector_targets({**row, "detector_copter_as_wall": 0.05})[1].met


def test_a_run_without_bounds_keeps_beating_the_baseline():
    row = {"copters": 6, "arena": "conf/arena/swarmlab.xml", "logs": ".", "detector_wall_recall": 0.5,
           "detector_copter_as_wall": 0.3, "baseline_wall_recall": 0.6, "baseline_copter_as_wall": 0.2}
    recall, as_wall = detector_targets(row)
    assert (recall.goal, recall.met, as_wall.met) == ("above baseline", False, False)
    assert recall.checks == {"wall_recall_beats_baseline_at_6": False}


def test_the_targets_table_names_each_figure_its_comparison_and_the_missed_ones():
    rows = [{"copters": 4, "arena": "conf/arena/swarmlab.xml", "logs": ".", "detector_wall_recall": 0.997,
             "detector_copter_as_wall": 0.011, "baseline_wall_recall": 0.569, "baseline_copter_as_wall": 0.103},
            {"copters": 8, "arena": "conf/arena/swarmlab.xml", "logs": "crowd_8", "detector_wall_recall": 0.85,
             "detector_copter_as_wall": 0.0, "baseline_wall_recall": 0.118, "baseline_copter_as_wall": 0.08}]
    main = {"cohesion_on": 0.427, "cohesion_off": 0.616, "targets": {"cohesion_tighter_with_detector": True}}
    table = format_targets([t for row in rows for t in detector_targets(row)] + [cohesion_target(main, rows[0])])
    lines = table.splitlines()
    assert "  wall recall                  8 copters, swarmlab       0.850  baseline 0.118          " \
           ">= 0.90, above baseline  MISSED" in lines
    assert "  swarm cohesion [m]           4 copters, swarmlab       0.427  without detector 0.616  " \
           "below without detector   met" in lines
    assert lines[-1] == "1 of 5 targets missed: wall recall, 8 copters, swarmlab"
    assert "issue" not in table and max(map(len, lines)) <= 120
    assert format_targets(detector_targets(rows[0])).splitlines()[-1] == "all 2 targets met"


def test_the_targets_table_keeps_its_columns_for_a_long_arena_name():
    row = {"copters": 8, "arena": "conf/arena/swarmlab_pillar.xml", "logs": "crowd_8_swarmlab_pillar",
           "detector_wall_recall": 0.89, "detector_copter_as_wall": 0.0, "baseline_wall_recall": 0.18,
           "baseline_copter_as_wall": 0.04}
    short = {**row, "copters": 4, "arena": "conf/arena/swarmlab.xml"}
    lines = format_targets(detector_targets(short) + detector_targets(row)).splitlines()[1:-1]
    assert len({line.index(" baseline ") for line in lines[1:]}) == 1     # the values' column lines up


def test_the_crowd_table_has_a_row_per_run():
    row = {"copters": 8, "arena": "conf/arena/swarmlab.xml", "logs": "crowd_8", "detector_wall_recall": 0.9,
           "detector_copter_as_wall": 0.05, "baseline_wall_recall": 0.1, "baseline_copter_as_wall": 0.06}
    table = format_crowd_table([row])
    assert "      8  swarmlab.xml                     0.900     0.100       0.050     0.060" in table
    assert max(map(len, table.splitlines())) <= 120


def test_a_score_json_holds_as_null_is_nan_in_the_main_runs_row():
    metrics = {"classification": {"on": {who: {"wall_recall": 1.0, "copter_as_wall": None, "walls": 3, "copters": 0}
                                         for who in ("detector", "baseline")}}}
    row = row_from_metrics(1, "conf/arena/swarmlab.xml", metrics)
    assert row["detector_copter_as_wall"] != row["detector_copter_as_wall"]           # NaN
    assert [t.met for t in detector_targets(row)] == [False, False]


def test_metrics_json_gets_crowd_and_keeps_every_other_key(fake):
    host, out, _ = fake
    rows = fly_crowd(host, out, split_host_args(["--vehicles", "4"]), "conf/arena/swarmlab.xml")
    rows[2]["detector_copter_as_wall"] = float("nan")                      # no copter echo: null in JSON
    add_to_metrics(out / "metrics.json", rows, {"wall_recall_at_least_0.90_at_8": True})
    metrics = json.loads((out / "metrics.json").read_text())
    assert {k: v for k, v in metrics.items() if k != "crowd"} == MAIN
    assert list(metrics["crowd"]) == ["4_swarmlab", "8_swarmlab", "16_swarmlab_16", "4_swarmlab_l", "8_swarmlab_l",
                                      "4_swarmlab_pillar", "8_swarmlab_pillar", "targets"]
    assert metrics["crowd"]["16_swarmlab_16"]["detector_copter_as_wall"] is None
    assert metrics["crowd"]["targets"] == {"wall_recall_at_least_0.90_at_8": True}


@pytest.mark.parametrize("folder, status", [("sim", 0), ("sim_LOW", 3)])
def test_make_sims_last_step_exits_3_when_a_target_is_missed_and_names_it(fake, repo, monkeypatch, folder, status):
    host, out, _ = fake
    out = out.rename(out.with_name(folder))
    monkeypatch.chdir(repo)                      # the crowd's arenas are relative to the repository, as in make sim
    done = run_tool("sim_crowd.py", "--out", out, "--host", host, "--airframe", "conf/airframes/finken_nps.xml",
                    "--", "--vehicles", "4", "--seed", "1")
    assert done.returncode == status, done.stdout + done.stderr
    last = done.stdout.splitlines()[-2]          # the targets' verdict, then the line naming metrics.json
    if status == 0:
        assert last == "all 15 targets met"
    else:   # every echo labelled wall in the crowd runs: copter echoes labelled wall 1.0, above 0.05 and the baseline
        assert last == "6 of 15 targets missed: copter echoes labelled wall, 8 copters, swarmlab; " \
                       "copter echoes labelled wall, 16 copters, swarmlab_16; " + "; ".join(
                           f"copter echoes labelled wall, {n} copters, {stem}"
                           for stem in ("swarmlab_l", "swarmlab_pillar") for n in (4, 8))
    assert json.loads((out / "metrics.json").read_text())["crowd"]["targets"]["copter_as_wall_at_most_0.05_at_8"] \
        is (status == 0)
