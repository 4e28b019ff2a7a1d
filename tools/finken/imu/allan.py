"""The overlapping Allan deviation of one axis, at octave-spaced averaging times (AllanTools' oadev on rate data)."""
from dataclasses import dataclass

import allantools
import numpy as np


@dataclass
class AllanCurve:
    """Allan deviation adev [unit] at averaging times tau [s] of n_samples samples at rate_hz."""
    tau: np.ndarray
    adev: np.ndarray
    rate_hz: float
    n_samples: int

    def averaging_factors(self):
        """m = tau * rate, the samples per averaging interval."""
        return np.rint(self.tau * self.rate_hz).astype(np.int64)


def allan_deviation(samples, rate_hz, tau_max_s):
    """AllanCurve of the samples (rate data in any unit) at octave taus from 1/rate_hz up to tau_max_s."""
    tau, adev, _, _ = allantools.oadev(np.asarray(samples, dtype=np.float64), rate=rate_hz, data_type="freq",
                                       taus="octave")
    keep = tau <= tau_max_s * (1.0 + 1e-9)
    return AllanCurve(tau[keep], adev[keep], float(rate_hz), len(samples))
