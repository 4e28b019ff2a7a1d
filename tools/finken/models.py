"""Sensor models (chains of error effects) from Python: load, edit, save, simulate, log-densities.

Everything numerical runs in the C library (sw/simulator/nps, through finken._native): the same code the
NPS simulator runs. This module holds the model as plain dataclasses, writes model files and calls C, which
also reads every model (one grammar: the same files are accepted and refused with the same messages).

Conditions are small expressions over context columns ("ctx_blocked", "ctx_nlos == 0 and ctx_rssi < -85.5",
nps_condition.h), parsed and evaluated by C only (condition_mask, condition_columns, canonical_condition). They
name columns their user has: the simulator's, or for the replay of a range log also that log's own ctx_ columns
(`log_columns` of the loaders, SensorModel.for_log). So does a bias curve's `over`.

EFFECT_NAMES are the effects of the discrepancy spec, whose parameters are numbers (or a mixture): what the
calibration workflow searches. ALL_EFFECT_NAMES adds the effects with list parameters: glitch (Effect.values)
and bias_curve (Effect.curve, a BiasCurve).

Units: ranges in metres, times in seconds. A reading of NaN means "no reading".
"""
from __future__ import annotations

import copy
import functools
import re
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np
from lxml import etree

from finken import _native
from finken.atomic_output import write_text

KINDS = ("sonar", "ranging")
SOUND_SPEED_MPS = 343.0  # default of the sonar chain's speed_of_sound (nps_crosstalk.h)
MODELS_DIR = _native.REPO / "conf" / "sensor_models"
DEFAULT_MODEL_PATH = MODELS_DIR / "finken_default.xml"
GAUSSIAN_ONLY_PATH = MODELS_DIR / "gaussian_only.xml"

_ERR_RE = re.compile(r"^(.*?):(\d+): (.*)$", re.S)


class ModelError(ValueError):
    """A model (file) that cannot be used; str() is "file:line: reason"."""

    def __init__(self, message):
        super().__init__(message)
        m = _ERR_RE.match(message)
        self.path, self.line, self.reason = (m.group(1), int(m.group(2)), m.group(3)) if m else (None, 0, message)


# ---------------------------------------------------------------- the effects library (tables from C)

@functools.cache
def _all_effect_names():
    ffi, lib = _native.load()
    names = []
    while lib.nps_effect_name(len(names)) != ffi.NULL:
        names.append(_native.text(lib.nps_effect_name(len(names))))
    return tuple(names)


def _effect_names():
    return tuple(name for name in _all_effect_names() if not effect_text_params(name))


def _kind(name):
    _, lib = _native.load()
    k = lib.nps_effect_kind_from_name(str(name).encode())
    if k < 0:
        raise ValueError(f"unknown effect '{name}' (known: {', '.join(_all_effect_names())})")
    return k


def effect_params(name: str) -> tuple[str, ...]:
    """Parameter names of an effect, in spec order (range_noise -> ('sigma0', 'sigma1')); gmm -> ()."""
    _, lib = _native.load()
    k = _kind(name)
    return tuple(_native.text(lib.nps_effect_param_name(k, j)) for j in range(lib.nps_effect_param_count(k)))


def effect_text_params(name: str) -> tuple[str, ...]:
    """The parameters of an effect that are not one number (glitch -> ('values',), bias_curve -> ('over', 'at',
    'b')); they are Effect.values and Effect.curve, not params."""
    _, lib = _native.load()
    k = _kind(name)
    count = lib.nps_effect_text_param_count(k)
    return tuple(_native.text(lib.nps_effect_text_param_name(k, j)) for j in range(count))


def effect_has_logpdf(name: str) -> bool:
    """Whether effect_logpdf() has a closed form for this effect."""
    _, lib = _native.load()
    return bool(lib.nps_effect_has_logpdf(_kind(name)))


def __getattr__(name):
    # EFFECT_NAMES comes from the C tables; resolved on first use so that importing needs no library.
    if name == "EFFECT_NAMES":
        return _effect_names()
    if name == "ALL_EFFECT_NAMES":
        return _all_effect_names()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# ---------------------------------------------------------------- mixtures

