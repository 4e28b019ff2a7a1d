"""make paparazzi-sim without a Paparazzi tree: the conf file and airframes it writes, the merge of the per-aircraft
logs, and the process management (through small Python scripts standing in for simsitl)."""
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from lxml import etree

from finken.paparazzi.aircraft_logs import KINDS, MergeError, merge_all, merge_kind, newest_time, write_atomically
from finken.paparazzi.fleet import Member, run_fleet
from finken.paparazzi.ground import ground_members, ground_programs
from finken.paparazzi.sim import VARIANTS, _progress_text, ivy_bus, main, max_aircraft, run_base_port, wall_limit_s
from finken.paparazzi.swarm_conf import swarm_airframe, swarm_conf, template_aircraft
from finken.paparazzi.tree import PaparazziFailed
from finken.xml_errors import XmlInputError

REPO = Path(__file__).resolve().parents[2]
EXAMPLE_CONF = REPO / "conf/userconf/finken/finken_conf.xml"
EXAMPLE_AIRFRAME = REPO / "conf/airframes/finken/finken_quad.xml"


# ---------------------------------------------------------------- conf file and airframes

def test_the_conf_file_has_n_aircraft_with_ids_1_to_n_as_the_example_aircraft():
    template = template_aircraft(EXAMPLE_CONF)
    root = etree.fromstring(swarm_conf(template, "airframes/finken/paparazzi_sim_off.xml", "FINKEN_OFF_", 6))
    aircraft = root.findall("aircraft")
    assert [a.get("name") for a in aircraft] == [f"FINKEN_OFF_{i}" for i in range(1, 7)]
    assert [a.get("ac_id") for a in aircraft] == [str(i) for i in range(1, 7)]
    for a in aircraft:
        assert a.get("airframe") == "airframes/finken/paparazzi_sim_off.xml"
        for name in ("radio", "telemetry", "flight_plan", "settings", "settings_modules"):
            assert a.get(name) == template[name]
    assert len({a.get("gui_color") for a in aircraft}) == 6


def test_a_swarm_of_no_aircraft_is_refused():
    with pytest.raises(ValueError, match="at least one aircraft"):
        swarm_conf(template_aircraft(EXAMPLE_CONF), "airframes/x.xml", "FINKEN_", 0)


def test_a_conf_without_aircraft_is_named(tmp_path):
    conf = tmp_path / "conf.xml"
    conf.write_text("<conf/>\n")
    with pytest.raises(XmlInputError, match=f"{conf}:1: no <aircraft>"):
        template_aircraft(conf)


def _without(root, xpath):
    for element in root.xpath(xpath):
        element.getparent().remove(element)
    return etree.tostring(root, method="c14n")


def _parse(text):
    return etree.fromstring(text.encode(), etree.XMLParser(remove_blank_text=True))


ADDED_SEED = "//section[@name='FINKEN_WORLD']/define[@name='SEED']"   # in the airframe's own FINKEN_WORLD section
ADDED_SWITCH = "//module[@name='swarm']/define[@name='SWARM_USE_WALL_DETECTOR']"


def test_the_detector_off_airframe_adds_the_switch_and_the_seed_and_nothing_else():
    variant = _parse(swarm_airframe(EXAMPLE_AIRFRAME, seed=7, use_wall_detector=False))
    switch = variant.xpath(ADDED_SWITCH)
    assert len(switch) == 1 and switch[0].get("value") == "FALSE"
    seed = variant.xpath(ADDED_SEED)
    assert len(seed) == 1 and seed[0].get("value") == "7" and seed[0].getparent().get("prefix") == "FINKEN_WORLD_"
    assert len(variant.xpath("//section[@prefix='FINKEN_WORLD_']")) == 1
    original = _parse(EXAMPLE_AIRFRAME.read_text())
    assert _without(variant, f"{ADDED_SEED} | {ADDED_SWITCH}") == etree.tostring(original, method="c14n")


