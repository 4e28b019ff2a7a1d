"""`make bench`'s paparazzi stage without a Paparazzi tree: finken_world's stop line, the holds-real-time criterion,
the search for the largest swarm, the figures and the side-by-side table, the airframe without our world, and the
stage's line when PAPARAZZI_HOME is not set. No timing is asserted."""
import json
import os
import re
from pathlib import Path

import pytest
from lxml import etree

from finken.bench import report as bench_report
from finken.bench.paparazzi_figures import (NPS_LAG_WARNING, START_S, WALL_TOLERANCE, Exchange, Flight, exchange_figure,
                                            exchange_of, lag_warnings, largest_held, next_size, parse_stop_line,
                                            search_figures, side_by_side, why_not_real_time)
from finken.paparazzi.swarm_conf import WORLD_MODULES, bare_airframe
from finken.xml_errors import XmlInputError
from run_tool import run_tool

REPO = Path(__file__).resolve().parents[2]
EXAMPLE_AIRFRAME = REPO / "conf/airframes/finken/finken_quad.xml"
# the line of the issue, and one as finken_world prints a long wait (%.3g: exponent notation)
ISSUE_LINE = ("finken_world: aircraft 1: 30708 steps, 92103 peer poses (0 moved on from an older sample, age mean 0 s, "
              "max 0 s), exchange 380 us per step (of which waiting for others 364 us)")
LONG_WAIT_LINE = ("finken_world: aircraft 12: 10239 steps, 112618 peer poses (3 moved on from an older sample, age "
                  "mean 2.5e-08 s, max 0.00039 s), exchange 1.81e+03 us per step (of which waiting for others 1.79e+03 "
                  "us)")


# ---------------------------------------------------------------- finken_world's stop line

def test_the_stop_line_gives_the_exchange_less_its_waiting():
    e = parse_stop_line(ISSUE_LINE)
    assert e == Exchange(ac_id=1, steps=30708, peer_poses=92103, exchange_us=380.0, waiting_us=364.0)
    assert e.own_us == 16.0
    long_wait = parse_stop_line(LONG_WAIT_LINE)
    assert (long_wait.ac_id, long_wait.exchange_us, long_wait.waiting_us) == (12, 1810.0, 1790.0)


def test_the_pattern_reads_the_line_finken_world_prints():
    """The printf format of finken_world.c, filled in as C would: a change of the line breaks this test."""
    source = (REPO / "sw/airborne/modules/finken_world/finken_world.c").read_text()
    call = re.search(r"static void print_exchange_figures.*?printf\((.*?),\s*\(int\)", source, re.S)[1]
    c_format = "".join(re.findall(r'"((?:[^"\\]|\\.)*)"', call)).replace("\\n", "").replace("%lu", "%d")
    line = c_format % (7, 5119, 15354, 1, 6.2e-08, 0.00095, 74.8, 56.2)
    assert parse_stop_line("  " + line) == Exchange(7, 5119, 15354, 74.8, 56.2)


@pytest.mark.parametrize("line", ["finken_world: aircraft 1 in world \"bench\" (world time = simulated time + 0 s)",
                                  "finken_world: 20.0 s simulated (FINKEN_WORLD_DURATION), stopping", "", "exchange"])
def test_other_lines_are_no_stop_line(line):
    assert parse_stop_line(line) is None


def test_a_process_output_gives_its_last_stop_line_or_none():
    assert exchange_of(f"Simulating with dt of 0.001953\n{LONG_WAIT_LINE}\n{ISSUE_LINE}\n").ac_id == 1
    assert exchange_of("Simulating with dt of 0.001953\nkilled\n") is None


def test_npss_lag_warnings_are_counted():
    warning = f"Warning: {NPS_LAG_WARNING} for efficient operation! Please reduce the time factor.\n"
    assert lag_warnings("Time factor is 1.000000. (Press Ctrl-Z to change)\n" + warning * 3) == 3
    assert lag_warnings("Time factor is 1.000000.\n") == 0


