"""The Paparazzi flight check's analysis (tools/finken/paparazzi/flight_check.py) on synthetic flights with known
answers, its binding of the host's lag model (sw/simulator/nps/nps_finken_lag.cdef) against the exact first-order
law, and the check flight plan it derives from finken_arena.xml. Flying in Paparazzi itself needs a Paparazzi tree
and is not run here (docs/paparazzi-fdm.md)."""
import math
import re
import shutil

import numpy as np
import pytest
from lxml import etree

from finken.paparazzi import flight_check as fc


def test_the_time_constant_of_an_exact_first_order_step_is_recovered():
    t = np.arange(0.0, 3.0, 0.02)
    v = fc.first_order(t, 0.1, 0.5, 0.53)
    assert fc.fit_time_constant(t, v, 0.1, 0.5) == pytest.approx(0.53, rel=1e-6)
    # 63.2 % of the way is reached at t = tau (linear interpolation between samples 0.02 s apart: error < 1e-3 s)
    assert fc.rise_time(t, v, 0.1, 0.5) == pytest.approx(0.53, abs=1e-3)
    # a step down too
    assert fc.fit_time_constant(t, fc.first_order(t, 0.5, -0.2, 0.4), 0.5, -0.2) == pytest.approx(0.4, rel=1e-6)
    assert math.isnan(fc.rise_time(t, np.zeros_like(t), 0.0, 0.5))


def test_the_lag_model_binding_follows_the_first_order_law():
    """nps_finken_lag through the cdef: v(tau) = v_cmd (1 - 1/e) exactly (a mismatched struct would not)."""
    t = np.arange(0.0, 1.0 + 1e-9, 0.02)
    vn, ve = fc.lag_model_velocities(t, np.full(len(t), 0.3), np.full(len(t), -0.4), 0.0, 0.0, 0.5)
    i = int(round(0.5 / 0.02))
    assert vn[i] == pytest.approx(0.3 * (1.0 - math.exp(-1.0)), abs=1e-12)
    assert ve[i] == pytest.approx(-0.4 * (1.0 - math.exp(-1.0)), abs=1e-12)


def test_the_lag_cdef_declares_what_the_header_declares(repo):
    def normalise(text):
        text = re.sub(r"/\*.*?\*/|//[^\n]*", " ", text, flags=re.S)
        return re.sub(r"\s*([(),;*\[\]{}])\s*", r"\1", re.sub(r"\s+", " ", text))
    nps = repo / "sw/simulator/nps"
    header, cdef = normalise((nps / "nps_finken_lag.h").read_text()), normalise((nps / "nps_finken_lag.cdef").read_text())
    declaration = re.search(r"void nps_finken_lag_step\([^)]*\);", cdef).group(0)
    assert "extern " + declaration in header
    for struct in ("params", "memo", "state"):
        members = re.search(r"struct nps_finken_lag_%s\{([^}]*)\}" % struct, cdef).group(1)
        assert re.search(r"struct nps_finken_lag_%s\{%s\}" % (struct, re.escape(members)), header), struct


def synthetic_log(tau_s, step_at=20.0, step_s=3.0, vn=0.5, height=0.62):
    """A flight as the flight model logs it: GUIDED at 16 s, a north step at 20 s answered with time constant tau."""
    t = np.round(np.arange(0.02, 35.0, 0.02), 6)
    on = (t >= step_at) & (t < step_at + step_s)
    v = np.where(t < step_at, 0.0, fc.first_order(np.maximum(t - step_at, 0.0), 0.0, vn, tau_s))
    after = t >= step_at + step_s
    v_stop = fc.first_order(step_s, 0.0, vn, tau_s)
    v[after] = v_stop * np.exp(-(t[after] - step_at - step_s) / tau_s)
    zeros = np.zeros_like(t)
    return {"t_s": t, "ap_mode": np.where(t >= 16.0, fc.AP_MODE_GUIDED, 13), "vn_mps": v, "ve_mps": zeros,
            "agl_m": np.full_like(t, height), "sp_vn_mps": np.where(on, vn, 0.0), "sp_ve_mps": zeros}


def test_a_flight_that_is_the_lag_model_passes_with_no_gap():
    fig = fc.analyse(synthetic_log(0.5), hold_s=4.0, step_s=3.0, vn_cmd=0.5, ve_cmd=0.0, lag_tau_s=0.5)
    assert fig["t_step_s"] == pytest.approx(20.0)
    assert fig["step_tau_fit_s"] == pytest.approx(0.5, rel=1e-4)
    assert fig["lag_max_gap_mps"] < 1e-9
    assert fig["hover_nav_max_err_m"] == pytest.approx(0.02)
    assert all(ok for _, ok, _ in fc.verdicts(fig, 0.05, 0.4, 0.7, 0.1))


def test_a_slower_flight_is_measured_and_fails_the_stated_tolerances():
    """tau 1 s against the lag model's 0.5 s: the gap 0.5 (1 - e^-t) vs 0.5 (1 - e^-2t) is 0.5 (e^-t - e^-2t),
    largest where e^-t = 1/2 (t = ln 2): 0.5 (1/2 - 1/4) = 0.125 m/s (by hand)."""
    fig = fc.analyse(synthetic_log(1.0), hold_s=4.0, step_s=3.0, vn_cmd=0.5, ve_cmd=0.0, lag_tau_s=0.5)
    assert fig["step_tau_fit_s"] == pytest.approx(1.0, rel=1e-4)
    assert fig["lag_max_gap_mps"] == pytest.approx(0.125, abs=1e-3)
    checks = {name: ok for name, ok, _ in fc.verdicts(fig, 0.05, 0.4, 0.7, 0.1)}
    assert checks == {"hover NAV": True, "hover GUIDED": True, "step tau": False, "lag model": False}


def test_a_flight_that_never_enters_guided_is_an_error():
    log = synthetic_log(0.5)
    log["ap_mode"] = np.full_like(log["t_s"], 13)
    with pytest.raises(fc.CheckError, match="GUIDED"):
        fc.analyse(log, 4.0, 3.0, 0.5, 0.0, 0.5)


def test_the_check_flight_plan_steps_inside_the_guided_block(repo, tmp_path):
    plan = tmp_path / fc.ARENA_PLAN
    plan.parent.mkdir(parents=True)
    shutil.copyfile(repo / fc.ARENA_PLAN, plan)
    fc.write_check_plan(tmp_path, 4.0, 3.0, 0.5, -0.25)
    block = etree.parse(str(tmp_path / fc.CHECK_PLAN)).find(".//block[@name='Guided']")
    stages = [(el.tag, el.get("cond") or el.get("fun")) for el in block if isinstance(el.tag, str)]   # not comments
    assert stages == [("call_once", "autopilot_set_mode(AP_MODE_GUIDED)"),
                      ("while", "LessThan(block_time, 4)"),
                      ("call_once", "autopilot_guided_move_ned(0.5, -0.25, 0., 0.)"),
                      ("while", "LessThan(block_time, 7)"),
                      ("call_once", "autopilot_guided_move_ned(0., 0., 0., 0.)"),
                      ("while", "TRUE")]


def test_the_host_airframe_time_constant_is_read(repo):
    assert fc.host_velocity_tau() == pytest.approx(0.5)