@dataclass(eq=False)
class Mixture:
    """Joint Gaussian mixture over (true range, measured range); the gmm effect conditions it on the truth.

    weights (K,), means (K, 2) [m] as (true, measured), covariances (K, 2, 2) [m^2].
    `diagonal` writes it as covariance="diag" (then every off-diagonal term must be 0).
    """
    weights: np.ndarray
    means: np.ndarray
    covariances: np.ndarray
    diagonal: bool = False
    _handle: object = field(default=None, repr=False)

    def __post_init__(self):
        self.weights = np.asarray(self.weights, dtype=np.float64).reshape(-1)
        self.means = np.asarray(self.means, dtype=np.float64).reshape(-1, 2)
        cov = np.asarray(self.covariances, dtype=np.float64).reshape(-1, 2, 2)
        self.covariances = 0.5 * (cov + cov.transpose(0, 2, 1))  # fitted matrices can be asymmetric in the last bit
        if not len(self.weights) == len(self.means) == len(self.covariances):
            raise ModelError(f"mixture:0: {len(self.weights)} weights, {len(self.means)} means and "
                             f"{len(self.covariances)} covariances: one of each per component")

    def __eq__(self, other):
        return (isinstance(other, Mixture) and self.diagonal == other.diagonal
                and np.array_equal(self.weights, other.weights) and np.array_equal(self.means, other.means)
                and np.array_equal(self.covariances, other.covariances))

    def __deepcopy__(self, memo):
        return Mixture(self.weights.copy(), self.means.copy(), self.covariances.copy(), self.diagonal)

    @property
    def k(self) -> int:
        """Number of components."""
        return len(self.weights)

    def native(self):
        """The C mixture (validated; cached). Raises ModelError naming the bad component."""
        if self._handle is None:
            ffi, lib = _native.load()
            w, mu, cov = (np.ascontiguousarray(a) for a in (self.weights, self.means, self.covariances))
            bad = ffi.new("size_t *")
            err = _native.err_buffer()
            g = lib.nps_gmm_new(self.k, _native.ptr(w), _native.ptr(mu), _native.ptr(cov), bad, err, _native.ERR_LEN)
            if g == ffi.NULL:
                raise ModelError(f"mixture:0: {_native.text(err)}")
            self._handle = ffi.gc(g, lib.nps_gmm_free)
        return self._handle

    def _conditional(self, t, m, want):
        ffi, lib = _native.load()
        t, m = np.broadcast_arrays(np.asarray(t, dtype=np.float64), np.asarray(m, dtype=np.float64))
        shape = t.shape
        t, m = np.ascontiguousarray(t.ravel()), np.ascontiguousarray(m.ravel())
        out = {name: np.empty(len(t)) for name in want}
        args = [_native.ptr(out[name]) if name in out else ffi.NULL for name in ("mean", "var", "logpdf", "cdf")]
        lib.nps_gmm_conditional_n(self.native(), len(t), _native.ptr(t), _native.ptr(m), *args)
        return [out[name].reshape(shape) for name in want]

    def conditional_moments(self, true_range):
        """(mean [m], variance [m^2]) of the measured range given the true range (law of total variance)."""
        return tuple(self._conditional(true_range, 0.0, ("mean", "var")))

    def conditional_logpdf(self, true_range, measured):
        """log p(measured | true) [log 1/m], computed in log space (finite far from every component)."""
        return self._conditional(true_range, measured, ("logpdf",))[0]

    def conditional_cdf(self, true_range, measured):
        """P(reading <= measured | true)."""
        return self._conditional(true_range, measured, ("cdf",))[0]

    @classmethod
    def _from_native(cls, g):
        ffi, lib = _native.load()
        k = lib.nps_gmm_size(g)
        w, mean, cov = ffi.new("double *"), ffi.new("double[2]"), ffi.new("double[4]")
        weights, means, covs = np.empty(k), np.empty((k, 2)), np.empty((k, 2, 2))
        for i in range(k):
            lib.nps_gmm_component(g, i, w, mean, cov)
            weights[i], means[i] = w[0], list(mean)
            covs[i] = np.reshape(list(cov), (2, 2))
        return cls(weights, means, covs, diagonal=bool(lib.nps_gmm_is_diagonal(g)))

    @classmethod
    def load(cls, path) -> "Mixture":
        """Read a mixture file (<mixture> root). Raises ModelError "file:line: reason"."""
        ffi, lib = _native.load()
        err = _native.err_buffer()
        g = lib.nps_sensor_model_load_mixture(str(path).encode(), err, _native.ERR_LEN)
        if g == ffi.NULL:
            raise ModelError(_native.text(err))
        try:
            return cls._from_native(g)
        finally:
            lib.nps_gmm_free(g)

    def to_element(self) -> etree._Element:
        """The <mixture> element of the model-file format."""
        mix = etree.Element("mixture", components=str(self.k), covariance="diag" if self.diagonal else "full")
        for w, mu, c in zip(self.weights, self.means, self.covariances):
            attrs = OrderedDict(weight=_num(w), mean_true=_num(mu[0]), mean_measured=_num(mu[1]),
                                var_true=_num(c[0, 0]), var_measured=_num(c[1, 1]))
            if not self.diagonal:
                attrs["cov"] = _num(c[0, 1])
            etree.SubElement(mix, "component", attrs)
        return mix

    def save(self, path, header: str | None = None) -> None:
        """Write a mixture file, with `header` as its leading comment (where the numbers come from)."""
        root = self.to_element()
        text = etree.tostring(root, pretty_print=True, encoding="unicode")
        comment = f"<!--\n{_comment_text(header)}\n-->\n" if header else ""
        write_text(path, f'<?xml version="1.0" encoding="UTF-8"?>\n{comment}{text}')


