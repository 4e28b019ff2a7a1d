"""Glitches: readings a sensor reports that have nothing to do with the range (shared/spec/range-log.md).

A reading is a glitch when it is negative, zero, infinite, or absurd: farther than ABSURD_FACTOR times the longer
of the model's maximum range and the longest true range of its kind in the log (no sensor of that kind could have
measured it). A missing reading (NaN) is no glitch: the sensor reported nothing.

Glitches are data about the sensor: they are counted per sensor and stream, kept out of the fit and the gap of
the continuous error (their rows are not scored, and the continuous error is simulated without the model's
`glitch` effects, which replace a reading at random whatever it was: nps_effect.h), and modelled by the `glitch`
effect of each kind: with probability p a reading becomes one of the glitch values seen (all of them up to
MAX_VALUES, else MAX_VALUES of their quantiles). The workflow sets that effect when the log's glitch count is not
what the model gives on the same rows (SIM_REPLICATES simulations of the model; Fisher's exact test of the two
proportions, two-sided, at level RATE_ALPHA: a simulation's own count is a random number too) and reports the
rates before and after.
"""
import copy
import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy import stats

from finken import models
from finken.discrepancy.dataset import sample_blocks, simulate_subset
from finken.discrepancy.ranges import rows_of
from finken.rangelog import stream_ids

#: A reading farther than this multiple of max(model's maximum range, longest true range) is absurd.
ABSURD_FACTOR = 2.0
#: Glitch values a glitch effect holds at most (the C library's limit, nps_effect.h).
MAX_VALUES = 64
#: Level of the test that decides whether the model's glitch rate must change; simulations of the model it counts,
#: and the rows they cover at most.
RATE_ALPHA, SIM_REPLICATES, SIM_ROWS = 0.01, 4, 200000
#: Glitch types, in the order of their codes (0: no glitch).
TYPES = ("negative", "zero", "non_finite", "absurd")
#: The rule, for reports.
RULE = (f"a reading is a glitch when it is negative, zero, infinite, or farther than {ABSURD_FACTOR:g} times the "
        "longer of the model's maximum range and the longest true range of its kind in the log")


def absurd_limit(max_range_m, true_range):
    """The reading [m] beyond which a reading of this kind is absurd."""
    longest = float(np.max(true_range)) if len(true_range) else 0.0
    return ABSURD_FACTOR * max(float(max_range_m), longest)


def classify(measured, limit_m):
    """Glitch type code per reading: 0 none, then 1 + the index in TYPES (NaN, no reading, is none)."""
    measured = np.asarray(measured, dtype=np.float64)
    code = np.zeros(measured.shape, dtype=np.int8)
    with np.errstate(invalid="ignore"):
        code[measured > limit_m] = 4
        code[np.isinf(measured)] = 3
        code[measured == 0] = 2
        code[(measured < 0) & np.isfinite(measured)] = 1
    return code


def limits(log, model):
    """{kind: absurd_limit} of the kinds of a RangeLog the model has a chain for."""
    kind_rows = rows_of(log)
    return {kind: absurd_limit(chain.max_range, log.true_range[kind_rows[kind]])
            for kind, chain in model.chains.items() if kind_rows[kind].any()}


def classify_log(log, kind_limits):
    """Glitch type codes of every row of a RangeLog ({kind: limit}: limits; rows of other kinds: 0)."""
    code = np.zeros(len(log), dtype=np.int8)
    kind_rows = rows_of(log)
    for kind, limit in kind_limits.items():
        code[kind_rows[kind]] = classify(log.measured[kind_rows[kind]], limit)
    return code


def continuous(model):
    """The model without its glitch effects: what the continuous error of a reading is simulated with."""
    if not any(e.name == "glitch" for c in model.chains.values() for e in c.effects):
        return model
    out = copy.deepcopy(model)
    out.source = None
    for chain in out.chains.values():
        chain.effects = [e for e in chain.effects if e.name != "glitch"]
    return out


def glitch_effects(model, kind):
    """The glitch effects of a kind's chain."""
    chain = model.chains.get(kind)
    return [e for e in chain.effects if e.name == "glitch"] if chain else []


def with_glitches(model, kind, effects):
    """A copy of the model whose `kind` chain has these glitch effects instead of its own (last in the chain)."""
    out = copy.deepcopy(model)
    out.source = None
    chain = out.chains[kind]
    chain.effects = [e for e in chain.effects if e.name != "glitch"] + copy.deepcopy(list(effects))
    out.native()
    return out


def fitted_effect(glitch_values, rows):
    """The glitch effect of a kind from its glitch readings on `rows` rows: p = their share, the values
    themselves (or MAX_VALUES of their quantiles, lowest and highest included)."""
    values = np.sort(np.asarray(glitch_values, dtype=np.float64))
    if values.size > MAX_VALUES:
        values = np.quantile(values, np.linspace(0.0, 1.0, MAX_VALUES), method="inverted_cdf")
    return models.Effect("glitch", {"p": len(glitch_values) / rows}, values=values.tolist())


