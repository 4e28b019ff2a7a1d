"""Pieces of the discrepancy workflow that need no fitting: data preparation, conditions, the gap, the tests
and their correction, the selection rule.

Statistical tests here (fixed seeds, so each outcome is deterministic; the stated probability is that of a
false failure over random seeds):
- lag estimate: N = 20 000 rows, residual = -tau * rate + N(0, 0.02 m); the estimate must lie within 5 of its
  own standard errors (HC0) of tau: false failure < 1e-6.
- no disagreement: measured and simulated from the same model; Holm at family-wise error 0.01 flags nothing
  with probability >= 0.99.
- a bias of 0.05 m on the rows of one flag (n ~ 1 200 rows, noise 0.02 m: a shift of 2.5 sigma) must be
  flagged in that condition; power ~ 1 - 1e-12 (KS at n = 1 200 resolves shifts of ~0.2 sigma).
"""
import numpy as np
import pytest
from scipy import stats

from finken import models
from finken.discrepancy import conditions, dataset, gap, localize, selection, synthetic
from finken.discrepancy.candidates import Candidate, effective_mask, same_explanation
from finken.discrepancy.fitting import Fit, KindFitter, lattice_step
from finken.discrepancy.hidden import simulate_measured
from finken.discrepancy.workflow import sim_seed


@pytest.fixture(scope="module")
def base():
    return models.SensorModel.load(models.GAUSSIAN_ONLY_PATH)


@pytest.fixture(scope="module")
def truth():
    return synthetic.ground_truth(4, 60.0, seed=11)


def test_w1_equals_scipy_for_equal_sizes_and_uses_scipy_otherwise():
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=1000), rng.exponential(size=1000)
    assert gap.w1(a, b) == pytest.approx(stats.wasserstein_distance(a, b), rel=1e-12)
    assert gap.w1(a, b[:700]) == pytest.approx(stats.wasserstein_distance(a, b[:700]), rel=1e-12)
    assert gap.w1(a, a + 0.25) == pytest.approx(0.25)        # a shift moves every quantile by 0.25 m


def test_holm_matches_hand_computed_values():
    # p sorted: 0.01, 0.02, 0.03, 0.5 -> 4*0.01, max(.04, 3*.02), max(.06, 2*.03), max(.06, .5)
    np.testing.assert_allclose(localize.holm([0.03, 0.01, 0.5, 0.02]), [0.06, 0.04, 0.5, 0.06])
    assert localize.holm([]).size == 0


def test_range_rate_per_stream():
    t = np.array([0.0, 0.0, 1.0, 1.0, 2.0, 2.0])
    x = np.array([1.0, 5.0, 1.5, 5.0, 2.0, 5.0])       # stream 0 moves at 0.5 m/s, stream 1 stands still
    s = np.array([0, 1, 0, 1, 0, 1])
    np.testing.assert_allclose(dataset.range_rate(t, x, s), [0.5, 0, 0.5, 0, 0.5, 0])


def test_blocks_split_and_subsets(truth, base):
    kinds = dataset.prepare(truth, base, seed=3)
    kr = kinds["sonar"]
    ids = np.unique(kr.block)
    held = np.unique(kr.block[kr.heldout])
    assert 0 < len(held) < len(ids)
    assert not set(held) & set(np.unique(kr.block[~kr.heldout]))      # whole blocks on one side
    again = dataset.prepare(truth, base, seed=3)["sonar"]
    np.testing.assert_array_equal(again.heldout, kr.heldout)             # deterministic for a seed
    sub = dataset.sample_blocks(kr, "train", 3000, np.random.default_rng(0))
    scored = sub.idx[sub.scored]
    assert not kr.heldout[scored].any()
    assert 3000 <= len(scored) < 3000 + np.bincount(kr.block).max()
    # warm-up rows come before their block and are simulated in that block's stream segment
    assert (~sub.scored).any()
    for seg in np.unique(sub.sim_stream):
        rows = sub.idx[sub.sim_stream == seg]
        assert np.all(np.diff(kr.t[rows]) >= 0)