def test_the_detector_on_airframe_only_sets_the_seed():
    variant = _parse(swarm_airframe(EXAMPLE_AIRFRAME, seed=1, use_wall_detector=True))
    assert variant.xpath(ADDED_SWITCH) == []
    original = _parse(EXAMPLE_AIRFRAME.read_text())
    assert _without(variant, ADDED_SEED) == etree.tostring(original, method="c14n")


def test_an_airframe_without_a_finken_world_section_gets_one_with_the_seed(tmp_path):
    original = _parse(EXAMPLE_AIRFRAME.read_text())
    for section in original.xpath("//section[@prefix='FINKEN_WORLD_']"):
        section.getparent().remove(section)
    airframe = tmp_path / "airframe.xml"
    airframe.write_bytes(etree.tostring(original))
    variant = _parse(swarm_airframe(airframe, seed=3, use_wall_detector=True))
    sections = variant.xpath("//section[@prefix='FINKEN_WORLD_']")
    assert len(sections) == 1 and [(d.get("name"), d.get("value")) for d in sections[0]] == [("SEED", "3")]


def test_an_arena_is_set_as_finken_worlds_define_and_not_twice(tmp_path):
    variant = _parse(swarm_airframe(EXAMPLE_AIRFRAME, seed=1, use_wall_detector=True,
                                    arena="conf/arena/swarmlab_pillar.xml"))
    arena = variant.xpath("//section[@prefix='FINKEN_WORLD_']/define[@name='ARENA']")
    assert [d.get("value") for d in arena] == ['"conf/arena/swarmlab_pillar.xml"']
    original = _parse(EXAMPLE_AIRFRAME.read_text())
    etree.SubElement(original.xpath("//section[@prefix='FINKEN_WORLD_']")[0], "define", name="ARENA", value='"a.xml"')
    airframe = tmp_path / "airframe.xml"
    airframe.write_bytes(etree.tostring(original))
    with pytest.raises(XmlInputError, match="sets FINKEN_WORLD_ARENA already"):
        swarm_airframe(airframe, seed=2, use_wall_detector=True, arena="conf/arena/swarmlab.xml")


def test_the_switch_has_the_name_the_swarm_module_reads():
    descriptor = etree.parse(str(REPO / "conf/modules/swarm.xml")).getroot()
    assert descriptor.xpath("//doc/define[@name='SWARM_USE_WALL_DETECTOR']")
    assert "#ifndef SWARM_USE_WALL_DETECTOR" in (REPO / "sw/airborne/modules/swarm/swarm.c").read_text()


@pytest.mark.parametrize("body, message", [
    ('<firmware name="rotorcraft"><module name="nav"/></firmware>', "no <module name=\"swarm\">"),
    ('<firmware name="rotorcraft"><module name="swarm"><define name="SWARM_USE_WALL_DETECTOR" value="TRUE"/>'
     '</module></firmware>', "sets SWARM_USE_WALL_DETECTOR already"),
])
def test_an_airframe_the_switch_cannot_go_into_is_named(tmp_path, body, message):
    airframe = tmp_path / "a.xml"
    airframe.write_text(f"<airframe name='x'>{body}</airframe>\n")
    with pytest.raises(XmlInputError, match=f"{airframe}.*{message}"):
        swarm_airframe(airframe, seed=1, use_wall_detector=False)


def test_an_airframe_with_its_own_seed_is_named(tmp_path):
    airframe = tmp_path / "a.xml"
    airframe.write_text('<airframe name="x"><section name="FINKEN_WORLD" prefix="FINKEN_WORLD_">'
                        '<define name="SEED" value="3"/></section></airframe>\n')
    with pytest.raises(XmlInputError, match="sets FINKEN_WORLD_SEED already"):
        swarm_airframe(airframe, seed=1, use_wall_detector=True)


