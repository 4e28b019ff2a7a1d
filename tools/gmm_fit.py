#!/usr/bin/env python3
"""Fit a conditional-GMM error model (a joint mixture over (true, measured)) to a range log.

    python tools/gmm_fit.py LOG.csv -o mixture.xml [--sensor ranging] [--components 100]
                            [--covariance full|diag] [--seed 0] [--max-rows N]

Rows of the chosen sensor with a reading are used (sonar_* rows for --sensor sonar). The mixture is fitted
by EM (scikit-learn GaussianMixture) and written with a header naming the log, the options and the fit's
log-likelihood; a gmm effect can then name the file.
"""
import argparse
import sys

import numpy as np

from finken.atomic_output import WriteError
from finken.cli_types import integer
from finken.models import Mixture
from finken.rangelog import SENSOR_NAMES, RangeLogError, read_range_log
from gmm_import import from_sklearn

REG_COVAR_M2 = 1e-6  # added to every variance by EM, so no component collapses onto a few rows [m^2]
EM_TOL = 1e-5        # EM stops when the mean log-likelihood gains less than this per iteration
SEED_MAX = 2**32 - 1  # scikit-learn's random_state


def fit_mixture(true_range, measured, components: int = 100, covariance: str = "full", seed: int = 0,
                max_iter: int = 500) -> Mixture:
    """EM fit of a joint mixture to paired (true [m], measured [m]) readings (NaN rows dropped)."""
    from sklearn.mixture import GaussianMixture  # lazily: scikit-learn is slow to import
    x = np.column_stack([np.asarray(true_range, dtype=np.float64), np.asarray(measured, dtype=np.float64)])
    x = x[np.all(np.isfinite(x), axis=1)]
    if len(x) < 10 * components:
        raise ValueError(f"{len(x)} readings are too few for {components} components (need {10 * components})")
    gm = GaussianMixture(components, covariance_type=covariance, random_state=seed, max_iter=max_iter,
                         reg_covar=REG_COVAR_M2, tol=EM_TOL).fit(x)
    mixture = from_sklearn(gm)
    mixture.fit_info = {"rows": len(x), "mean_loglik": float(gm.score(x)), "converged": bool(gm.converged_),
                        "iterations": int(gm.n_iter_)}
    return mixture


def sensor_rows(log, sensor: str):
    """Mask of a log's rows for 'ranging' or 'sonar' (any sonar_*), or one exact sensor name."""
    names = log.sensor.astype(str)
    return np.char.startswith(names, "sonar_") if sensor == "sonar" else names == sensor


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log", help="range log CSV (shared/spec/range-log.md)")
    ap.add_argument("-o", "--out", required=True, help="mixture file to write")
    ap.add_argument("--sensor", choices=("sonar",) + SENSOR_NAMES, default="ranging", metavar="SENSOR",
                    help="ranging, sonar (every sonar_*), or one sensor name: " + ", ".join(SENSOR_NAMES)
                    + " (default ranging)")
    ap.add_argument("--components", type=integer(1), default=100)
    ap.add_argument("--covariance", choices=("full", "diag"), default="full")
    ap.add_argument("--seed", type=integer(0, SEED_MAX), default=0, help=f"0 to {SEED_MAX} (default 0)")
    ap.add_argument("--max-rows", type=integer(1), default=None, help="fit on a random subset of this many rows")
    args = ap.parse_args(argv)
    try:
        log = read_range_log(args.log)
    except RangeLogError as err:
        print(f"gmm_fit: {err}", file=sys.stderr)
        return 1
    rows = np.flatnonzero(sensor_rows(log, args.sensor) & np.isfinite(log.measured))
    if args.max_rows is not None and len(rows) > args.max_rows:
        rows = np.sort(np.random.default_rng(args.seed).choice(rows, args.max_rows, replace=False))
    try:
        mixture = fit_mixture(log.true_range[rows], log.measured[rows], args.components, args.covariance, args.seed)
    except ValueError as err:
        print(f"gmm_fit: {args.log}: {err}", file=sys.stderr)
        return 1
    info = mixture.fit_info
    header = (f"Fitted by tools/gmm_fit.py to {args.log} ({args.sensor} rows with a reading: {info['rows']}),\n"
              f"{args.components} components, {args.covariance} covariances, seed {args.seed}; mean log-likelihood "
              f"{info['mean_loglik']:.4f}, converged {info['converged']} after {info['iterations']} EM iterations.")
    try:
        mixture.save(args.out, header)
    except WriteError as err:
        print(f"gmm_fit: {err}", file=sys.stderr)
        return 1
    print(f"wrote {args.out}: {mixture.k} components from {info['rows']} readings")
    return 0


if __name__ == "__main__":
    sys.exit(main())
