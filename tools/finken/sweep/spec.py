"""A sweep file (YAML): the airframe, the parameters of the runs and how they vary, seeds, what to keep and plot.

    airframe: conf/airframes/finken_nps.xml      required; its modules must include wall_detector and swarm
    description: text                            shown in the summary
    seeds: 10                                    seeds 1..10 per parameter point, or a list [3, 7]
    sample: grid                                 every combination (default), or {random: 50, seed: 1}
    keep_logs: false                             true: every run's logs are kept in OUT/logs/<run>/
    vehicles: 4                                  copters (default 4)
    duration: 180                                simulated seconds (default 180, as make sim)
    arena: conf/arena/swarmlab.xml               default: the airframe's NPS_ARENA_FILE
    sensor_model: conf/sensor_models/finken_default.xml   default: the airframe's NPS_SENSOR_MODEL
    defines:                                     defines documented by the airframe's modules, or of its sections
      WALL_DETECTOR_WALL_THRESHOLD: [0.5, 1, 2]
    model_parameters:                            <chain>.<effect>.<parameter> or <chain>.min_range / max_range
      sonar.rayleigh_short.sigma: {from: 0.02, to: 0.2, count: 4, log: true}
    plots:                                       panels of metrics drawn against each swept parameter
      - [detector_wall_recall, baseline_wall_recall]

Every parameter takes one value, a list or a range (finken.sweep.values). A file is refused before any run, with
file, line and key, for an unknown key, define, model parameter or metric, an empty list or range, or a value of the
wrong type; a value the sensor model refuses is named the same way (docs/sweeps.md).
"""
import copy
import difflib
from dataclasses import dataclass
from pathlib import Path

from finken.cli_types import SEED_MAX
from finken.conf.airframe import read_airframe
from finken.conf.airframe_modules import REPO_ROOT, load_modules, main_frequency
from finken.models import ModelError, SensorModel, effect_params
from finken.sweep.metrics import metric_names
from finken.sweep.points import grid_points, random_points
from finken.sweep.values import Param, Where, check_value, parse_values
from finken.sweep.yaml_lines import Mapping, SweepFileError, load_yaml
from finken.xml_errors import XmlInputError

TOP_KEYS = ("airframe", "description", "seeds", "sample", "keep_logs", "vehicles", "duration", "arena",
            "sensor_model", "defines", "model_parameters", "plots")
#: parameters every run has, with their types and defaults (arena and sensor model: the airframe's)
PARAMS = {"vehicles": Param("int", 1, 4096), "duration": Param("float", 0.0, 1e9, low_open=True),
          "arena": Param("file"), "sensor_model": Param("file")}
DEFAULTS = {"vehicles": 4, "duration": 180.0}
#: the host's limits of --seed
SEED = Param("int", 0, SEED_MAX)
#: the modules make sim's metrics need
NEEDED_MODULES = ("wall_detector", "swarm")
#: defines a sweep may not set: every run flies the detector on and off (as make sim); files have their own keys
RESERVED_DEFINES = {"SWARM_USE_WALL_DETECTOR": "every run flies the swarm with the detector and without (as make "
                                               "sim): it cannot be swept",
                    "NPS_ARENA_FILE": "give the arena with the key arena",
                    "NPS_SENSOR_MODEL": "give the sensor model with the key sensor_model"}
#: C type of a module's documented define -> the values it takes
DEFINE_TYPES = {"float": Param("float"), "int": Param("int"), "uint": Param("int", 0), "bool": Param("bool")}
MODEL_CHAIN_ATTRIBUTES = ("min_range", "max_range")
DEFAULT_PLOTS = (("detector_wall_recall", "baseline_wall_recall"),
                 ("detector_copter_as_wall", "baseline_copter_as_wall"), ("cohesion_on", "cohesion_off"))


@dataclass
class Sweep:
    """A checked sweep file. points: every parameter point (each parameter's value, by its key); seeds: the seeds
    of every point; swept: the keys of the parameters that vary; log_scale: those given as a log range; models: the
    sensor model of each point key (model text, parameters applied)."""
    path: str
    name: str
    description: str
    airframe: str
    seeds: tuple
    keep_logs: bool
    sampling: str
    points: list
    swept: tuple
    log_scale: tuple
    plots: tuple
    models: dict

    @property
    def runs(self):
        """(point, seed) of every run, point by point."""
        return [(point, seed) for point in self.points for seed in self.seeds]


