"""make imu-calibrate: noise recovered from synthetic static logs of known parameters, Paparazzi's model given by the
written defines, the example airframe holding the tool's output, and bad input named by file, line and column.

Recovery tolerances: over 40 seeds of the test log (1800 s at 50 Hz; white N, bias instability B, rate random walk K
with crossovers near 3 s and 30 s), the fitted/true ratios had standard deviations 0.2 % (N), 4.2 % (B) and 17.5 % (K);
each check allows 4 of them (N 1 %, B 17 %, K 70 %: a false-failure probability of about 6e-5 per check for a
normal estimator). A fit that mistook the density's convention (a factor sqrt(2) on N), or dropped a term, fails.
The bootstrap intervals' widths (bounded by 3 times a 95 % interval of those standard errors) and the Allan deviation
of Paparazzi's recursion (within 5 standard errors from its equivalent degrees of freedom; a drive q or a white noise
off by 1.5 fails) state their sample counts and false-failure probabilities at their tests.
"""
import subprocess
import sys

import numpy as np
import pytest
from lxml import etree

from finken.imu import synthetic
from finken.imu.calibration import calibrate
from finken.imu.imu_log import ImuLog, ImuLogError, check_at_rest, parse_imu_columns, read_imu_log
from finken.imu.paparazzi import TC_S, markov_adev, markov_drive, paparazzi_adev
from finken.imu.synthetic import AxisNoise, ImuPreset

TOLERANCE = {"white": 0.01, "bias_instability": 0.17, "rate_random_walk": 0.70}
# the estimators' relative standard errors on the test log: the sd of fitted/true over 40 seeds (module comment)
REL_SE = {"white": 0.002, "bias_instability": 0.042, "rate_random_walk": 0.175}
GYRO = AxisNoise(1.15e-4, 1e-4, 2.1e-5)
ACCEL = AxisNoise(2.3e-3, 2e-3, 4.2e-4)
TEST_PRESET = ImuPreset(GYRO, ACCEL, (0.01, -0.02, 0.03), "test")
RATE_HZ, DURATION_S = 50.0, 1800.0


def tool(*args):
    from conftest import REPO
    return subprocess.run([sys.executable, str(REPO / "tools/imu_calibrate.py"), *map(str, args)], cwd=REPO,
                          capture_output=True, text=True)


@pytest.fixture(scope="module")
def test_log(tmp_path_factory):
    path = tmp_path_factory.mktemp("imu") / "static.csv"
    synthetic.write_log(path, synthetic.static_log(TEST_PRESET, RATE_HZ, DURATION_S, seed=7))
    return path


@pytest.fixture(scope="module")
def calibrated(test_log):
    log = read_imu_log(test_log)
    check_at_rest(log)
    return calibrate(log, reps=0)


def test_noise_is_recovered_within_the_stated_tolerances(calibrated):
    for name, fit in calibrated.fits.items():
        truth = GYRO if name.startswith("gyro") else ACCEL
        for term, tolerance in TOLERANCE.items():
            value = getattr(fit, term).value
            assert abs(value / getattr(truth, term) - 1) <= tolerance, (name, term, value, getattr(truth, term))
    # the turn-on bias is the log's mean; the drift moves a mean over T by about K sqrt(T / 3): 4 of those
    assert calibrated.means["gyro z"] == pytest.approx(0.03, abs=4 * GYRO.rate_random_walk * np.sqrt(DURATION_S / 3))
    assert calibrated.tau_max_s == pytest.approx(DURATION_S / 10)


