"""The gap between simulated and measured readings: Wasserstein-1 distance [m], per condition and overall.

Per condition (a bin of a view, conditions.py): W1 (scipy.stats.wasserstein_distance) between the measured and
the simulated values of the rows in the bin; the values are residuals (reading - true range) or readings, a
missing reading counting as the sensor's maximum range, so that a change in the rate of missing readings moves
probability mass and shows in the gap. Per view: the mean of its bins' W1, each bin counting equally, so that
a disagreement confined to a rare condition (a blocked line of sight on 4 % of the rows) is not drowned by the
common one (bins of true range, rate and continuous ctx_ columns hold equal numbers of rows anyway). Per kind:
the mean over its views. Overall: the row-weighted mean over kinds.
The noise floor is the same quantity between two simulations of one model on the same rows (other seeds).
"""
import copy

import numpy as np
from scipy.stats import wasserstein_distance

#: Fewest rows a condition (other than "all rows") needs to enter a gap (W1 of fewer rows is mostly noise).
MIN_ROWS = 30

METRIC = ("conditional Wasserstein-1 distance [m] between measured and simulated residuals (reading - true range; "
          "a missing reading counts as the sensor's maximum range; one variable compares the readings themselves): "
          "per conditioning variable the mean of W1 over its bins, averaged over the variables, then over the "
          "sensor kinds weighted by rows")


def w1(a, b):
    """Wasserstein-1 distance between two samples [m]: scipy.stats.wasserstein_distance. For samples of
    equal size (always the case here: measured and simulated values of the same rows) this equals the mean
    absolute difference of the sorted samples, computed directly (several times faster: it runs in the
    fitting loop); tests/python/test_discrepancy_stats.py checks that both give the same number."""
    if len(a) == len(b):
        return w1_presorted(np.sort(a), b)
    return float(wasserstein_distance(a, b))


def w1_presorted(a_sorted, b):
    """w1() of two samples of equal size, the first already sorted [m]."""
    return float(np.mean(np.abs(a_sorted - np.sort(b)))) if len(b) else 0.0


def quantity(name, reading, true_range):
    """Residual (reading - true range) or the reading itself [m]."""
    return reading - true_range if name == "residual" else reading


class GapEvaluator:
    """Gaps of simulated readings against fixed reference readings (the measured ones, or another simulation's:
    with_reference) on the scored rows of a Subset of one kind."""

    def __init__(self, kr, views, subset):
        self.kind, self.views = kr.kind, views
        self.scored = np.flatnonzero(subset.scored)
        rows = subset.idx[self.scored]
        self.true_range = kr.true_range[rows]
        self.n = len(rows)
        positions = []   # (view index, bin index, positions among the scored rows: int32, for big subsets)
        for vi, view in enumerate(views):
            code = view.code[rows]
            for b in range(len(view.labels)):
                pos = np.flatnonzero(code == b).astype(np.int32)
                if pos.size >= (1 if view.name == "all" else MIN_ROWS):    # all rows count, however few
                    positions.append((vi, b, pos))
        self._set_reference(kr.reading(kr.measured[rows]), positions)

    def _set_reference(self, reference, positions):
        self.reference = {q: quantity(q, np.asarray(reference), self.true_range) for q in ("residual", "reading")}
        self.bins = [(vi, b, pos, np.sort(self.reference[self.views[vi].quantity][pos])) for vi, b, pos in positions]

    def with_reference(self, reference):
        """The same evaluator (rows, bins) against other reference readings of the scored rows (the noise
        floor's: another simulation), sharing the bins' positions."""
        other = copy.copy(self)
        other._set_reference(reference, [(vi, b, pos) for vi, b, pos, _ in self.bins])
        return other

    def bin_gaps(self, sim_reading):
        """W1 of each bin [m]; `sim_reading` holds the simulated readings of every row of the subset (missing
        readings already counted as the maximum range, see KindRows.reading)."""
        sim = np.asarray(sim_reading)[self.scored]
        values = {q: quantity(q, sim, self.true_range) for q in ("residual", "reading")}
        out = np.empty(len(self.bins))
        for i, (vi, _, pos, ref_sorted) in enumerate(self.bins):
            out[i] = w1_presorted(ref_sorted, values[self.views[vi].quantity][pos])
        return out

    def overall(self, gaps):
        """The kind's gap from its bins' gaps: the mean over views of the mean over their bins [m]."""
        per_view = {}
        for (vi, _, _, _), g in zip(self.bins, gaps):
            per_view.setdefault(vi, []).append(g)
        return float(np.mean([np.mean(v) for v in per_view.values()])) if per_view else 0.0

    def gap(self, sim_reading):
        return self.overall(self.bin_gaps(sim_reading))


def combine(gaps_and_rows):
    """Overall gap from (gap, rows) per kind: the row-weighted mean [m]."""
    total = sum(n for _, n in gaps_and_rows)
    return float(sum(g * n for g, n in gaps_and_rows) / total) if total else 0.0
