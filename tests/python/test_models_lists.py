"""Effects with list parameters (glitch, bias_curve) and the ctx_vehicle slot from Python (finken.models): read back
from C, written by to_xml, replayed by simulate.

Statistics: a glitch rate p = 0.0018 estimated from N = 2 000 000 replayed rows has the binomial standard error
sqrt(p (1 - p) / N) = 3.0e-5 (1.7 % of p); the tolerance is K_SIGMA = 5 standard errors (false failure 5.7e-7), and a
rate 20 % off is 12 standard errors away: the same check against 0.8 p and 1.2 p must fail on the same rows. Each
value's share of the glitches with p = 1 on 200 000 rows, within 5 binomial standard errors (share 1/4: +-0.005).
"""
import numpy as np
import pytest

from finken import models as M

K_SIGMA = 5.0
P = 0.0018
VALUES = [-12.84, 0.0, 270.1, 1e5, float("inf"), float("-inf")]
KNOTS, BIASES = [0.0, 10.0, 30.0, 60.0], [0.02, 0.05, 0.2, 0.3]


def chain(kind, *effects, log_columns=(), min_range=0.2, max_range=3.0):
    """A model of one chain [min_range, max_range] holding `effects`, for a replay of a log with `log_columns`."""
    base = M.SensorModel({kind: M.SensorChain(kind, min_range, max_range, "none", [])}).for_log(log_columns)
    for effect in effects:
        base = base.with_effect(kind, effect)
    return base


