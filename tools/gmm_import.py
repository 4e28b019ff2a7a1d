#!/usr/bin/env python3
"""Convert a fitted Gaussian mixture (scikit-learn GaussianMixture or gmr GMM) to a mixture file.

    python tools/gmm_import.py fitted.pkl -o mixture.xml [--true-dim 0 --measured-dim 1] [--header TEXT]

`fitted.pkl` is a pickle/joblib dump of either model. When the model has more than two dimensions, the
marginal over (true, measured) is taken: same weights, the two dimensions' means and covariance block.
The mixture file is what a gmm effect names (<effect name="gmm" mixture="mixture.xml"/>).
"""
import argparse
import sys

import numpy as np

from finken.atomic_output import WriteError
from finken.cli_types import integer
from finken.models import Mixture, ModelError


class DimensionError(ValueError):
    """true_dim / measured_dim that do not name two different dimensions of the model."""


def _marginal(weights, means, covs, true_dim, measured_dim, diagonal):
    """The Mixture over (true_dim, measured_dim); diagonal None: told from the covariances."""
    dims = [true_dim, measured_dim]
    d = np.shape(means)[1]
    for name, dim in (("true", true_dim), ("measured", measured_dim)):
        if not 0 <= dim < d:
            raise DimensionError(f"--{name}-dim {dim}: the model has {d} dimensions (0 to {d - 1})")
    if true_dim == measured_dim:
        raise DimensionError(f"--true-dim and --measured-dim are both {true_dim}: they must differ")
    weights = np.asarray(weights, dtype=np.float64)
    means = np.asarray(means, dtype=np.float64)[:, dims]
    covs = np.asarray(covs, dtype=np.float64)[:, dims][:, :, dims]
    if diagonal is None:  # from the covariances: diagonal when no component correlates the two
        diagonal = bool(np.all(covs[:, 0, 1] == 0.0))
    return Mixture(weights / weights.sum(), means, covs, diagonal=diagonal)


def from_sklearn(gm, true_dim: int = 0, measured_dim: int = 1) -> Mixture:
    """A Mixture from a fitted sklearn.mixture.GaussianMixture (any covariance_type)."""
    k, d = gm.means_.shape
    kind = gm.covariance_type
    if kind == "full":
        covs = gm.covariances_
    elif kind == "diag":
        covs = np.stack([np.diag(c) for c in gm.covariances_])
    elif kind == "spherical":
        covs = np.stack([v * np.eye(d) for v in gm.covariances_])
    elif kind == "tied":
        covs = np.repeat(gm.covariances_[None], k, axis=0)
    else:
        raise ValueError(f"unknown covariance_type '{kind}'")
    return _marginal(gm.weights_, gm.means_, covs, true_dim, measured_dim, kind in ("diag", "spherical"))


def from_gmr(gmm, true_dim: int = 0, measured_dim: int = 1) -> Mixture:
    """A Mixture from a gmr.GMM (priors, means, covariances)."""
    return _marginal(gmm.priors, gmm.means, gmm.covariances, true_dim, measured_dim, diagonal=None)


def convert(model, true_dim: int = 0, measured_dim: int = 1) -> Mixture:
    """from_sklearn or from_gmr, by the model's attributes."""
    if hasattr(model, "weights_") and hasattr(model, "covariance_type"):
        return from_sklearn(model, true_dim, measured_dim)
    if getattr(model, "priors", None) is not None and getattr(model, "covariances", None) is not None:
        return from_gmr(model, true_dim, measured_dim)
    raise ValueError(f"{type(model).__name__} is neither a fitted sklearn GaussianMixture nor a gmr GMM")


def _load(path):
    """The object pickled in `path` (pickle or joblib). Unpickling a file that is not a pickle can raise
    almost any exception; all are turned into ValueError naming what went wrong."""
    import joblib  # lazily: only the CLI reads pickles
    try:
        return joblib.load(path)
    except OSError:
        raise
    except Exception as err:  # noqa: BLE001 (see the docstring)
        raise ValueError(f"not a pickle or joblib file of a fitted mixture ({type(err).__name__}: {err})") from None


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("model", help="pickle or joblib file of a fitted GaussianMixture or gmr GMM")
    ap.add_argument("-o", "--out", required=True, help="mixture file to write")
    ap.add_argument("--true-dim", type=integer(0), default=0, help="dimension of the true range (default 0)")
    ap.add_argument("--measured-dim", type=integer(0), default=1, help="dimension of the measured range (default 1)")
    ap.add_argument("--header", default=None, help="comment saying where the numbers come from")
    args = ap.parse_args(argv)
    try:
        mixture = convert(_load(args.model), args.true_dim, args.measured_dim)
        mixture.native()  # validate before writing
    except DimensionError as err:
        ap.error(f"{args.model}: {err}")
    except (ValueError, ModelError, OSError) as err:
        print(f"gmm_import: {args.model}: {err}", file=sys.stderr)
        return 1
    try:
        mixture.save(args.out, args.header or f"Imported from {args.model} by tools/gmm_import.py.")
    except WriteError as err:
        print(f"gmm_import: {err}", file=sys.stderr)
        return 1
    print(f"wrote {args.out}: {mixture.k} components ({'diagonal' if mixture.diagonal else 'full'} covariances)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