@pytest.mark.skipif(not os.environ.get("PAPARAZZI_HOME"), reason="PAPARAZZI_HOME is not set (airframe.dtd)")
def test_both_airframes_match_paparazzis_airframe_dtd(tmp_path):
    dtd = etree.DTD(str(Path(os.environ["PAPARAZZI_HOME"], "conf/airframes/airframe.dtd")))
    for use in (True, False):
        assert dtd.validate(_parse(swarm_airframe(EXAMPLE_AIRFRAME, 1, use))), dtd.error_log.filter_from_errors()


def test_both_runs_fly_the_same_ids_under_different_names():
    on, off = VARIANTS
    assert [i for _, i in on.aircraft(5)] == [i for _, i in off.aircraft(5)] == [1, 2, 3, 4, 5]
    assert not {n for n, _ in on.aircraft(5)} & {n for n, _ in off.aircraft(5)}
    assert on.airframe() != off.airframe() and on.conf() != off.conf()


def test_the_progress_line_shows_the_clock_and_how_far_the_slowest_aircrafts_logs_have_got(tmp_path):
    aircraft = [("FINKEN_1", 1), ("FINKEN_2", 2), ("FINKEN_3", 3)]
    _raw(tmp_path, "poses", 1, "t,vehicle\n2.5,1\n3.2,1\n")
    _raw(tmp_path, "readings", 2, "t,vehicle\n1.5,2\n")
    _raw(tmp_path, "poses", 2, "t,vehicle\n2.0,2\n")
    text = _progress_text("run", aircraft, ["FINKEN_1", "FINKEN_2"], tmp_path, 20, 5, 1.2)
    assert text == ("  run:    6.0/20 s simulated (by the clock; logs of the slowest at 2.0 s), 2/3 aircraft flying, "
                    "1 s wall")
    text = _progress_text("run", aircraft, ["FINKEN_1", "FINKEN_3"], tmp_path, 20, 5, 9)
    assert text == "  run:   20.0/20 s simulated (by the clock), 2/3 aircraft flying, 9 s wall"


def test_the_wall_time_limit():
    assert wall_limit_s(180, 5) == pytest.approx(180 / 5 * 4 + 60)


# ---------------------------------------------------------------- the launcher's refusals and the ground segment

def test_without_paparazzi_home_it_says_so(monkeypatch, capsys, tmp_path):
    monkeypatch.delenv("PAPARAZZI_HOME", raising=False)
    assert main(["--out", str(tmp_path / "out")]) == 1
    assert "paparazzi-sim: FAILED: PAPARAZZI_HOME is not set" in capsys.readouterr().err


def test_gcs_without_a_display_or_xvfb_is_refused_before_anything_is_done(monkeypatch, capsys, tmp_path):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))   # no xvfb-run
    assert main(["--gcs", "--out", str(tmp_path / "out"), "--tree", str(tmp_path / "tree")]) == 1
    assert "GCS=1 needs a display or Xvfb: DISPLAY is not set and xvfb-run is missing" in capsys.readouterr().err
    assert not (tmp_path / "out").exists() and not (tmp_path / "tree").exists()


def test_a_taken_data_link_port_is_named_before_anything_starts(tmp_path, monkeypatch):
    _ground_tree(tmp_path)
    monkeypatch.setattr("finken.paparazzi.ground.udp_port_problem", lambda: "UDP port 4242 (...) is taken")
    with pytest.raises(PaparazziFailed, match=r"GCS=1: UDP port 4242 \(...\) is taken"):
        ground_programs(tmp_path, {"DISPLAY": ":0", "PATH": str(tmp_path)})


def test_missing_ground_programs_are_named(tmp_path):
    with pytest.raises(PaparazziFailed, match=r"tmtc/link, .*tmtc/server, .*cockpit/gcs \(and no pprzgcs on PATH\) "
                                              "not built"):
        ground_programs(tmp_path, {"DISPLAY": ":0", "PATH": str(tmp_path)})


