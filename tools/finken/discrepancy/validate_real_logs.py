"""Scenarios of `make validate` for real sensor logs as they come: glitches, per-unit offsets, the error's shape.
Each runs the workflow over validate_scenarios.SEEDS on the synthetic arena's ground truth with a hidden error and
checks that it is named right in every seed:

- glitches: a ranging bias, and GLITCH_SHARE of the readings of each kind replaced by glitches of every type
  (negative, zero, infinite, absurd: 270 m and a wrap-around of 1e5 m): the bias alone is named, its gap halves,
  every glitch is counted by type, and each kind gets a glitch effect whose rate is the log's;
- vehicle_offsets: each copter's ranging unit its own offset (VEHICLE_BIAS): `bias_per_vehicle` named, every
  vehicle's value within VALUE_TOLERANCE of its own, the gap after at most a quarter of the gap before;
- right_skew: late multipath arrivals on top of a constant antenna-delay offset (an exponential excess and a
  negative bias): nlos_bias and bias named (one of them may tie with a rival, named as undecided beside it),
  never the mirror (rayleigh_short) nor a mixture;
- curve_of_context: a ranging bias that grows smoothly with the copter's speed (a bias_curve over ctx_speed):
  `bias_curve over ctx_speed` named;
- tied: a scale error of the downward sonar at a hover height that hardly changes, where a bias reads the same:
  the effect named is the scale or the bias and the other is reported undecided beside it.
"""
import dataclasses

import numpy as np

from finken import models
from finken.discrepancy import hidden
from finken.discrepancy.validate_scenarios import SEEDS, hidden_log, named, report, runs_over_seeds

#: Share of each kind's readings made glitches, per type (so 5 x this in all).
GLITCH_SHARE = 0.0006
#: What a glitch reads, per type.
GLITCH_VALUES = {"negative": -12.84, "zero": 0.0, "non_finite": np.inf, "absurd": (270.3, 1.0e5)}
#: Each vehicle's ranging offset [m], and how close a fitted value must come [m].
VEHICLE_BIAS, VALUE_TOLERANCE = {1: -0.11, 2: -0.10, 3: 0.08, 4: 0.0}, 0.03


def with_glitches(log, seed):
    """A copy of `log` with GLITCH_SHARE of each kind's rows per glitch type replaced by that type's value; also
    the counts put in: {(kind, type): n}."""
    rng = np.random.default_rng(seed)
    measured, put = log.measured.copy(), {}
    ranging = log.sensor == "ranging"
    for kind, rows in (("sonar", np.flatnonzero(~ranging)), ("ranging", np.flatnonzero(ranging))):
        n = max(1, round(GLITCH_SHARE * rows.size))
        chosen = rng.permutation(rows)[:n * len(GLITCH_VALUES)].reshape(len(GLITCH_VALUES), n)
        for (glitch_type, value), where in zip(GLITCH_VALUES.items(), chosen):
            measured[where] = np.resize(value, n)
            put[(kind, glitch_type)] = n
    return dataclasses.replace(log, measured=measured), put


def glitch_scenario(base, truth):
    bias = models.Effect("bias", {"b": 0.1})
    logs = {s: with_glitches(hidden_log(truth, base, "ranging", bias, 600 + s), s) for s in SEEDS}
    runs = runs_over_seeds(lambda s: logs[s][0], base)

    def right(seed, result):
        put = logs[seed][1]
        counted = {(c.label, t): n for c in result.glitch_counts["kinds"] for t, n in c.by_type.items()}
        rates = {t.kind: t for t in result.glitch_tests}
        return (named(result) == ["ranging: bias"] and result.gap_after <= 0.5 * result.gap_before
                and counted == put and all(rates[k].changed and rates[k].effect is not None and np.isclose(
                    rates[k].effect.params["p"], sum(n for (kk, _), n in put.items() if kk == k) / rates[k].rows)
                    for k in ("sonar", "ranging")))
    ok = all(right(s, r) for s, r in runs)
    return report("glitches", runs, ok, f"ranging: bias alone named, every glitch counted by type "
                  f"({GLITCH_SHARE:.2%} of each kind's rows per type), glitch effects at the log's rates")


