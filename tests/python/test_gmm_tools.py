"""Mixture converters (tools/gmm_import.py), the fitter (tools/gmm_fit.py) and the default synthetic mixture.

Conversions are checked against the source library's own densities and conditionals to 1e-9 (both are exact
formulas; only rounding differs). The fit is checked on a log with a known linear-Gaussian error.
"""
import joblib
import numpy as np
import pytest
from scipy import stats
from sklearn.mixture import GaussianMixture

import gmm_default_model
import gmm_fit
import gmm_import
from finken import models as M
from finken.rangelog import RangeLog, write_range_log


def joint_data(n=3000, seed=1):
    """(true, measured) pairs: measured = t + 0.03 + N(0, (0.02 + 0.03 t)^2), t in [0.3, 2.5] m (never negative)."""
    rng = np.random.default_rng(seed)
    t = rng.uniform(0.3, 2.5, n)
    return np.column_stack([t, t + 0.03 + rng.normal(0.0, 0.02 + 0.03 * t)])


def marginal_logpdf_t(gm, t):
    """log p(t) of a fitted sklearn mixture, from its full covariances."""
    covs = M.Mixture(*_params(gm)).covariances
    comps = [w * stats.norm(mu[0], np.sqrt(c[0, 0])).pdf(t) for w, mu, c in zip(gm.weights_, gm.means_, covs)]
    return np.log(np.sum(comps, axis=0))


def _params(gm):
    m = gmm_import.from_sklearn(gm)
    return m.weights, m.means, m.covariances


@pytest.mark.parametrize("kind", ["full", "diag", "spherical", "tied"])
def test_sklearn_conversion_gives_the_same_conditional_density(kind):
    x = joint_data()
    gm = GaussianMixture(3, covariance_type=kind, random_state=0).fit(x)
    mix = gmm_import.from_sklearn(gm)
    assert mix.diagonal == (kind in ("diag", "spherical"))
    t, m = x[:200, 0], x[:200, 1]
    expected = gm.score_samples(x[:200]) - marginal_logpdf_t(gm, t)  # log p(t, m) - log p(t)
    assert np.allclose(mix.conditional_logpdf(t, m), expected, rtol=0, atol=1e-9)


def test_extra_dimensions_are_marginalised():
    x = joint_data()
    x3 = np.column_stack([np.random.default_rng(2).normal(size=len(x)), x[:, 1], x[:, 0]])  # (noise, meas, true)
    gm = GaussianMixture(2, random_state=0).fit(x3)
    mix = gmm_import.from_sklearn(gm, true_dim=2, measured_dim=1)
    assert np.array_equal(mix.means, gm.means_[:, [2, 1]])
    assert np.array_equal(mix.covariances[:, 0, 1], gm.covariances_[:, 2, 1])


def test_gmr_conversion_matches_gmr_conditioning():
    from gmr import GMM
    x = joint_data()
    gm = GaussianMixture(4, random_state=0).fit(x)
    g = GMM(4, priors=gm.weights_, means=gm.means_, covariances=gm.covariances_, random_state=0)
    mix = gmm_import.from_gmr(g)
    for t in (0.0, 0.8, 2.3, 4.0):
        cond = g.condition([0], np.array([t]))
        mean_gmr = np.sum(cond.priors * cond.means[:, 0])
        var_gmr = np.sum(cond.priors * (cond.covariances[:, 0, 0] + (cond.means[:, 0] - mean_gmr) ** 2))
        mean, var = mix.conditional_moments(t)
        assert mean == pytest.approx(mean_gmr, abs=1e-9) and var == pytest.approx(var_gmr, rel=1e-9)
        assert mix.conditional_logpdf(t, t + 0.05) == pytest.approx(
            np.log(cond.to_probability_density(np.array([[t + 0.05]]))[0]), abs=1e-9)


def test_import_cli_writes_a_loadable_mixture(tmp_path):
    gm = GaussianMixture(3, random_state=0).fit(joint_data())
    joblib.dump(gm, tmp_path / "fitted.pkl")
    out = tmp_path / "mix.xml"
    assert gmm_import.main([str(tmp_path / "fitted.pkl"), "-o", str(out), "--header", "from a test"]) == 0
    assert "from a test" in out.read_text()
    assert M.Mixture.load(out) == gmm_import.from_sklearn(gm)
    joblib.dump({"not": "a model"}, tmp_path / "junk.pkl")
    assert gmm_import.main([str(tmp_path / "junk.pkl"), "-o", str(tmp_path / "x.xml")]) == 1


