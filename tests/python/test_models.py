"""finken.models: the Python face of the C sensor models (loading, editing, replay, log-densities).

Statistical checks use fixed seeds, KS tests against scipy's distributions at alpha = 1e-4, each paired with a
wrong model that must be rejected, and moment checks within 5 standard errors (formula at each check).
"""
import os
import subprocess
import sys

import numpy as np
import pytest
from scipy import stats

from finken import models as M

ALPHA = 1e-4
K_SIGMA = 5.0
SPEC_EFFECTS = ("bias", "scale", "gaussian", "range_noise", "rayleigh_short", "crosstalk", "dropout", "outlier",
                "quantization", "latency", "nlos_bias", "gmm")


def rows(n, true_range, stream=0):
    return np.arange(n) * 0.05, np.full(n, float(true_range)), np.full(n, stream)


def test_effect_names_and_parameters_follow_the_spec():
    assert M.EFFECT_NAMES == SPEC_EFFECTS
    expected = {"bias": ("b",), "scale": ("k",), "gaussian": ("sigma",), "range_noise": ("sigma0", "sigma1"),
                "rayleigh_short": ("sigma", "offset"), "crosstalk": ("p",), "dropout": ("p", "p_per_m"),
                "outlier": ("p",), "quantization": ("step",), "latency": ("tau",), "nlos_bias": ("mean",), "gmm": ()}
    assert {name: M.effect_params(name) for name in SPEC_EFFECTS} == expected
    assert {n for n in SPEC_EFFECTS if M.effect_has_logpdf(n)} == {"gaussian", "range_noise", "rayleigh_short",
                                                                    "nlos_bias", "gmm"}
    with pytest.raises(ValueError, match="unknown effect 'blur'"):
        M.effect_params("blur")


def test_every_effect_with_zero_parameters_is_the_identity():
    # scale's parameter is a ratio (measured / true): its identity is k = 1; gmm has no parameters
    chain = [M.Effect(name, {p: 1.0 if name == "scale" else 0.0 for p in M.effect_params(name)})
             for name in M.EFFECT_NAMES if name != "gmm"]
    model = M.SensorModel({"sonar": M.SensorChain("sonar", 0.2, 3.0, "max", chain)})
    n = 5000
    truth = np.random.default_rng(1).uniform(0.2, 3.0, n)
    out = M.simulate(model, "sonar", np.arange(n) * 0.05, truth, np.zeros(n), {"ctx_facing_sonars": np.ones(n)}, 9)
    assert np.array_equal(out, truth)


def test_gaussian_only_is_exactly_the_reference_model():
    m = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    assert m.chains["sonar"] == M.SensorChain("sonar", 0.2, 3.0, "max", [M.Effect("gaussian", {"sigma": 0.02})])
    assert m.chains["ranging"] == M.SensorChain("ranging", 0.0, 2.5, "max", [M.Effect("gaussian", {"sigma": 0.05})])


def test_default_model_and_round_trips(tmp_path):
    m = M.SensorModel.load(M.DEFAULT_MODEL_PATH)
    sonar = m.chains["sonar"]
    assert [e.name for e in sonar.effects] == ["rayleigh_short", "crosstalk", "gaussian", "dropout", "gaussian",
                                               "dropout"]
    assert [e.condition for e in sonar.effects[2:]] == ["ctx_floor == 2"] * 2 + ["ctx_floor == 3"] * 2
    assert sonar.effects[0].params["offset"] == pytest.approx(np.sqrt((4 - np.pi) / 2) * 0.05, rel=1e-15)
    gmm = m.chains["ranging"].effects[0]
    assert gmm.name == "gmm" and gmm.params == {} and gmm.mixture.k == 100
    assert M.SensorModel.from_xml(m.to_xml()) == m
    m.save(tmp_path / "copy.xml")
    assert M.SensorModel.load(tmp_path / "copy.xml") == m


def test_bad_files_raise_model_error_with_file_and_line(tmp_path):
    bad = tmp_path / "bad.xml"
    bad.write_text('<sensor_model>\n  <sonar>\n    <effect name="gaussian" sigma="-1"/>\n  </sonar>\n</sensor_model>\n')
    with pytest.raises(M.ModelError) as info:
        M.SensorModel.load(bad)
    assert str(info.value).startswith(f"{bad}:3: ")
    assert info.value.path == str(bad) and info.value.line == 3 and "sigma" in info.value.reason
    mix = tmp_path / "mix.xml"
    mix.write_text('<mixture components="2">\n<component weight="1" mean_true="1" mean_measured="1" var_true="0.1" '
                   'var_measured="0.1" cov="0"/>\n</mixture>\n')
    with pytest.raises(M.ModelError, match=r"mix.xml:1: mixture declares 2 components but has 1"):
        M.Mixture.load(mix)
    with pytest.raises(M.ModelError, match=r"^<model text>:1: the root element"):
        M.SensorModel.from_xml("<other/>")