def vehicle_offsets(base, truth):
    hid = [models.Effect("bias", {"b": b}, f"ctx_vehicle == {v}") for v, b in VEHICLE_BIAS.items()]

    def make(seed):
        model = base
        for effect in hid:
            model = model.with_effect("ranging", effect)
        return hidden.simulate_measured(truth, model, 700 + seed)
    runs = runs_over_seeds(make, base)

    def right(result):
        fits = [e.fit for e in result.effects if e.fit.candidate.name == "bias_per_vehicle"]
        return (len(fits) == 1 and result.gap_after <= 0.25 * result.gap_before
                and all(abs(fits[0].params[f"vehicle {v}"] - b) <= VALUE_TOLERANCE for v, b in VEHICLE_BIAS.items()))
    ok = all(right(r) for _, r in runs)
    values = ", ".join(f"{v} {b:+g}" for v, b in VEHICLE_BIAS.items())
    return report("vehicle_offsets", runs, ok, f"ranging: bias_per_vehicle named (hidden {values} m), each within "
                  f"{VALUE_TOLERANCE} m, gap after <= 0.25 x before")


def explained(result, hidden_labels):
    """The sorted labels of the effects named, an effect that tied with one of `hidden_labels` (its undecided
    rival) counted as that one: the report names both, the data cannot tell them apart."""
    labels = []
    for e in result.effects:
        own = e.fit.candidate.label
        rival = e.undecided.candidate.label if e.undecided is not None else None
        labels.append(rival if own not in hidden_labels and rival in hidden_labels else own)
    return sorted(labels)


def right_skew(base, truth):
    model = base.with_effect("ranging", models.Effect("nlos_bias", {"mean": 0.15})).with_effect(
        "ranging", models.Effect("bias", {"b": -0.08}))
    runs = runs_over_seeds(lambda s: hidden.simulate_measured(truth, model, 800 + s), base)
    hidden_labels = ["ranging: bias", "ranging: nlos_bias"]
    ok = all(explained(r, hidden_labels) == hidden_labels for _, r in runs)
    return report("right_skew", runs, ok, "ranging: nlos_bias and bias named (an exponential excess of 0.15 m on "
                  "an offset of -0.08 m), no mirror, no mixture")


def curve_of_context(base, truth):
    curve = models.BiasCurve("ctx_speed", [0.0, 0.3, 0.6, 0.9], [0.0, 0.04, 0.14, 0.2])
    effect = models.Effect("bias_curve", {}, curve=curve)
    runs = runs_over_seeds(lambda s: hidden_log(truth, base, "ranging", effect, 900 + s), base)
    ok = all(named(r) == ["ranging: bias_curve over ctx_speed"] for _, r in runs)
    return report("curve_of_context", runs, ok, "ranging: bias_curve over ctx_speed named (0 m at rest to 0.2 m at "
                  "0.9 m/s)")


def tied(base, truth):
    down = truth.select(np.flatnonzero(truth.sensor == "sonar_down"))
    runs = runs_over_seeds(lambda s: hidden_log(down, base, "sonar", models.Effect("scale", {"k": 1.1}), 1000 + s),
                           base)

    def right(result):
        if len(result.effects) != 1 or result.effects[0].undecided is None:
            return False
        e = result.effects[0]
        return {e.fit.candidate.name, e.undecided.candidate.name} == {"scale", "bias"}
    ok = all(right(r) for _, r in runs)
    return report("tied", runs, ok, "sonar_down at a hover height of 0.6 +- 0.03 m with a scale of 1.1: scale and "
                  "bias named as undecided")


def scenarios(base, truth):
    """[(passed, text)] of every scenario."""
    return [glitch_scenario(base, truth), vehicle_offsets(base, truth), right_skew(base, truth),
            curve_of_context(base, truth), tied(base, truth)]
