"""Which side of each context column an effect may be conditioned on, and where a continuous one is cut.

An effect can only help where the current model disagrees with the measurements, so each `ctx_` column offers
one condition: the side with the larger gap between measured and simulated residuals on the training rows.
- A flag or count (at most conditions.CTX_MAX_LEVELS distinct values): `ctx_x` (non-zero) or `ctx_x == 0`.
- A continuous column: `ctx_x >= c` or `ctx_x < c`, the cut c fitted as the change point of the disagreement:
  among the CUT_QUANTILES of the column, the c that maximises |gap(rows >= c) - gap(rows < c)| sqrt(q (1 - q)),
  q the share of rows above c. Where an effect acts only above c0, a cut below c0 dilutes the upper side with
  rows it does not touch and a cut above c0 dilutes the lower side, so the difference peaks at c0; the weight
  sqrt(q (1 - q)) (that of a two-sample statistic, as in binary segmentation) keeps a cut near the ends, where
  one side is small and its gap noisy, from winning when the disagreement is everywhere. The cut is rounded to
  CUT_DIGITS significant digits (a readable model file) and reported in the condition.
Conditions are texts in the model's grammar (nps_condition.h), evaluated by models.condition_mask.
"""
import numpy as np

from finken.discrepancy.conditions import CTX_MAX_LEVELS
from finken.discrepancy.gap import MIN_ROWS, w1

#: Quantiles of a continuous column tried as cuts; significant digits a cut keeps.
CUT_QUANTILES, CUT_DIGITS = np.linspace(0.05, 0.95, 19), 4


def number_text(x):
    """A cut as the model's canonical text writes it: the shortest round-trip digits, no trailing '.0'."""
    text = repr(float(f"{x:.{CUT_DIGITS}g}"))
    return text[:-2] if text.endswith(".0") else text


def _gap(measured, simulated, mask):
    return w1(measured[mask], simulated[mask]) if mask.sum() >= MIN_ROWS else 0.0


def side_conditions(ctx, measured_residual, simulated_residual):
    """{column: condition text} for the ctx_ columns (`ctx`: {column: values of the training rows}), each the
    side where the residuals disagree more; columns that cannot be cut (one value, too few rows) are left out."""
    out = {}
    for column in sorted(ctx):
        values = np.asarray(ctx[column], dtype=float)
        finite = np.isfinite(values)
        levels = np.unique(values[finite])
        if levels.size < 2:
            continue
        if levels.size <= CTX_MAX_LEVELS:
            nonzero = finite & (values != 0)
            zero = finite & (values == 0)
            if nonzero.sum() < MIN_ROWS or zero.sum() < MIN_ROWS:
                continue
            above = _gap(measured_residual, simulated_residual, nonzero)
            below = _gap(measured_residual, simulated_residual, zero)
            out[column] = column if above >= below else f"{column} == 0"
            continue
        best = None
        for cut in np.unique([float(number_text(c)) for c in np.quantile(values[finite], CUT_QUANTILES)]):
            upper, lower = finite & (values >= cut), finite & (values < cut)
            if upper.sum() < MIN_ROWS or lower.sum() < MIN_ROWS:
                continue
            above = _gap(measured_residual, simulated_residual, upper)
            below = _gap(measured_residual, simulated_residual, lower)
            q = upper.sum() / finite.sum()
            contrast = abs(above - below) * np.sqrt(q * (1 - q))
            if best is None or contrast > best[0]:
                best = (contrast, cut, above >= below)
        if best is not None:
            _, cut, upper_side = best
            out[column] = f"{column} {'>=' if upper_side else '<'} {number_text(cut)}"
    return out


def both(first, second):
    """The condition that holds where both hold."""
    return f"{first} and {second}"


def terms(condition):
    """Number of terms of a condition text, and how many compare with a fitted cut (for candidates.complexity)."""
    if not condition:
        return 0, 0
    parts = condition.split(" and ")
    return len(parts), sum(("<" in p or ">" in p) for p in parts)

