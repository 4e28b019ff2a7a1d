"""The loop closed in Paparazzi's NPS, a step of `make paparazzi-check`: four aircraft fly with a sensor model that
carries a hidden effect; what their range_recorder modules wrote and their true poses (as a motion capture would
give them) become a range log (finken.flight, what `make rangelog` runs), and the calibration workflow, started from
the model without the effect, must name it and shrink the held-out gap. Also printed: how well the true ranges
computed from the poses agree with the simulator's own, and why they differ where they do (finken.flight.loop).
"""
import os
import time

import numpy as np

from finken import models
from finken.discrepancy.report import write_outputs
from finken.discrepancy.workflow import calibrate
from finken.flight.flight_log import flight_range_log
from finken.flight.loop import flight_files, hidden_model, truth_agreement
from finken.flight.mocap import read_mocap
from finken.flight.mounts import sonar_mounts, sonar_timing
from finken.flight.records import read_records
from finken.flight.truth import ArenaTruth
from finken.paparazzi.overlay import REPO_ROOT
from finken.paparazzi.sim import VARIANTS, fly_and_merge, ivy_bus, run_base_port, simsitl_command
from finken.paparazzi.tree import PaparazziFailed
from finken.rangelog import read_range_log, write_range_log

BASE_MODEL = REPO_ROOT / "conf/sensor_models/finken_default.xml"
ARENA = REPO_ROOT / "conf/arena/swarmlab.xml"
AIRFRAME = REPO_ROOT / "conf/airframes/finken_nps.xml"
HIDDEN = ("sonar", {"name": "bias", "b": "0.1"})   # every sonar reads 10 cm long
PER_VEHICLE_TOLERANCE_M = 0.02   # a bias per vehicle names the hidden bias when each vehicle's is this close to it
POSE_RATE_HZ = 50.0                                # the motion capture's rate (OptiTrack: 100-240 Hz)


def check_loop(tree, env, out, logs, step, vehicles=4, duration_s=60.0, time_factor=5.0, seed=1):
    """Fly, turn the flight into a range log, calibrate; raises PaparazziFailed when the hidden effect is not named
    or the held-out gap does not shrink. The aircraft of VARIANTS[0] must be built (check_swarm builds them)."""
    loop = out / "loop"
    loop.mkdir(parents=True, exist_ok=True)
    kind, effect = HIDDEN
    model = hidden_model(BASE_MODEL, loop / "hidden_model.xml", kind, effect)
    print(f"        hidden: {kind} {effect['name']} " +
          " ".join(f"{k}={v}" for k, v in effect.items() if k != "name") + f" ({model})", flush=True)
    variant = VARIANTS[0]
    base_port = run_base_port(os.getpid())
    aircraft = [(name, ac_id, simsitl_command(tree, name, time_factor, ivy_bus(base_port, ac_id)))
                for name, ac_id in variant.aircraft(vehicles)]
    result = fly_and_merge(f"{step} loop", aircraft, dict(env, FINKEN_WORLD_SENSOR_MODEL=str(model)), tree, loop,
                           logs, duration_s, time_factor, world=f"finken-loop-{os.getpid()}",
                           run_id=f"loop-{os.getpid()}-{time.time_ns()}", pose_rate_hz=POSE_RATE_HZ)
    if not result.ok:
        raise PaparazziFailed(f"the loop's flight did not complete (logs: {logs}, {loop / 'raw'})")
    return close_loop(loop, [ac_id for _, ac_id, _ in aircraft], seed)


def close_loop(loop, ids, seed=1):
    """The flight of aircraft `ids` in loop/raw to loop/flight.csv and its calibration in loop/calibrate; raises
    PaparazziFailed unless the hidden effect is named and the held-out gap shrinks."""
    kind, effect = HIDDEN
    record_path, mocap_path = flight_files(loop / "raw", ids, loop)
    try:
        records, poses = read_records(record_path), read_mocap(mocap_path)
        with ArenaTruth(ARENA) as arena:
            log, report = flight_range_log(arena, sonar_mounts(AIRFRAME, arena.sonar_offset_m), records, poses,
                                           timing=sonar_timing(AIRFRAME))
            radius_m = arena.copter_radius_m
    except ValueError as err:   # a reader's or the clock's refusal, which names the file and line
        raise PaparazziFailed(f"the loop: the flight did not become a range log: {err}") from err
    write_range_log(loop / "flight.csv", log)
    for line in report.lines() + [f"wrote {loop / 'flight.csv'}: {report.written} readings"]:
        print(f"        {line}", flush=True)
    sims = {ac_id: read_range_log(loop / "raw" / f"readings_{ac_id}.csv") for ac_id in ids}
    for line in truth_agreement(log, records, sims, poses, radius_m).lines():
        print(f"        {line}", flush=True)
    fitted = calibrate(log, models.SensorModel.load(BASE_MODEL, log_columns=log.ctx), seed=seed)
    write_outputs(loop / "calibrate", fitted, force=True)
    named = [(e.fit.candidate.kind, e.fit.candidate.name) for e in fitted.effects]
    print(f"        calibrate: {fitted.verdict}", flush=True)
    print(f"        held-out gap {fitted.gap_before:.4g} m before, {fitted.gap_after:.4g} m after (noise floor "
          f"{fitted.gap_floor:.4g} m); report {loop / 'calibrate' / 'report.html'}", flush=True)
    if not _names_the_bias(fitted, kind, float(effect["b"])):
        raise PaparazziFailed(f"the loop: the hidden {kind} {effect['name']} was not named (named: "
                              f"{', '.join(f'{k} {n}' for k, n in named) or 'nothing'})")
    if not fitted.gap_after < fitted.gap_before:
        raise PaparazziFailed(f"the loop: the held-out gap did not shrink ({fitted.gap_before:.4g} m before, "
                              f"{fitted.gap_after:.4g} m after)")
    return fitted


def _names_the_bias(fitted, kind, b_m):
    """Whether the workflow named the hidden bias:
    - `bias`;
    - `bias_per_vehicle` with every vehicle's bias within PER_VEHICLE_TOLERANCE_M of it (the same offset on each
      copter, which the data may fit per copter as well);
    - `bias_curve over ctx_crosstalk_path` whose bias at path 0, on the readings that hear no other sonar (nearly
      all), is within that tolerance of it. The log's cross-talk context is computed from the records' times and the
      estimated clock offsets, a few ms off, so it marks readings the simulator did not hear as cross-talk; the curve
      then bends there too (docs/calibration.md)."""
    for e in fitted.effects:
        fit = e.fit
        if fit.candidate.kind != kind:
            continue
        if fit.candidate.name == "bias":
            return True
        if fit.candidate.name == "bias_per_vehicle" and fit.params and all(
                abs(v - b_m) <= PER_VEHICLE_TOLERANCE_M for v in fit.params.values()):
            print("        the bias named per vehicle: " + ", ".join(f"{k} {v:+.3f} m" for k, v in
                                                                       fit.params.items()), flush=True)
            return True
        if fit.candidate.name == "bias_curve" and fit.candidate.over == "ctx_crosstalk_path":
            curve = fit.effects()[0].curve
            at_no_crosstalk = float(np.interp(0.0, curve.at, curve.b))   # constant beyond the knots
            if abs(at_no_crosstalk - b_m) <= PER_VEHICLE_TOLERANCE_M:
                print(f"        the bias named where no other sonar is heard: {at_no_crosstalk:+.3f} m at "
                      f"ctx_crosstalk_path 0 ({fit.values_text()})", flush=True)
                return True
    return False