def _comment_text(text):
    return text.replace("--", "- -")


def _num(x) -> str:
    """Shortest text that reads back as the same float."""
    return repr(float(x))


def _nums(xs) -> str:
    """A list attribute: the numbers separated by spaces."""
    return " ".join(_num(x) for x in xs)


# ---------------------------------------------------------------- conditions (nps_condition.h)

def _condition_text(function, condition) -> tuple[int, str]:
    """Run function(condition, out, out_len, err, err_len) of nps_condition.h: (its result, out); ValueError."""
    out, err = _native.err_buffer(), _native.err_buffer()
    rc = function(str(condition).encode(), out, _native.ERR_LEN, err, _native.ERR_LEN)
    if rc < 0:
        raise ValueError(_native.text(err))
    return rc, _native.text(out)


def canonical_condition(condition: str) -> str:
    """The canonical text of a condition ("ctx_rssi<-85.50" -> "ctx_rssi < -85.5"); ValueError if malformed."""
    _, lib = _native.load()
    return _condition_text(lib.nps_condition_canonical, condition)[1]


def condition_columns(condition: str | None) -> tuple[str, ...]:
    """The columns a condition names, each once, in order (None: none); ValueError if malformed."""
    if condition is None:
        return ()
    _, lib = _native.load()
    return tuple(_condition_text(lib.nps_condition_columns, condition)[1].split())


def condition_mask(condition: str | None, ctx: dict, n: int) -> np.ndarray:
    """Where a condition holds on n rows (bool; None: everywhere), evaluated in C as the simulator does (a NaN
    value satisfies no term). ctx: {column: n values}, keys with or without the "ctx_" prefix as for simulate.
    ValueError for a malformed condition or a column ctx lacks."""
    if condition is None:
        return np.ones(n, dtype=bool)
    ffi, lib = _native.load()
    given = [(name, col) for name in condition_columns(condition) if (col := _ctx_column(ctx, name, n)) is not None]
    count, names, _keep = _native.strings([name for name, _ in given])
    columns = ffi.new("double *[]", [_native.ptr(col) for _, col in given]) if given else ffi.NULL
    out = np.empty(n, dtype=np.uint8)
    err = _native.err_buffer()
    if lib.nps_condition_mask(str(condition).encode(), count, names, columns, n, _native.ptr(out, "unsigned char *"),
                              err, _native.ERR_LEN) != 0:
        raise ValueError(_native.text(err))
    return out.view(bool)