def test_bootstrap_intervals_hold_the_fit_and_are_reproducible(test_log):
    """The 95 % intervals hold the fit, are not absurdly wide for the estimator, and are the same for a seed.

    Width: a term's interval is est / (the 2.5 and 97.5 % quantiles of est*/est over REPS = 8 replicas), so its
    width in ln, ln(high / low), is at most the range of the 8 values ln(est*/est); their sd is the estimator's
    relative standard error on a log like this one, REL_SE (delta method), 0.89 to 1.38 times it at the fitted values
    (measured over 100 replicas per axis). A 95 % interval of a normal estimator spans 2 x 1.96 REL_SE; the bound is
    WIDTH_FACTOR = 3 times that, 11.76 REL_SE, at least 8.5 replica sd: P(range of 8 normals > 8.5) = 4.7e-8
    (8 int phi(x) [(1 - Phi(x))^7 - (Phi(x + w) - Phi(x))^7] dx) per interval. White noise and bias instability:
    ln(high / low) is bounded (12 intervals). Rate random walk: only ln(est / low), for its upper limit can be far or
    unbounded when a replica fits K = 0 (2 of 100 replicas of gyro y, whose K is fitted at 0.62 of its truth); it
    stays below the same bound but for P(the largest of 8 normals > 11.76 / 1.3) < 1e-17 (6 intervals).
    False failure, all 18: about 6e-7. An interval 4 times too wide (replicas spreading 4 times the estimator's sd)
    exceeds the bound with probability P(range of 8 > 11.76 / 4.8) = 0.67 for a replica sd of 1.2 REL_SE: the 12
    bounded widths all pass it with probability 2e-6.
    """
    WIDTH_FACTOR = 3.0
    log = read_imu_log(test_log)
    first = calibrate(log, reps=8, seed=2)
    again = calibrate(log, reps=8, seed=2)
    for name, fit in first.fits.items():
        for term in ("white", "bias_instability", "rate_random_walk"):
            t = getattr(fit, term)
            assert t.low <= t.value and (t.high is None or t.value <= t.high)
            assert t == getattr(again.fits[name], term)
            if term == "rate_random_walk":
                top = t.value
            else:
                assert t.high is not None, (name, term, t)
                top = t.high
            with np.errstate(divide="ignore"):
                width = np.log(top) - np.log(t.low)                 # ln(top / low); infinite for low = 0
            assert width <= WIDTH_FACTOR * 2 * 1.96 * REL_SE[term], (name, term, t, width)


def test_markov_process_limits():
    """Paparazzi's gyro bias (first-order Markov, 5 s): a rate random walk K = q at short averaging times,
    q Tc / sqrt(tau) at long ones (IEEE 952's Gauss-Markov Allan variance)."""
    q = 2e-4
    assert markov_adev(q, 0.01) == pytest.approx(q * np.sqrt(0.01 / 3), rel=2e-3)
    assert markov_adev(q, 5000.0) == pytest.approx(q * TC_S / np.sqrt(5000.0), rel=2e-3)