def test_models_are_read_by_the_c_loaders_only(tmp_path):
    # the name comes from C too: the Python side parses no model (an external entity once reached lxml here)
    assert M.SensorModel.load(M.DEFAULT_MODEL_PATH).name == "finken_default"
    assert M.SensorModel.from_xml('<sensor_model name="n"><sonar/></sensor_model>').name == "n"
    assert M.SensorModel.from_string("sonar:").name is None
    secret = tmp_path / "secret.txt"
    secret.write_text("hidden")
    model = tmp_path / "entity.xml"
    model.write_text(f'<!DOCTYPE sensor_model [<!ENTITY s SYSTEM "{secret}">]>\n<sensor_model name="&s;"><sonar/>'
                     '</sensor_model>\n')
    with pytest.raises(M.ModelError, match=r"entity.xml:1: a DOCTYPE is not allowed \(models and mixtures take no "
                                           r"DTD and no entities\)$"):
        M.SensorModel.load(model)
    with pytest.raises(M.ModelError, match=r"^<model text>:1: a DOCTYPE is not allowed"):
        M.SensorModel.from_xml(model.read_text())


def test_conditions_name_a_column_of_the_simulator_or_of_the_replayed_log(tmp_path):
    text = "ranging: bias(b=0.5) if ctx_quality_pct"
    with pytest.raises(M.ModelError, match=r"^<model text>:1: condition 'ctx_quality_pct': unknown context column "
                                           r"\(the simulator has ctx_facing_sonars, .*, ctx_floor, ctx_target_obstacle, ctx_vehicle\) "
                                           r"\(column 25\)$"):
        M.SensorModel.from_string(text)
    m = M.SensorModel.from_string(text, log_columns=["ctx_quality_pct"])
    assert m.log_columns == ("ctx_quality_pct",)
    path = tmp_path / "quality.xml"
    m.save(path)
    with pytest.raises(M.ModelError, match=r"quality.xml:4: condition 'ctx_quality_pct': unknown context column"):
        M.SensorModel.load(path)
    assert M.SensorModel.load(path, log_columns={"ctx_quality_pct": [], "ctx_speed": []}) == m
    # in replay the log is the ctx given: a column it has works, one it lacks is refused
    out = M.simulate(m, "ranging", [0.0, 0.1], [1.0, 1.0], [0, 0], {"ctx_quality_pct": [0.0, 80.0]}, seed=1)
    assert list(out) == [1.0, 1.5]
    with pytest.raises(M.ModelError, match=r"condition 'ctx_quality_pct': unknown context column \(the simulator "
                                           r"has .*; the log has ctx_speed\)"):
        M.simulate(m, "ranging", [0.0], [1.0], [0], {"ctx_speed": [0.0]}, seed=1)
    with pytest.raises(M.ModelError, match="the log has no such column"):
        M.check_replay(M.SensorModel.from_string("ranging: bias(b=0.5) if ctx_blocked"), "ranging", ["ctx_speed"])
    M.check_replay(m, "ranging", ["ctx_quality_pct"])
    # effects added in Python: on the log's columns once the model is for that log
    base = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    quality = M.Effect("bias", {"b": 0.1}, condition="ctx_quality_pct")
    with pytest.raises(M.ModelError, match="unknown context column"):
        base.with_effect("ranging", quality)
    assert base.for_log(["ctx_quality_pct"]).with_effect("ranging", quality).chains["ranging"].effects[1] == quality


def test_a_nul_byte_is_refused_not_the_end_of_the_text():
    with pytest.raises(M.ModelError, match=r"^X:1: NUL byte in the model \(column 27\)$"):
        M.SensorModel.from_string("sonar: gaussian(sigma=0.1)\0 | ranging: blur(x=1)", origin="X")
    with pytest.raises(M.ModelError, match=r"^<model text>:2: NUL byte in the model \(column 9\)$"):
        M.SensorModel.from_xml("<sensor_model>\n<sonar/>\0\n</sensor_model>")


