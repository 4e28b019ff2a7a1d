"""White noise N, bias instability B and rate random walk K of one axis, fitted to its Allan deviation.

Model (IEEE Std 952-1997, annex C): adev(tau)^2 = N^2 / tau + (2 ln 2 / pi) B^2 + K^2 tau / 3, the lines of slope
-1/2, 0 and +1/2 on a log-log plot, linear in (N^2, B^2, K^2).
Fit: weighted non-negative least squares on the Allan variances. The weight of each is 1 / its variance,
2 avar^2 / edf, with avar the model's value there and edf the equivalent degrees of freedom of the overlapping
estimator (Greenhall's, AllanTools' edf_greenhall) for the noise that dominates the model there (alpha 0 white,
-1 flicker, -2 random walk); FIT_PASSES passes, the first with the measured variances and white noise everywhere.
Intervals (95 %): a parametric bootstrap (the Allan variances of neighbouring averaging times are correlated, so the
least-squares covariance is too narrow): `reps` logs of the same length and rate simulated from the fit
(finken.imu.synthetic.noise), each fitted alike. A positive estimate's interval is est / (the 97.5 and 2.5 %
quantiles of est* / est), unbounded above (None) when more than 2.5 % of the replicas fit 0; a zero estimate is
"not resolved", its interval [0, the 97.5 % quantile of est*].
"""
from dataclasses import astuple, dataclass

import allantools
import numpy as np
from scipy.optimize import nnls

from finken.imu.allan import allan_deviation
from finken.imu.synthetic import AxisNoise, noise

FLICKER = 2.0 * np.log(2.0) / np.pi      # adev^2 of flicker noise per B^2
ALPHAS = (0, -1, -2)                     # power-law exponent of each term's rate noise (white, flicker, random walk)
FIT_PASSES = 3
MIN_TAUS = 4                             # averaging times a fit of three terms needs
CONFIDENCE = 0.95


@dataclass
class Term:
    """One fitted coefficient with its 95 % interval (high None: unbounded)."""
    value: float
    low: float
    high: float

    @property
    def resolved(self):
        return self.value > 0.0


@dataclass
class NoiseFit:
    """The three coefficients of one axis and the averaging times they were fitted on."""
    white: Term
    bias_instability: Term
    rate_random_walk: Term
    tau: np.ndarray

    def noise(self):
        return AxisNoise(self.white.value, self.bias_instability.value, self.rate_random_walk.value)

    def adev(self, tau):
        return model_adev(self.noise(), tau)


def model_adev(axis, tau):
    """Allan deviation of AxisNoise at averaging times tau [s]."""
    tau = np.asarray(tau, dtype=np.float64)
    return np.sqrt(axis.white ** 2 / tau + FLICKER * axis.bias_instability ** 2 + axis.rate_random_walk ** 2 * tau / 3)


def fit_coefficients(curve):
    """AxisNoise fitted to an AllanCurve by the weighted non-negative least squares of the module comment."""
    if len(curve.tau) < MIN_TAUS:
        raise ValueError(f"{len(curve.tau)} averaging times: a fit of three noise terms needs at least {MIN_TAUS}")
    design = np.column_stack([1.0 / curve.tau, FLICKER * np.ones_like(curve.tau), curve.tau / 3.0])
    avar = curve.adev ** 2
    expected, coef = avar, np.zeros(3)
    alpha = np.zeros(len(curve.tau), dtype=int)
    for _ in range(FIT_PASSES):
        edf = np.array([allantools.edf_greenhall(alpha=int(a), d=2, m=int(m), N=curve.n_samples + 1, overlapping=True)
                        for a, m in zip(alpha, curve.averaging_factors())])
        sd = np.sqrt(2.0 / edf) * expected
        coef, _ = nnls(design / sd[:, None], avar / sd)
        expected = np.maximum(design @ coef, 1e-300)
        alpha = np.array(ALPHAS)[np.argmax(design * coef, axis=1)]
    return AxisNoise(*(float(c) for c in np.sqrt(coef)))


def fit_axis(samples, rate_hz, tau_max_s, reps, rng):
    """NoiseFit of one axis's samples: the fit, and its intervals from `reps` simulated logs (numpy Generator rng)."""
    curve = allan_deviation(samples, rate_hz, tau_max_s)
    fitted = fit_coefficients(curve)
    replicas = np.array([astuple(fit_coefficients(allan_deviation(noise(fitted, rate_hz, len(samples), rng), rate_hz,
                                                                  tau_max_s)))
                         for _ in range(reps)]).reshape(reps, 3)
    terms = [_interval(float(value), replicas[:, k]) for k, value in enumerate(astuple(fitted))]
    return NoiseFit(*terms, curve.tau), curve


def _interval(value, replicas):
    """Term with the bootstrap interval of the module comment (no replicas: the value alone)."""
    if replicas.size == 0:
        return Term(value, value, value)
    tail = (1.0 - CONFIDENCE) / 2.0
    if value <= 0.0:
        return Term(0.0, 0.0, float(np.quantile(replicas, 1.0 - tail)))
    low_ratio, high_ratio = np.quantile(replicas / value, [tail, 1.0 - tail])
    return Term(value, value / high_ratio, value / low_ratio if low_ratio > 0.0 else None)