def test_views_cut_flags_by_value_and_ranges_by_quantile(truth, base):
    kr = dataset.prepare(truth, base, seed=3)["ranging"]
    views = {v.name: v for v in conditions.build_views(kr)}
    assert views["ctx_blocked"].labels == ["ctx_blocked = 0", "ctx_blocked = 1"]
    np.testing.assert_array_equal(views["ctx_blocked"].code, kr.ctx["ctx_blocked"].astype(int))
    counts = np.bincount(views["true_range"].code)
    assert len(counts) == conditions.RANGE_BINS and counts.min() > 0.8 * counts.max()   # equal-count bins
    assert views["reading"].quantity == "reading"
    assert "ctx_facing_sonars" not in views      # constant (0) on ranging rows: no second bin


def _localize(truth, model_meas, model_sim, seed):
    meas = simulate_measured(truth, model_meas, seed)
    kinds = dataset.prepare(meas, model_sim, seed)
    tests = []
    for i, (kind, kr) in enumerate(kinds.items()):
        sub = dataset.whole(kr)
        sims = [models.simulate(model_sim, kind, kr.t, kr.true_range, kr.stream, kr.ctx, sim_seed(seed, i, s))
                for s in (1, 2)]
        tests += localize.test_kind(kr, conditions.build_views(kr), sub, sims[0], sims[1],
                                    np.random.default_rng(seed))
    return localize.decide(tests)


def test_no_condition_stands_out_when_nothing_is_missing(truth, base):
    tests = _localize(truth, base, base, seed=5)
    assert len(tests) > 30
    assert not [t.label for t in tests if t.significant]


def test_a_bias_under_a_flag_is_localized_there(truth, base):
    hidden = base.with_effect("sonar", models.Effect("bias", {"b": 0.05}, "ctx_target_copter"))
    tests = _localize(truth, hidden, base, seed=6)
    flagged = {(t.kind, t.label) for t in tests if t.significant}
    assert ("sonar", "ctx_target_copter = 1") in flagged
    assert ("sonar", "ctx_target_copter = 0") not in flagged
    assert not any(k == "ranging" for k, _ in flagged)


def test_lag_estimate_recovers_a_known_lag():
    rng = np.random.default_rng(2)
    rate = rng.normal(0, 0.5, 20000)
    tau = 0.2
    est, se = localize.lag_estimate(-tau * rate + rng.normal(0, 0.02, rate.size), rate)
    assert abs(est - tau) < 5 * se and se < 0.001


def test_lattice_step_of_rounded_readings():
    rng = np.random.default_rng(4)
    readings = 0.07 * np.round(rng.uniform(0.2, 3.0, 5000) / 0.07)
    assert lattice_step(readings) == pytest.approx(0.07)
    assert lattice_step(rng.uniform(0.2, 3.0, 5000)) is None


def test_fitting_is_deterministic_for_a_seed(truth, base):
    hidden = base.with_effect("ranging", models.Effect("bias", {"b": 0.1}))
    kr = dataset.prepare(simulate_measured(truth, hidden, 9), base, seed=4)["ranging"]
    views = conditions.build_views(kr)
    fits = [KindFitter(kr, views, base, 77, np.random.default_rng(77)).fit(Candidate("ranging", "bias"))
            for _ in range(2)]
    assert fits[0].params == fits[1].params and fits[0].heldout_gap == fits[1].heldout_gap
    assert fits[0].params["b"] == pytest.approx(0.1, abs=0.01)     # 10 000 rows, noise 0.05 m: SE ~ 1 mm


def _fit(kind, name, gap_m, cond=None, params=None):
    return Fit(Candidate(kind, name, cond), params or {"x": 1.0}, "test", 0.0, heldout_gap=gap_m)


