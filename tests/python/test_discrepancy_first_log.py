"""Pieces of the discrepancy workflow for a lab's first real log (issue 29), each on hand-made data:
the model's range against the readings, values beyond physical sense, sensors left out, the condition each
context column offers (a flag's side, a fitted cut), recordings as blocks, the preference for library effects
over a mixture, the gain test and the stability text.

Statistical checks (fixed seeds; the stated probability is that of a false failure over random seeds):
- the cut of a continuous column: 20 000 rows, residual noise 0.02 m, a 0.1 m bias where x >= 0.6, x uniform
  on [0, 1]; the fitted cut must fall within one quantile step (0.05) of 0.6: the gap contrast at the true
  cut exceeds that one step away by ~0.005 m, ~25 standard errors of a W1 of 10 000 rows.
"""
import numpy as np
import pytest

from finken import models
from finken.discrepancy import condition_search, dataset, glitches, ranges, selection, stability, synthetic
from finken.discrepancy.candidates import Candidate, complexity
from finken.discrepancy.fitting import Fit
from finken.discrepancy.selection import GainTest
from finken.rangelog import RangeLog


@pytest.fixture(scope="module")
def base():
    return models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)


def _ranging_log(true_range, measured, ctx=None, group=None):
    n = len(true_range)
    return RangeLog("lab.csv", np.arange(n) * 0.1, np.ones(n), np.full(n, "ranging"), np.full(n, 2.0),
                    np.asarray(true_range, float), np.asarray(measured, float), ctx or {}, {},
                    line=np.arange(n) + 2, group=group,
                    group_names=None if group is None else np.unique(group).astype(str))


def test_readings_beyond_the_model_are_counted_and_the_range_fitted(base):
    tr = np.r_[np.linspace(0.5, 2.0, 300), np.linspace(3.0, 12.0, 700)]
    meas = tr + 0.02
    log = _ranging_log(tr, meas)
    (s,) = ranges.sensor_ranges(log, base)
    assert (s.sensor, s.rows, s.readings, s.true_beyond, s.readings_beyond) == ("ranging", 1000, 1000, 700, 700)
    fitted, kinds = ranges.fit_ranges(log, base)
    assert fitted.chains["ranging"].max_range == pytest.approx(12.02 * (1 + ranges.RANGE_HEADROOM))   # room beyond
    assert kinds["ranging"].source == "fitted" and kinds["ranging"].rows_affected == 700
    assert base.chains["ranging"].max_range == 2.5                       # the input model is left alone
    given, kinds = ranges.fit_ranges(log, base, {"ranging": 15.0})
    assert given.chains["ranging"].max_range == 15.0 and kinds["ranging"].source == "given"
    assert "700 of 1000 true ranges" in ranges.describe([s], base)[0]


def test_a_sensor_clamping_below_the_model_gets_that_maximum(base):
    tr = np.linspace(0.5, 4.0, 1000)
    log = _ranging_log(tr, np.minimum(tr, 2.0))                         # 43 % of the readings sit at 2.0
    fitted, kinds = ranges.fit_ranges(log, base)
    assert fitted.chains["ranging"].max_range == 2.0 and kinds["ranging"].changed
    unchanged, kinds = ranges.fit_ranges(_ranging_log(tr, np.minimum(tr, 2.5)), base)
    assert unchanged is base and not kinds["ranging"].changed


def test_glitches_are_no_readings_of_the_range_and_a_unit_error_is_said(base):
    tr = np.linspace(0.5, 2.0, 500)
    meas = tr + 0.02
    meas[[41, 42, 43, 44]] = [1e300, -12.84, 0.0, np.inf]
    log = _ranging_log(tr, meas)
    code = glitches.classify_log(log, glitches.limits(log, base))
    assert np.flatnonzero(code).tolist() == [41, 42, 43, 44]
    assert code[41:45].tolist() == [4, 1, 2, 3]                          # absurd, negative, zero, non-finite
    (s,) = ranges.sensor_ranges(log, base, code > 0)
    assert (s.readings, s.readings_beyond) == (496, 0)                  # the glitches hold no reading of the range
    unchanged, kinds = ranges.fit_ranges(log, base, glitch=code > 0)
    assert unchanged is base and not kinds["ranging"].changed
    assert ranges.unit_notes(_ranging_log(np.full(500, 2600.0), np.full(500, 2600.0)), base) == [
        "ranging: true ranges up to 2600 m, more than 1000 times the model's maximum range (2.5 m): a unit error? "
        "(see --unit)"]


def test_a_silent_sensor_and_a_short_log_are_left_out_and_said(base):
    silent = ranges.sensor_ranges(_ranging_log(np.ones(500), np.full(500, np.nan)), base)
    out, notes = ranges.left_out(silent)
    assert out == {"ranging"} and notes == ["ranging never reported: no reading on any of its 500 rows "
                                            "(measured empty); left out"]
    out, notes = ranges.left_out(ranges.sensor_ranges(_ranging_log([1.0, 1.1], [1.0, 1.1]), base))
    assert out == {"ranging"} and "2 rows with a reading, too few to decide" in notes[0]