@dataclass
class Count:
    """Rows, readings and glitches of a group of rows (a kind, a sensor or a stream), by type."""
    label: str
    rows: int
    readings: int          # rows with a reading (a glitch is one)
    by_type: dict          # type -> count

    @property
    def glitches(self):
        return sum(self.by_type.values())

    @property
    def rate(self):
        """Glitches per row (the glitch effect's p)."""
        return self.glitches / self.rows if self.rows else 0.0

    def to_dict(self):
        return {"group": self.label, "rows": self.rows, "readings": self.readings, "glitches": self.glitches,
                "rate": self.rate, **self.by_type}


def count(label, measured, code):
    """Count of the rows given by their readings and glitch codes."""
    return Count(label, len(measured), int(np.sum(~np.isnan(measured))),
                 {t: int(np.sum(code == i + 1)) for i, t in enumerate(TYPES)})


def counts(log, code):
    """{"kinds", "sensors", "streams": [Count]} of a RangeLog and its glitch codes; streams are named
    "vehicle V sensor" or "vehicle V ranging peer P"."""
    kind_rows = rows_of(log)
    out = {"kinds": [count(k, log.measured[rows], code[rows]) for k, rows in sorted(kind_rows.items()) if rows.any()],
           "sensors": [count(s, log.measured[log.sensor == s], code[log.sensor == s])
                       for s in np.unique(log.sensor).tolist()],
           "streams": []}
    streams, first, stream = np.unique(stream_ids(dataclasses.replace(log, group=None)), return_index=True,
                                       return_inverse=True)
    rows = np.bincount(stream, minlength=len(streams))
    readings = np.bincount(stream, ~np.isnan(log.measured), minlength=len(streams))
    by_type = {t: np.bincount(stream, code == i + 1, minlength=len(streams)) for i, t in enumerate(TYPES)}
    for s, row in enumerate(first):
        label = f"vehicle {log.vehicle[row]:g} {log.sensor[row]}" + (
            f" peer {log.peer[row]:g}" if log.sensor[row] == "ranging" else "")
        out["streams"].append(Count(label, int(rows[s]), int(readings[s]), {t: int(n[s]) for t, n in by_type.items()}))
    return out


@dataclass
class RateTest:
    """The log's glitch count on a kind's rows against the model's, and what the workflow did about it."""
    kind: str
    rows: int
    measured: int          # glitches in the log
    model_rate: float      # the input model's glitch rate on the same rows (simulated)
    p: float               # Fisher's exact test of the two counts, two-sided
    effect: object = None  # the glitch effect fitted from the log (None when it has no glitch)

    @property
    def changed(self):
        """The model's glitch rate is not the log's: its glitch effect is replaced by `effect` (or removed)."""
        return self.p < RATE_ALPHA

    def effects_after(self, model):
        """The glitch effects of the kind's chain in the output model."""
        if not self.changed:
            return glitch_effects(model, self.kind)
        return [self.effect] if self.effect is not None else []


def test_kind(kr, model, seed):
    """RateTest of a kind's rows (dataset.KindRows): the log's glitches against those of the model (its glitch
    effects and whatever else it gives that is a glitch, SIM_REPLICATES simulations of whole time blocks, up to
    SIM_ROWS rows); the fitted effect."""
    found = kr.glitch > 0
    subset = sample_blocks(kr, None, SIM_ROWS, np.random.default_rng(seed))
    simulated = sum(int(np.sum(classify(simulate_subset(model, kr, subset, seed + i)[subset.counted],
                                        kr.glitch_limit) > 0)) for i in range(SIM_REPLICATES))
    n_sim = SIM_REPLICATES * int(subset.counted.sum())
    model_rate = simulated / n_sim if n_sim else 0.0
    g = int(found.sum())
    p = 1.0 if kr.n == 0 else float(stats.fisher_exact([[g, kr.n - g], [simulated, n_sim - simulated]])[1])
    effect = fitted_effect(kr.measured[found], kr.n) if found.any() else None
    return RateTest(kr.kind, kr.n, int(found.sum()), model_rate, p, effect)


def describe(kind_counts, tests):
    """Lines for the terminal: each kind's glitches by type, and what the model makes of them."""
    lines = []
    for c in kind_counts:
        if c.glitches:
            types = ", ".join(f"{n} {t.replace('_', '-')}" for t, n in c.by_type.items() if n)
            lines.append(f"{c.label}: {c.glitches} glitches in {c.rows} rows ({c.rate:.3%}: {types})")
    for t in tests:
        if t.changed:
            what = (f"glitch effect p = {t.effect.params['p']:.4g} with {len(t.effect.values)} values"
                    if t.effect is not None else "glitch effect removed")
            lines.append(f"{t.kind}: glitch rate {t.measured / t.rows:.3%} in the log against {t.model_rate:.3%} "
                         f"in the model (Fisher's exact p = {t.p:.2g}): {what}")
    return lines