def test_selection_prefers_the_special_case_and_requires_the_margins(truth, base):
    kr = dataset.prepare(truth, base, seed=3)["sonar"]
    masks = lambda cand: effective_mask(kr, cand)  # noqa: E731
    no_refit = lambda winner, rival: pytest.fail("no complementarity check expected")  # noqa: E731
    # range_noise (3 quantities) ties with gaussian (1): gaussian wins, range_noise is no rival
    fits = [_fit("sonar", "range_noise", 0.0100, params={"sigma0": 1.0, "sigma1": 0.0}),
            _fit("sonar", "gaussian", 0.0101, params={"sigma": 1.0}), _fit("sonar", "bias", 0.05)]
    sel = selection.select("sonar", fits, 0.10, 0.004, masks, no_refit)
    assert sel.added and sel.winner.candidate.name == "gaussian" and sel.runner_up.candidate.name == "bias"
    # two different explanations within the margin, not complementary: a tie, both named as undecided, the model
    # carries the better of the two equally simple ones; a mixture beyond the margin of both does not take over
    fits = [_fit("sonar", "bias", 0.0100), _fit("sonar", "scale", 0.0105)]
    sel = selection.select("sonar", fits, 0.10, 0.004, masks, lambda w, r: 0.0100)
    assert sel.added and sel.winner.candidate.name == "bias" and sel.undecided.candidate.name == "scale"
    assert "ties with sonar: scale" in sel.reason and "undecided" in sel.reason
    beyond = selection.select("sonar", fits[::-1] + [_fit("sonar", "gmm", 0.0050, params={"components": 6})], 0.10,
                              0.004, masks, lambda w, r: 0.0100)
    assert sel.undecided is not None and beyond.winner.candidate.name == "gmm"     # the mixture beats both clearly
    # two explanations far apart: no tie
    sel = selection.select("sonar", [_fit("sonar", "bias", 0.0100), _fit("sonar", "scale", 0.0500)], 0.10, 0.004,
                           masks, lambda w, r: 0.0100)
    assert sel.added and sel.undecided is None and "beats the runner-up sonar: scale" in sel.reason
    # the same, but the rival still helps once the winner is in: complementary, the winner is added
    sel = selection.select("sonar", fits + [_fit("sonar", "outlier", 0.09)], 0.10, 0.004, masks,
                           lambda w, r: 0.002)
    assert sel.added and sel.complementary and sel.runner_up.candidate.name == "outlier"
    # no candidate beats the current model by the margin
    sel = selection.select("sonar", [_fit("sonar", "bias", 0.0999)], 0.10, 0.004, masks, no_refit)
    assert not sel.added and "less than the margin" in sel.reason


def test_conditions_that_select_the_same_rows_are_one_explanation(truth, base):
    kr = dataset.prepare(truth, base, seed=3)["sonar"]
    masks = lambda cand: effective_mask(kr, cand)  # noqa: E731
    assert masks(Candidate("sonar", "bias", "ctx_speed")).mean() > 0.98
    assert same_explanation(Candidate("sonar", "bias"), Candidate("sonar", "bias", "ctx_speed"), masks)
    # a condition that narrows another (here: all rows) is a version of the same explanation, no rival
    assert same_explanation(Candidate("sonar", "bias"), Candidate("sonar", "bias", "ctx_target_copter"), masks)
    assert not same_explanation(Candidate("sonar", "bias", "ctx_target_copter"),
                                Candidate("sonar", "bias", "ctx_target_copter == 0"), masks)
    assert same_explanation(Candidate("sonar", "gaussian"), Candidate("sonar", "range_noise"), masks)
    assert not same_explanation(Candidate("sonar", "gaussian"), Candidate("sonar", "bias"), masks)
    # cross-talk acts only where a sonar faces this one, so these conditions change nothing
    assert same_explanation(Candidate("sonar", "crosstalk"), Candidate("sonar", "crosstalk", "ctx_crosstalk_path"),
                            masks)


def test_octile_skewness_against_its_closed_form():
    """Octile skewness of an exponential law: (ln 8 + ln(8/7) - 2 ln 2) / (ln 8 - ln(8/7)) = 0.4248; of its mirror
    -0.4248; of a normal law 0. 200 000 draws: the estimator's standard error is below 0.003, tolerance 0.015."""
    from finken.discrepancy.shape import octile_skew
    rng = np.random.default_rng(4)
    exact = (np.log(8) + np.log(8 / 7) - 2 * np.log(2)) / (np.log(8) - np.log(8 / 7))
    draws = rng.exponential(0.15, 200000)
    assert octile_skew(draws) == pytest.approx(exact, abs=0.015)
    assert octile_skew(-draws) == pytest.approx(-exact, abs=0.015)
    assert octile_skew(rng.normal(0.0, 0.1, 200000)) == pytest.approx(0.0, abs=0.015)
    assert octile_skew(np.ones(100)) == 0.0 and octile_skew(draws[:7]) == 0.0
