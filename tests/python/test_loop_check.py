"""What `make paparazzi-check`'s loop step (finken.paparazzi.loop_check) accepts as the hidden sonar bias of +0.10 m
named, on the workflow's fits as it builds them, and the cross-talk readings it counts in the flight's log and the
simulator's (no Paparazzi needed)."""
from types import SimpleNamespace

import numpy as np
import pytest

from finken import models
from finken.discrepancy.candidates import Candidate
from finken.discrepancy.fitting import Fit
from finken.flight.loop import truth_agreement
from finken.paparazzi.loop_check import _names_the_bias

HIDDEN_B = 0.1


def fitted_with(fit):
    return SimpleNamespace(effects=[SimpleNamespace(fit=fit)])


def curve_fit(over, at, b, kind="sonar"):
    effect = models.Effect("bias_curve", {}, curve=models.BiasCurve(over, at, b))
    return Fit(Candidate(kind, "bias_curve", over=over), {f"b at {k:.4g}": v for k, v in zip(at, b)}, "curve",
               float("nan"), built=[effect])


def test_a_bias_on_the_hidden_kind_is_named():
    assert _names_the_bias(fitted_with(Fit(Candidate("sonar", "bias"), {"b": 0.09}, "", 0.0)), "sonar", HIDDEN_B)
    assert not _names_the_bias(fitted_with(Fit(Candidate("ranging", "bias"), {"b": 0.1}, "", 0.0)), "sonar",
                               HIDDEN_B)


@pytest.mark.parametrize("values, named", [({"1": 0.091, "2": 0.118}, True), ({"1": 0.091, "2": 0.121}, False)])
def test_a_bias_per_vehicle_is_named_when_every_vehicle_is_within_2_cm(values, named):
    fit = Fit(Candidate("sonar", "bias_per_vehicle"), values, "", 0.0)
    assert _names_the_bias(fitted_with(fit), "sonar", HIDDEN_B) is named


@pytest.mark.parametrize("at_path_0, named", [(0.092, True), (0.081, True), (0.079, False), (0.121, False)])
def test_a_curve_over_the_crosstalk_path_is_named_by_its_bias_where_no_sonar_is_heard(at_path_0, named):
    # a Paparazzi flight whose log marked 2380 readings cross-talk that the simulator did not hear: 0 +0.092,
    # 1.41 +0.421 m
    fit = curve_fit("ctx_crosstalk_path", [0.0, 1.41], [at_path_0, 0.421])
    assert _names_the_bias(fitted_with(fit), "sonar", HIDDEN_B) is named


def test_a_curve_over_another_variable_is_not_the_bias():
    assert not _names_the_bias(fitted_with(curve_fit("ctx_speed", [0.0, 0.5], [0.1, 0.1])), "sonar", HIDDEN_B)
    assert not _names_the_bias(fitted_with(curve_fit("ctx_crosstalk_path", [0.0, 1.0], [0.1, 0.3], "ranging")),
                               "sonar", HIDDEN_B)


def test_the_truth_agreement_counts_the_readings_each_log_marks_as_cross_talk():
    n = 5
    path = np.array([0.0, 1.2, 1.3, 0.0, 0.9])       # computed: rows 1, 2 and 4 (a ranging row) hear a pulse
    sim_path = np.array([0.7, 1.2, 0.0, 0.0, 0.0])   # the simulator: rows 0 and 1
    ctx = {"ctx_crosstalk_path": path, "ctx_target_copter": np.zeros(n)}

    class Log(SimpleNamespace):       # the RangeLog's fields truth_agreement reads
        def __len__(self):
            return n

    log = Log(line=np.arange(n), vehicle=np.ones(n, int), t=np.arange(n) * 0.1, true_range=np.ones(n),
              sensor=np.array(["sonar_front"] * 4 + ["ranging"]), ctx=ctx)
    records = SimpleNamespace(line=np.arange(n), vehicle=np.ones(n, int))
    sim = SimpleNamespace(true_range=np.ones(n), ctx={"ctx_crosstalk_path": sim_path,
                                                      "ctx_target_copter": np.zeros(n)})
    level = (np.zeros((n, 3)), np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)), np.ones(n, bool))
    poses = SimpleNamespace(vehicles=[1], at=lambda v, t: level)
    agreement = truth_agreement(log, records, {1: sim}, poses, 0.2)
    assert agreement.heard == {"computed": 2, "simulator": 2, "both": 1}
    assert "2 readings computed, 2 in the simulator's log, 1 in both" in agreement.lines()[-1]
