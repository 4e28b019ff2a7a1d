"""The shape of the error, not only its size: the octile skewness of residuals, and the check that sets aside a
candidate whose error is skewed the other way from the measured one (selection.py)."""
import numpy as np

#: Bootstrap resamples of the measured skewness, and how many of its standard errors a skewness difference must
#: exceed to count.
SKEW_BOOT, SKEW_K = 200, 3.0
#: Fewest residuals the check needs.
MIN_ROWS = 30


def octile_skew(values):
    """Octile skewness (q87.5 + q12.5 - 2 q50) / (q87.5 - q12.5): the asymmetry of a distribution's body and
    tails, -1 to 1, moved by a handful of outliers no more than their share (Moors et al. 1996); 0 for fewer
    than 8 values or no spread."""
    if len(values) < 8:
        return 0.0
    lo, mid, hi = np.quantile(values, [0.125, 0.5, 0.875])
    return float((hi + lo - 2 * mid) / (hi - lo)) if hi > lo else 0.0


def mirror_reason(fitter, fit):
    """Why a fit's error has the mirror shape of the measured one where it acts ("" when it has not), on the
    held-out rows of `fitter` (a fitting.KindFitter, whose model the fit adds to): the measured residuals are
    skewed away from the current model's one way (octile_skew), the fit skews them the other way, both by more
    than SKEW_K standard errors of the measured skewness (a bootstrap of the rows, SKEW_BOOT resamples). A
    right-skewed excess (late arrivals) is then not named as a tail of short readings, nor the reverse."""
    rows_pos = np.flatnonzero(fitter.heldout.scored)
    acts = fitter.mask_of(fit.candidate)[fitter.heldout.idx[rows_pos]]
    tr = fitter.kr.true_range[fitter.heldout.idx[rows_pos]][acts]
    meas = fitter.kr.measured[fitter.heldout.idx[rows_pos]][acts]

    def residual(readings):
        ok = fitter.kr.inside(readings)
        return readings[ok] - tr[ok]

    def skew_of(model):
        return float(np.mean([octile_skew(residual(fitter.raw(model, fitter.heldout, s)[rows_pos][acts]))
                              for s in fitter.seeds_score]))

    measured = residual(meas)
    if measured.size < MIN_ROWS:
        return ""
    boot = [octile_skew(fitter.rng.choice(measured, measured.size)) for _ in range(SKEW_BOOT)]
    se = float(np.std(boot))
    current = skew_of(fitter.model)
    d_meas, d_fit = octile_skew(measured) - current, skew_of(fit.model) - current
    if abs(d_meas) > SKEW_K * se and abs(d_fit) > SKEW_K * se and d_meas * d_fit < 0:
        side = "right (long tail of long readings)" if d_meas > 0 else "left (long tail of short readings)"
        return (f"{fit.candidate.label} skews the error the other way (octile skewness {d_fit:+.3f} against "
                f"the measured {d_meas:+.3f}, standard error {se:.3f}): the measured error is skewed {side}")
    return ""
