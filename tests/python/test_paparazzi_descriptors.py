"""The finken_world descriptor compiles the whole simulator core in a Paparazzi build: its list of sw/simulator/nps
files is every core file, none missing, none that does not exist (the flight models have their own modules)."""
from lxml import etree

FLIGHT_MODELS = ("nps_fdm_", "nps_finken_lag.", "nps_finken_quadrotor.")


def test_finken_world_lists_every_simulator_core_file(repo):
    root = etree.parse(str(repo / "conf/modules/finken_world.xml")).getroot()
    listed = sorted(f.get("name") for f in root.iter("file") if f.get("dir") == "nps")
    core = sorted(p.name for p in (repo / "sw/simulator/nps").glob("*.c") if not p.name.startswith(FLIGHT_MODELS))
    assert listed == core