# ---------------------------------------------------------------- model dataclasses

@dataclass
class BiasCurve:
    """The bias of a bias_curve effect, b(u): linear between the knots (at[i], b[i]), constant beyond the first and
    the last. over: u, "true_range" or a ctx_ column; at: 2 to 16 knots, strictly increasing (u's unit); b [m]."""
    over: str
    at: list[float]
    b: list[float]

    def __post_init__(self):
        self.at = [float(u) for u in self.at]
        self.b = [float(b) for b in self.b]


@dataclass
class Effect:
    """One error effect. params: {name: value} in the effect's units (effect_params(name)).

    condition: where the effect applies, e.g. "ctx_blocked" (non-zero) or "ctx_nlos == 0 and ctx_rssi < -85.5"
    (condition_mask); kept as its canonical text. For gmm the mixture is `mixture` (params is empty). For glitch
    `values` are the readings a glitch reports [m] (1 to 64, finite or +-inf), params {"p": ...}; for bias_curve
    the curve is `curve` (params is empty).
    """
    name: str
    params: dict[str, float] = field(default_factory=dict)
    condition: str | None = None
    mixture: Mixture | None = None
    values: list[float] | None = None
    curve: BiasCurve | None = None

    def __post_init__(self):
        if self.condition:
            self.condition = canonical_condition(self.condition)
        if self.values is not None:
            self.values = [float(v) for v in self.values]


@dataclass
class SensorChain:
    """The effects of one sensor kind in order, then its range limits.

    beyond_max: what the sensor reports with no echo in range: 'max' (the maximum) or 'none' (no reading).
    """
    kind: str
    min_range: float
    max_range: float
    beyond_max: str
    effects: list[Effect] = field(default_factory=list)
    speed_of_sound: float = SOUND_SPEED_MPS


def _lists_from_native(e) -> tuple[list[float] | None, BiasCurve | None]:
    """(values, curve) of a C effect: a glitch's values, a bias_curve's curve, else None."""
    ffi, lib = _native.load()
    n = ffi.new("size_t *")
    values = lib.nps_effect_glitch_values(e, n)
    glitch = None if values == ffi.NULL else [values[i] for i in range(n[0])]
    at, b = ffi.new("double **"), ffi.new("double **")
    over = lib.nps_effect_bias_curve(e, n, at, b)
    curve = None if over == ffi.NULL else BiasCurve(_native.text(over), [at[0][i] for i in range(n[0])],
                                                    [b[0][i] for i in range(n[0])])
    return glitch, curve


class _NativeModel:
    """A C model owned by Python."""

    def __init__(self, ptr):
        ffi, lib = _native.load()
        self.ptr = ffi.gc(ptr, lib.nps_sensor_model_free)


def _columns(log_columns) -> tuple[str, ...]:
    """The ctx_ columns of a replayed log as a sorted tuple (a dict of columns gives its keys)."""
    return tuple(sorted(str(c) for c in (log_columns or ())))


def _load_native(load, log_columns) -> _NativeModel:
    """Run a C loader, load(n_log_columns, log_column, model, err, err_len); ModelError when it refuses."""
    ffi, _ = _native.load()
    n, names, _keep = _native.strings(log_columns)
    out = ffi.new("struct nps_sensor_model **")
    err = _native.err_buffer()
    if load(n, names, out, err, _native.ERR_LEN) != 0:
        raise ModelError(_native.text(err))
    return _NativeModel(out[0])


_native_cache: OrderedDict[tuple, _NativeModel] = OrderedDict()
_NATIVE_CACHE_SIZE = 8


