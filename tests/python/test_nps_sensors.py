"""The simulated sonar ring and ranging, end to end through the host, on copters flying known circles
(tests/data/airframes/sensors_nps.xml) with the default sensor model.

Statistical checks use two-sided KS tests at alpha = 0.001 per test (false-failure probability 0.1 % each)
on thousands of readings from fixed seeds, so a wrong distribution (e.g. a Gaussian in place of the Rayleigh
law, or ranging errors that ignore the model) fails.
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
    """The host's ranging readings and the sensor model's own sampler on the same true ranges agree (KS)."""
    from conftest import REPO
    from finken.models import SensorModel, simulate
    log = noisy_log
    rows = (log.sensor == "ranging") & (log.true_range < 2.5)
    true = log.true_range[rows]
    model = SensorModel.load(REPO / "conf/sensor_models/finken_default.xml")
    replay = simulate(model, "ranging", log.t[rows], true, np.zeros(true.size, dtype=int), {}, seed=11)
    assert true.size > 3000
    assert stats.ks_2samp(log.measured[rows] - true, replay - true).pvalue > ALPHA