def _ground_tree(tree):
    """A tree with the ground programs built and Paparazzi's tools (conf/tools/*.xml)."""
    from test_paparazzi_session import TOOLS
    for program in ("sw/ground_segment/tmtc/link", "sw/ground_segment/tmtc/server", "sw/ground_segment/cockpit/gcs"):
        (tree / program).parent.mkdir(parents=True, exist_ok=True)
        (tree / program).write_text("")
    (tree / "conf/tools").mkdir(parents=True)
    for name, text in TOOLS.items():
        (tree / "conf/tools" / name).write_text(text + "\n")
    run_conf = tree / "run_conf.xml"
    run_conf.write_text('<conf><aircraft name="FINKEN_1" flight_plan="flight_plans/finken/finken_arena.xml"/></conf>\n')
    return run_conf


def test_the_ground_segment_is_the_sessions_on_one_bus_reading_the_runs_conf(tmp_path, monkeypatch):
    monkeypatch.setattr("finken.paparazzi.ground.udp_port_problem", lambda: None)   # whatever runs on this machine
    run_conf = _ground_tree(tmp_path)
    members = ground_members(tmp_path, run_conf, "127.255.255.255:10000", tmp_path / "logs",
                             {"DISPLAY": ":0", "PATH": str(tmp_path)})
    assert [m.name for m in members] == ["data_link", "server", "pprzgcs", "arena_shapes"]
    assert all(m.helper for m in members)
    assert all(m.command[-2:] == ["-b", "127.255.255.255:10000"] for m in members[:3])
    assert members[0].command[1:3] == ["-udp", "-udp_broadcast"]
    # gcs_launch.py hands what follows -- to the GCS
    assert members[2].command == [str(tmp_path / "sw/tools/gcs_launch.py"), "--", "-b", "127.255.255.255:10000"]
    assert (tmp_path / "conf/conf.xml").read_text() == run_conf.read_text()
    # the arena's walls on the same bus, placed by the run's aircraft's flight plan
    walls = members[3].command
    assert walls[1:3] == ["-m", "finken.paparazzi.arena_shapes"]
    assert walls[walls.index("--bus") + 1] == "127.255.255.255:10000"
    assert walls[walls.index("--arena") + 1].endswith("conf/arena/swarmlab.xml")
    assert walls[walls.index("--flight-plan") + 1] == str(tmp_path / "conf/flight_plans/finken/finken_arena.xml")


def test_without_a_display_the_gcs_runs_under_xvfb(tmp_path, monkeypatch):
    monkeypatch.setattr("finken.paparazzi.ground.udp_port_problem", lambda: None)
    run_conf = _ground_tree(tmp_path)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    (bin_dir / "xvfb-run").write_text("#!/bin/sh\n")
    (bin_dir / "xvfb-run").chmod(0o755)
    members = ground_members(tmp_path, run_conf, "127.255.255.255:10000", tmp_path / "logs", {"PATH": str(bin_dir)})
    gcs = members[2].command
    assert gcs[0] == "xvfb-run" and gcs[gcs.index("-s") + 1].startswith("-screen 0") and "gcs_launch.py" in gcs[4]
    assert members[0].command[0] != "xvfb-run"


