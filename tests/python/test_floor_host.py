"""The floor under the downward sonar, end to end through the host: copters circling the arena centre
(tests/data/airframes/sensors_nps.xml, radius 1 m around (1.5, 2)) over tests/data/arena/floor_mat.xml, whose foam
mat covers x <= 1.5 (the west half of the circle) and a carpet x >= 1.5, y >= 3 (the circle's top) on a hard floor.

Statistics: a missing-reading rate p estimated from n downward readings over the mat has the binomial standard error
sqrt(p (1 - p) / n); the tolerance is 4 standard errors (false-failure probability 6e-5 each); with n ~ 2400 that is
+-0.03 around 0.3 and 0.2, so a mat that is ignored (rate 0) or applied everywhere fails.
"""
import subprocess

import numpy as np
import pytest

K_SIGMA = 4.0
MAT_ARENA = "tests/data/arena/floor_mat.xml"
HARD, CARPET, FOAM = 1, 2, 3


@pytest.fixture(scope="module")
def host():
    from conftest import REPO
    subprocess.run(["make", "-s", "--no-print-directory", "host", "AIRFRAME=tests/data/airframes/sensors_nps.xml"],
                   cwd=REPO, check=True, stdout=subprocess.DEVNULL)
    return REPO / "build/host/sensors_nps/nps_host"


def run(host, out, *args):
    from conftest import REPO
    result = subprocess.run([str(host), "--out", str(out), "--quiet", "--duration", "60", "--seed", "5", *args],
                            cwd=REPO, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    from finken.rangelog import read_range_log
    return read_range_log(out / "readings.csv")


def assert_rate(missing, expected):
    n = missing.size
    tolerance = K_SIGMA * np.sqrt(expected * (1 - expected) / n)
    assert abs(missing.mean() - expected) <= tolerance, (missing.mean(), expected, tolerance, n)


def test_ctx_floor_is_the_material_under_the_copter_on_downward_readings_only(host, tmp_path):
    from finken.run_logs import read_poses
    log = run(host, tmp_path, "--arena", MAT_ARENA)
    assert "ctx_floor" in log.ctx
    floor = log.ctx["ctx_floor"]
    down = log.sensor == "sonar_down"
    assert np.all(floor[~down] == 0)
    assert {HARD, FOAM} <= set(np.unique(floor[down])) <= {HARD, CARPET, FOAM}
    poses = read_poses(tmp_path / "poses.csv")
    for vehicle in np.unique(log.vehicle):
        rows = down & (log.vehicle == vehicle)
        mine = poses["vehicle"] == vehicle
        x = np.interp(log.t[rows], poses["t"][mine], poses["x"][mine])
        y = np.interp(log.t[rows], poses["t"][mine], poses["y"][mine])
        # 10 Hz poses: away from the regions' edges (x = 1.5, y = 3) by more than a pose step
        clear = (np.abs(x - 1.5) > 0.05) & (np.abs(y - 3.0) > 0.05)
        assert clear.sum() > 500
        expected = np.where(x <= 1.5, FOAM, np.where(y >= 3.0, CARPET, HARD))
        assert np.array_equal(floor[rows][clear], expected[clear])


def test_a_foam_mat_changes_the_missing_reading_rate_as_configured(host, tmp_path):
    """dropout(p=0.3) if ctx_floor == 3 with beyond_max=none: 30 % of the downward readings over the mat are
    missing (empty), none elsewhere."""
    model = "sonar(min_range=0.2, max_range=3, beyond_max=none): dropout(p=0.3) if ctx_floor == 3"
    log = run(host, tmp_path, "--arena", MAT_ARENA, "--sensor-model", model)
    down = log.sensor == "sonar_down"
    over_mat = down & (log.ctx["ctx_floor"] == FOAM)
    assert over_mat.sum() > 1500
    assert_rate(np.isnan(log.measured[over_mat]), 0.3)
    assert not np.any(np.isnan(log.measured[down & ~over_mat]))


def test_the_default_model_loses_a_fifth_of_the_echoes_over_foam(host, tmp_path):
    """finken_default.xml: dropout p = 0.2 over foam; a lost echo reads max_range (3 m, beyond_max="max")."""
    log = run(host, tmp_path, "--arena", MAT_ARENA)
    down = log.sensor == "sonar_down"
    no_echo = log.measured == 3.0
    assert_rate(no_echo[down & (log.ctx["ctx_floor"] == FOAM)], 0.2)
    assert not np.any(no_echo[down & (log.ctx["ctx_floor"] == HARD)])


def test_a_floor_without_other_materials_changes_no_reading(host, tmp_path):
    """The SwarmLab arena without a <floor> element, with <floor material="hard"/> (the shipped file) and with a
    hard region over the copters' circle: byte-identical logs for the same seed (no condition holds, no random
    number is drawn)."""
    from conftest import REPO
    shipped = (REPO / "conf/arena/swarmlab.xml").read_text()
    start, end = shipped.index("<floor"), shipped.index("</arena>")
    without = tmp_path / "without_floor.xml"
    without.write_text(shipped[:start] + shipped[end:])
    hard_region = tmp_path / "hard_region.xml"
    hard_region.write_text(shipped.replace('<floor material="hard"/>', '<floor material="hard">'
                                           '<region material="hard" x0="0.2" y0="0.5" x1="2.8" y1="3.5"/></floor>'))
    outputs = []
    for arena in (without, REPO / "conf/arena/swarmlab.xml", hard_region):
        out = tmp_path / arena.stem
        run(host, out, "--arena", str(arena))
        outputs.append((out / "readings.csv").read_bytes())
    assert outputs[0] == outputs[1] == outputs[2]