@pytest.mark.skipif(not os.environ.get("PAPARAZZI_HOME"), reason="PAPARAZZI_HOME is not set (NPS's source)")
def test_the_warning_is_the_one_nps_prints():
    source = Path(os.environ["PAPARAZZI_HOME"], "sw/simulator/nps/nps_main_sitl.c").read_text()
    assert f'printf("Warning: {NPS_LAG_WARNING}' in source


# ---------------------------------------------------------------- holding real time

def _flight(world=True, aircraft=4, duration_s=20.0, wall_s=20.3, cpu_s=1.6, **kw):
    return Flight(world, aircraft, duration_s, wall_s, cpu_s, **kw)


def test_a_run_that_kept_up_holds_real_time():
    assert why_not_real_time(_flight()) is None
    assert why_not_real_time(_flight(world=False, wall_s=20.1)) is None


def test_a_process_that_did_not_run_to_the_end_fails_the_run():
    why = why_not_real_time(_flight(unexpected=["FINKEN_3: killed by SIGSEGV"]))
    assert why == "1 of 4 processes did not run to the end (FINKEN_3: killed by SIGSEGV)"


def test_npss_warning_fails_the_run_with_or_without_our_world():
    for world in (True, False):
        assert why_not_real_time(_flight(world=world, lag_warnings=3)) == \
            "NPS warned 3 times that its simulated time fell behind"


def test_our_world_may_take_5_percent_and_half_a_second_more_wall_time_than_it_simulated():
    assert (WALL_TOLERANCE, START_S) == (1.05, 0.5)
    assert why_not_real_time(_flight(wall_s=21.5)) is None
    assert why_not_real_time(_flight(wall_s=21.6)) == \
        "21.6 s of wall time for 20 s simulated (more than 1.05 x + 0.5 s)"
    assert why_not_real_time(_flight(duration_s=5.0, wall_s=5.3)) is None          # a short run: mostly start-up
    assert why_not_real_time(_flight(world=False, wall_s=30.0)) is None   # alone: stopped by us, its wall is ours


def test_cpu_per_simulated_second_per_aircraft():
    assert _flight(aircraft=4, duration_s=20.0, wall_s=20.5, cpu_s=1.6).cpu_per_simulated_s == pytest.approx(0.02)
    # NPS alone runs until stopped: its simulated time is the run's wall time
    assert _flight(world=False, aircraft=4, wall_s=25.0, cpu_s=1.0).cpu_per_simulated_s == pytest.approx(0.01)


# ---------------------------------------------------------------- the search for the largest swarm

def _search(limit, cap):
    """The sizes next_size picks when every size up to `limit` holds, and what largest_held makes of them."""
    held = {}
    while (size := next_size(held, cap)) is not None:
        assert size not in held
        held[size] = size <= limit
    flights = [_flight(aircraft=n, lag_warnings=0 if ok else 1) for n, ok in held.items()]
    return list(held), largest_held(flights)


@pytest.mark.parametrize("limit, cap, sizes, largest", [
    (26, 64, [2, 4, 8, 16, 32, 24, 28, 26], 26),
    (64, 64, [2, 4, 8, 16, 32, 64], 64),
    (100, 10, [2, 4, 8, 10], 10),
    (4, 4, [2, 4], 4),
    (0, 64, [2], 0),
    (6, 64, [2, 4, 8, 6], 6),
    (30, 64, [2, 4, 8, 16, 32, 24, 28, 30], 30),
    (17, 64, [2, 4, 8, 16, 32, 24, 20, 18], 16),    # even sizes only
])
def test_doubling_then_halving_the_gap_finds_the_largest_even_size(limit, cap, sizes, largest):
    assert _search(limit, cap) == (sizes, largest)


def test_a_size_that_failed_below_one_that_held_ends_the_count_there():
    flights = [_flight(aircraft=2), _flight(aircraft=4, lag_warnings=1), _flight(aircraft=8)]
    assert largest_held(flights) == 2
    assert largest_held([]) == 0


