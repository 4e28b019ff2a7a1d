"""Hidden-effect cases: "measured" logs made by the simulator from a base model plus effects drawn at random
from the library (random parameters, random condition), which the workflow is not told.

The parameter ranges are those of effects a lab would want its simulation to reproduce: each moves the
readings by clearly more than the base model's own noise (a few centimetres), and none is so large that the
sensor becomes useless. Conditions are the context flags of the synthetic arena (synthetic.py).
"""
import dataclasses
from dataclasses import dataclass

import numpy as np

from finken import models
from finken.rangelog import stream_ids
from finken.discrepancy.dataset import sensor_kind

#: Flags an effect may be conditioned on, per kind, and the chance that a drawn effect gets one.
CONDITION_FLAGS = {"sonar": ("ctx_target_copter",), "ranging": ("ctx_blocked",)}
CONDITION_PROBABILITY = 0.3
#: Effects that cannot act on a kind (cross-talk needs facing sonars, which ranging rows never have).
EXCLUDED_EFFECTS = {"sonar": (), "ranging": ("crosstalk",)}


@dataclass
class HiddenEffect:
    kind: str
    effect: object        # finken.models.Effect

    @property
    def label(self):
        c = f" | {self.effect.condition}" if self.effect.condition else ""
        return f"{self.kind}: {self.effect.name}{c}"


@dataclass
class Case:
    number: int
    hidden: list          # HiddenEffect, in the order they were added
    log: object           # RangeLog with the measured column simulated


def _u(rng, lo, hi):
    return float(rng.uniform(lo, hi))


def draw_params(name, rng, base_sigma):
    """Random parameters of a detectable size for effect `name` (base_sigma: the model's noise [m]);
    returns (params, mixture)."""
    sign = 1.0 if rng.random() < 0.5 else -1.0
    if name == "bias":
        return {"b": sign * _u(rng, 0.05, 0.25)}, None
    if name == "scale":
        return {"k": 1.0 + sign * _u(rng, 0.05, 0.15)}, None
    if name == "gaussian":
        return {"sigma": _u(rng, 2.5, 6.0) * base_sigma}, None
    if name == "range_noise":
        return {"sigma0": _u(rng, 0.0, 1.0) * base_sigma, "sigma1": _u(rng, 0.04, 0.10)}, None
    if name == "rayleigh_short":
        sigma = _u(rng, 0.05, 0.15)
        return {"sigma": sigma, "offset": float(np.sqrt((4 - np.pi) / 2) * sigma)}, None
    if name == "crosstalk":
        return {"p": _u(rng, 0.4, 0.9)}, None
    if name == "dropout":
        return {"p": _u(rng, 0.05, 0.25), "p_per_m": 0.0 if rng.random() < 0.5 else _u(rng, 0.03, 0.08)}, None
    if name == "outlier":
        return {"p": _u(rng, 0.03, 0.15)}, None
    if name == "quantization":
        return {"step": _u(rng, 2.5, 5.0) * base_sigma}, None
    if name == "latency":
        return {"tau": _u(rng, 0.15, 0.4)}, None
    if name == "nlos_bias":
        return {"mean": _u(rng, 0.06, 0.2)}, None
    if name == "gmm":
        return {}, _bimodal_mixture(rng, base_sigma)
    raise ValueError(f"no parameter range for effect '{name}'")


def _bimodal_mixture(rng, base_sigma):
    """A two-component joint mixture of (true, measured): mostly the true range with the base noise, sometimes
    a reading displaced by 0.15-0.3 m (a second echo path), a shape no single simple effect reproduces."""
    var_t = 0.5                                 # spread of the true range [m^2]
    shift, s2 = _u(rng, 0.15, 0.3), _u(rng, 0.03, 0.08)
    w2 = _u(rng, 0.2, 0.35)
    means = [[1.5, 1.5], [1.5, 1.5 + shift]]
    covs = [[[var_t, var_t], [var_t, var_t + base_sigma ** 2]], [[var_t, var_t], [var_t, var_t + s2 ** 2]]]
    return models.Mixture([1 - w2, w2], means, covs)


def base_sigma(model, kind):
    """The noise of a model's chain [m]: the sigma of its first gaussian effect, else 0.03 m."""
    for e in model.chains[kind].effects:
        if e.name == "gaussian":
            return float(e.params["sigma"])
    return 0.03


def draw_effect(rng, model, kind, name, log):
    """A HiddenEffect of effect `name` on `kind` with random parameters and maybe a condition that holds on
    at least 5 % of the kind's rows of `log`."""
    params, mixture = draw_params(name, rng, base_sigma(model, kind))
    condition = None
    if name != "crosstalk" and rng.random() < CONDITION_PROBABILITY:
        rows = np.array([sensor_kind(s) == kind for s in log.sensor])
        usable = [c for c in CONDITION_FLAGS[kind] if c in log.ctx and np.mean(log.ctx[c][rows] != 0) >= 0.05]
        if usable:
            condition = usable[int(rng.integers(len(usable)))]
    return HiddenEffect(kind, models.Effect(name, params, condition, mixture))


def hidden_model(model, hidden):
    for h in hidden:
        model = model.with_effect(h.kind, h.effect)
    return model


def simulate_measured(truth, model, seed):
    """A copy of the RangeLog `truth` whose measured column is simulated by `model` (rows in file order)."""
    measured = np.full(len(truth), np.nan)
    streams = stream_ids(truth)
    kinds = np.array([sensor_kind(s) for s in truth.sensor])
    for i, kind in enumerate(("sonar", "ranging")):
        rows = np.flatnonzero(kinds == kind)
        if rows.size:
            ctx = {**{k: v[rows] for k, v in truth.ctx.items()}, "ctx_vehicle": truth.vehicle[rows]}
            measured[rows] = models.simulate(model, kind, truth.t[rows], truth.true_range[rows], streams[rows], ctx,
                                             seed + i)
    return dataclasses.replace(truth, measured=measured, ctx=dict(truth.ctx), extra=dict(truth.extra))


def make_cases(truth, model, n_cases, seed, n_none=3, n_two=3):
    """`n_cases` Cases on the ground truth `truth`: n_none without effect, n_two with two effects (on one
    kind or both), the rest with one; single effects go through the whole library in a random order, then
    are drawn at random. Deterministic for a seed."""
    rng = np.random.default_rng(seed)
    names = list(models.EFFECT_NAMES)
    n_one = n_cases - n_none - n_two
    singles = list(rng.permutation(names))
    while len(singles) < n_one:
        singles.append(names[int(rng.integers(len(names)))])
    plan = [[] for _ in range(n_none)] + [[s] for s in singles[:n_one]]
    for _ in range(n_two):
        plan.append(list(rng.choice(names, 2, replace=False)))
    order = rng.permutation(len(plan))
    cases = []
    for number, k in enumerate(order, start=1):
        hidden = []
        for name in plan[k]:
            kinds = [kd for kd in ("sonar", "ranging") if name not in EXCLUDED_EFFECTS[kd]]
            kind = kinds[int(rng.integers(len(kinds)))]
            hidden.append(draw_effect(rng, model, kind, str(name), truth))
        measured = simulate_measured(truth, hidden_model(model, hidden), int(rng.integers(1, 2**31)))
        cases.append(Case(number, hidden, measured))
    return cases
