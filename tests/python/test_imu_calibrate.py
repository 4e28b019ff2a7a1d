"""make imu-calibrate: noise recovered from synthetic static logs of known parameters, Paparazzi's model given by the
written defines, the example airframe holding the tool's output, and bad input named by file, line and column.

Recovery tolerances: over 40 seeds of the test log (1800 s at 50 Hz; white N, bias instability B, rate random walk K
with crossovers near 3 s and 30 s), the fitted/true ratios had standard deviations 0.2 % (N), 4.2 % (B) and 17.5 % (K);
each check allows 4 of them (N 1 %, B 17 %, K 70 %: a false-failure probability of about 6e-5 per check for a
normal estimator). A fit that mistook the density's convention (a factor sqrt(2) on N), or dropped a term, fails.
"""
import subprocess
import sys

import numpy as np
import pytest
from lxml import etree

from finken.imu import synthetic
from finken.imu.allan import allan_deviation
from finken.imu.calibration import calibrate
from finken.imu.imu_log import ImuLog, ImuLogError, check_at_rest, parse_imu_columns, read_imu_log
from finken.imu.paparazzi import TC_S, markov_adev, markov_drive, paparazzi_adev
from finken.imu.synthetic import AxisNoise, ImuPreset

TOLERANCE = {"white": 0.01, "bias_instability": 0.17, "rate_random_walk": 0.70}
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
    log = read_imu_log(test_log)
    first = calibrate(log, reps=8, seed=2)
    again = calibrate(log, reps=8, seed=2)
    for name, fit in first.fits.items():
        for term in ("white", "bias_instability", "rate_random_walk"):
            t = getattr(fit, term)
            assert t.low <= t.value and (t.high is None or t.value <= t.high)
            assert t == getattr(again.fits[name], term)


def test_markov_process_limits():
    """Paparazzi's gyro bias (first-order Markov, 5 s): a rate random walk K = q at short averaging times,
    q Tc / sqrt(tau) at long ones (IEEE 952's Gauss-Markov Allan variance)."""
    q = 2e-4
    assert markov_adev(q, 0.01) == pytest.approx(q * np.sqrt(0.01 / 3), rel=2e-3)
    assert markov_adev(q, 5000.0) == pytest.approx(q * TC_S / np.sqrt(5000.0), rel=2e-3)


def test_paparazzi_s_recursion_with_the_defines_gives_the_promised_allan_deviation():
    """Close the loop: Paparazzi's gyro error (white NOISE_STD_DEV and b += dt (BIAS_RANDOM_WALK_STD_DEV n - b/5))
    simulated with the defines of a fit has, at 1, 10 and 60 s, the Allan deviation paparazzi_adev promised, within
    4 standard errors of the estimate (1 / sqrt(2 edf); edf >= 40 here, so 45 %; a q off by 2 fails at 10 s)."""
    from scipy.signal import lfilter
    dt = 1.0 / 512.0
    fitted = AxisNoise(GYRO.white, GYRO.bias_instability, GYRO.rate_random_walk)
    taus = np.geomspace(0.02, 180.0, 14)
    q, worst = markov_drive(fitted, taus)
    assert 1.0 <= worst < 4.0
    noise_std, walk_std = fitted.white / np.sqrt(dt), q / np.sqrt(dt)
    rng = np.random.default_rng(5)
    n = int(3600 / dt)
    bias = lfilter([walk_std * dt], [1.0, -(1.0 - dt / TC_S)], rng.standard_normal(n))
    error = noise_std * rng.standard_normal(n) + bias
    curve = allan_deviation(error, 1.0 / dt, 60.0)
    for tau in (1.0, 10.0, 60.0):
        measured = np.interp(np.log(tau), np.log(curve.tau), curve.adev)
        assert measured == pytest.approx(paparazzi_adev(True, fitted.white, q, tau), rel=0.45), tau
    assert paparazzi_adev(True, fitted.white, 2 * q, 10.0) > 1.45 * paparazzi_adev(True, fitted.white, q, 10.0)


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
