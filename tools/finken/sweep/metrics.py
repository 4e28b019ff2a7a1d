"""The metrics of a sweep's run: make sim's metrics.json flattened to one number per name.

Nested keys are joined with dots (`sensor_errors.sonar_front.rmse_m`, `classification.on.detector.wall_recall`,
`targets.wall_recall_beats_baseline`); true and false become 1 and 0, so that the mean over seeds of a target is the
fraction of runs meeting it; null (a figure with nothing to compute it from) stays None.
"""
import functools
from types import SimpleNamespace

import numpy as np

from finken.rangelog import SENSOR_NAMES
from finken.sim_report.detector_metrics import summarize, targets_met
from finken.sim_report.sensor_errors import sensor_error_stats


def flatten(document, prefix=""):
    """{dotted name: number or None} of a metrics.json document (a dict read from JSON)."""
    flat = {}
    for key, value in document.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            flat.update(flatten(value, name + "."))
        elif isinstance(value, bool):
            flat[name] = int(value)
        elif value is None or isinstance(value, (int, float)):
            flat[name] = value
    return flat


@functools.cache
def metric_names():
    """Every name a run's metrics may have, in metrics.json's order: make sim's functions applied to a run of two
    echoes (one wall, one copter) and one reading per sensor, so that the names cannot drift from theirs."""
    detections = {"target_copter": np.array([False, True]), "detector_class": np.array(["wall", "copter"]),
                  "baseline_class": np.array(["wall", "copter"])}
    poses = {"t": np.array([0.0, 0.1]), "vehicle": np.array([1.0, 1.0]), "x": np.array([1.0, 1.0]),
             "y": np.array([1.0, 1.0])}
    run = {"detections": detections, "poses": poses}
    metrics = summarize({"on": run, "off": run}, np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0], [0.0, 4.0]]))
    one_each = np.ones(len(SENSOR_NAMES))
    errors = sensor_error_stats(SimpleNamespace(sensor=np.array(SENSOR_NAMES), measured=one_each,
                                                true_range=one_each))
    return tuple(flatten({**metrics, "targets": targets_met(metrics), "sensor_errors": errors}))