def test_paparazzi_s_recursion_with_the_defines_gives_the_promised_allan_deviation():
    """Close the loop: Paparazzi's gyro error (white NOISE_STD_DEV and b += dt (BIAS_RANDOM_WALK_STD_DEV n - b/5))
    simulated with the defines of a fit has, at 1, 10 and 60 s, the Allan deviation paparazzi_adev promised.

    Samples: RECORDS = 4 independent records of 3600 s at 512 Hz (N = 1 843 200 rates each, the bias started from
    its stationary law); the overlapping Allan variance (AllanTools' oadev) at tau = m dt of each, averaged.
    Its equivalent degrees of freedom: edf = RECORDS edf_1, with edf_1 that of one record (N + 1 phase points)
    for random-walk FM noise (NIST SP 1065, Riley 2008, table 5; Howe, Allan and Barnes 1981):
        edf_1 = (N - 2) / (m (N - 3)^2) ((N - 1)^2 - 3 m (N - 1) + 4 m^2) ~ N / m - 3,
    the smallest of the power-law noises' (white FM: ~ 3 N / (2 m)), so conservative for this error, white noise
    plus a Markov bias (random-walk FM below its 5 s, white FM above): over 150 records the sd of ln adev was 0.011,
    0.036, 0.071 at 1, 10, 60 s against 1 / sqrt(2 edf_1) = 0.012, 0.037, 0.094.
    edf avar_hat / avar ~ chi2(edf), so sd(ln adev_hat) = 1 / sqrt(2 edf) (delta method): 0.0059, 0.019, 0.047 at
    1, 10, 60 s (edf 14 388, 1 428, 228). Each check: |ln(measured / promised)| <= K_SIGMA / sqrt(2 edf) with
    K_SIGMA = 5 (normal approximation of ln chi2): two-sided false failure 5.7e-7 per check, 1.7e-6 for the three.
    Wrong models, rejected by the same measured values and tolerances (asserted): q 1.5 times too large or too
    small at every tau (its adev +26 % / -14 % at 1 s, +49 % / -32 % at 10 s, +49 % / -33 % at 60 s; the widest
    tolerance, at 60 s, is 0.234 in ln: x or / 1.26); the white noise 1.5 times too large or too small at 1 s
    (+29 % / -16 %), the one tau where it matters.
    """
    import allantools
    from scipy.signal import lfilter
    RECORDS, RECORD_S, K_SIGMA = 4, 3600.0, 5.0
    dt = 1.0 / 512.0
    fitted = AxisNoise(GYRO.white, GYRO.bias_instability, GYRO.rate_random_walk)
    q, worst = markov_drive(fitted, np.geomspace(0.02, 180.0, 14))
    assert 1.0 <= worst < 4.0
    noise_std, walk_std = fitted.white / np.sqrt(dt), q / np.sqrt(dt)
    a = 1.0 - dt / TC_S         # b_k+1 = a b_k + dt walk_std n_k: stationary Var b = (dt walk_std)^2 / (1 - a^2)
    taus = np.array([1.0, 10.0, 60.0])
    rng = np.random.default_rng(5)
    n = int(RECORD_S / dt)
    avar = np.zeros(taus.size)
    for _ in range(RECORDS):
        b0 = dt * walk_std / np.sqrt(1.0 - a * a) * rng.standard_normal()
        bias = lfilter([walk_std * dt], [1.0, -a], rng.standard_normal(n), zi=[a * b0])[0]
        got_taus, adev, _, _ = allantools.oadev(noise_std * rng.standard_normal(n) + bias, rate=1.0 / dt,
                                                data_type="freq", taus=taus)
        assert np.allclose(got_taus, taus)
        avar += adev ** 2 / RECORDS
    measured = np.log(np.sqrt(avar))
    m, phase_points = np.rint(taus / dt), n + 1
    edf = RECORDS * ((phase_points - 2) / (m * (phase_points - 3) ** 2)
                     * ((phase_points - 1) ** 2 - 3 * m * (phase_points - 1) + 4 * m ** 2))
    tolerance = K_SIGMA / np.sqrt(2.0 * edf)

    def off(white, drive):
        return measured - np.log(paparazzi_adev(True, white, drive, taus))

    assert np.all(np.abs(off(fitted.white, q)) <= tolerance), (off(fitted.white, q), tolerance)
    for factor in (1.5, 1 / 1.5):
        assert np.all(np.abs(off(fitted.white, factor * q)) > tolerance), (factor, off(fitted.white, factor * q))
        assert abs(off(factor * fitted.white, q)[0]) > tolerance[0], (factor, off(factor * fitted.white, q))


