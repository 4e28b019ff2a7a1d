"""Sweep files (finken.sweep.spec, sweep_values, sweep_points): the example sweeps, grids and random samples, and
every kind of bad input refused before any run with file, line and key."""
import textwrap

import pytest

from finken.models import SensorModel
from finken.sweep.points import grid_points
from finken.sweep.spec import DEFAULT_PLOTS, load_sweep
from finken.sweep.values import Param, Where, parse_values
from finken.sweep.yaml_lines import Mapping, SweepFileError

HEAD = "airframe: conf/airframes/finken_nps.xml\n"


@pytest.fixture(autouse=True)
def at_repository_root(repo, monkeypatch):
    """Paths in sweep files are relative to the working directory (make runs from the repository's root)."""
    monkeypatch.chdir(repo)


def sweep_file(tmp_path, text):
    path = tmp_path / "s.yaml"
    path.write_text(HEAD + textwrap.dedent(text))
    return path


def refused(tmp_path, text):
    with pytest.raises(SweepFileError) as err:
        load_sweep(sweep_file(tmp_path, text))
    return str(err.value)


def test_the_example_sweeps_load():
    sizes = load_sweep("conf/sweeps/detector_vs_swarm_size.yaml")
    assert sizes.swept == ("vehicles", "defines.WALL_DETECTOR_MAP")      # the wall map and the law before it
    assert [(p.values["vehicles"], p.values["defines.WALL_DETECTOR_MAP"]) for p in sizes.points] == \
        [(n, law) for n in (2, 4, 6, 8, 10, 12, 14, 16) for law in (True, False)]
    assert sizes.seeds == tuple(range(1, 11)) and len(sizes.runs) == 160
    assert sizes.points[0].values["arena"] == "conf/arena/swarmlab.xml"        # the airframe's
    noise = load_sweep("conf/sweeps/sonar_noise.yaml")
    assert noise.swept == ("model_parameters.sonar.rayleigh_short.sigma", "model_parameters.sonar.crosstalk.p")
    assert len(noise.points) == 10
    assert noise.log_scale == ("model_parameters.sonar.rayleigh_short.sigma",)


def test_a_grid_is_every_combination_and_defaults_are_make_sims(tmp_path):
    sweep = load_sweep(sweep_file(tmp_path, """
        vehicles: [2, 3]
        seeds: [5, 9]
        defines:
          WALL_DETECTOR_WALL_THRESHOLD: {from: 0.5, to: 1.5, step: 0.5}
        """))
    assert [(p.values["vehicles"], p.values["defines.WALL_DETECTOR_WALL_THRESHOLD"]) for p in sweep.points] == \
        [(2, 0.5), (2, 1.0), (2, 1.5), (3, 0.5), (3, 1.0), (3, 1.5)]
    assert sweep.points[0].values["duration"] == 180.0 and sweep.seeds == (5, 9) and len(sweep.runs) == 12
    assert sweep.plots == DEFAULT_PLOTS and not sweep.keep_logs
    assert len({p.key for p in sweep.points}) == 6


def test_a_point_key_depends_on_the_values_not_their_order():
    a = grid_points({"x": parse_values([1, 2], Param("int"), None, True), "y": parse_values(3, Param("int"), None,
                                                                                              True)})
    b = grid_points({"y": parse_values(3, Param("int"), None, True), "x": parse_values([2, 1], Param("int"), None,
                                                                                         True)})
    assert {p.key for p in a} == {p.key for p in b}


@pytest.mark.parametrize("spec, expected", [
    ({"from": 0.1, "to": 0.3, "step": 0.1}, (0.1, 0.2, 0.3)),           # 0.1 + 0.1 + 0.1 is above 0.3
    ({"from": 1, "to": 100, "count": 3, "log": True}, (1.0, 10.0, 100.0)),
    ({"from": 0.0, "to": 1.0, "count": 5}, (0.0, 0.25, 0.5, 0.75, 1.0)),
    ({"from": 2, "to": 2, "step": 1}, (2.0,)),
])
def test_ranges_by_step_and_by_count(spec, expected):
    mapping = Mapping()
    mapping.update(spec)
    assert parse_values(mapping, Param("float"), Where("f", 1, "k"), grid=True).choices == expected


def test_a_random_sample_draws_within_ranges_and_is_reproducible(tmp_path):
    text = """
        sample: {random: 12, seed: 4}
        vehicles: {from: 2, to: 9}
        model_parameters:
          sonar.rayleigh_short.sigma: {from: 0.01, to: 0.2, log: true}
          sonar.crosstalk.p: [0.0, 0.68]
        """
    sweep = load_sweep(sweep_file(tmp_path, text))
    again = load_sweep(sweep_file(tmp_path, text))
    assert [p.values for p in sweep.points] == [p.values for p in again.points]
    assert len(sweep.points) == 12
    for p in sweep.points:
        assert isinstance(p.values["vehicles"], int) and 2 <= p.values["vehicles"] <= 9
        assert 0.01 <= p.values["model_parameters.sonar.rayleigh_short.sigma"] <= 0.2
        assert p.values["model_parameters.sonar.crosstalk.p"] in (0.0, 0.68)
    first = sweep.points[0]
    model = SensorModel.from_xml(sweep.models[first.key])
    rayleigh = next(e for e in model.chains["sonar"].effects if e.name == "rayleigh_short")
    assert rayleigh.params["sigma"] == first.values["model_parameters.sonar.rayleigh_short.sigma"]


