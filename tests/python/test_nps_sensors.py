"""The simulated sonar ring and ranging, end to end through the host, on copters flying known circles
(tests/data/airframes/sensors_nps.xml) with the default sensor model, and with inline models: per-vehicle effects
(conditioned on ctx_vehicle) and glitches.

Statistical checks use two-sided KS tests at alpha = 0.001 per test (false-failure probability 0.1 % each)
on thousands of readings from fixed seeds, so a wrong distribution (e.g. a Gaussian in place of the Rayleigh
law, or ranging errors that ignore the model) fails. The ranging readings are tested against the mixture
conditioned by a reference that shares no code with the C sampler (gmm_reference.py), and two slightly wrong
mixtures must fail the same test on the same readings.
"""
import subprocess

import numpy as np
import pytest
from scipy import stats

ALPHA = 1e-3


@pytest.fixture(scope="module")
def host():
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host", "AIRFRAME=tests/data/airframes/sensors_nps.xml"],
                   cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    return REPO / "build/host/sensors_nps/nps_host"


def run(host, out, *args):
    from conftest import REPO
    result = subprocess.run([str(host), "--out", str(out), "--quiet", *args], cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    from finken.rangelog import read_range_log
    return read_range_log(out / "readings.csv")


@pytest.fixture(scope="module")
def noisy_log(host, tmp_path_factory):
    return run(host, tmp_path_factory.mktemp("noisy"), "--duration", "60", "--seed", "3")


def test_without_noise_every_reading_is_the_ray_cast_truth(host, tmp_path):
    log = run(host, tmp_path, "--duration", "10",
              "--sensor-model", "sonar(min_range=0, max_range=100) | ranging(min_range=0, max_range=100)")
    assert len(log) > 1000
    assert np.array_equal(log.measured, log.true_range)


def test_each_sonar_reads_at_20_hz_and_ranging_at_10_hz(noisy_log):
    log = noisy_log
    duration = log.t.max()
    for sensor in ("sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down"):
        for vehicle in (1, 2, 3, 4):
            n = np.sum((log.sensor == sensor) & (log.vehicle == vehicle))
            assert abs(n / duration - 20.0) < 0.1, (sensor, vehicle, n)
    ranging = log.sensor == "ranging"
    assert abs(np.sum(ranging & (log.vehicle == 1) & (log.peer == 2)) / duration - 10.0) < 0.1


def test_sonar_errors_follow_the_configured_rayleigh_law(noisy_log):
    """Default model: measured = true - (R - offset), R ~ Rayleigh(0.05 m), offset = sqrt((4 - pi) / 2) 0.05 m,
    wherever no other copter's pulse is heard and the reading is not clamped."""
    log = noisy_log
    sigma = 0.05
    offset = np.sqrt((4 - np.pi) / 2) * sigma
    rows = (log.sensor != "ranging") & (log.ctx["ctx_facing_sonars"] == 0) & (log.true_range > 0.6) & (log.true_range < 2.9)
    r = log.true_range[rows] - log.measured[rows] + offset
    assert r.size > 5000
    assert stats.kstest(r, stats.rayleigh(scale=sigma).cdf).pvalue > ALPHA
    assert stats.kstest(r, stats.norm(loc=r.mean(), scale=r.std()).cdf).pvalue < ALPHA   # the test has power


def test_crosstalk_only_where_the_geometry_allows_it(noisy_log):
    """A reading far shorter than the Rayleigh law allows (R > 8 sigma: probability e^-32) only with a facing emitter."""
    log = noisy_log
    sonar = log.sensor != "ranging"
    very_short = sonar & (log.true_range < 2.9) & (log.true_range - log.measured > 8 * 0.05)
    assert very_short.sum() > 0
    assert np.all(log.ctx["ctx_facing_sonars"][very_short] > 0)
    pulse_reading = (log.ctx["ctx_crosstalk_path"] + 343.0 * log.ctx["ctx_trigger_offset"]) / 2
    # the foreign pulse beats the own echo by a margin no Rayleigh error (R < 8 sigma) can close
    facing = sonar & (log.ctx["ctx_facing_sonars"] > 0) & (pulse_reading > 0.25) & (pulse_reading < log.true_range - 0.5)
    crosstalk = facing & (np.abs(log.measured - pulse_reading) < 1e-3)
    # the default model's p = 0.68 (report 3.2); binomial standard error sqrt(p (1 - p) / n)
    p_hat, n = crosstalk.sum() / facing.sum(), facing.sum()
    assert abs(p_hat - 0.68) < 4 * np.sqrt(0.68 * 0.32 / n)


def test_ranging_errors_follow_the_model_of_the_airframe(noisy_log):
    """The host's ranging readings follow the airframe's mixture (finken_default.xml) conditioned on their true
    ranges, computed by an independent reference (gmm_reference.py: the mixture file read with lxml, conditioned
    in numpy/scipy; no code shared with the C sampler the host and finken.models.simulate run).

    Probability integral transform: u = F(measured | true) is Uniform(0, 1) under the model. The chain clamps
    readings to [0, 2.5] m, so a reading at a limit gets u uniform over the mass the clamp put there, [F(2.5 | true),
    1] at 2.5 m, [0, F(0 | true)] at 0 (randomized PIT, exactly uniform too). The log keeps 4 decimals: F moves by at
    most the conditional density (< 13 /m) times 5e-5 m, 7e-4, a thirtieth of the tolerance (and as little for the
    true range's rounding).
    n = 7200 readings (4 copters: 12 ordered pairs at 10 Hz for 60 s); D = sup |F_n(u) - u| must stay within
    EPS = sqrt(ln(2 / ALPHA) / (2 n)) = 0.0230: P(D > EPS) <= 2 exp(-2 n EPS^2) = ALPHA = 1e-3 for every n
    (Dvoretzky-Kiefer-Wolfowitz inequality with Massart's constant): the false-failure probability.
    Wrong models the same readings must reject (D > EPS): every component's measured mean 1 cm higher (under 9 % of
    the conditional s.d., 0.11-0.16 m at these ranges; population D 0.035), and the weights 30 % up and down on
    alternate components (population D 0.035). Each was rejected by all of 100 replays of these true ranges
    (simulate, other seeds): power above 0.97 (95 % confidence).
    The host also agrees with the replay of the same true ranges (two-sample KS at ALPHA): the host's path to the
    sampler (its streams and seeds) is the replay's.
    """
    from conftest import REPO
    from finken.models import SensorModel, simulate
    from gmm_reference import ReferenceMixture
    log = noisy_log
    rows = (log.sensor == "ranging") & (log.true_range < 2.5)
    true, measured = log.true_range[rows], log.measured[rows]
    n = true.size
    assert n >= 7000
    eps = np.sqrt(np.log(2 / ALPHA) / (2 * n))
    low, high = 0.0, 2.5                      # the ranging chain's min_range and max_range (finken_default.xml)

    def ks_distance(mixture):
        """sup |F_n(u) - u| of the randomized PIT of the readings under `mixture` (the same uniforms each time)."""
        cdf = mixture.conditional_cdf(true, np.clip(measured, low, high))
        lo = np.where(measured <= low, 0.0, cdf)
        hi = np.where(measured >= high, 1.0, np.where(measured <= low, cdf, lo))
        u = np.sort(lo + np.random.default_rng(1).uniform(size=n) * (hi - lo))
        i = np.arange(1, n + 1)
        return max(np.max(i / n - u), np.max(u - (i - 1) / n))

    model_path = REPO / "conf/sensor_models/finken_default.xml"
    mixture = ReferenceMixture.read(model_path)
    assert ks_distance(mixture) <= eps, (ks_distance(mixture), eps)
    k = np.arange(mixture.weights.size)
    shifted = ReferenceMixture(mixture.weights, mixture.means + [0.0, 0.01], mixture.covariances)
    reweighted = mixture.weights * (1 + 0.3 * (-1.0) ** k)
    reweighted = ReferenceMixture(reweighted / reweighted.sum(), mixture.means, mixture.covariances)
    for wrong in (shifted, reweighted):
        assert ks_distance(wrong) > eps, (ks_distance(wrong), eps)

    model = SensorModel.load(model_path)
    replay = simulate(model, "ranging", log.t[rows], true, np.zeros(n, dtype=int), {}, seed=11)
    assert stats.ks_2samp(measured - true, replay - true).pvalue > ALPHA


LOG_HEADER = ("t,vehicle,sensor,peer,true_range,measured,ctx_facing_sonars,ctx_target_copter,ctx_blocked,ctx_wall_dist,"
              "ctx_speed,ctx_crosstalk_path,ctx_trigger_offset,ctx_floor,ctx_target_obstacle")


def test_a_per_vehicle_bias_shifts_that_vehicles_readings_only(host, tmp_path):
    """Biases conditioned on ctx_vehicle == 2 and no other error: aircraft 2's sonar readings are 0.25 m long and its
    ranging readings 0.11 m short (to the log's 4 decimals: each number rounded, so within 1e-4), every other copter's
    readings are the truth; the log keeps its columns (ctx_vehicle is its `vehicle` column)."""
    model = ("sonar(min_range=0, max_range=1000): bias(b=0.25) if ctx_vehicle == 2 "
             "| ranging(min_range=0, max_range=1000): bias(b=-0.11) if ctx_vehicle == 2")
    log = run(host, tmp_path, "--duration", "10", "--seed", "2", "--sensor-model", model)
    assert (tmp_path / "readings.csv").open().readline().rstrip("\n") == LOG_HEADER
    assert set(np.unique(log.vehicle).tolist()) == {1, 2, 3, 4}
    error, two, sonar = log.measured - log.true_range, log.vehicle == 2, log.sensor != "ranging"
    assert (two & sonar).sum() > 900 and (two & ~sonar).sum() > 250
    assert np.all(np.abs(error[two & sonar] - 0.25) <= 1.0001e-4)
    assert np.all(np.abs(error[two & ~sonar] + 0.11) <= 1.0001e-4)
    assert np.array_equal(log.measured[~two], log.true_range[~two])


def test_glitches_reach_the_log_as_their_values(host, tmp_path):
    """glitch(p=0.05) on both chains and no other error: a reading is the truth (clamped to the limits) or one of its
    chain's glitch values, written as they are (-12.84, 1e5, inf, -inf: never clamped); the share of glitches is p
    within 5 binomial standard errors (about 4000 sonar readings: +-0.017)."""
    model = ("sonar(min_range=0.2, max_range=3): glitch(p=0.05, values=-12.84 1e5 inf) "
             "| ranging(min_range=0, max_range=2.5): glitch(p=0.05, values=-inf -1)")
    log = run(host, tmp_path, "--duration", "10", "--seed", "2", "--sensor-model", model)
    for sensor, values, (low, high) in ((log.sensor != "ranging", {-12.84, 1e5, np.inf}, (0.2, 3.0)),
                                        (log.sensor == "ranging", {-np.inf, -1.0}, (0.0, 2.5))):
        measured, truth = log.measured[sensor], np.clip(log.true_range[sensor], low, high)
        glitched = measured != truth
        assert set(measured[glitched].tolist()) == values
        n = measured.size
        assert abs(glitched.mean() - 0.05) <= 5 * np.sqrt(0.05 * 0.95 / n), (glitched.mean(), n)