def _native_from_xml(xml: str, origin: str, log_columns: tuple[str, ...] = ()) -> _NativeModel:
    """Load model text in C (cached by text and log columns: a loaded model is immutable)."""
    key = (xml, log_columns)
    hit = _native_cache.get(key)
    if hit is not None:
        _native_cache.move_to_end(key)
        return hit
    ffi, lib = _native.load()
    data = xml.encode()
    native = _load_native(lambda *rest: lib.nps_sensor_model_load_memory_for_log(data, len(data), origin.encode(),
                                                                                ffi.NULL, *rest), log_columns)
    _native_cache[key] = native
    if len(_native_cache) > _NATIVE_CACHE_SIZE:
        _native_cache.popitem(last=False)
    return native


class SensorModel:
    """A sensor model: chains keyed 'sonar' and/or 'ranging'.

    log_columns: the ctx_ columns of the range log it replays, which its conditions may name besides the
    simulator's (empty: the model is for the simulator).
    """

    def __init__(self, chains: dict[str, SensorChain], name: str | None = None, source: str | None = None,
                 log_columns=()):
        self.chains = chains
        self.name = name
        self.source = source  # the file it was loaded from, if any
        self.log_columns = _columns(log_columns)

    def __repr__(self):
        return f"SensorModel(name={self.name!r}, chains={self.chains!r})"

    def __eq__(self, other):
        return isinstance(other, SensorModel) and self.chains == other.chains

    # ---- reading (by the C loaders)
    @classmethod
    def load(cls, path, log_columns=()) -> "SensorModel":
        """Read a model file (mixture files it names are read too). Raises ModelError "file:line: reason".
        log_columns: the ctx_ columns of a range log it will replay (a dict of columns gives its keys)."""
        _, lib = _native.load()
        columns = _columns(log_columns)
        native = _load_native(lambda *rest: lib.nps_sensor_model_load_for_log(str(path).encode(), *rest), columns)
        return cls._from_native(native, source=str(path), log_columns=columns)

    @classmethod
    def from_xml(cls, xml: str, origin: str = "<model text>", log_columns=()) -> "SensorModel":
        """Read model-file text; `origin` names it in errors."""
        columns = _columns(log_columns)
        return cls._from_native(_native_from_xml(xml, origin, columns), log_columns=columns)

    @classmethod
    def from_string(cls, text: str, origin: str = "<model text>", log_columns=()) -> "SensorModel":
        """Read the one-line form used by airframe defines (docs/sensors.md); mixture paths relative to cwd."""
        _, lib = _native.load()
        data, columns = text.encode(), _columns(log_columns)
        native = _load_native(lambda *rest: lib.nps_sensor_model_from_text_for_log(data, len(data), origin.encode(),
                                                                                  *rest), columns)
        return cls._from_native(native, log_columns=columns)

    @classmethod
    def _from_native(cls, native: _NativeModel, source=None, log_columns=()) -> "SensorModel":
        ffi, lib = _native.load()
        name = lib.nps_sensor_model_name(native.ptr)
        chains = {}
        for kind in KINDS:
            c = lib.nps_sensor_model_chain(native.ptr, kind.encode())
            if c == ffi.NULL:
                continue
            effects = []
            for i in range(lib.nps_sensor_chain_effect_count(c)):
                e = lib.nps_sensor_chain_effect(c, i)
                name_i = _native.text(lib.nps_effect_name(lib.nps_effect_kind(e)))
                params = {p: float(lib.nps_effect_param(e, j)) for j, p in enumerate(effect_params(name_i))}
                cond = lib.nps_effect_condition(e)
                g = lib.nps_effect_gmm(e)
                effects.append(Effect(name_i, params, None if cond == ffi.NULL else _native.text(cond),
                                      None if g == ffi.NULL else Mixture._from_native(g), *_lists_from_native(e)))
            chains[kind] = SensorChain(kind, float(lib.nps_sensor_chain_min_range(c)),
                                       float(lib.nps_sensor_chain_max_range(c)),
                                       _native.text(lib.nps_sensor_chain_beyond_max(c)), effects,
                                       float(lib.nps_sensor_chain_speed_of_sound(c)))
        return cls(chains, name=None if name == ffi.NULL else _native.text(name), source=source,
                   log_columns=log_columns)

    # ---- editing and writing
    def for_log(self, log_columns) -> "SensorModel":
        """A copy for the replay of a range log with these ctx_ columns (a dict of columns gives its keys):
        effects added to it may be conditioned on them."""
        model = copy.deepcopy(self)
        model.log_columns = _columns(log_columns)
        return model

    def with_effect(self, kind: str, effect: Effect) -> "SensorModel":
        """A copy with `effect` appended to the `kind` chain (effects come before the range limits).
        Raises ModelError when the effect is not valid."""
        if kind not in self.chains:
            raise ModelError(f"<model>:0: the model has no {kind} chain")
        model = copy.deepcopy(self)
        model.source = None
        model.chains[kind].effects.append(copy.deepcopy(effect))
        model.native()  # validates in C
        return model

    def to_xml(self) -> str:
        """The model-file text (mixtures inline)."""
        root = etree.Element("sensor_model")
        if self.name:
            root.set("name", self.name)
        for kind in KINDS:
            chain = self.chains.get(kind)
            if chain is None:
                continue
            el = etree.SubElement(root, kind, OrderedDict(
                min_range=_num(chain.min_range), max_range=_num(chain.max_range), beyond_max=chain.beyond_max))
            if chain.speed_of_sound != SOUND_SPEED_MPS:
                el.set("speed_of_sound", _num(chain.speed_of_sound))
            for eff in chain.effects:
                e = etree.SubElement(el, "effect", name=eff.name)
                for key, value in eff.params.items():
                    e.set(key, _num(value))
                if eff.values is not None:
                    e.set("values", _nums(eff.values))
                if eff.curve is not None:
                    e.set("over", eff.curve.over)
                    e.set("at", _nums(eff.curve.at))
                    e.set("b", _nums(eff.curve.b))
                if eff.condition:
                    e.set("condition", eff.condition)
                if eff.mixture is not None:
                    e.append(eff.mixture.to_element())
        text = etree.tostring(root, pretty_print=True, encoding="unicode")
        return f'<?xml version="1.0" encoding="UTF-8"?>\n{text}'

    def save(self, path) -> None:
        """Write the model file (loadable by SensorModel.load and by the simulator)."""
        write_text(path, self.to_xml())

    def native(self, log_columns=None) -> _NativeModel:
        """The model loaded in C (validated; cached by content), for the replay of a log with `log_columns`
        (default: self.log_columns)."""
        columns = self.log_columns if log_columns is None else _columns(log_columns)
        return _native_from_xml(self.to_xml(), self.source or f"<model {self.name}>", columns)


