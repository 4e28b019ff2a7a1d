"""Per parameter point, the mean of each metric over its seeds and a 95 % confidence interval of that mean.

The interval is Student's: mean +- t(0.975, n - 1) s / sqrt(n), s the sample standard deviation of the n runs
(seeds) that gave a value; it needs n >= 2 (else NaN). Runs are independent (one seed each), and a metric of a run is
itself an average over many readings, so its spread over seeds is close to normal for the fractions and distances
make sim reports; for a fraction near 0 or 1 over few seeds the interval may cross the bound.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

LEVEL = 0.95


@dataclass(frozen=True)
class Interval:
    """Mean of n values and the bounds of its 95 % interval (NaN where there are not enough values)."""
    mean: float
    low: float
    high: float
    n: int

    def text(self):
        """'mean [low, high]', 3 decimals below 1000 (fractions and metres), '-' without a mean."""
        def number(x):
            return f"{x:.3f}" if abs(x) < 1000 else f"{x:.4g}"
        if math.isnan(self.mean):
            return "-"
        return number(self.mean) if math.isnan(self.low) else \
            f"{number(self.mean)} [{number(self.low)}, {number(self.high)}]"


def interval(values):
    """Interval of the finite values among `values` (None and NaN are left out)."""
    x = np.array([v for v in values if v is not None], dtype=float)
    x = x[np.isfinite(x)]
    if x.size == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    mean = float(x.mean())
    if x.size < 2:
        return Interval(mean, math.nan, math.nan, int(x.size))
    half = float(stats.t.ppf(0.5 + LEVEL / 2, x.size - 1) * x.std(ddof=1) / math.sqrt(x.size))
    return Interval(mean, mean - half, mean + half, int(x.size))


@dataclass
class PointSummary:
    """One parameter point: its parameter values, its runs done and failed, and an Interval per metric."""
    point: object
    done: int
    failed: int
    metrics: dict


def summarize_points(points, rows, metrics):
    """A PointSummary per point (finken.sweep.points.Point) from the stored rows of its runs
    (finken.sweep.store.RunStore.rows), for each metric name in `metrics`."""
    by_point = {}
    for row in rows:
        by_point.setdefault(row["point_key"], []).append(row)
    summaries = []
    for point in points:
        runs = by_point.get(point.key, [])
        done = [row for row in runs if row["status"] == "done"]
        summaries.append(PointSummary(point, len(done), len(runs) - len(done),
                                      {name: interval(row.get(name) for row in done) for name in metrics}))
    return summaries