# ---------------------------------------------------------------- figures and the table

def test_the_exchange_figure_is_the_median_over_the_aircraft_with_their_spread():
    exchanges = [Exchange(i, 100, 300, exchange, wait) for i, (exchange, wait) in
                 enumerate([(182, 162), (190, 173), (98, 89.3), (189, 181)], 1)]
    f = exchange_figure(exchanges, 4)
    assert (f["name"], f["unit"], f["reps"]) == ("pprz_exchange_us_4", "us", 4)
    assert f["value"] == pytest.approx((17 + 8.7) / 2) and f["min"] == 8.0 and f["max"] == 20.0


def test_without_a_stop_line_the_exchange_figure_is_null_in_bench_json(tmp_path):
    f = exchange_figure([], 4)
    assert f["value"] is None and f["reps"] == 0
    bench_report.write_json({f["name"]: f}, tmp_path / "bench.json")
    assert json.loads((tmp_path / "bench.json").read_text())["results"][0]["value"] is None
    assert "pprz_exchange_us_4" in bench_report.table({f["name"]: f}, {"nproc": 2, "cpu": "c", "python": "3"})


def test_search_figures_names_units_and_the_cpu_ratios_at_4_16_and_32_aircraft():
    world = [_flight(aircraft=n, wall_s=20.2, cpu_s=0.016 * n * 20) for n in (2, 4, 8)] + \
        [_flight(aircraft=16, lag_warnings=5, cpu_s=0.02 * 16 * 20)]
    alone = [_flight(world=False, aircraft=n, wall_s=20.0, cpu_s=0.004 * n * 20) for n in (2, 4, 8, 16, 32)]
    figures = {f["name"]: f for f in search_figures(world, alone, cap=32)}
    assert {n: (f["value"], f["unit"]) for n, f in figures.items()} == {
        "pprz_realtime_aircraft_world": (8, "aircraft"), "pprz_realtime_aircraft_alone": (32, "aircraft"),
        "pprz_realtime_cap": (32, "aircraft"),
        "pprz_cpu_per_sim_s_world_4": (pytest.approx(0.016), "s/s"),
        "pprz_cpu_per_sim_s_world_16": (pytest.approx(0.02), "s/s"),
        "pprz_cpu_per_sim_s_alone_4": (pytest.approx(0.004), "s/s"),
        "pprz_cpu_per_sim_s_alone_16": (pytest.approx(0.004), "s/s"),
        "pprz_cpu_per_sim_s_alone_32": (pytest.approx(0.004), "s/s")}
    bench_report.derive(figures)
    assert figures["pprz_world_cpu_factor_4"]["value"] == pytest.approx(4.0)
    assert figures["pprz_world_cpu_factor_16"]["value"] == pytest.approx(5.0)
    assert figures["pprz_world_cpu_factor_4"]["unit"] == "x"
    assert "pprz_world_cpu_factor_32" not in figures   # our world was not flown at 32
    assert bench_report.target_met("pprz_world_cpu_factor_16", 5.0) is False


def test_the_side_by_side_table_has_a_row_per_size_and_says_why_a_run_failed():
    world = [_flight(aircraft=2, wall_s=20.3, cpu_s=0.8), _flight(aircraft=4, wall_s=22.0, cpu_s=1.76)]
    alone = [_flight(world=False, aircraft=n, wall_s=20.0, cpu_s=0.1 * n) for n in (2, 4, 8)]
    lines = side_by_side(world, alone, cap=8)
    assert "with finken_world" in lines[0] and "Paparazzi NPS alone" in lines[0]
    assert lines[1].split() == ["aircraft", "held", "wall", "[s]", "CPU", "[s/s]", "held", "CPU", "[s/s]", "world",
                                "/", "alone"]
    assert lines[2].split() == ["2", "yes", "20.3", "0.0200", "yes", "0.0050", "4.00", "x"]
    assert lines[3].split() == ["4", "NO", "22.0", "0.0220", "yes", "0.0050", "4.40", "x"]
    assert lines[4].split() == ["8", "yes", "0.0050"]                     # our world did not fly 8
    assert lines[5:] == ["  with finken_world, 4 aircraft: 22.0 s of wall time for 20 s simulated (more than 1.05 x "
                         "+ 0.5 s)",
                         "  alone: every size up to 8, the largest flown, held real time: the machine's limit is "
                         "higher"]