def test_vehicles_beyond_what_a_shared_world_holds_are_refused(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("PAPARAZZI_HOME", str(tmp_path))
    monkeypatch.setattr("finken.paparazzi.sim.tree_problem", lambda home: None)
    limit = max_aircraft()
    assert limit >= 4   # read from the simulator's header
    assert main(["--out", str(tmp_path / "out"), "--vehicles", str(limit + 1)]) == 1
    assert f"VEHICLES={limit + 1}, DURATION=180, TIME_FACTOR=1: VEHICLES must be 1..{limit}" in capsys.readouterr().err


def test_every_aircraft_has_a_bus_of_its_own_apart_from_the_ground_segments():
    base = run_base_port(os.getpid())
    buses = {ivy_bus(base, ac_id) for ac_id in range(0, 256)}
    assert len(buses) == 256 and max(int(b.split(":")[1]) for b in buses) < 65536
    assert run_base_port(1) != run_base_port(2)


# ---------------------------------------------------------------- merging the per-aircraft logs

HEADER = "t,vehicle,x\n"


def _raw(folder, kind, ac_id, text):
    folder.mkdir(parents=True, exist_ok=True)
    (folder / f"{kind}_{ac_id}.csv").write_text(text)


def test_rows_are_ordered_by_time_then_aircraft_each_aircraft_keeping_its_order(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "poses", 1, HEADER + "0.1,1,a\n0.3,1,b\n0.3,1,c\n")
    _raw(raw, "poses", 2, HEADER + "0.0,2,d\n0.3,2,e\n0.25,2,f\n")
    _raw(raw, "poses", 10, HEADER + "0.3,10,g\n")
    result = merge_kind("poses", raw, [10, 2, 1], tmp_path)
    assert result.complete and result.rows == 7 and not result.missing and not result.warnings
    assert (tmp_path / "poses.csv").read_text() == (HEADER + "0.0,2,d\n0.1,1,a\n0.25,2,f\n0.3,1,b\n0.3,1,c\n"
                                                    "0.3,2,e\n0.3,10,g\n")


def test_the_time_column_is_found_by_name(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "walls", 1, "wall,t\nA,2\nB,1\n")
    merge_kind("walls", raw, [1], tmp_path)
    assert (tmp_path / "walls.csv").read_text() == "wall,t\nB,1\nA,2\n"


def test_a_different_header_stops_that_merge_naming_the_file_and_keeps_the_earlier_file(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "readings", 1, HEADER + "0.1,1,a\n")
    _raw(raw, "readings", 2, "t,vehicle,y\n0.2,2,b\n")
    (tmp_path / "readings.csv").write_text("an earlier run's file\n")
    with pytest.raises(MergeError, match=r"readings_2\.csv:1: header 't,vehicle,y' differs"):
        merge_kind("readings", raw, [1, 2], tmp_path)
    assert (tmp_path / "readings.csv").read_text() == "an earlier run's file\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["raw", "readings.csv"]


def test_a_torn_last_row_is_left_out_with_a_warning_naming_file_and_line(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "readings", 1, HEADER + "0.1,1,a\n0.2,1,b\n0.3,1")
    _raw(raw, "readings", 2, HEADER + "0.15,2,c\n")
    result = merge_kind("readings", raw, [1, 2], tmp_path)
    assert result.rows == 3
    assert len(result.warnings) == 1
    assert f"{raw / 'readings_1.csv'}:4: torn last row" in result.warnings[0]
    assert (tmp_path / "readings.csv").read_text() == HEADER + "0.1,1,a\n0.15,2,c\n0.2,1,b\n"


def test_missing_and_empty_files_are_reported(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "detections", 2, HEADER + "0.5,2,a\n")
    _raw(raw, "detections", 3, "")
    result = merge_kind("detections", raw, [1, 2, 3], tmp_path)
    assert result.written and result.rows == 1 and not result.complete
    assert result.missing == [raw / "detections_1.csv"]
    assert result.empty == [raw / "detections_3.csv"]


def test_files_without_a_header_give_no_file(tmp_path):
    raw = tmp_path / "raw"
    _raw(raw, "readings", 1, "")
    _raw(raw, "readings", 2, "t,vehi")
    result = merge_kind("readings", raw, [1, 2], tmp_path)
    assert not result.written and result.empty == [raw / "readings_1.csv", raw / "readings_2.csv"]
    assert "readings_2.csv:1: torn last row" in result.warnings[0]
    assert not (tmp_path / "readings.csv").exists()


def test_a_kind_no_aircraft_wrote_is_not_written(tmp_path):
    (tmp_path / "raw").mkdir()
    result = merge_kind("poses", tmp_path / "raw", [1, 2], tmp_path)
    assert not result.written and len(result.missing) == 2
    assert not (tmp_path / "poses.csv").exists()


def test_header_only_files_give_a_header_only_file(tmp_path):
    raw = tmp_path / "raw"
    for ac_id in (1, 2):
        _raw(raw, "walls", ac_id, HEADER)
    assert merge_kind("walls", raw, [1, 2], tmp_path).rows == 0
    assert (tmp_path / "walls.csv").read_text() == HEADER


@pytest.mark.parametrize("row, message", [("x,1,a\n", "column t is 'x'"), ("nan,1,a\n", "column t is 'nan'"),
                                          ("0.1,1\n", "2 fields, the header has 3")])
def test_a_bad_row_is_named_with_its_line(tmp_path, row, message):
    raw = tmp_path / "raw"
    _raw(raw, "poses", 1, HEADER + "0.0,1,a\n" + row + "0.2,1,c\n")
    with pytest.raises(MergeError, match=f"poses_1.csv:3: {message}"):
        merge_kind("poses", raw, [1], tmp_path)


def test_merge_all_merges_the_other_kinds_when_one_fails(tmp_path):
    raw = tmp_path / "raw"
    for kind in KINDS:
        _raw(raw, kind, 1, HEADER + "0.1,1,a\n")
    _raw(raw, "walls", 2, "other\n")
    outcome = merge_all(raw, [1, 2], tmp_path)
    assert isinstance(outcome["walls"], MergeError)
    assert all(outcome[k].written for k in KINDS if k != "walls")


def test_an_error_while_writing_keeps_the_earlier_file_whole(tmp_path):
    target = tmp_path / "readings.csv"
    target.write_text("earlier\n")

    def rows():
        yield ["1", "2"]
        raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        write_atomically(target, ["a", "b"], rows())
    assert target.read_text() == "earlier\n"
    assert [p.name for p in tmp_path.iterdir()] == ["readings.csv"]


def test_newest_time_reads_the_last_complete_row(tmp_path):
    log = tmp_path / "readings_1.csv"
    assert newest_time(log) is None
    log.write_text(HEADER)
    assert newest_time(log) is None
    log.write_text(HEADER + "".join(f"{i * 0.01:.2f},1,a\n" for i in range(2000)) + "20.0,1")
    assert newest_time(log) == pytest.approx(19.99)


# ---------------------------------------------------------------- processes (dummies standing in for simsitl)

DUMMY = textwrap.dedent("""\
    # stands in for simsitl with finken_world: logs rows until FINKEN_WORLD_DURATION "simulated" seconds (10 per
    # wall second) or SIGTERM/SIGINT, then exits with status $DUMMY_EXIT_<ac_id> (0 by default)
    import os, signal, sys, time
    ac_id = sys.argv[1]
    stop = []
    signal.signal(signal.SIGTERM, lambda s, f: stop.append("SIGTERM"))
    signal.signal(signal.SIGINT, lambda s, f: stop.append("SIGINT"))
    print("pid", os.getpid(), *(f"{k}={os.environ[k]}" for k in ("FINKEN_WORLD", "FINKEN_WORLD_RUN",
          "FINKEN_WORLD_AIRCRAFT", "FINKEN_WORLD_OUT", "FINKEN_WORLD_DURATION")), flush=True)
    out, duration = os.environ["FINKEN_WORLD_OUT"], float(os.environ["FINKEN_WORLD_DURATION"])
    for kind in ("poses", "detections", "walls"):
        open(f"{out}/{kind}_{ac_id}.csv", "w").write("t,vehicle,x\\n")
    with open(f"{out}/readings_{ac_id}.csv", "w") as f:
        f.write("t,vehicle,x\\n")
        t = 0.0
        while not stop and t < duration:
            f.write(f"{t:.2f},{ac_id},r\\n")
            f.flush()
            t += 0.1
            time.sleep(0.01)
    print("stopped by", stop[0] if stop else "duration", flush=True)
    sys.exit(int(os.environ.get(f"DUMMY_EXIT_{ac_id}", "0")))
    """)

DRIVER = textwrap.dedent("""\
    # the launcher's flight of one swarm (finken.paparazzi.sim.fly_and_merge) with dummies for simsitl
    import os, sys
    from pathlib import Path
    from finken.paparazzi.sim import fly_and_merge
    dummy, out, vehicles, duration = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    aircraft = [(f"FINKEN_{i}", i, [sys.executable, dummy, str(i)]) for i in range(1, vehicles + 1)]
    result = fly_and_merge("dummy run", aircraft, dict(os.environ), out, out, out / "logs", duration, 10.0,
                           world="finken-test-on", run_id="run-1")
    print("interrupted:", result.fleet.interrupted, "complete:", ",".join(result.complete_kinds), flush=True)
    sys.exit(130 if result.fleet.interrupted else 0 if result.ok else 1)
    """)


@pytest.fixture
def dummy_launcher(tmp_path):
    (tmp_path / "dummy.py").write_text(DUMMY)
    (tmp_path / "driver.py").write_text(DRIVER)
    env = dict(os.environ, PYTHONPATH=str(REPO / "tools"), PYTHONUNBUFFERED="1")

    def start(vehicles, duration, **extra_env):
        return subprocess.Popen([sys.executable, tmp_path / "driver.py", tmp_path / "dummy.py", tmp_path / "out",
                                 str(vehicles), str(duration)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                text=True, env=dict(env, **extra_env))
    return start, tmp_path / "out"


def _wait_for_rows(raw, vehicles, rows=5, timeout_s=30):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        files = [raw / f"readings_{i}.csv" for i in range(1, vehicles + 1)]
        if all(f.is_file() and f.read_text().count("\n") > rows for f in files):
            return
        time.sleep(0.05)
    raise AssertionError(f"the dummies wrote no rows in {raw} within {timeout_s} s")


def _alive(pid):
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_to_the_launcher_stops_every_aircraft_and_what_they_wrote_is_merged(dummy_launcher, sig):
    start, out = dummy_launcher
    launcher = start(vehicles=3, duration=10000)
    _wait_for_rows(out / "raw", 3)
    launcher.send_signal(sig)
    output, _ = launcher.communicate(timeout=60)
    assert launcher.returncode == 130, output
    assert f"INTERRUPTED ({sig.name})" in output and f"interrupted: {sig.name}" in output
    logs = [(out / "logs" / f"FINKEN_{i}.log").read_text() for i in (1, 2, 3)]
    pids = [int(log.split()[1]) for log in logs]
    assert all("stopped by SIGTERM" in log for log in logs), logs    # exactly our SIGTERM, not the signal we got
    assert not any(_alive(pid) for pid in pids)
    merged = (out / "readings.csv").read_text().splitlines()
    assert merged[0] == "t,vehicle,x"
    times = [float(row.split(",")[0]) for row in merged[1:]]
    assert times == sorted(times) and {row.split(",")[1] for row in merged[1:]} == {"1", "2", "3"}
    assert sum(log.count("\n") - 1 for log in [(out / "raw" / f"readings_{i}.csv").read_text()
                                                for i in (1, 2, 3)]) == len(merged) - 1


def test_each_process_gets_the_shared_worlds_environment(dummy_launcher):
    start, out = dummy_launcher
    launcher = start(vehicles=2, duration=3)
    output, _ = launcher.communicate(timeout=60)
    assert launcher.returncode == 0, output
    for i in (1, 2):
        log = (out / "logs" / f"FINKEN_{i}.log").read_text()
        assert (f"FINKEN_WORLD=finken-test-on FINKEN_WORLD_RUN=run-1 FINKEN_WORLD_AIRCRAFT=2 "
                f"FINKEN_WORLD_OUT={out / 'raw'} FINKEN_WORLD_DURATION=3") in log
        assert "stopped by duration" in log
    assert "complete: readings,poses,detections,walls" in output
    assert (out / "readings.csv").read_text().count("\n") == 1 + 2 * 30


def test_an_aircraft_that_fails_is_named_with_its_log_and_the_others_fly_on(dummy_launcher):
    start, out = dummy_launcher
    launcher = start(vehicles=3, duration=3, DUMMY_EXIT_2="3")
    output, _ = launcher.communicate(timeout=60)
    assert launcher.returncode == 1, output
    assert "FINKEN_2 ended with exit 3; the last lines of its log:" in output
    assert "stopped by duration" in output   # its log's tail
    assert "2 of 3 aircraft ended with exit 0" in output
    assert (out / "readings.csv").read_text().count("\n") == 1 + 3 * 30


def _wait_for_line(log, line, proc, timeout_s=120):
    """Until a child's log has `line` (it says it is ready); a child that ends first, or has not said it within
    timeout_s, is killed and the test fails."""
    deadline = time.monotonic() + timeout_s
    while line not in log.read_text().splitlines():
        if proc.poll() is not None or time.monotonic() > deadline:
            proc.kill()
            proc.wait()
            pytest.fail(f"{log} has no line {line!r} (status {proc.returncode}): {log.read_text()!r}")
        time.sleep(0.05)


def test_the_wall_time_limit_stops_the_fleet_and_one_deaf_to_sigterm_is_killed(tmp_path, monkeypatch):
    import finken.paparazzi.fleet
    sleeper = [sys.executable, "-c", "import time; time.sleep(600)"]
    deaf = [sys.executable, "-c", "import signal, time; signal.signal(signal.SIGTERM, signal.SIG_IGN); "
                                  "print('deaf', flush=True); time.sleep(600)"]
    members = [Member("A", sleeper, tmp_path / "A.log"), Member("B", deaf, tmp_path / "B.log")]
    # the fleet goes on only once B says it ignores SIGTERM, however long a loaded machine takes to start Python: the
    # limit (whose clock runs meanwhile: it may pass at once then) always finds B deaf
    start = finken.paparazzi.fleet._start

    def start_and_wait_until_deaf(member):
        proc = start(member)
        if member.name == "B":
            _wait_for_line(member.log, "deaf", proc)
        return proc
    monkeypatch.setattr(finken.paparazzi.fleet, "_start", start_and_wait_until_deaf)
    outcome = run_fleet(members, wall_limit_s=1.0, grace_s=1.0, poll_s=0.05)
    assert outcome.timed_out and not outcome.interrupted
    a, b = outcome.ended
    assert a.how == "killed by SIGTERM" and a.stopped == "wall-time limit 1 s"
    assert b.how == "killed by SIGKILL" and b.stopped == "wall-time limit 1 s" and b.log_tail == ["deaf"]
    assert outcome.failures() == [a, b]


def test_helpers_are_stopped_when_the_aircraft_have_ended(tmp_path):
    members = [Member("FINKEN_1", [sys.executable, "-c", "pass"], tmp_path / "a.log"),
               Member("server", [sys.executable, "-c", "import time; time.sleep(600)"], tmp_path / "s.log",
                      helper=True)]
    outcome = run_fleet(members, wall_limit_s=60, poll_s=0.05)
    aircraft, server = outcome.ended
    assert aircraft.how == "exit 0" and server.stopped == "aircraft ended"
    assert outcome.failures() == []


def test_a_command_that_cannot_start_leaves_nothing_running(tmp_path, monkeypatch):
    import finken.paparazzi.fleet
    started = []

    class RecordedPopen(subprocess.Popen):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            started.append(self)

    monkeypatch.setattr(finken.paparazzi.fleet.subprocess, "Popen", RecordedPopen)
    members = [Member("FINKEN_1", [sys.executable, "-c", "import time; time.sleep(600)"], tmp_path / "a.log"),
               Member("FINKEN_2", [tmp_path / "no_such_simsitl"], tmp_path / "b.log")]
    with pytest.raises(FileNotFoundError):
        run_fleet(members, wall_limit_s=60)
    assert len(started) == 1 and started[0].returncode == -signal.SIGTERM
