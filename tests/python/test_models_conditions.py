"""Conditions of effects from Python (finken.models: condition_mask, condition_columns, canonical_condition, and
conditions in models): the C parser and evaluator through cffi. Expected values are worked out by hand."""
import numpy as np
import pytest

from finken import models as M

NAN = float("nan")
TWO_TERMS = "ctx_nlos == 0 and ctx_rssi < -85.5"


def test_a_mask_over_columns():
    nlos = np.array([0.0, 1.0, -0.0, NAN, 2.0])
    rssi = np.array([-90.0, -85.5, -85.0, -90.0, NAN])
    ctx = {"ctx_nlos": nlos, "ctx_rssi": rssi}
    assert M.condition_mask("ctx_nlos == 0", ctx, 5).tolist() == [True, False, True, False, False]
    assert M.condition_mask("ctx_nlos", ctx, 5).tolist() == [False, True, False, False, True]   # non-zero
    assert M.condition_mask("ctx_rssi<-85.5", ctx, 5).tolist() == [True, False, False, True, False]
    assert M.condition_mask("ctx_rssi >= -85.5", ctx, 5).tolist() == [False, True, True, False, False]
    assert M.condition_mask("ctx_rssi != -85.5", ctx, 5).tolist() == [True, False, True, True, False]  # NaN: no
    assert M.condition_mask(TWO_TERMS, ctx, 5).tolist() == [True, False, False, False, False]
    # keys without the prefix, a scalar for every row, no condition
    assert M.condition_mask("ctx_nlos == 0", {"nlos": nlos}, 5).tolist() == [True, False, True, False, False]
    assert M.condition_mask("ctx_rssi > -100", {"ctx_rssi": -90.0}, 3).tolist() == [True] * 3
    mask = M.condition_mask(None, {}, 4)
    assert mask.dtype == bool and mask.tolist() == [True] * 4


def test_a_malformed_condition_or_a_missing_column_is_refused():
    with pytest.raises(ValueError, match=r"^condition 'ctx_a or ctx_b': 'or' is not supported"):
        M.condition_mask("ctx_a or ctx_b", {"ctx_a": [1.0], "ctx_b": [1.0]}, 1)
    with pytest.raises(ValueError, match=r"^condition 'ctx_nlos == 0 and ctx_rssi < -85.5': no column 'ctx_rssi' "
                                         r"was given$"):
        M.condition_mask(TWO_TERMS, {"ctx_nlos": [0.0]}, 1)
    with pytest.raises(ValueError, match="at most 2 terms"):
        M.condition_columns("ctx_a and ctx_b and ctx_c")
    with pytest.raises(ValueError, match=r"unknown operator '=>'"):
        M.Effect("bias", {"b": 0.1}, condition="ctx_a => 1")


def test_columns_and_canonical_text():
    assert M.condition_columns(TWO_TERMS) == ("ctx_nlos", "ctx_rssi")
    assert M.condition_columns("ctx_d > 0.5 and ctx_d <= 1.5") == ("ctx_d",)
    assert M.condition_columns("ctx_blocked") == ("ctx_blocked",)
    assert M.condition_columns(None) == ()
    assert M.canonical_condition(" ctx_nlos==0.0  and ctx_rssi<-85.50") == TWO_TERMS
    assert M.canonical_condition("ctx_blocked") == "ctx_blocked"
    assert M.Effect("bias", {"b": 0.1}, condition="ctx_rssi<=1e-5").condition == "ctx_rssi <= 1e-05"
    # a number is written as repr() writes it, without a trailing ".0", and reads back as the same double
    for value in (0.1, -85.5, 1 / 3, 1e-300, 1.7976931348623157e308, 123456789012345678.0, 100.0, 1e16, 2.5e-7):
        number = M.canonical_condition(f"ctx_a < {value!r}").split()[-1]
        assert number == repr(value).removesuffix(".0") and float(number) == value, number


def _replay_model(condition, log_columns=("ctx_nlos", "ctx_rssi")):
    base = M.SensorModel({"ranging": M.SensorChain("ranging", 0.0, 100.0, "max", [])}).for_log(log_columns)
    return base.with_effect("ranging", M.Effect("bias", {"b": 0.5}, condition=condition))


def test_a_condition_round_trips_through_the_model_file(tmp_path):
    model = _replay_model(TWO_TERMS)
    xml = model.to_xml()
    assert 'condition="ctx_nlos == 0 and ctx_rssi &lt; -85.5"' in xml
    assert M.SensorModel.from_xml(xml, log_columns=model.log_columns) == model
    model.save(tmp_path / "m.xml")
    loaded = M.SensorModel.load(tmp_path / "m.xml", log_columns=model.log_columns)
    assert loaded == model and loaded.chains["ranging"].effects[0].condition == TWO_TERMS
    # a condition written another way is kept in canonical text, so the model still round-trips
    other = _replay_model("ctx_rssi<-85.50 and ctx_nlos==0.0")
    assert other.chains["ranging"].effects[0].condition == "ctx_rssi < -85.5 and ctx_nlos == 0"
    assert M.SensorModel.from_xml(other.to_xml(), log_columns=other.log_columns) == other


def test_simulate_applies_an_effect_only_where_its_condition_holds():
    model = _replay_model(TWO_TERMS)
    ctx = {"ctx_nlos": [0.0, 0.0, 1.0, NAN, 0.0], "ctx_rssi": [-90.0, -80.0, -90.0, -90.0, NAN]}
    out = M.simulate(model, "ranging", np.arange(5) * 0.05, np.full(5, 1.0), np.zeros(5), ctx, seed=1)
    assert out.tolist() == [1.5, 1.0, 1.0, 1.0, 1.0]
    # on many rows the simulator applies it exactly where condition_mask says it holds
    rng = np.random.default_rng(3)
    n = 2000
    ctx = {"ctx_nlos": rng.choice([0.0, 1.0, NAN], n), "ctx_rssi": rng.uniform(-100.0, -70.0, n)}
    truth = rng.uniform(0.5, 2.0, n)
    out = M.simulate(model, "ranging", np.arange(n) * 0.05, truth, np.zeros(n), ctx, seed=1)
    mask = M.condition_mask(TWO_TERMS, ctx, n)
    assert 0 < mask.sum() < n
    assert np.array_equal(out, truth + 0.5 * mask)


def test_a_replay_needs_every_column_of_a_condition():
    model = _replay_model("ctx_blocked == 0 and ctx_wall_dist < 0.5", log_columns=())
    with pytest.raises(M.ModelError, match=r"^condition 'ctx_blocked == 0 and ctx_wall_dist < 0.5' of the ranging "
                                           r"chain's effect 1 \(bias\): the log has no column ctx_wall_dist$"):
        M.check_replay(model, "ranging", ["ctx_blocked"])
    M.check_replay(model, "ranging", ["ctx_blocked", "ctx_wall_dist"])
    with pytest.raises(M.ModelError, match=r"condition 'ctx_rssi': unknown context column"):
        M.check_replay(_replay_model(TWO_TERMS), "ranging", ["ctx_nlos"])