def test_a_flag_offers_the_side_where_the_disagreement_is():
    rng = np.random.default_rng(1)
    flag = (rng.random(4000) < 0.3).astype(float)
    simulated = rng.normal(0, 0.02, 4000)
    measured = rng.normal(0, 0.02, 4000) + 0.1 * (flag == 0)
    got = condition_search.side_conditions({"ctx_los": flag}, measured, simulated)
    assert got == {"ctx_los": "ctx_los == 0"}
    assert condition_search.side_conditions({"ctx_los": flag}, simulated + 0.1 * flag, simulated) == \
        {"ctx_los": "ctx_los"}


def test_a_continuous_column_is_cut_where_the_disagreement_starts():
    rng = np.random.default_rng(2)
    x = rng.random(20000)
    simulated = rng.normal(0, 0.02, x.size)
    measured = rng.normal(0, 0.02, x.size) + 0.1 * (x >= 0.6)
    (cond,) = condition_search.side_conditions({"ctx_rssi": x}, measured, simulated).values()
    column, op, cut = cond.split()
    assert (column, op) == ("ctx_rssi", ">=") and abs(float(cut) - 0.6) <= 0.05
    assert models.canonical_condition(cond) == cond                 # written as the model file writes it


def test_complexity_counts_terms_and_cuts():
    assert complexity(Candidate("ranging", "bias"), {"b": 0}) == 1
    assert complexity(Candidate("ranging", "bias", "ctx_nlos"), {"b": 0}) == 2
    assert complexity(Candidate("ranging", "bias", "ctx_nlos == 0"), {"b": 0}) == 2
    assert complexity(Candidate("ranging", "bias", "ctx_rssi < -85"), {"b": 0}) == 3
    assert complexity(Candidate("ranging", "bias", "ctx_nlos and ctx_rssi < -85"), {"b": 0}) == 4


def test_recordings_are_blocks_held_out_whole_without_history_across_them(base):
    group = np.repeat(np.arange(20), 50)
    log = _ranging_log(np.ones(1000), np.ones(1000), group=group)
    kr = dataset.prepare(log, base, seed=3)["ranging"]
    assert kr.by_recording and np.array_equal(kr.block, group)
    held = {int(g) for g in np.unique(group[kr.heldout])}
    assert len(held) == 8 and all(kr.heldout[group == g].all() for g in held)
    sub = dataset.sample_blocks(kr, "heldout", 10**6, np.random.default_rng(0))
    assert sub.scored.all()                                          # no warm-up rows from another recording
    assert len(np.unique(sub.sim_stream)) == 8                       # one simulator stream per recording


def _fit(name, gap_m, cond=None, params=None):
    return Fit(Candidate("ranging", name, cond), params or {"x": 1.0}, "test", 0.0, heldout_gap=gap_m)


def test_a_mixture_is_named_only_when_no_library_effect_comes_close():
    masks = lambda cand: np.ones(10, bool)  # noqa: E731
    far = lambda winner, rival: 0.5  # noqa: E731
    gmm = _fit("gmm", 0.028, "ctx_nlos", {"components": 6.0})      # margin: max(0.25 x 0.003, 0.02 x 0.156)
    close = [gmm, _fit("nlos_bias", 0.031, "ctx_nlos")]               # within the margin 0.00312 m
    sel = selection.select("ranging", close, 0.156, 0.003, masks, far)
    assert sel.added and sel.winner.candidate.name == "nlos_bias" and "comes within" in sel.mixture_set_aside
    distant = [gmm, _fit("nlos_bias", 0.037, "ctx_nlos"), _fit("bias", 0.12)]   # no pair helps either
    sel = selection.select("ranging", distant, 0.156, 0.003, masks, far)
    assert sel.winner.candidate.name == "gmm" and not sel.mixture_set_aside
    pair = selection.select("ranging", distant, 0.156, 0.003, masks, lambda winner, rival: 0.03)
    assert pair.winner.candidate.name == "nlos_bias" and "on top" in pair.mixture_set_aside


def test_the_gain_test_needs_significance_the_floor_and_a_share_of_the_start():
    assert GainTest(0.02, 1e-6, 0.003, 0.15).passed
    assert "not significant" in GainTest(0.02, 0.2, 0.003, 0.15).reason()
    assert "not above the noise floor" in GainTest(0.002, 1e-6, 0.003, 0.15).reason()
    assert "less than 5%" in GainTest(0.0045, 1e-6, 0.001, 0.15).reason()
    sel = selection.select("ranging", [_fit("crosstalk", 0.0955)], 0.1, 0.001, lambda c: np.ones(3, bool),
                           lambda w, r: 0.5, lambda winner: GainTest(0.0045, 1e-6, 0.001, 0.15))
    assert not sel.added and "fails the gain test" in sel.reason


def test_an_unstable_name_names_its_rivals():
    s = stability.Stability("ranging: gmm | ctx_nlos", 0.6, 10, {"ranging: nlos_bias | ctx_nlos": 4})
    assert not s.stable and s.text() == ("ranging: gmm | ctx_nlos: chosen in 60% of 10 resamples; the data "
                                         "cannot tell it from ranging: nlos_bias | ctx_nlos (4)")
    assert stability.Stability("ranging: bias", 0.9, 10, {"ranging: scale": 1}).stable
