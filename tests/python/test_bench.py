"""The `make bench` tooling (tools/bench.py, tools/finken/bench_*.py): scaled arenas that the C loader accepts
with the stated size and plates, the crowding reference against a Monte-Carlo count, reading the figures of
the C benchmark programs, and bench.json with the issue's names, units and targets.

Timing itself is never asserted here (speed belongs to `make bench`)."""
import json
import math

import numpy as np
import pytest

from finken.bench import report as bench_report
from finken.bench.arena import arena_size_m, scale_factor, scaled_arena, write_scaled_arena
from finken.bench.host import (LARGE_SWARM, MAX_DURATION_S, SWARM_MAX_DURATION_S, max_duration_s, timed_runs,
                               uniform_peers)
from finken.bench.programs import BenchProgramError, run_program


def test_scale_factor_keeps_the_floor_area_per_copter():
    assert scale_factor(4) == 1.0
    assert scale_factor(100) == 5.0
    assert scale_factor(1000) == pytest.approx(math.sqrt(250.0), rel=1e-15)
    with pytest.raises(ValueError, match="copters"):
        scale_factor(0)


def test_scaled_arena_polygon_walls_and_plates(repo, tmp_path):
    path = write_scaled_arena(repo / "conf" / "arena" / "swarmlab.xml", tmp_path, 100, 1000)
    assert path == tmp_path / "arena_100_1000.xml"
    assert arena_size_m(path) == pytest.approx((15.0, 20.0), rel=1e-12)     # 3 m x 4 m, x5
    root = scaled_arena(repo / "conf" / "arena" / "swarmlab.xml", 100, 1000).getroot()
    assert root.find("walls").get("numSegments") == "1000"
    assert sorted(float(w.get("wallWidth")) for w in root.iter("wall")) == pytest.approx([15.0, 15.0, 20.0, 20.0])
    # heights, thresholds, bodies and sonars keep their values
    assert root.get("flightHeight") == "0.6" and root.find("walls").get("threshold") == "1"
    assert root.find("copters").get("radius") == "0.2"
    with pytest.raises(ValueError, match="segments_per_wall"):
        scaled_arena(repo / "conf" / "arena" / "swarmlab.xml", 4, 0)


def test_the_c_loader_accepts_the_scaled_arena(repo, tmp_path, arena_native):
    """The generated file passes nps_arena_load (its wallWidth checks against the polygon included)."""
    ffi, lib = arena_native
    err = ffi.new("char[]", 512)
    for copters, plates in ((16, 20), (1000, 1000)):
        path = write_scaled_arena(repo / "conf" / "arena" / "swarmlab.xml", tmp_path, copters, plates)
        arena = lib.nps_arena_load(str(path).encode(), err, 512)
        assert arena != ffi.NULL, ffi.string(err).decode()
        lib.nps_arena_free(arena)


def test_uniform_peers_matches_a_monte_carlo_count():
    """Mean number of other copters within 5 m for uniform copters in the 1000-copter arena.

    10^6 random pairs (seed 3): the fraction within 5 m has standard error sqrt(p (1 - p) / n) ~ 1.5e-4
    (p ~ 0.024); 5 sigma, false-failure probability 6e-7. Dropping the border term (pi r^2 / area) would move
    the expected fraction by 2.0e-3, 13 standard errors: the test fails for that mistake."""
    width_m, depth_m, copters, n = math.sqrt(250.0) * 3.0, math.sqrt(250.0) * 4.0, 1000, 1_000_000
    rng = np.random.default_rng(3)
    a = rng.uniform(0.0, 1.0, (n, 2)) * [width_m, depth_m]
    b = rng.uniform(0.0, 1.0, (n, 2)) * [width_m, depth_m]
    p = np.mean(np.hypot(*(a - b).T) < 5.0)
    sigma = math.sqrt(p * (1.0 - p) / n)
    assert uniform_peers(width_m, depth_m, copters) / (copters - 1) == pytest.approx(p, abs=5.0 * sigma)
    assert uniform_peers(3.0, 4.0, 4) == 3.0                       # the diagonal is 5 m: everyone is in range
    assert math.isnan(uniform_peers(3.0, 8.0, 4))                  # between: not computed