def test_model_parameters_change_the_model_each_point_flies(tmp_path):
    sweep = load_sweep(sweep_file(tmp_path, """
        model_parameters:
          sonar.crosstalk.p: [0.1, 0.5]
          sonar.max_range: 2.5
        """))
    texts = [sweep.models[p.key] for p in sweep.points]
    assert 'p="0.1"' in texts[0] and 'p="0.5"' in texts[1]
    assert all('max_range="2.5"' in t and "<mixture" in t for t in texts)   # self-contained: the mixture inline


@pytest.mark.parametrize("text, line, message", [
    ("vehicle: 4\n", 2, "s.yaml:2: vehicle: not a key of a sweep file; did you mean vehicles?"),
    ("defines:\n  WALL_DETECTOR_WALL_TRESHOLD: 2\n", 3, "s.yaml:3: defines.WALL_DETECTOR_WALL_TRESHOLD: not a define "
                                                        "of the airframe's modules"),
    ("model_parameters:\n  sonar.quantization.step: 0.1\n", 3, "model_parameters.sonar.quantization.step: the sonar "
                                                               "chain has 0 effects 'quantization'"),
    ("model_parameters:\n  sonar.crosstalk.q: 0.1\n", 3, "crosstalk has no parameter 'q' (it has p)"),
    ("vehicles: {from: 16, to: 2, step: 2}\n", 2, "s.yaml:2: vehicles: empty range: from 16 is above to 2"),
    ("vehicles: []\n", 2, "s.yaml:2: vehicles: empty list"),
    ("vehicles: four\n", 2, "s.yaml:2: vehicles: expected a number, got 'four'"),
    ("vehicles: 2.5\n", 2, "s.yaml:2: vehicles: expected a whole number, got 2.5"),
    ("vehicles: 0\n", 2, "s.yaml:2: vehicles: 0 is out of range: expected >= 1 and <= 4096"),
    ("duration: [10, -1]\n", 2, "duration: -1 is out of range: expected > 0"),
    ("defines:\n  WALL_DETECTOR_MAX_PEERS: 2.5\n", 3, "defines.WALL_DETECTOR_MAX_PEERS: expected a whole number"),
    ("defines:\n  SWARM_USE_WALL_DETECTOR: FALSE\n", 3, "SWARM_USE_WALL_DETECTOR: every run flies the swarm"),
    ("model_parameters:\n  sonar.crosstalk.p: [0.5, 1.5]\n", 3,
     "model_parameters.sonar.crosstalk.p: the sensor model refuses sensor_model=conf/sensor_models/finken_default.xml, "
     "model_parameters.sonar.crosstalk.p=1.5: crosstalk p = 1.5 is outside [0, 1]"),
    ("arena: conf/arena/nope.xml\n", 2, "s.yaml:2: arena: no file conf/arena/nope.xml"),
    ("vehicles: {from: 2, to: 8}\n", 2, "vehicles: a range in a grid needs step or count"),
    ("vehicles: {from: 2, to: 8, stp: 2}\n", 2, "s.yaml:2: vehicles.stp: unknown key in a range"),
    ("seeds: 2\nseeds: 3\n", 3, "s.yaml:3: seeds: given twice (first at line 2)"),
    ("plots:\n  - [detector_wall_recal]\n", 2, "plots: detector_wall_recal is not a metric of make sim; did you mean "
                                              "detector_wall_recall"),
    ("sample: {random: 0}\n", 2, "s.yaml:2: sample: 0 is out of range"),
    ("vehicles: [2, 4\n", 3, "not YAML"),
])
def test_bad_input_is_refused_with_file_line_and_key(tmp_path, text, line, message):
    error = refused(tmp_path, text)
    assert message in error
    assert error.startswith(f"{tmp_path / 's.yaml'}:{line}: ")


def test_an_airframe_without_the_detector_and_swarm_is_refused(repo, tmp_path):
    airframe = (repo / "conf/airframes/finken_nps.xml").read_text()
    (tmp_path / "af.xml").write_text(airframe.replace('<module name="wall_detector"/>', "")
                                     .replace('<module name="swarm"/>', ""))
    path = tmp_path / "s.yaml"
    path.write_text(f"airframe: {tmp_path / 'af.xml'}\n")
    with pytest.raises(SweepFileError, match=r"s.yaml:1: airframe: make sim's metrics need the modules wall_detector, "
                                             "swarm"):
        load_sweep(path)