def test_with_effect_appends_to_a_copy_and_validates():
    m = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    m2 = m.with_effect("ranging", M.Effect("nlos_bias", {"mean": 0.1}, condition="ctx_blocked"))
    assert [e.name for e in m2.chains["ranging"].effects] == ["gaussian", "nlos_bias"]
    assert len(m.chains["ranging"].effects) == 1
    assert M.SensorModel.from_xml(m2.to_xml()) == m2
    with pytest.raises(M.ModelError, match="outside"):
        m.with_effect("ranging", M.Effect("dropout", {"p": 2.0}))
    with pytest.raises(M.ModelError, match="unknown parameter 'sd'"):
        m.with_effect("ranging", M.Effect("gaussian", {"sd": 0.1}))
    with pytest.raises(M.ModelError, match="not a context column"):
        m.with_effect("ranging", M.Effect("bias", {"b": 0.1}, condition="blocked"))


def test_simulate_is_reproducible_and_streams_are_independent():
    m = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    n = 20000
    t = np.repeat(np.arange(n) * 0.05, 2)
    truth = np.full(2 * n, 1.2)
    stream = np.tile([7, 8], n)
    a = M.simulate(m, "ranging", t, truth, stream, {}, seed=3)
    assert np.array_equal(a, M.simulate(m, "ranging", t, truth, stream, {}, seed=3))
    assert not np.array_equal(a, M.simulate(m, "ranging", t, truth, stream, {}, seed=4))
    # correlation of two interleaved streams: SE 1/sqrt(n) under independence
    r = np.corrcoef(a[0::2], a[1::2])[0, 1]
    assert abs(r) < K_SIGMA / np.sqrt(n)
    # a stream's readings do not depend on the other streams in the batch
    alone = M.simulate(m, "ranging", t[1::2], truth[1::2], stream[1::2], {}, seed=3)
    assert np.array_equal(alone, a[1::2])


def test_replayed_noise_follows_the_model_and_fits_back():
    # close the loop: the C model writes readings, scipy recovers the configured sigma
    m = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    n = 100000
    resid = M.simulate(m, "ranging", *rows(n, 1.25), {}, seed=11) - 1.25
    assert stats.kstest(resid, stats.norm(0, 0.05).cdf).pvalue > ALPHA
    # power: a sigma 5 % off moves the cdf by up to phi(1) x 0.05 = 0.012, sqrt(n) x 0.012 = 3.8 (p ~ 1e-12); 3 %
    # (sqrt(n) D = 2.3, p ~ 1e-4) sat on ALPHA itself and passed or failed with the random stream
    assert stats.kstest(resid, stats.norm(0, 0.05 * 1.05).cdf).pvalue < ALPHA
    _, sigma_hat = stats.norm.fit(resid)
    assert sigma_hat == pytest.approx(0.05, abs=K_SIGMA * 0.05 / np.sqrt(2 * n))  # SE of sigma_hat: sigma/sqrt(2n)


def test_rayleigh_short_replay_fits_back():
    model = M.SensorModel({"sonar": M.SensorChain("sonar", 0.2, 3.0, "max", [])}).with_effect(
        "sonar", M.Effect("rayleigh_short", {"sigma": 0.06, "offset": 0.0}))
    n = 100000
    r = 1.5 - M.simulate(model, "sonar", *rows(n, 1.5), {}, seed=5)  # R ~ Rayleigh(0.06)
    assert stats.kstest(r, stats.rayleigh(scale=0.06).cdf).pvalue > ALPHA
    assert stats.kstest(r, stats.rayleigh(scale=0.06 * 1.03).cdf).pvalue < ALPHA


def test_conditions_and_crosstalk_in_replay():
    base = M.SensorModel({"sonar": M.SensorChain("sonar", 0.2, 3.0, "max", [])})
    biased = base.with_effect("sonar", M.Effect("bias", {"b": 0.5}, condition="ctx_blocked"))
    n = 10
    blocked = np.arange(n) % 2
    out = M.simulate(biased, "sonar", *rows(n, 1.0), {"ctx_blocked": blocked}, seed=1)
    assert np.array_equal(out, np.where(blocked == 1, 1.5, 1.0))
    assert np.array_equal(M.simulate(biased, "sonar", *rows(n, 1.0), {"blocked": blocked}, seed=1), out)
    # a log without the condition's column: refused (the effect would never apply)
    with pytest.raises(M.ModelError, match=r"^condition 'ctx_blocked' of the sonar chain's effect 1 \(bias\): the log "
                                           r"has no such column$"):
        M.simulate(biased, "sonar", *rows(n, 1.0), {"ctx_speed": np.zeros(n)}, seed=1)
    # cross-talk hears a facing emitter only: path = true range unless ctx_crosstalk_path, offset 0 unless given
    talk = base.with_effect("sonar", M.Effect("crosstalk", {"p": 1.0}))
    facing = np.arange(n) % 2
    out = M.simulate(talk, "sonar", *rows(n, 2.4), {"ctx_facing_sonars": facing}, seed=1)
    assert np.array_equal(out, np.where(facing == 1, 1.2, 2.4))
    out = M.simulate(talk, "sonar", *rows(n, 2.4), {"ctx_facing_sonars": np.ones(n), "ctx_crosstalk_path": 2.0,
                                                    "ctx_trigger_offset": 0.001}, seed=1)
    assert np.allclose(out, 0.5 * (2.0 + 343.0 * 0.001), rtol=0, atol=1e-15)
    # with p = 0.68 the rate is binomial: SE sqrt(p (1 - p) / n)
    talk68 = base.with_effect("sonar", M.Effect("crosstalk", {"p": 0.68}))
    n = 50000
    out = M.simulate(talk68, "sonar", *rows(n, 2.4), {"ctx_facing_sonars": np.ones(n)}, seed=2)
    assert np.mean(out == 1.2) == pytest.approx(0.68, abs=K_SIGMA * np.sqrt(0.68 * 0.32 / n))