def test_large_swarms_are_timed_before_they_contract():
    assert max_duration_s(4) == max_duration_s(LARGE_SWARM - 1) == MAX_DURATION_S
    assert max_duration_s(LARGE_SWARM) == max_duration_s(4096) == SWARM_MAX_DURATION_S < MAX_DURATION_S


def test_reading_the_figures_of_a_program(tmp_path):
    good = tmp_path / "good.sh"
    figure = '{"name": "x_per_s", "value": 2.5e6, "unit": "1/s", "reps": 3}'
    good.write_text(f"#!/bin/sh\necho note >&2\necho '{figure}'\n")
    bad = tmp_path / "bad.sh"
    bad.write_text("#!/bin/sh\necho not json\n")
    failing = tmp_path / "failing.sh"
    failing.write_text("#!/bin/sh\necho broken >&2\nexit 3\n")
    for script in (good, bad, failing):
        script.chmod(0o755)
    assert run_program(good, [], echo_stderr=False) == [{"name": "x_per_s", "value": 2.5e6, "unit": "1/s", "reps": 3}]
    with pytest.raises(BenchProgramError, match="bad.sh: stdout line 1: not JSON"):
        run_program(bad, [])
    with pytest.raises(BenchProgramError, match="exit status 3: broken"):
        run_program(failing, [])


def test_each_batch_run_is_paired_with_the_clock_around_it(tmp_path):
    """The clock figure of timed_runs, through stand-ins: a launcher whose runs take 0.5, 0.25, 0.2 and 0.4 s of
    wall time (a pilot, then three timed runs) and a clock program that reads 4, 2, 3, 1, 1, 3 GHz in turn (before
    and after each timed run). Each run's clock is the mean of its two readings (3, 2, 2 GHz); the figure is their
    median with their spread."""
    walls = tmp_path / "walls"
    walls.write_text("0.5 0.25 0.2 0.4")
    spawn = tmp_path / "spawn.sh"   # bench_spawn RESULT_FILE COMMAND...: the next wall time, the command unrun
    spawn.write_text(f'#!/bin/sh\nset -- "$1" $(cat {walls})\nprintf \'{{"wall_s": %s, "peak_rss_kb": 2048, '
                     f'"exit_status": 0}}\' "$2" > "$1"\nshift 2\necho "$@" > {walls}\n')
    readings = tmp_path / "readings"
    readings.write_text("4 2 3 1 1 3")
    clock = tmp_path / "clock.sh"
    clock.write_text(f'#!/bin/sh\nset -- $(cat {readings})\nprintf \'{{"name": "clock_ghz", "value": %s, '
                     f'"unit": "GHz", "reps": 1}}\\n\' "$1"\nshift\necho "$@" > {readings}\n')
    for script in (spawn, clock):
        script.chmod(0o755)
    results = {r["name"]: r for r in timed_runs(spawn, tmp_path / "host", 4, tmp_path / "arena.xml", "4", reps=3,
                                               run_s=1.0, logs=False, clock=clock)}
    assert results["sim_seconds_4"]["value"] == 0.2   # the pilot's 0.1 s simulated took 0.5 s; 1 s wanted
    assert results["sim_rtf_4"]["value"] == pytest.approx(0.8)             # 0.2 s over 0.25, 0.2 and 0.4 s
    assert results["clock_ghz_4"]["value"] == pytest.approx(2.0)
    assert (results["clock_ghz_4"]["min"], results["clock_ghz_4"]["max"]) == pytest.approx((2.0, 3.0))
    assert results["clock_ghz_4"]["unit"] == "GHz" and results["clock_ghz_4"]["reps"] == 3
    assert readings.read_text().split() == []                               # two readings per timed run, no more
    walls.write_text("0.5 0.5")
    plain = timed_runs(spawn, tmp_path / "host", 4, tmp_path / "arena.xml", "4", reps=1, run_s=1.0, logs=False)
    assert not any(r["name"].startswith("clock") for r in plain)            # no clock program: no clock figure
    clock.write_text('#!/bin/sh\necho \'{"name": "gmm_draws_per_s", "value": 1, "unit": "1/s"}\'\n')
    walls.write_text("0.5 0.5")
    with pytest.raises(BenchProgramError, match="clock.sh: expected the one figure clock_ghz"):
        timed_runs(spawn, tmp_path / "host", 4, tmp_path / "arena.xml", "4", reps=1, run_s=1.0, logs=False, clock=clock)