# ---------------------------------------------------------------- simulation and densities

def _ctx_name(key: str) -> str:
    """The column name of a ctx key given with or without the "ctx_" prefix."""
    return key if key.startswith("ctx_") else "ctx_" + key


def _ctx_column(ctx: dict, name: str, n: int):
    for key in (name, name[len("ctx_"):]):
        if key in ctx:
            value = np.asarray(ctx[key], dtype=np.float64)
            if value.ndim > 1 or value.size not in (1, n):
                raise ValueError(f"ctx column '{key}' has {value.size} values for {n} rows")
            return _native.doubles(value, n)
    return None


def simulate(model: SensorModel, kind: str, t, true_range, stream, ctx: dict | None, seed: int) -> np.ndarray:
    """Measured readings [m] (NaN = no reading) for rows given as arrays.

    t [s], true_range [m], stream: int id per sensor stream (rows of one stream in time order);
    ctx: {ctx column name: array} (keys with or without the "ctx_" prefix; "ctx_vehicle", the log's vehicle
    column, for per-vehicle effects conditioned on it). Each stream has its own state (latency history) and
    random stream, derived from (seed, stream id, kind) as nps_rng.h documents; the result is deterministic for
    a seed. Runs in C, one call per batch.
    In log replay, cross-talk hears a facing emitter on rows with ctx_facing_sonars > 0, over the path
    ctx_crosstalk_path (else the true range) with trigger offset ctx_trigger_offset (else 0).
    Raises ModelError when a condition or a bias curve names a column `ctx` does not have.
    """
    ffi, lib = _native.load()
    ctx = ctx or {}
    native = model.native(log_columns=[_ctx_name(key) for key in ctx])
    chain = lib.nps_sensor_model_chain(native.ptr, kind.encode())
    if chain == ffi.NULL:
        raise ValueError(f"the model has no {kind} chain")
    true_range = _native.doubles(true_range)
    n = len(true_range)
    t = _native.doubles(t)
    stream = np.asarray(stream)
    if t.shape != (n,) or stream.shape != (n,):
        raise ValueError(f"t, true_range and stream must be 1-D of one length (got {t.shape}, {true_range.shape}, "
                         f"{stream.shape})")
    keys, index = np.unique(stream.astype(np.int64), return_inverse=True)
    keys = np.ascontiguousarray(keys, dtype=np.int64)
    index = np.ascontiguousarray(index.ravel(), dtype=np.uint32)
    n_slots = lib.nps_sensor_ctx_slot_count()
    keep, columns = [], ffi.new("double *[]", n_slots)
    for slot in range(n_slots):
        name = lib.nps_sensor_model_ctx_slot_name(native.ptr, slot)
        col = None if name == ffi.NULL else _ctx_column(ctx, _native.text(name), n)
        if col is not None:
            keep.append(col)
            columns[slot] = _native.ptr(col)
    err = _native.err_buffer()
    if lib.nps_sensor_chain_check_columns(chain, columns, err, _native.ERR_LEN) != 0:
        raise ModelError(_native.text(err))
    out = np.empty(n)
    rc = lib.nps_sensor_chain_simulate(chain, int(seed) & (2**64 - 1), n, _native.ptr(t), _native.ptr(true_range),
                                       _native.ptr(index, "uint32_t *"), len(keys), _native.ptr(keys, "int64_t *"),
                                       columns, _native.ptr(out), err, _native.ERR_LEN)
    if rc != 0:
        raise RuntimeError(_native.text(err))
    return out