def test_no_reading_and_latency_per_stream():
    base = M.SensorModel({"ranging": M.SensorChain("ranging", 0.0, 2.5, "none", [])})
    out = M.simulate(base, "ranging", [0.0, 0.1], [2.4, 2.6], [0, 0], {}, seed=1)
    assert out[0] == 2.4 and np.isnan(out[1])
    lat = base.with_effect("ranging", M.Effect("latency", {"tau": 0.1}))
    t = np.repeat(np.arange(5) * 0.1, 2)
    truth = np.where(np.arange(10) % 2 == 0, 1.0, 2.0) + t  # two streams, each a ramp
    out = M.simulate(lat, "ranging", t, truth, np.arange(10) % 2, {}, seed=1)
    expected = np.where(np.arange(10) % 2 == 0, 1.0, 2.0) + np.maximum(t - 0.1, 0.0)
    assert np.allclose(out, expected, rtol=0, atol=1e-12)


def test_simulate_rejects_bad_input():
    m = M.SensorModel.load(M.GAUSSIAN_ONLY_PATH)
    with pytest.raises(ValueError, match="one length"):
        M.simulate(m, "sonar", [0.0, 1.0], [1.0], [0, 0], {}, seed=1)
    with pytest.raises(ValueError, match="ctx column 'ctx_facing_sonars' has 3 values for 2 rows"):
        M.simulate(m.with_effect("sonar", M.Effect("crosstalk", {"p": 1.0})), "sonar", [0.0, 1.0], [1.0, 1.0], [0, 0],
                   {"ctx_facing_sonars": [1, 0, 1]}, seed=1)
    with pytest.raises(ValueError, match="no sonar chain"):
        M.simulate(M.SensorModel({"ranging": m.chains["ranging"]}), "sonar", [0.0], [1.0], [0], {}, seed=1)


def test_effect_logpdf_matches_scipy():
    x_in = np.linspace(0.5, 2.5, 7)
    x_out = x_in + np.linspace(-0.04, 0.05, 7)
    assert np.allclose(M.effect_logpdf("gaussian", {"sigma": 0.05}, x_in, x_out),
                       stats.norm(0, 0.05).logpdf(x_out - x_in), rtol=1e-12)
    assert np.allclose(M.effect_logpdf("range_noise", {"sigma0": 0.01, "sigma1": 0.02}, x_in, x_out),
                       stats.norm(0, 0.01 + 0.02 * x_in).logpdf(x_out - x_in), rtol=1e-12)
    x_short = x_in - np.linspace(0.0, 0.08, 7)
    assert np.allclose(M.effect_logpdf("rayleigh_short", {"sigma": 0.05, "offset": 0.03}, x_in, x_short),
                       stats.rayleigh(scale=0.05).logpdf(x_in - x_short + 0.03), rtol=1e-12)
    x_long = x_in + np.linspace(0.01, 0.5, 7)
    assert np.allclose(M.effect_logpdf("nlos_bias", {"mean": 0.2}, x_in, x_long),
                       stats.expon(scale=0.2).logpdf(x_long - x_in), rtol=1e-12)
    for name in ("bias", "crosstalk", "latency"):
        with pytest.raises(ValueError, match="no closed-form"):
            M.effect_logpdf(name, {}, x_in, x_out)
    with pytest.raises(ValueError, match="needs mixture"):
        M.effect_logpdf("gmm", {}, x_in, x_out)