# ---------------------------------------------------------------- Paparazzi's NPS alone: the airframe

def _parse(text):
    return etree.fromstring(text.encode(), etree.XMLParser(remove_blank_text=True))


def test_the_airframe_alone_lacks_our_world_and_the_modules_that_need_it_and_nothing_else():
    alone = _parse(bare_airframe(EXAMPLE_AIRFRAME))
    assert alone.xpath("//module/@name") and not set(alone.xpath("//module/@name")) & set(WORLD_MODULES)
    original = _parse(EXAMPLE_AIRFRAME.read_text())
    for module in original.xpath(" | ".join(f"//module[@name='{m}']" for m in WORLD_MODULES)):
        before = module.getprevious()
        if before is not None and before.tag is etree.Comment:
            before.getparent().remove(before)
        module.getparent().remove(module)
    assert etree.tostring(alone, method="c14n") == etree.tostring(original, method="c14n")
    assert alone.xpath("//module[@name='fdm']/@type") == ["finken"]         # the same flight model


def test_the_airframe_alone_keeps_the_indentation():
    text = bare_airframe(EXAMPLE_AIRFRAME)
    assert '      <module name="telemetry" type="nps"/>\n    </target>' in text
    assert '    <module name="nav" type="basic_rotorcraft"/>\n\n  </firmware>' in text


def test_an_airframe_without_our_world_is_named(tmp_path):
    airframe = tmp_path / "a.xml"
    airframe.write_text('<airframe name="x"><firmware name="rotorcraft"><module name="nav"/></firmware></airframe>\n')
    with pytest.raises(XmlInputError, match=f"{airframe}.*no <module name=\"finken_world\">"):
        bare_airframe(airframe)


@pytest.mark.skipif(not os.environ.get("PAPARAZZI_HOME"), reason="PAPARAZZI_HOME is not set (airframe.dtd)")
def test_the_airframe_alone_matches_paparazzis_airframe_dtd():
    dtd = etree.DTD(str(Path(os.environ["PAPARAZZI_HOME"], "conf/airframes/airframe.dtd")))
    assert dtd.validate(_parse(bare_airframe(EXAMPLE_AIRFRAME))), dtd.error_log.filter_from_errors()


# ---------------------------------------------------------------- the stage in tools/bench.py

def _bench(tmp_path):
    return run_tool("bench.py", "--bin", tmp_path, "--host", tmp_path / "host", "--arena", tmp_path / "arena.xml",
                    "--mixture", tmp_path / "mixture.xml", "--work", tmp_path / "work", "--json",
                    tmp_path / "bench.json", "--only", "paparazzi")


def test_without_paparazzi_home_the_stage_is_one_line(tmp_path, monkeypatch):
    monkeypatch.delenv("PAPARAZZI_HOME", raising=False)
    result = _bench(tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[0] == "paparazzi: skipped (PAPARAZZI_HOME is not set)"
    assert "== paparazzi" not in result.stdout
    assert json.loads((tmp_path / "bench.json").read_text()) == {"results": []}


def test_a_paparazzi_home_that_is_no_tree_fails_the_stage_by_name(tmp_path, monkeypatch):
    monkeypatch.setenv("PAPARAZZI_HOME", str(tmp_path / "nothing"))
    result = _bench(tmp_path)
    assert result.returncode == 1
    assert re.search(r"^paparazzi: FAILED: .*nothing lacks Makefile.ac", result.stdout, re.M)
    assert result.stdout.rstrip().endswith("FAILED: paparazzi (see above)")
