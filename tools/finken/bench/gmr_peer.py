"""The peer of the C conditional-GMM sampler in `make bench`: the Python `gmr` package (tools/requirements.txt).

The same mixture (finken.models.Mixture: weights, means, covariances over (true, measured) range) is built as a
gmr.GMM; each reading, as the simulator needs it, is a conditioning on its own true range followed by one
draw: `gmm.condition([0], [t]).sample(1)`. gmr has no batched conditional sampler: conditioning is per value
of the true range.
"""
import time

import numpy as np
from gmr import GMM

from finken.models import Mixture

#: largest relative difference between gmr's and our conditional mean before the mixtures count as different
SAME_MIXTURE_RTOL = 1e-9


def gmr_mixture(mixture: Mixture, seed: int) -> GMM:
    """The mixture as a gmr.GMM (priors, means (K, 2) [m], covariances (K, 2, 2) [m^2])."""
    return GMM(n_components=mixture.k, priors=mixture.weights.copy(), means=mixture.means.copy(),
               covariances=mixture.covariances.copy(), random_state=np.random.RandomState(seed))


def check_same_mixture(mixture: Mixture, gmm: GMM, true_ranges_m) -> None:
    """Raise ValueError unless gmr's conditional mean equals ours at each true range [m] (same law sampled)."""
    ours, _ = mixture.conditional_moments(np.asarray(true_ranges_m, dtype=float))
    for t, mean_m in zip(true_ranges_m, ours):
        cond = gmm.condition([0], np.array([t]))
        theirs = float(np.dot(cond.priors, cond.means[:, 0]))
        if not abs(theirs - mean_m) <= SAME_MIXTURE_RTOL * max(1.0, abs(mean_m)):
            raise ValueError(f"gmr and finken disagree on the conditional mean at {t} m: {theirs} vs {mean_m}")


def gmr_draws_per_s(gmm: GMM, draws: int, max_range_m: float, rng: np.random.Generator) -> float:
    """Conditional draws per second [1/s], each at its own true range, uniform on [0, max_range_m]."""
    true_m = rng.uniform(0.0, max_range_m, size=draws)
    t0 = time.perf_counter()
    for t in true_m:
        gmm.condition([0], np.array([t])).sample(1)
    return draws / (time.perf_counter() - t0)


def gmr_figures(mixture_path, reps: int, draws: int, max_range_m: float = 2.5, seed: int = 1) -> list[dict]:
    """Median (over reps) of gmr's conditional draws per second, as bench results (name, value, unit, ...)."""
    mixture = Mixture.load(mixture_path)
    gmm = gmr_mixture(mixture, seed)
    check_same_mixture(mixture, gmm, [0.1, 1.0, 2.4])
    rng = np.random.default_rng(seed)
    gmr_draws_per_s(gmm, max(1, draws // 10), max_range_m, rng)   # warm-up (imports, caches)
    rates = sorted(gmr_draws_per_s(gmm, draws, max_range_m, rng) for _ in range(reps))
    return [{"name": "gmr_draws_per_s", "value": float(np.median(rates)), "unit": "1/s", "reps": reps,
             "min": rates[0], "max": rates[-1]}]