def test_gmm_logpdf_is_the_mixture_conditioned_by_hand():
    """effect_logpdf('gmm') (C: nps_gmm.c) against the default mixture read from its file with lxml and conditioned
    by its definition in numpy, p(m | t) = p(t, m) / p(t) (gmm_reference.py: no code shared with C); it integrates
    to 1 over the measured range; and the reference's conditional CDF (test_nps_sensors.py tests the host's
    readings with it) is the integral of that density.
    Deterministic: both sides compute in double precision (they agree to ~1e-14 in log density), so LOG_TOL = 1e-9
    leaves room for rounding only.
    Wrong densities the same checks reject (asserted at the end): the components' prior weights w_k in place of the
    conditional ones (integrates to 1, but is off by up to 17 in log density), the unconditioned variances s_mm
    (off by 6), the joint p(t, m) not divided by p(t) (integrates to p(t), 0.33 at t = 1 m), a constant."""
    from scipy.integrate import cumulative_simpson
    from scipy.special import logsumexp
    from gmm_reference import ReferenceMixture
    LOG_TOL = 1e-9
    # The trapezoid rule over the whole line on a smooth density errs by ~exp(-2 pi^2 sd^2 / h^2), below 1e-280
    # for the narrowest conditional component (sd 0.018 m) at h = 1e-3 m: INTEGRAL_TOL is rounding of the sum.
    # Cumulative Simpson errs by at most h^4 / 180 times the integral of |p''''|, E|He4(Z)| / sd^4 = 2.80 / sd^4 for
    # one Gaussian (He4 the 4th Hermite polynomial): 1.5e-7 at sd 0.018 m, whatever the weights; CDF_TOL = 1e-6.
    INTEGRAL_TOL, CDF_TOL = 1e-9, 1e-6
    mix = M.SensorModel.load(M.DEFAULT_MODEL_PATH).chains["ranging"].effects[0].mixture
    ref = ReferenceMixture.read(M.DEFAULT_MODEL_PATH)
    # true ranges inside the ranging span and beyond both ends; measured from 0.6 m short to 1.2 m long
    t = np.array([-0.3, 0.0, 0.4, 1.0, 1.7, 2.5, 3.0])[:, None]
    m = t + np.linspace(-0.6, 1.2, 37)[None, :]
    got = M.effect_logpdf("gmm", {}, t, m, mixture=mix)
    want = ref.conditional_logpdf(t, m)
    assert np.ptp(want) > 20                                       # the tails are on the grid
    assert np.max(np.abs(got - want)) <= LOG_TOL, np.max(np.abs(got - want))
    grid = np.linspace(-2.0, 7.0, 9001)                            # h = 1e-3 m; no component reaches its ends
    density = np.exp(M.effect_logpdf("gmm", {}, t, grid[None, :], mixture=mix))
    assert np.max(np.abs(np.trapezoid(density, grid, axis=1) - 1.0)) <= INTEGRAL_TOL
    for true in (0.0, 1.0, 2.5):
        integral = cumulative_simpson(np.exp(ref.conditional_logpdf(true, grid)), x=grid, initial=0.0)
        assert np.max(np.abs(integral - ref.conditional_cdf(np.full(grid.size, true), grid))) <= CDF_TOL, true

    # the wrong densities: each fails the comparison, and those far off only in mass fail the integral
    def conditioned(t, m, weights, sd):
        t, m = np.broadcast_arrays(t, m)
        w, mean, cond_sd = ref.conditional_components(t.ravel())
        with np.errstate(divide="ignore"):                         # weights that underflow to 0
            log_w = np.log(weights(w))
        return logsumexp(log_w + stats.norm.logpdf(m.ravel()[None, :], mean, sd(cond_sd)),
                         axis=0).reshape(m.shape)

    def prior_weights(t, m):
        return conditioned(t, m, lambda w: np.broadcast_to(ref.weights[:, None], w.shape), lambda sd: sd)

    def unconditioned_variances(t, m):
        return conditioned(t, m, lambda w: w, lambda sd: np.sqrt(ref.covariances[:, 1, 1])[:, None])

    def constant(t, m):
        return np.full(np.broadcast(t, m).shape, -np.log(3.0))

    for wrong in (prior_weights, unconditioned_variances, ref.joint_logpdf, constant):
        assert np.max(np.abs(wrong(t, m) - got)) > 1.0, wrong
    for wrong in (ref.joint_logpdf, constant):
        assert np.max(np.abs(np.trapezoid(np.exp(wrong(1.0, grid)), grid) - 1.0)) > 0.5, wrong


def test_a_missing_library_says_to_run_make_build(tmp_path):
    code = "from finken import models; models.EFFECT_NAMES"
    env = dict(os.environ, FINKEN_LIB=str(tmp_path / "absent.so"))
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert res.returncode != 0 and "make build" in res.stderr and "absent.so" in res.stderr