def load_sweep(path):
    """Read and check the sweep file at `path`. Raises SweepFileError (and OSError when it cannot be read)."""
    doc = load_yaml(path)
    for key in doc:
        if key not in TOP_KEYS:
            raise _unknown(path, doc.lines[key], key, key, TOP_KEYS, "not a key of a sweep file")
    if "airframe" not in doc:
        raise SweepFileError(path, None, "airframe", "missing: the airframe the runs fly")
    where = {key: Where(str(path), doc.lines[key], key) for key in doc}
    airframe, modules = _airframe(doc["airframe"], where["airframe"])
    grid, random_count, random_seed = _sampling(doc.get("sample", "grid"), where.get("sample"))
    values, lines = _parameters(doc, airframe, modules, where, grid)
    points = grid_points(values) if grid else random_points(values, random_count, random_seed)
    return Sweep(path=str(path), name=Path(path).stem, description=_text(doc, "description", where),
                 airframe=airframe.path, seeds=_seeds(doc.get("seeds", 1), where.get("seeds")),
                 keep_logs=_flag(doc, "keep_logs", where),
                 sampling="grid" if grid else f"random sample of {random_count} (seed {random_seed})",
                 points=points, swept=tuple(key for key in values if values[key].swept),
                 log_scale=tuple(key for key in values if values[key].log),
                 plots=_plots(doc.get("plots"), where.get("plots")), models=_models(points, lines, str(path)))


def _parameters(doc, airframe, modules, where, grid):
    """({key: Values}, {key: line}) of every parameter: vehicles, duration, arena, sensor_model, then the defines
    and the model parameters in the file's order."""
    path = where["airframe"].path
    values, lines = {}, {}
    for key, param in PARAMS.items():
        if key in doc:
            spec = doc[key]
        else:
            spec = DEFAULTS[key] if key in DEFAULTS else _airframe_file(airframe, key)
        values[key] = parse_values(spec, param, where.get(key) or Where(path, None, key), grid)
        lines[key] = doc.lines.get(key)
    for key, (spec, param, line) in _defines(doc, airframe, modules, where).items():
        values[key] = parse_values(spec, param, Where(path, line, key), grid)
        lines[key] = line
    for key, (spec, line) in _model_parameters(doc, values["sensor_model"].choices, where).items():
        values[key] = parse_values(spec, Param("float"), Where(path, line, key), grid)
        lines[key] = line
    return values, lines


def _airframe(path_text, where):
    if not isinstance(path_text, str) or not Path(path_text).is_file():
        raise where.error(f"no airframe file {path_text!r}")
    try:
        airframe = read_airframe(path_text, "nps")
        modules = [module for _, module in load_modules(airframe, REPO_ROOT / "conf" / "modules",
                                                        main_frequency(airframe))]
    except XmlInputError as err:
        raise where.error(f"the airframe is refused: {err}") from None
    missing = [name for name in NEEDED_MODULES if name not in {m.name for m in modules}]
    if missing:
        raise where.error(f"make sim's metrics need the modules {', '.join(NEEDED_MODULES)}; {path_text} lacks "
                          f"{', '.join(missing)}")
    return airframe, modules


def _airframe_file(airframe, key):
    """The airframe's NPS_ARENA_FILE or NPS_SENSOR_MODEL (a quoted C string), the default of arena, sensor_model."""
    name = {"arena": "NPS_ARENA_FILE", "sensor_model": "NPS_SENSOR_MODEL"}[key]
    for define in airframe.section_defines:
        if define.name == name and define.value:
            return define.value.strip('"')
    raise SweepFileError(airframe.path, None, key, f"the airframe sets no {name}: give {key} in the sweep file")


def _defines(doc, airframe, modules, where):
    """{"defines.NAME": (value spec, Param, line)} of the defines: key."""
    if "defines" not in doc:
        return {}
    defines = doc["defines"]
    if not isinstance(defines, Mapping):
        raise where["defines"].error("expected a mapping of define names to values")
    known = {name: DEFINE_TYPES.get(attributes.get("type"), Param("text"))
             for module in modules for name, attributes in module.documented_defines.items()}
    known.update({d.name: Param("text") for d in airframe.section_defines})
    result = {}
    for name, spec in defines.items():
        line, key = defines.lines[name], f"defines.{name}"
        if name in RESERVED_DEFINES:
            raise SweepFileError(where["defines"].path, line, key, RESERVED_DEFINES[name])
        if name not in known:
            raise _unknown(where["defines"].path, line, key, name, known, "not a define of the airframe's modules "
                           f"({', '.join(m.name for m in modules)}) or of its sections")
        result[key] = (spec, known[name], line)
    return result


def _model_parameters(doc, base_models, where):
    """{"model_parameters.NAME": (value spec, line)}, each name checked against every base model."""
    if "model_parameters" not in doc:
        return {}
    params = doc["model_parameters"]
    if not isinstance(params, Mapping):
        raise where["model_parameters"].error("expected a mapping of <chain>.<effect>.<parameter> to values")
    result = {}
    for name, spec in params.items():
        key = f"model_parameters.{name}"
        for base in base_models:
            problem = _model_parameter_problem(_load_model(base, where.get("sensor_model")), name)
            if problem:
                raise SweepFileError(where["model_parameters"].path, params.lines[name], key, f"{problem} ({base})")
        result[key] = (spec, params.lines[name])
    return result


