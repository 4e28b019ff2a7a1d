"""The values a sweep gives one parameter: one value, a list, or a range, checked against the parameter's type.

    vehicles: 4                              one value: the parameter is fixed
    vehicles: [2, 4, 8]                      a list
    vehicles: {from: 2, to: 16, step: 2}     a range by step (2, 4, ..., 16; `to` included when on a step)
    sigma: {from: 0.01, to: 0.2, count: 5, log: true}   a range of `count` values, evenly or log spaced
    sigma: {from: 0.01, to: 0.2, log: true}  (random sample only) drawn from the whole interval, log-uniform

A grid takes every value; a random sample draws one of the values of a list or stepped range, or a value of the
interval (a whole number for an integer parameter).
"""
import math
import re
from dataclasses import dataclass
from pathlib import Path

from finken.sweep.yaml_lines import Mapping, SweepFileError

RANGE_KEYS = ("from", "to", "step", "count", "log")
#: a text value (a define's): what make passes on unquoted
WORD = re.compile(r"[\w.+-]+")
#: a range bound this close to a step (relative to the step) counts as on it (0.1 + 0.1 + 0.1 is not 0.3)
STEP_TOLERANCE = 1e-9


@dataclass(frozen=True)
class Param:
    """What a parameter accepts. kind: "int", "float" (within [low, high], low excluded when low_open), "file"
    (an existing file), "bool" or "text" (a number or a name: WORD)."""
    kind: str
    low: float | None = None
    high: float | None = None
    low_open: bool = False


@dataclass(frozen=True)
class Where:
    """Where a value was written: file, line and key, for errors."""
    path: str
    line: int
    key: str

    def error(self, reason):
        return SweepFileError(self.path, self.line, self.key, reason)


@dataclass(frozen=True)
class Values:
    """A parameter's values: `choices` (a list or a stepped range), or an interval [low, high] to draw from; log: given
    as a log range (drawn log-uniformly, plotted on a log scale)."""
    choices: tuple | None
    low: float | None = None
    high: float | None = None
    log: bool = False
    integer: bool = False

    @property
    def swept(self):
        return self.choices is None or len(self.choices) > 1

    def draw(self, rng):
        """One value at random (rng: a numpy Generator)."""
        if self.choices is not None:
            return self.choices[int(rng.integers(len(self.choices)))]
        if self.integer:
            return int(rng.integers(int(self.low), int(self.high) + 1))
        if self.log:
            return float(math.exp(rng.uniform(math.log(self.low), math.log(self.high))))
        return float(rng.uniform(self.low, self.high))


def check_value(value, param, where):
    """The value as the parameter takes it (a number, a file path as written, True/False, a word); raises
    SweepFileError naming the key."""
    if param.kind == "file":
        if not isinstance(value, str):
            raise where.error(f"expected a file name, got {value!r}")
        if not Path(value).is_file():
            raise where.error(f"no file {value}")
        return value
    if param.kind == "bool":
        if not isinstance(value, bool):
            raise where.error(f"expected true or false, got {value!r}")
        return value
    if param.kind == "text":
        text = ("TRUE" if value else "FALSE") if isinstance(value, bool) else value
        if not isinstance(text, (str, int, float)) or not WORD.fullmatch(str(text)):
            raise where.error(f"expected a number or a name (letters, digits, _ . + -), got {value!r}")
        return str(text)
    number = _number(value, where)
    if param.kind == "int" and number != int(number):
        raise where.error(f"expected a whole number, got {value!r}")
    if (param.low is not None and (number < param.low or (param.low_open and number == param.low))) or \
            (param.high is not None and number > param.high):
        raise where.error(f"{value!r} is out of range: expected {_bounds(param)}")
    return int(number) if param.kind == "int" else float(number)


def parse_values(spec, param, where, grid):
    """Values from a sweep file's one value, list or range (module docstring). grid: the sweep takes every value
    (a range then needs step or count)."""
    if isinstance(spec, list):
        if not spec:
            raise where.error("empty list: give at least one value")
        return Values(tuple(check_value(v, param, where) for v in spec))
    if not isinstance(spec, Mapping):
        return Values((check_value(spec, param, where),))
    if param.kind not in ("int", "float"):
        raise where.error(f"a range needs a numeric parameter; this one takes {param.kind} values: give a list")
    return _range(spec, param, where, grid)


def value_text(value):
    """A parameter's value for a table: a float in 6 significant digits (a log range's have 17), a bool as the C
    define's TRUE or FALSE."""
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def _range(spec, param, where, grid):
    for key in spec:
        if key not in RANGE_KEYS:
            raise SweepFileError(where.path, spec.lines[key], f"{where.key}.{key}",
                                 f"unknown key in a range (expected {', '.join(RANGE_KEYS)})")
    for key in ("from", "to"):
        if key not in spec:
            raise where.error(f"a range needs from and to (it has {', '.join(spec) or 'nothing'})")
    low, high = check_value(spec["from"], param, where), check_value(spec["to"], param, where)
    if low > high:
        raise where.error(f"empty range: from {low:g} is above to {high:g}")
    log = spec.get("log", False)
    if not isinstance(log, bool):
        raise where.error(f"log: expected true or false, got {log!r}")
    if log and low <= 0:
        raise where.error(f"a log range needs from > 0, got {low:g}")
    if "step" in spec and "count" in spec:
        raise where.error("a range takes step or count, not both")
    if "step" in spec:
        if log:
            raise where.error("a log range takes count, not step")
        return Values(_stepped(low, high, _number(spec["step"], where), param, where))
    if "count" in spec:
        return Values(_counted(low, high, spec["count"], log, param, where), log=log)
    if grid:
        raise where.error("a range in a grid needs step or count (or give a list)")
    return Values(None, low, high, log, param.kind == "int")


def _stepped(low, high, step, param, where):
    if not step > 0:
        raise where.error(f"step must be above 0, got {step:g}")
    if param.kind == "int" and step != int(step):
        raise where.error(f"an integer parameter needs a whole step, got {step:g}")
    count = math.floor((high - low) / step + STEP_TOLERANCE) + 1
    values = [low + k * step for k in range(count)]
    return tuple(int(v) if param.kind == "int" else float(f"{v:.12g}") for v in values)


def _counted(low, high, count, log, param, where):
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise where.error(f"count must be a whole number of at least 1, got {count!r}")
    if count == 1:
        return (low,)
    if log:
        values = [math.exp(math.log(low) + k * (math.log(high) - math.log(low)) / (count - 1)) for k in range(count)]
    else:
        values = [low + k * (high - low) / (count - 1) for k in range(count)]
    values = [float(f"{v:.12g}") for v in values]
    if param.kind == "int":
        if any(v != int(v) for v in values):
            raise where.error(f"{count} values from {low} to {high} are not all whole numbers: give a step")
        values = [int(v) for v in values]
    return tuple(values)


def _number(value, where):
    """A finite number from an int, a float, or text such as 1e-3 (PyYAML reads YAML 1.1, where 1e-3 is text)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise where.error(f"expected a number, got {value!r}")
    try:
        number = float(value)
    except ValueError:
        raise where.error(f"expected a number, got {value!r}") from None
    if not math.isfinite(number):
        raise where.error(f"expected a finite number, got {value!r}")
    return int(value) if isinstance(value, int) else number


def _bounds(param):
    low = "" if param.low is None else f"{'>' if param.low_open else '>='} {param.low:g}"
    high = "" if param.high is None else f"<= {param.high:g}"
    return " and ".join(b for b in (low, high) if b)
