"""An independent reference for the gmm effect: the joint Gaussian mixture over (true, measured) range read from
its XML file with lxml and conditioned on the true range with numpy/scipy. It shares no code with the C library
(nps_gmm.c, nps_sensor_model.c) that the simulator, the host and finken.models run, so a bug there cannot pass a
comparison with it by being on both sides.
"""
from pathlib import Path

import numpy as np
from lxml import etree
from scipy import stats
from scipy.special import logsumexp


class ReferenceMixture:
    """weights (K,), means (K, 2) as (true, measured) [m], covariances (K, 2, 2) [m^2]."""

    def __init__(self, weights, means, covariances):
        self.weights = np.asarray(weights, dtype=np.float64)
        self.means = np.asarray(means, dtype=np.float64)
        self.covariances = np.asarray(covariances, dtype=np.float64)

    @classmethod
    def read(cls, path):
        """The <mixture> of a mixture file, or of a model file's ranging gmm effect (inline or named by its
        `mixture` attribute, relative to the model file)."""
        path = Path(path)
        root = etree.parse(str(path)).getroot()
        if root.tag != "mixture":
            effect = root.find("ranging/effect[@name='gmm']")
            inline = effect.find("mixture")
            if inline is None:
                return cls.read(path.parent / effect.get("mixture"))
            root = inline
        comps = root.findall("component")

        def num(c, key):
            return float(c.get(key, "0"))            # covariance="diag" writes no cov

        return cls([num(c, "weight") for c in comps],
                   [[num(c, "mean_true"), num(c, "mean_measured")] for c in comps],
                   [[[num(c, "var_true"), num(c, "cov")], [num(c, "cov"), num(c, "var_measured")]] for c in comps])

    def joint_logpdf(self, t, m):
        """log p(true, measured) = log sum_k w_k N2((t, m); mu_k, S_k), each bivariate normal written out:
        log N2(x; mu, S) = -log(2 pi) - log(det S) / 2 - (x - mu)' S^-1 (x - mu) / 2."""
        t, m = np.broadcast_arrays(np.asarray(t, float), np.asarray(m, float))
        shape, t, m = t.shape, t.reshape(1, -1), m.reshape(1, -1)
        stt, smm, stm = (self.covariances[:, i, j][:, None] for i, j in ((0, 0), (1, 1), (0, 1)))
        det = stt * smm - stm ** 2
        dt, dm = t - self.means[:, 0:1], m - self.means[:, 1:2]
        quad = (smm * dt ** 2 - 2.0 * stm * dt * dm + stt * dm ** 2) / det
        terms = np.log(self.weights)[:, None] - np.log(2.0 * np.pi) - 0.5 * np.log(det) - 0.5 * quad
        return logsumexp(terms, axis=0).reshape(shape)

    def marginal_logpdf(self, t):
        """log p(true) = log sum_k w_k N(t; mu_t,k, s_tt,k)."""
        t = np.asarray(t, float)
        terms = np.log(self.weights)[:, None] + stats.norm.logpdf(t.reshape(1, -1), self.means[:, 0:1],
                                                                   np.sqrt(self.covariances[:, 0, 0])[:, None])
        return logsumexp(terms, axis=0).reshape(t.shape)

    def conditional_logpdf(self, t, m):
        """log p(measured | true) by its definition, log p(t, m) - log p(t): no conditioning formula."""
        return self.joint_logpdf(t, m) - self.marginal_logpdf(t)

    def conditional_components(self, t):
        """(weights, means, standard deviations), each (K, n), of the mixture conditioned on 1-D t: weights
        w_k N(t; mu_t,k, s_tt,k) normalised over k, means mu_m,k + s_tm,k / s_tt,k (t - mu_t,k), variances
        s_mm,k - s_tm,k^2 / s_tt,k (each component's Gaussian conditional)."""
        t = np.atleast_1d(np.asarray(t, float))[None, :]
        mt, mm = self.means[:, 0:1], self.means[:, 1:2]
        stt, smm, stm = (self.covariances[:, i, j][:, None] for i, j in ((0, 0), (1, 1), (0, 1)))
        logw = np.log(self.weights)[:, None] + stats.norm.logpdf(t, mt, np.sqrt(stt))
        return np.exp(logw - logsumexp(logw, axis=0)), mm + stm / stt * (t - mt), np.sqrt(smm - stm ** 2 / stt)

    def conditional_cdf(self, t, m):
        """P(measured <= m | true = t), elementwise over 1-D t and m."""
        w, mean, sd = self.conditional_components(t)
        return np.sum(w * stats.norm.cdf((np.atleast_1d(np.asarray(m, float))[None, :] - mean) / sd), axis=0)