def replay(model, kind, true_range, ctx=None, seed=1, streams=1):
    n = len(true_range)
    return M.simulate(model, kind, np.arange(n) // streams * 0.05, true_range, np.arange(n) % streams, ctx, seed)


def within(count, n, p):
    return abs(count / n - p) <= K_SIGMA * np.sqrt(p * (1 - p) / n)


def test_names_parameters_and_a_round_trip_through_the_model_file(tmp_path):
    assert M.ALL_EFFECT_NAMES == M.EFFECT_NAMES + ("glitch", "bias_curve")   # EFFECT_NAMES: the spec's, as before
    assert M.effect_params("glitch") == ("p",) and M.effect_text_params("glitch") == ("values",)
    assert M.effect_params("bias_curve") == () and M.effect_text_params("bias_curve") == ("over", "at", "b")
    assert M.effect_text_params("bias") == ()
    glitch = M.Effect(name="glitch", params={"p": P}, values=VALUES, condition="ctx_vehicle == 2")
    curve = M.Effect("bias_curve", curve=M.BiasCurve("ctx_rssi", [-90, -60], [0.3, 0]))
    model = chain("ranging", glitch, M.Effect("bias_curve", curve=M.BiasCurve("true_range", KNOTS, BIASES)), curve,
                  log_columns=["ctx_rssi"])
    xml = model.to_xml()
    assert ('<effect name="glitch" p="0.0018" values="-12.84 0.0 270.1 100000.0 inf -inf" '
            'condition="ctx_vehicle == 2"/>') in xml
    assert '<effect name="bias_curve" over="true_range" at="0.0 10.0 30.0 60.0" b="0.02 0.05 0.2 0.3"/>' in xml
    model.save(tmp_path / "m.xml")
    loaded = M.SensorModel.load(tmp_path / "m.xml", log_columns=["ctx_rssi"])
    assert loaded == model   # read back from C: values, over, at and b as given
    effects = loaded.chains["ranging"].effects
    assert effects[0].values == VALUES and effects[0].curve is None
    assert effects[2].curve == M.BiasCurve("ctx_rssi", [-90.0, -60.0], [0.3, 0.0]) and effects[2].values is None
    text = M.SensorModel.from_string("ranging: glitch(p=0.0018, values=-12.84 0 270.1 1e5 inf -inf) "
                                     "if ctx_vehicle == 2; bias_curve(over=true_range, at=0 10 30 60, "
                                     "b=0.02 0.05 0.2 0.3)")
    assert text.chains["ranging"].effects == effects[:2]


def test_glitches_happen_at_rate_p_with_their_values_unclamped_and_reproducibly():
    model = chain("sonar", M.Effect("gaussian", {"sigma": 0.01}), M.Effect("glitch", {"p": P}, values=VALUES))
    n = 2_000_000
    out = replay(model, "sonar", np.full(n, 1.5), streams=20)
    glitched = ~((out >= 0.2) & (out <= 3.0))   # every value lies outside the limits (0 too): none is clamped
    assert set(out[glitched].tolist()) <= set(VALUES)
    count = int(glitched.sum())
    assert within(count, n, P), count
    assert not within(count, n, 0.8 * P) and not within(count, n, 1.2 * P)
    first, again = replay(model, "sonar", np.full(n, 1.5), streams=20), replay(model, "sonar", np.full(n, 1.5), seed=2)
    assert np.array_equal(first, out) and not np.array_equal(again, out)   # per seed
    # each value with its share; a no-echo reading is replaced too (true range beyond the maximum)
    every = chain("sonar", M.Effect("glitch", {"p": 1.0}, values=[-1.0, 0.0, 1e5, float("inf")]))
    m = 200_000
    out = replay(every, "sonar", np.full(m, 5.0))
    for value in (-1.0, 0.0, 1e5, float("inf")):
        assert within(int(np.sum(out == value)), m, 0.25), value


def test_a_bias_curve_over_the_true_range_and_over_a_log_column():
    model = chain("ranging", M.Effect("bias_curve", curve=M.BiasCurve("true_range", KNOTS, BIASES)), min_range=0.0,
                  max_range=1000)
    truth = np.array([0.0, 10.0, 30.0, 60.0, 5.0, 20.0, 45.0, 0.2, 61.0, 500.0])
    expected = np.array([0.02, 0.05, 0.2, 0.3, 0.035, 0.125, 0.25, 0.02 + 0.02 * 0.03, 0.3, 0.3])
    out = replay(model, "ranging", truth)
    assert np.array_equal(out[:4], truth[:4] + BIASES)              # exact at the knots
    assert np.allclose(out[4:], truth[4:] + expected[4:], rtol=0, atol=1e-12)
    # over a replayed log's received power: constant below -90 dBm and above -60 dBm
    rssi = M.Effect("bias_curve", curve=M.BiasCurve("ctx_rssi", [-90, -60], [0.3, 0.0]))
    model = chain("ranging", rssi, log_columns=["ctx_rssi"], min_range=0.0)
    power = np.array([-100.0, -90.0, -75.0, -60.0, -30.0, np.nan])
    out = replay(model, "ranging", np.ones(6), {"ctx_rssi": power})
    assert np.allclose(out, 1.0 + np.array([0.3, 0.3, 0.15, 0.0, 0.0, 0.0]), rtol=0, atol=1e-15)  # NaN: no bias
    with pytest.raises(M.ModelError, match=r"bias_curve over 'ctx_rssi': unknown context column"):
        replay(model, "ranging", np.ones(6), {})


@pytest.mark.parametrize("effect, reason", [
    (M.Effect("glitch", {"p": 0.1}, values=[1.0, float("nan")]),
     r"glitch values: 'nan' is not a number \(finite or \+-inf, never NaN\)"),
    (M.Effect("glitch", {"p": 0.1}, values=[]), r"glitch values: none given \(1 to 64 numbers\)"),
    (M.Effect("glitch", {"p": 0.1}, values=list(range(65))), r"glitch values: more than 64 values"),
    (M.Effect("glitch", {"p": 0.1}), r"effect 'glitch' needs parameter 'values'"),
    (M.Effect("bias_curve", curve=M.BiasCurve("true_range", [0, 10, 10], [0, 1, 2])),
     r"bias_curve at: the knots must increase strictly \(10 then 10\)"),
    (M.Effect("bias_curve", curve=M.BiasCurve("true_range", [0, 1, 2], [0, 1])),
     r"bias_curve: at has 3 values and b has 2 \(need 2 to 16 knots, one b per knot\)"),
    (M.Effect("bias_curve", curve=M.BiasCurve("true_range", [1], [0])),
     r"bias_curve: at has 1 values and b has 1 \(need 2 to 16 knots, one b per knot\)"),
    (M.Effect("bias_curve", curve=M.BiasCurve("true_range", range(17), [0] * 17)),
     r"bias_curve at: more than 16 values"),
    (M.Effect("bias_curve", curve=M.BiasCurve("ctx_rssi", [0, 1], [0, 1])),
     r"bias_curve over 'ctx_rssi': unknown context column \(the simulator has .*, ctx_floor, ctx_target_obstacle, ctx_vehicle\)"),
])
def test_a_bad_list_is_refused_with_the_line_and_the_value(effect, reason):
    with pytest.raises(M.ModelError, match=rf"^<model None>:4: {reason}$"):
        chain("ranging", effect)


def test_ctx_vehicle_fills_the_slot_of_per_vehicle_effects_in_replay():
    model = chain("sonar", M.Effect("bias", {"b": -0.11}, "ctx_vehicle == 1"),
                  M.Effect("scale", {"k": 1.14}, "ctx_vehicle == 2"))
    vehicle = np.array([1.0, 2.0, 3.0, 1.0, 2.0, 3.0])
    out = replay(model, "sonar", np.full(6, 2.0), {"ctx_vehicle": vehicle})
    assert np.allclose(out, [1.89, 2.28, 2.0, 1.89, 2.28, 2.0], rtol=0, atol=1e-15)
    with pytest.raises(M.ModelError, match=r"condition 'ctx_vehicle == 1' of the sonar chain's effect 1 \(bias\): "
                                           r"the log has no column ctx_vehicle"):
        replay(model, "sonar", np.full(6, 2.0), {})