def test_bench_json_names_units_targets_and_ratios(tmp_path):
    figures = {f["name"]: f for f in [
        {"name": "gmm_draws_per_s", "value": 2e7, "unit": "1/s", "reps": 5},
        {"name": "gmr_draws_per_s", "value": 100.0, "unit": "1/s", "reps": 3},
        {"name": "copter_step_us_16", "value": 2.0, "unit": "us", "reps": 3},
        {"name": "copter_step_us_1000", "value": 5.0, "unit": "us", "reps": 3},
        {"name": "sim_rtf_4", "value": 500.0, "unit": "x", "reps": 3},
        {"name": "copter_step_us_logged_1000", "value": 7.5, "unit": "us", "reps": 3},
        {"name": "peak_rss_mb_1000", "value": float("nan"), "unit": "MB", "reps": 3},
    ]}
    bench_report.derive(figures)
    assert figures["gmm_vs_gmr_ratio"]["value"] == 2e5
    assert figures["cost_growth_16_1000"]["value"] == 2.5
    assert figures["host_log_cost_factor_1000"]["value"] == 1.5
    assert "host_log_cost_factor_4" not in figures                  # its figures were not measured
    path = tmp_path / "bench.json"
    bench_report.write_json(figures, path)
    results = {r["name"]: r for r in json.loads(path.read_text())["results"]}
    assert all(set(r) == {"name", "value", "unit", "target"} for r in results.values())
    assert results["gmm_draws_per_s"]["target"] == ">= 1e+07"
    assert results["gmr_draws_per_s"]["target"] is None
    assert results["peak_rss_mb_1000"]["value"] is None             # not finite: null, never NaN in JSON
    assert bench_report.target_met("gmm_vs_gmr_ratio", 2e5) is True
    assert bench_report.target_met("cost_growth_16_1000", 2.5) is False
    assert bench_report.target_met("sim_rtf_4", 500.0) is False
    assert bench_report.target_met("gmr_draws_per_s", 1.0) is None
    table = bench_report.table(figures, {"nproc": 2, "cpu": "test cpu", "python": "3"})
    assert "NOT MET" in table and "test cpu" in table


def test_the_sweep_stage_speedup_and_overhead_against_their_targets():
    figures = {f["name"]: f for f in [{"name": "sweep_runs_per_min_1", "value": 100.0, "unit": "1/min", "reps": 3},
                                      {"name": "sweep_runs_per_min_2", "value": 190.0, "unit": "1/min", "reps": 3},
                                      {"name": "sweep_overhead_pct", "value": 0.8, "unit": "%", "reps": 3}]}
    bench_report.derive(figures)
    assert figures["sweep_speedup_2_1"]["value"] == pytest.approx(1.9)
    assert bench_report.target_text("sweep_speedup_2_1") == ">= 1.8"
    assert bench_report.target_met("sweep_speedup_2_1", 1.9) is True
    assert bench_report.target_met("sweep_speedup_2_1", 1.5) is False
    assert bench_report.target_met("sweep_overhead_pct", 0.8) is True
    assert bench_report.target_met("sweep_overhead_pct", 5.0) is False


def test_crowded_runs_are_named():
    figures = {f"peers_5m_{when}_{label}": {"name": f"peers_5m_{when}_{label}", "value": v, "unit": "copters"}
               for label, values in (("1000", (999.0, 990.0, 24.1)), ("16", (15.0, 13.0, 11.4)))
               for when, v in zip(("start", "end", "uniform"), values)}
    notes = bench_report.crowding_notes(figures)
    assert len(notes) == 1 and notes[0].startswith("host 1000: median 999 other copters within 5 m")
