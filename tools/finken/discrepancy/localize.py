"""Localize a disagreement: which conditions differ between simulated and measured readings beyond chance.

For each condition (conditions.py) of each sensor kind, on the same rows:
- gap:   W1 between measured and simulated values (gap.py) [m];
- floor: W1 between two simulations of the same model with other seeds (the noise floor) [m];
- tests, each a two-sample p-value from scipy.stats:
    shape    Kolmogorov-Smirnov on the values of the readings present and inside the range limits;
    missing  Fisher exact test of the rate of missing readings;
    max      Fisher exact test of the rate of readings at the maximum range;
    tail     Fisher exact test of the rate of values outside the pooled 0.5 % and 99.5 % quantiles;
    lag      (on "all rows" only) z-test of the difference of the lags estimated from measured and simulated
             residuals by least squares on the true-range rate (residual ~ a - lag * rate), robust (HC0) errors;
  and, reported but not part of the decision, the Anderson-Darling k-sample statistic (tail-weighted) with
  scipy's p-value, which scipy limits to [0.001, 0.25] (too coarse for a corrected decision).
All p-values of one round (all conditions, all kinds) form one family, corrected by Holm's step-down method
(family-wise error rate ALPHA). A condition *stands above the noise floor* when one of its tests is significant
after the correction and its gap exceeds its floor.
Under the null hypothesis the measured and the simulated reading of a row have the same distribution and are
independent, so each test is valid or conservative although rows differ in true range and context.
"""
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from finken.discrepancy.gap import MIN_ROWS, quantity, w1

#: Family-wise error rate of one localization round.
ALPHA = 0.01
#: Values are rounded to this resolution before the shape and tail tests [m]: no range sensor resolves less,
#: and without it two lattices of readings (quantization) a micrometre apart would differ "significantly".
RESOLUTION_M = 1e-4
#: Largest sample per side given to the Anderson-Darling test (it is only reported) [rows].
AD_MAX_ROWS = 20000
TAIL_QUANTILE = 0.005
#: Largest sample for the exact KS distribution; beyond it the asymptotic one is accurate to < 1e-3.
KS_EXACT_ROWS = 1000


@dataclass
class ConditionTest:
    kind: str
    view: str
    label: str
    n: int
    gap: float                   # W1 measured vs simulated [m]
    floor: float                 # W1 simulated vs simulated [m]
    p: dict = field(default_factory=dict)   # test name -> p-value before correction
    ad_stat: float = float("nan")
    ad_p: float = float("nan")
    lag_s: tuple = None          # (measured lag, simulated lag, standard error) [s], "all rows" only
    p_adjusted: float = 1.0      # smallest Holm-adjusted p-value of its tests
    significant: bool = False


def test_kind(kr, views, subset, sim_a, sim_b, rng):
    """ConditionTest per condition of one kind; `sim_a`, `sim_b` are simulated measurements (NaN = missing)
    of the subset's rows with two different seeds."""
    pos_scored = np.flatnonzero(subset.scored)
    rows = subset.idx[pos_scored]
    tr = kr.true_range[rows]
    raw = {"m": kr.measured[rows], "a": np.asarray(sim_a)[pos_scored], "b": np.asarray(sim_b)[pos_scored]}
    reading = {k: kr.reading(v) for k, v in raw.items()}
    results = []
    for view in views:
        code = view.code[rows]
        for b, label in enumerate(view.labels):
            pos = np.flatnonzero(code == b)
            if pos.size < MIN_ROWS:
                continue
            vals = {k: quantity(view.quantity, reading[k][pos], tr[pos]) for k in reading}
            res = ConditionTest(kr.kind, view.name, label, int(pos.size),
                                w1(vals["m"], vals["a"]), w1(vals["b"], vals["a"]))
            _two_sample_tests(res, kr, raw["m"][pos], raw["a"][pos], vals["m"], vals["a"], rng)
            if view.name == "all":
                _lag_test(res, kr, rows, raw)
            results.append(res)
    return results