def check_replay(model: SensorModel, kind: str, log_columns) -> None:
    """Raise ModelError unless `model`'s `kind` chain can replay a log with these ctx_ columns (a dict of
    columns gives its keys): every condition names one of them (simulate on no rows)."""
    simulate(model, kind, [], [], [], {c: [] for c in log_columns}, seed=0)


def effect_logpdf(name: str, params: dict, x_in, x_out, mixture: Mixture | None = None) -> np.ndarray:
    """log density [log 1/m] of an effect's output x_out given its input x_in (arrays broadcast).

    Closed forms exist for gaussian, range_noise, rayleigh_short, nlos_bias and gmm (pass `mixture`;
    x_in is then the true range); ValueError for the others.
    """
    x_in, x_out = np.broadcast_arrays(np.asarray(x_in, dtype=np.float64), np.asarray(x_out, dtype=np.float64))
    if name == "gmm":
        if mixture is None:
            raise ValueError("effect_logpdf('gmm', ...) needs mixture=")
        return mixture.conditional_logpdf(x_in, x_out)
    if not effect_has_logpdf(name):
        raise ValueError(f"effect '{name}' has no closed-form log-density")
    ffi, lib = _native.load()
    keys = [ffi.new("char[]", str(k).encode()) for k in params]
    key_array = ffi.new("char *[]", keys)
    values = _native.doubles([float(v) for v in params.values()])
    shape = x_in.shape
    a, b = np.ascontiguousarray(x_in.ravel()), np.ascontiguousarray(x_out.ravel())
    out = np.empty(len(a))
    err = _native.err_buffer()
    value_ptr = _native.ptr(values) if len(values) else ffi.NULL
    if lib.nps_effect_logpdf_named(name.encode(), len(keys), key_array, value_ptr, len(a), _native.ptr(a),
                                   _native.ptr(b), _native.ptr(out), err, _native.ERR_LEN) != 0:
        raise ValueError(_native.text(err))
    return out.reshape(shape)
