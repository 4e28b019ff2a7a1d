"""Conditions: the subsets of rows on which simulated and measured readings are compared.

A *view* is one conditioning variable cut into bins: all rows; the sensor; the vehicle; true-range bins; true-range rate
bins (a time-series property: latency shows where the range changes fast); each `ctx_` column (one bin per
value for flags and counts, quantile bins otherwise). Each bin is a *condition*. Views compare residuals
(reading - true range), except the `reading` view, which compares the readings themselves within true-range
bins (rounding to a step leaves the residual spread almost unchanged but puts readings on a lattice).
"""
from dataclasses import dataclass

import numpy as np

#: Quantile bins of the true range, of its rate, and of a continuous ctx_ column.
RANGE_BINS, RATE_BINS, CTX_BINS = 5, 3, 4
#: A ctx_ column with at most this many distinct values gets one bin per value.
CTX_MAX_LEVELS = 6
#: Bin codes are small: one byte per row and view (a two-million-row log has a dozen views).
CODE = np.int8


@dataclass
class View:
    name: str          # conditioning variable: all, sensor, vehicle, true_range, range_rate, reading, or a ctx_ column
    quantity: str      # 'residual' or 'reading'
    labels: list       # description of each bin
    code: np.ndarray   # bin of each row of the kind, -1 outside every bin (e.g. a missing ctx value); int8


def build_views(kr):
    """The views of one kind's rows (KindRows); views with fewer than two bins are left out (except 'all')."""
    views = [View("all", "residual", ["all rows"], np.zeros(kr.n, dtype=CODE))]
    names = np.unique(kr.sensor)
    if len(names) > 1:
        views.append(View("sensor", "residual", [f"sensor = {s}" for s in names],
                          np.searchsorted(names, kr.sensor).astype(CODE)))
    vehicles = np.unique(kr.vehicle) if kr.vehicle is not None else []
    if 1 < len(vehicles) <= np.iinfo(CODE).max:
        views.append(View("vehicle", "residual", [f"vehicle = {v:g}" for v in vehicles],
                          np.searchsorted(vehicles, kr.vehicle).astype(CODE)))
    range_labels, range_code = _quantile_bins(kr.true_range, RANGE_BINS, "true_range", "m")
    candidates = [View("true_range", "residual", range_labels, range_code),
                  View("range_rate", "residual", *_quantile_bins(kr.range_rate, RATE_BINS, "true-range rate", "m/s")),
                  View("reading", "reading", [f"readings, {label}" for label in range_labels], range_code)]
    for name, values in kr.ctx.items():
        candidates.append(View(name, "residual", *_ctx_bins(name, values)))
    views += [v for v in candidates if len(v.labels) >= 2]
    return views


def _ctx_bins(name, values):
    finite = values[np.isfinite(values)]
    levels = np.unique(finite)
    if len(levels) <= CTX_MAX_LEVELS:
        code = np.full(len(values), -1, dtype=CODE)
        ok = np.isfinite(values)
        code[ok] = np.searchsorted(levels, values[ok])
        return [f"{name} = {v:g}" for v in levels], code
    return _quantile_bins(values, CTX_BINS, name, "")


def _quantile_bins(values, n_bins, name, unit):
    """Labels and bin codes for quantile bins, edges rounded to 3 significant digits; NaN -> -1."""
    finite = np.isfinite(values)
    if not finite.any():
        return [], np.full(len(values), -1, dtype=CODE)
    inner = np.quantile(values[finite], np.linspace(0, 1, n_bins + 1)[1:-1])
    inner = np.unique([float(f"{e:.3g}") for e in inner])
    lo, hi = float(np.min(values[finite])), float(np.max(values[finite]))
    inner = inner[(inner > lo) & (inner <= hi)]
    code = np.full(len(values), -1, dtype=CODE)
    code[finite] = np.searchsorted(inner, values[finite], side="right")
    edges = [f"{e:.3g}" for e in inner]
    u = f" {unit}" if unit else ""
    if not edges:
        return [f"{name} in [{lo:.3g}, {hi:.3g}]{u}"], code
    labels = [f"{name} < {edges[0]}{u}"]
    labels += [f"{name} in [{a}, {b}){u}" for a, b in zip(edges[:-1], edges[1:])]
    labels.append(f"{name} >= {edges[-1]}{u}")
    return labels, code