def _model_parameter_problem(model, name):
    """Why `name` is not a parameter of the model (None when it is)."""
    parts = name.split(".")
    chain = model.chains.get(parts[0])
    if chain is None:
        return f"the model has no chain {parts[0]!r} (it has {', '.join(model.chains)})"
    if len(parts) == 2 and parts[1] in MODEL_CHAIN_ATTRIBUTES:
        return None
    if len(parts) != 3:
        return f"expected <chain>.<effect>.<parameter> or <chain>.{'/'.join(MODEL_CHAIN_ATTRIBUTES)}"
    matching = [e for e in chain.effects if e.name == parts[1]]
    if len(matching) != 1:
        have = ", ".join(e.name for e in chain.effects) or "none"
        return f"the {parts[0]} chain has {len(matching)} effects {parts[1]!r} (it has {have}): expected one"
    if parts[2] not in effect_params(parts[1]):
        return f"{parts[1]} has no parameter {parts[2]!r} (it has {', '.join(effect_params(parts[1])) or 'none'})"
    return None


def _load_model(path, where):
    try:
        return SensorModel.load(path)
    except ModelError as err:
        raise (where.error(str(err)) if where else SweepFileError(path, err.line, None, err.reason)) from None


def _models(points, lines, path):
    """{point key: model text}: each point's base model with its model parameters set, checked by the C loader
    (points with the same model share one text)."""
    models, texts, bases = {}, {}, {}
    for point in points:
        changed = [key for key in point.values if key.startswith("model_parameters.")]
        model_values = point.label(["sensor_model", *changed])
        if model_values not in texts:
            base = point.values["sensor_model"]
            if base not in bases:
                bases[base] = _load_model(base, None)
            model = copy.deepcopy(bases[base])
            for key in changed:
                _set_model_parameter(model, key.split(".", 1)[1], point.values[key])
            try:
                model.native()
            except ModelError as err:
                raise SweepFileError(path, lines[changed[0]] if changed else None, ", ".join(changed) or
                                     "sensor_model", f"the sensor model refuses {model_values}: {err.reason}") from None
            texts[model_values] = model.to_xml()
        models[point.key] = texts[model_values]
    return models


def _set_model_parameter(model, name, value):
    parts = name.split(".")
    chain = model.chains[parts[0]]
    if len(parts) == 2:
        setattr(chain, parts[1], value)
    else:
        next(e for e in chain.effects if e.name == parts[1]).params[parts[2]] = value


def _sampling(spec, where):
    """(grid, random count, random seed) from sample: grid | {random: N, seed: S}."""
    if spec == "grid":
        return True, None, None
    if not isinstance(spec, Mapping) or "random" not in spec or set(spec) - {"random", "seed"}:
        raise where.error("expected grid or {random: <number of points>, seed: <seed>}")
    count = check_value(spec["random"], Param("int", 1), where)
    return False, count, check_value(spec.get("seed", 1), SEED, where)


def _seeds(spec, where):
    if isinstance(spec, list):
        if not spec:
            raise where.error("empty list: give at least one seed")
        seeds = tuple(check_value(s, SEED, where) for s in spec)
        if len(set(seeds)) != len(seeds):
            raise where.error("a seed is listed twice")
        return seeds
    return tuple(range(1, check_value(spec, Param("int", 1), where) + 1))


def _plots(spec, where):
    if spec is None:
        return DEFAULT_PLOTS
    if not isinstance(spec, list) or not spec:
        raise where.error("expected a list of panels, each a metric or a list of metrics")
    panels = tuple(tuple(p) if isinstance(p, list) else (p,) for p in spec)
    for metric in (m for panel in panels for m in panel):
        if metric not in metric_names():
            raise _unknown(where.path, where.line, "plots", metric, metric_names(),
                           f"{metric} is not a metric of make sim")
    return panels


def _flag(doc, key, where):
    return check_value(doc[key], Param("bool"), where[key]) if key in doc else False


def _text(doc, key, where):
    if key in doc and not isinstance(doc[key], str):
        raise where[key].error("expected text")
    return doc.get(key, "")


def _unknown(path, line, key, name, known, what):
    """SweepFileError for an unknown `name`, with the closest known names."""
    close = difflib.get_close_matches(name, list(known), n=3)
    hint = f"; did you mean {' or '.join(close)}?" if close else ""
    return SweepFileError(path, line, key, f"{what}{hint}")