def test_fit_recovers_a_known_error_from_a_range_log(tmp_path):
    x = joint_data(n=6000, seed=3)
    n = len(x)
    log = RangeLog(str(tmp_path / "log.csv"), np.arange(n) * 0.05, np.zeros(n), np.array(["ranging"] * n),
                   np.ones(n), x[:, 0], x[:, 1])
    write_range_log(tmp_path / "log.csv", log)
    out = tmp_path / "fit.xml"
    assert gmm_fit.main([str(tmp_path / "log.csv"), "-o", str(out), "--components", "4"]) == 0
    mix = M.Mixture.load(out)
    assert mix.k == 4 and "Fitted by tools/gmm_fit.py" in out.read_text()
    grid = np.linspace(0.5, 2.3, 5)
    mean, var = mix.conditional_moments(grid)
    # truth: mean t + 0.03, sd 0.02 + 0.03 t; a 4-component fit to 6000 rows gets within 1 cm and 20 %
    assert np.allclose(mean, grid + 0.03, atol=0.01)
    assert np.allclose(np.sqrt(var), 0.02 + 0.03 * grid, rtol=0.2)
    model = M.SensorModel({"ranging": M.SensorChain("ranging", 0.0, 2.5, "max", [])})
    model = model.with_effect("ranging", M.Effect("gmm", {}, mixture=mix))
    sim = M.simulate(model, "ranging", log.t, log.true_range, np.zeros(n), {}, seed=1)
    assert stats.ks_2samp(sim - log.true_range, log.measured - log.true_range).pvalue > 1e-4


def test_fit_refuses_too_few_rows():
    with pytest.raises(ValueError, match="too few"):
        gmm_fit.fit_mixture(np.ones(50), np.ones(50), components=10)


def test_default_mixture_is_documented_and_reproduces_its_assumptions():
    path = M.MODELS_DIR / "finken_ranging_gmm_k100.xml"
    header = path.read_text().split("<mixture")[0]
    assert "SYNTHETIC" in header and "tools/gmm_default_model.py" in header and "not available" in header
    mix = M.Mixture.load(path)
    assert mix.k == 100 and not mix.diagonal
    grid = np.linspace(0.1, 2.4, 24)
    mean, var = mix.conditional_moments(grid)
    mean_a, sd_a = gmm_default_model.assumed_moments(grid)
    assert np.allclose(mean, mean_a, atol=0.01)          # means track the true distance (+ 3.6 cm)
    assert np.allclose(np.sqrt(var), sd_a, rtol=0.1)     # spread ~9 cm at 0 growing to ~17 cm
    # a heavier tail than a normal of the same spread: P(m > mean + 3 sd | t = 1) vs 0.00135
    p_tail = 1.0 - mix.conditional_cdf(1.0, mean[8] + 3 * np.sqrt(var[8]))
    assert p_tail > 3 * stats.norm.sf(3)


def test_import_cli_names_a_file_that_is_not_a_fitted_mixture(tmp_path, capsys):
    from gmr import GMM
    (tmp_path / "junk.pkl").write_bytes(b"junk\n")
    (tmp_path / "empty.pkl").write_bytes(b"")
    joblib.dump(GMM(2), tmp_path / "unfitted_gmr.pkl")
    for name, words in (("junk.pkl", "not a pickle or joblib file of a fitted mixture (UnpicklingError"),
                        ("empty.pkl", "not a pickle or joblib file of a fitted mixture (EOFError"),
                        ("unfitted_gmr.pkl", "GMM is neither a fitted sklearn GaussianMixture nor a gmr GMM")):
        assert gmm_import.main([str(tmp_path / name), "-o", str(tmp_path / "x.xml")]) == 1
        assert capsys.readouterr().err.startswith(f"gmm_import: {tmp_path / name}: {words}")
    assert not (tmp_path / "x.xml").exists()