def _two_sample_tests(res, kr, m_raw, s_raw, m_val, s_val, rng):
    n = len(m_raw)
    miss_m, miss_s = np.isnan(m_raw), np.isnan(s_raw)
    if miss_m.any() or miss_s.any():
        res.p["missing"] = _fisher(miss_m.sum(), n, miss_s.sum(), n)
    top = kr.max_range - 1e-9
    max_m, max_s = m_raw >= top, s_raw >= top
    if max_m.any() or max_s.any():
        res.p["max"] = _fisher(max_m.sum(), n, max_s.sum(), n)
    lo = kr.min_range + 1e-9
    inside_m = ~miss_m & (m_raw > lo) & (m_raw < top)
    inside_s = ~miss_s & (s_raw > lo) & (s_raw < top)
    a, b = np.round(m_val[inside_m] / RESOLUTION_M), np.round(s_val[inside_s] / RESOLUTION_M)
    if min(a.size, b.size) < MIN_ROWS:
        return
    with warnings.catch_warnings():     # "exact calculation unsuccessful, switching to asymp" is expected
        warnings.simplefilter("ignore", RuntimeWarning)
        method = "exact" if max(a.size, b.size) <= KS_EXACT_ROWS else "asymp"
        res.p["shape"] = float(stats.ks_2samp(a, b, method=method).pvalue)
    q_lo, q_hi = np.quantile(np.r_[a, b], [TAIL_QUANTILE, 1 - TAIL_QUANTILE])
    out_a = int(np.sum((a < q_lo) | (a > q_hi)))
    out_b = int(np.sum((b < q_lo) | (b > q_hi)))
    res.p["tail"] = _fisher(out_a, a.size, out_b, b.size)
    if np.ptp(np.r_[a, b]) > 0:
        sa = a if a.size <= AD_MAX_ROWS else rng.choice(a, AD_MAX_ROWS, replace=False)
        sb = b if b.size <= AD_MAX_ROWS else rng.choice(b, AD_MAX_ROWS, replace=False)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ad = stats.anderson_ksamp([sa, sb])
        res.ad_stat, res.ad_p = float(ad.statistic), float(ad.pvalue)   # statistic of values in RESOLUTION_M


def _fisher(k1, n1, k2, n2):
    return float(stats.fisher_exact([[int(k1), int(n1 - k1)], [int(k2), int(n2 - k2)]]).pvalue)


def lag_estimate(residual, rate):
    """Least-squares lag of residual ~ a - lag * rate [s] and its HC0 (heteroscedasticity-robust) standard
    error; (nan, nan) with too few rows or no motion."""
    if residual.size < MIN_ROWS or np.ptp(rate) == 0:
        return float("nan"), float("nan")
    x = rate - rate.mean()
    sxx = float(x @ x)
    slope = float(x @ (residual - residual.mean())) / sxx
    e = residual - residual.mean() - slope * x
    se = float(np.sqrt(np.sum((x * e) ** 2)) / sxx)
    return -slope, se


def _lag_test(res, kr, rows, raw):
    tr, rate = kr.true_range[rows], kr.range_rate[rows]
    lo, hi = kr.min_range + 1e-9, kr.max_range - 1e-9
    inside = (tr > lo) & (tr < hi)
    est = {}
    for k in ("m", "a"):
        ok = inside & np.isfinite(raw[k]) & (raw[k] > lo) & (raw[k] < hi)
        est[k] = lag_estimate(raw[k][ok] - tr[ok], rate[ok])
    (tm, sm), (ts, ss) = est["m"], est["a"]
    se = float(np.hypot(sm, ss))
    if np.isfinite(se) and se > 0:
        res.lag_s = (tm, ts, se)
        res.p["lag"] = float(2 * stats.norm.sf(abs(tm - ts) / se))


def holm(pvalues):
    """Holm step-down adjusted p-values (same order as given)."""
    p = np.asarray(pvalues, dtype=float)
    m = p.size
    if m == 0:
        return p
    order = np.argsort(p)
    adjusted = np.minimum(1.0, np.maximum.accumulate((m - np.arange(m)) * p[order]))
    out = np.empty(m)
    out[order] = adjusted
    return out


def decide(tests, alpha=ALPHA):
    """Holm-correct all p-values of `tests` together; set p_adjusted and significant on each."""
    flat = [(i, name) for i, t in enumerate(tests) for name in t.p]
    adjusted = holm([tests[i].p[name] for i, name in flat])
    for t in tests:
        t.p_adjusted = 1.0
    for (i, _), a in zip(flat, adjusted):
        tests[i].p_adjusted = min(tests[i].p_adjusted, float(a))
    for t in tests:
        t.significant = t.p_adjusted < alpha and t.gap > t.floor
    return tests