def test_the_command_line_writes_the_fragment_the_figure_and_the_report(test_log, tmp_path):
    done = tool("--log", test_log, "--out", tmp_path / "out", "--bootstrap", "4", "--quiet")
    assert done.returncode == 0, done.stderr
    fragment = (tmp_path / "out/imu_simulator.xml").read_text()
    section = etree.fromstring(fragment[fragment.index("<section"):])
    assert (section.get("name"), section.get("prefix")) == ("SIMULATOR", "NPS_")
    names = [d.get("name") for d in section.findall("define")]
    assert names == ["GYRO_DT"] + [f"GYRO_{k}_{a}" for a in "PQR" for k in ("NOISE_STD_DEV", "BIAS_INITIAL",
                                                                          "BIAS_RANDOM_WALK_STD_DEV")] + \
        ["ACCEL_DT"] + [f"ACCEL_{k}_{a}" for a in "XYZ" for k in ("NOISE_STD_DEV", "BIAS")]
    value = {d.get("name"): d.get("value") for d in section.findall("define")}
    assert float(value["GYRO_NOISE_STD_DEV_P"]) == pytest.approx(GYRO.white * np.sqrt(512), rel=0.01)
    assert float(value["ACCEL_NOISE_STD_DEV_Z"]) == pytest.approx(ACCEL.white * np.sqrt(512), rel=0.01)
    assert value["GYRO_DT"] == "(1./512)"
    assert str(test_log) in fragment and "bootstrap" in fragment
    import json
    report = json.loads((tmp_path / "out/imu_report.json").read_text())
    assert report["rows"] == RATE_HZ * DURATION_S and report["bootstrap"]["reps"] == 4
    assert set(report["axes"]) == {"gyro x", "gyro y", "gyro z", "accel x", "accel y", "accel z"}
    assert report["paparazzi"]["defines"]["NPS_GYRO_NOISE_STD_DEV_P"] == value["GYRO_NOISE_STD_DEV_P"]
    assert (tmp_path / "out/allan.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_example_airframe_holds_the_tool_s_output_on_its_stated_log():
    """conf/airframes/finken/finken_quad.xml: the defines of make imu-calibrate on the synthetic MPU-9250 log its
    comment names (seed 1, 7200 s at 100 Hz), made here in memory (the CSV keeps 9 digits; the defines 4)."""
    from conftest import REPO
    columns = synthetic.static_log(synthetic.MPU9250, 100.0, 7200.0, seed=1)
    t = columns["t"]
    log = ImuLog("mpu9250", t, np.column_stack([columns[c] for c in ("gx", "gy", "gz")]),
                 np.column_stack([columns[c] for c in ("ax", "ay", "az")]), np.arange(t.size) + 2, 100.0)
    expected = {name: value for name, value, _ in calibrate(log, reps=0).defines.rows}
    airframe = etree.parse(str(REPO / "conf/airframes/finken/finken_quad.xml"))
    simulator = airframe.find("section[@name='SIMULATOR']")
    got = {d.get("name"): d.get("value") for d in simulator.findall("define") if d.get("name") in expected}
    assert set(got) == set(expected)
    for name, value in expected.items():
        if value.startswith("("):
            assert got[name] == value
        else:
            assert float(got[name]) == pytest.approx(float(value), rel=1e-3, abs=1e-12), name
    target = airframe.find("firmware/target[@name='nps']")
    params = target.find("define[@name='NPS_SENSORS_PARAMS']")
    assert params.get("value") == "nps_sensors_params_finken.h"
    assert (REPO / "sw/simulator/nps" / params.get("value")).is_file()


def write_csv(path, header, rows):
    path.write_text(header + "\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))
    return path


def static_rows(n=600, rate=50.0, seed=1):
    columns = synthetic.static_log(TEST_PRESET, rate, n / rate, seed)
    return np.column_stack([columns[c] for c in ("t", "gx", "gy", "gz", "ax", "ay", "az")])


@pytest.mark.parametrize("rows, edit, message", [
    (50, None, "{path}: 50 rows: too few for an Allan deviation (at least 100)"),
    (600, (10, 3, "fast"), "{path}:12: column 'gz': 'fast' is not a number"),
    (600, (7, 4, ""), "{path}:9: column 'ax': no value (the Allan deviation needs every sample)"),
    (600, (8, 1, "inf"), "{path}:10: column 'gx': 'inf' is not a finite number"),
    (600, (20, 0, "0.38"), "{path}:22: column 't': time 0.38 s does not increase (previous row 0.38 s)"),
])
def test_bad_values_are_named_by_file_line_and_column(tmp_path, rows, edit, message):
    table = static_rows(rows).astype(object)
    if edit:
        table[edit[0], edit[1]] = edit[2]
    path = write_csv(tmp_path / "bad.csv", "t,gx,gy,gz,ax,ay,az", table)
    with pytest.raises(ImuLogError) as info:
        read_imu_log(path)
    assert str(info.value) == message.format(path=path)


def test_a_missing_axis_is_refused_and_a_missing_sensor_warned(tmp_path):
    rows = static_rows(3000)
    path = write_csv(tmp_path / "no_gz.csv", "t,gx,gy,ax,ay,az", np.delete(rows, 3, axis=1))
    with pytest.raises(ImuLogError, match=r"no_gz.csv:1: column 'gz': missing: the gyroscope needs gx, gy, gz \(the "
                                          r"file has t, gx, gy, ax, ay, az; name yours with --columns gz=<column>\)"):
        read_imu_log(path)
    path = write_csv(tmp_path / "no_gyro.csv", "t,ax,ay,az", rows[:, [0, 4, 5, 6]])
    log = read_imu_log(path)
    assert log.gyro is None and log.warnings == [f"{path}: no gyroscope columns (gx, gy, gz): only the accelerometer "
                                                 "is calibrated"]
    done = tool("--log", path, "--out", tmp_path / "out", "--bootstrap", "0", "--quiet")
    assert done.returncode == 0 and "warning: " + log.warnings[0] in done.stderr
    assert "GYRO_" not in (tmp_path / "out/imu_simulator.xml").read_text()


def test_a_copter_that_moved_is_refused_naming_the_column_line_and_time(tmp_path):
    rows = static_rows(3000)
    rows[1500:, 5] += 0.5                  # ay: tilted by 3 deg at t = 30 s
    path = write_csv(tmp_path / "moved.csv", "t,gx,gy,gz,ax,ay,az", rows)
    log = read_imu_log(path)
    with pytest.raises(ImuLogError, match=r"moved.csv:1502: column 'ay': the copter moved: the 1-s mean jumped by "
                                          r"0.5\d* m/s\^2 at t = 30 s"):
        check_at_rest(log)
    done = tool("--log", path, "--out", tmp_path / "out")
    assert done.returncode == 2 and "moved.csv:1502: column 'ay': the copter moved" in done.stderr
    assert not (tmp_path / "out").exists()


def test_a_log_too_short_for_the_averaging_time_asked_is_refused(test_log, tmp_path):
    done = tool("--log", test_log, "--out", tmp_path / "out", "--tau-max", "200")
    assert done.returncode == 2
    assert f"{test_log}: column 't': 1800 s of data (90000 rows) are too short for --tau-max 200 s: an Allan " \
           "deviation at tau needs 10 tau of data (2000 s); record longer or ask for at most 180 s" in done.stderr


def test_a_lab_s_columns_and_units(tmp_path):
    """Its own names (--columns) in deg/s and g read as the same log in SI units; the accelerometer in g without
    --accel-unit is warned about."""
    rows = static_rows(3000)
    own = rows.copy()
    own[:, 1:4] *= 180 / np.pi
    own[:, 4:7] /= 9.80665
    path = write_csv(tmp_path / "lab.csv", "time_s,GyroX,GyroY,GyroZ,AccX,AccY,AccZ,temp",
                     np.column_stack([own, np.full(len(own), 25.0)]))
    columns = parse_imu_columns("t=time_s,gx=GyroX,gy=GyroY,gz=GyroZ,ax=AccX,ay=AccY,az=AccZ")
    log = read_imu_log(path, columns, gyro_unit="deg/s", accel_unit="g")
    assert np.allclose(log.gyro, rows[:, 1:4], rtol=1e-8) and np.allclose(log.accel, rows[:, 4:7], rtol=1e-8)
    assert log.warnings == []
    unwarned = read_imu_log(path, columns)
    assert "the accelerometer's mean norm is 1 m/s^2" in unwarned.warnings[0] and "--accel-unit" in unwarned.warnings[0]
    with pytest.raises(ValueError, match="columns: unknown column 'gyro_x'"):
        parse_imu_columns("gyro_x=GyroX")
    with pytest.raises(ValueError, match="columns: 'gx' is given twice"):
        parse_imu_columns("gx=A,gx=B")


def test_make_forwards_the_options():
    from conftest import REPO
    done = subprocess.run(["make", "-n", "--no-print-directory", "imu-calibrate", "LOG=x.csv", "OUT=o",
                           "COLUMNS=t=time_s", "GYRO_UNIT=deg/s", "ACCEL_UNIT=g", "TAU_MAX=60", "SIM_RATE=100",
                           "BOOTSTRAP=5", "SEED=3"], cwd=REPO, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "tools/imu_calibrate.py --log x.csv --out o --columns t=time_s --gyro-unit 'deg/s' --accel-unit 'g' " \
           "--tau-max 60 --sim-rate 100 --bootstrap 5 --seed 3" in done.stdout
