"""Fit candidate effects on training time blocks and score them on held-out time blocks.

The candidate model is the current model with the effect appended to the kind's chain (before the range
limits): finken.models.SensorModel.with_effect. Parameters are fitted
- by maximum (simulated) likelihood where the effect has a closed-form density (finken.models.effect_logpdf:
  gaussian, range_noise, rayleigh_short, nlos_bias). The effect acts on the current chain's output, which is
  random, so the likelihood of a reading y is averaged over S_DRAWS simulated chain outputs z_s:
  L(y) = (1 - EPS) mean_s p(y | z_s) + EPS / (max - min range) (a defensive uniform component keeps the
  estimate finite where few draws reach y). Rows whose reading sits at a range limit are left out.
- by the mixture's own maximum likelihood (EM, scikit-learn) for gmm: a joint mixture of (true range, reading),
  the number of components by BIC;
- per vehicle (candidates.PER_VEHICLE: a bias or a scale of each copter's unit): each vehicle's value from the
  medians of its measured and simulated readings on the training rows (bias: the difference of the median
  residuals; scale: the ratio of the median readings over true ranges), a robust moment estimate a handful of
  glitches or tails cannot move; a bias curve (bias_curve over a variable u) the same way: knots at quantiles of u
  (candidates.CURVE_QUANTILES), each knot's bias the difference of the median residuals of the rows nearest it;
- by simulation otherwise (bias, scale, crosstalk, dropout, outlier, quantization, latency): the parameters
  minimising the training gap (gap.py) between measured readings and readings simulated with fixed seeds
  (common random numbers, so the objective changes with the parameters, not with the draws): a grid over the
  search range (candidates.PARAM_BOUNDS), then bounded Brent (one parameter) or Nelder-Mead (two).
Every candidate is scored the same way: its gap on held-out blocks, averaged over SCORE_SEEDS simulations with
the same seeds for every candidate.
Confidence intervals (95 %, percentile) come from a bootstrap over training time blocks (refits on blocks drawn
with replacement; simulation fits also with new seeds), for the added effects only.

Subsampling: fitting uses at most FIT_ROWS rows of whole training blocks and scoring at most SCORE_ROWS of
held-out blocks. The gap of n rows has a sampling error of order sigma / sqrt(n) (sigma: the spread of the
residuals); with 20 000 rows that is under 1 % of sigma, far below the size of any effect worth modelling, so
more rows would only cost time (the whole held-out set still gives the reported gaps).
"""
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from finken import models
from finken.discrepancy.candidates import (CURVE_QUANTILES, LOG_GRID, MIN_VEHICLE_ROWS, PARAM_BOUNDS, PER_VEHICLE,
                                           condition_mask, effective_mask, variable)
from finken.discrepancy.condition_search import side_conditions
from finken.discrepancy.dataset import sample_blocks
from finken.discrepancy.gap import GapEvaluator
from finken.discrepancy.localize import lag_estimate
from finken.discrepancy.selection import GAIN_ALPHA, GAIN_SEEDS, GainTest
from finken.discrepancy.shape import mirror_reason

FIT_ROWS = 20000
SCORE_ROWS = 30000
#: Simulations (seeds) averaged in a held-out score: the same seeds for every candidate.
SCORE_SEEDS = 3
#: Effects that fire at random on some readings (which ones, a seed decides): their minimum-gap objective on
#: one simulation is rugged in their probability (outlier under a flag: p = 0.08 beat the hidden 0.10), so it
#: is averaged over FIRING_SEEDS simulations.
FIRING_EFFECTS, FIRING_SEEDS = ("crosstalk", "dropout", "outlier"), 3
#: Chain draws per row in the simulated likelihood; rows used for it.
S_DRAWS, MLE_ROWS = 24, 5000
#: Weight of the defensive uniform component of the simulated likelihood.
EPS = 1e-3
#: Grid points per parameter: one-parameter effects, two-parameter effects.
GRID_1D, GRID_2D = 11, 6
#: Half-width of the grid of a bootstrap refit around the estimate [fraction of the estimate].
LOCAL_SPAN = 0.3
#: Bootstrap replicates for the confidence intervals: likelihood fits (cheap), simulation fits.
BOOT_MLE, BOOT_SIM = 30, 16
#: Fine grid of a step size around its start [fraction]; readings per distinct value that mark a lattice.
LATTICE_SPAN, LATTICE_MIN_REPEAT = 0.05, 5
#: Largest number of rows for the mixture fit, and the component counts tried.
GMM_ROWS, GMM_COMPONENTS = 4000, (1, 2, 3, 4, 6)
#: Fewest rows a line of a mixture's summary stands on.
MIN_SUMMARY_ROWS = 30
#: Objective evaluations per parameter when several effects are fitted together (KindFitter.fit_jointly).
JOINT_EVALUATIONS = 30


@dataclass
class Fit:
    candidate: object            # candidates.Candidate
    params: dict                 # fitted parameters (gmm: {"components": K})
    method: str                  # how they were fitted
    objective: float             # training objective at the fit
    model: object = None         # the current model with this effect added
    mixture: object = None       # gmm only
    heldout_gap: float = float("nan")
    ci: dict = field(default_factory=dict)    # parameter -> (low, high), 95 %
    note: str = ""
    summary: list = field(default_factory=list)   # gmm: what the mixture does, per condition (mixture_summary)
    built: list = None           # the effects it adds when they are not the candidate's one effect (per vehicle)

    def effect(self):
        params = {} if self.candidate.name == "gmm" else dict(self.params)
        return models.Effect(self.candidate.name, params, self.candidate.condition, self.mixture)

    def effects(self):
        """The effects the fit adds to its kind's chain, in order."""
        return list(self.built) if self.built is not None else [self.effect()]

    def values_text(self):
        """The fitted values of a per-vehicle fit or a curve as a person reads them ("1 -0.11, 2 -0.1, 3 +0.08 m",
        "over true_range: 0.5 +0.02, 2.1 +0.05 m"); "" for other fits."""
        if self.candidate.name == "bias_curve":
            return f"over {self.candidate.over}: " + ", ".join(f"{k.split()[-1]} {v:+.3g}"
                                                               for k, v in self.params.items()) + " m"
        if self.candidate.name not in PER_VEHICLE:
            return ""
        unit = " m" if PER_VEHICLE[self.candidate.name] == "bias" else ""
        sign = "+" if unit else ""
        return ", ".join(f"{k.split()[-1]} {v:{sign}.3g}" for k, v in self.params.items()) + unit


def add_effects(model, kind, effects):
    """A copy of `model` with `effects` appended to its `kind` chain (models.SensorModel.with_effect)."""
    for effect in effects:
        model = model.with_effect(kind, effect)
    return model


class KindFitter:
    """Fits and scores the candidates of one sensor kind against one current model."""

    def __init__(self, kr, views, model, seed, rng, bootstrap=False):
        """`bootstrap`: training blocks drawn with replacement (stability.py) instead of without."""
        self.kr, self.views, self.model, self.rng = kr, views, model, rng
        self._columns = {}    # the subset last simulated and its columns (kept with it, so its id stays valid)
        self.seed_fit, self.seed_floor = seed, seed + 1
        self.seeds_score = [seed + 2 + i for i in range(SCORE_SEEDS)]
        self.train = sample_blocks(kr, "train", FIT_ROWS, rng, blocks=_bootstrap_blocks(kr, rng) if bootstrap else None)
        self.heldout = sample_blocks(kr, "heldout", SCORE_ROWS, rng)
        self.train_eval = GapEvaluator(kr, views, self.train)
        self.heldout_eval = GapEvaluator(kr, views, self.heldout)
        self._masks = {}      # condition -> rows where it holds
        self._effective = {}
        self.current_gap = self.score(model)
        floor_eval = self.heldout_eval.with_reference(self.readings(model, self.heldout, self.seed_floor)
                                                      [self.heldout.scored])
        self.floor_gap = float(np.mean([floor_eval.gap(self.readings(model, self.heldout, s))
                                        for s in self.seeds_score]))
        self._current_train = self.raw(model, self.train, self.seed_fit)
        self._draws = None
        self._gain_current = None     # held-out gaps of the current model over the gain test's seeds
        self._mirrored = {}           # id(fit) -> (fit, mirrored(fit)): the check simulates, it runs once a fit

    def condition_rows(self, condition):
        """Rows where a condition holds (candidates.condition_mask), cached."""
        if condition not in self._masks:
            self._masks[condition] = condition_mask(self.kr, condition)
        return self._masks[condition]

    def side_conditions(self):
        """The condition each ctx_ column offers (condition_search.side_conditions) on the training rows."""
        rows = self.train.idx[self.train.scored]
        tr = self.kr.true_range[rows]
        measured = self.kr.reading(self.kr.measured[rows]) - tr
        simulated = self.kr.reading(self._current_train[self.train.scored]) - tr
        return list(side_conditions({k: v[rows] for k, v in self.kr.ctx.items()}, measured, simulated).values())

    def mask_of(self, cand):
        """Rows where a candidate can act (candidates.effective_mask), cached."""
        if cand not in self._effective:
            self._effective[cand] = effective_mask(self.kr, cand)
        return self._effective[cand]

    # ---- simulation helpers
    def raw(self, model, subset, seed):
        """Simulated measurements (NaN = none) of the subset's rows [m]."""
        key = id(subset)
        if key not in self._columns:
            idx = subset.idx
            self._columns = {key: (subset, self.kr.t[idx], self.kr.true_range[idx], self.kr.ctx_of(idx))}
        _, t, tr, ctx = self._columns[key]
        return models.simulate(model, self.kr.kind, t, tr, subset.sim_stream, ctx, seed)

    def readings(self, model, subset, seed):
        return self.kr.reading(self.raw(model, subset, seed))

    def score(self, model):
        """Held-out gap of a model [m], the mean over SCORE_SEEDS simulations."""
        return float(np.mean([self.heldout_eval.gap(self.readings(model, self.heldout, s))
                              for s in self.seeds_score]))

    # ---- fitting
    def fit(self, cand):
        """Fit and score one candidate; returns a Fit (heldout_gap NaN and a note when it cannot be fitted)."""
        try:
            if cand.name == "gmm":
                fit = self._fit_gmm(cand)
            elif cand.name in PER_VEHICLE:
                fit = self._fit_per_vehicle(cand, self.train)
            elif cand.name == "bias_curve":
                fit = self._fit_curve(cand, self.train)
            elif models.effect_has_logpdf(cand.name):
                fit = self._fit_mle(cand, self._mle_data(cand))
            else:
                fit = self._fit_simulated(cand, self.train, self.train_eval)
        except (models.ModelError, ValueError, np.linalg.LinAlgError) as err:
            return Fit(cand, {}, "not fitted", float("nan"), note=str(err))
        fit.heldout_gap = self.score(fit.model)
        return fit

    def _with(self, cand, params, mixture=None):
        return self.model.with_effect(cand.kind, models.Effect(cand.name, params, cand.condition, mixture))

    # ---- simulation-based
    def _fit_simulated(self, cand, subset, evaluator, start=None, seed=None, local=False):
        """Minimum-gap fit: a grid over the search range (or, `local`, only around `start`), then bounded
        Brent (one parameter) or Nelder-Mead (two)."""
        names = models.effect_params(cand.name)
        bounds = [PARAM_BOUNDS[(cand.name, p)] for p in names]
        start = start or self._moment_start(cand, subset)

        first = self.seed_fit if seed is None else seed
        seeds = range(first, first + (FIRING_SEEDS if cand.name in FIRING_EFFECTS else 1))

        def objective(theta):
            theta = [float(np.clip(v, lo, hi)) for v, (lo, hi) in zip(np.atleast_1d(theta), bounds)]
            model = self._with(cand, dict(zip(names, theta)))
            return float(np.mean([evaluator.gap(self.readings(model, subset, s)) for s in seeds]))

        n_grid = GRID_1D if len(names) == 1 else GRID_2D
        if local:
            grids = [_local_grid(cand.name, p, b, n_grid, start[p]) for p, b in zip(names, bounds)]
        else:
            grids = [_grid(cand.name, p, b, n_grid, start.get(p)) for p, b in zip(names, bounds)]
        points = np.array(np.meshgrid(*grids, indexing="ij")).reshape(len(names), -1).T
        values = np.array([objective(p) for p in points])
        best = points[int(np.argmin(values))]
        if len(names) == 1:
            g = grids[0]
            i = int(np.searchsorted(g, best[0]))
            lo, hi = g[max(i - 1, 0)], g[min(i + 1, len(g) - 1)]
            if hi > lo:
                res = optimize.minimize_scalar(lambda v: objective([v]), bounds=(lo, hi), method="bounded",
                                               options={"xatol": (hi - lo) * 1e-3, "maxiter": 20})
                if res.fun < values.min():
                    best = np.array([res.x])
        else:
            steps = [max((g[-1] - g[0]) / (len(g) - 1), 1e-6) for g in grids]
            simplex = np.array([best] + [best + np.eye(len(names))[j] * steps[j] * 0.5 for j in range(len(names))])
            res = optimize.minimize(objective, best, method="Nelder-Mead", bounds=bounds,
                                    options={"initial_simplex": simplex, "maxfev": 40, "xatol": 1e-4,
                                             "fatol": 1e-7})
            if res.fun < values.min():
                best = res.x
        params = {p: float(np.clip(v, lo, hi)) for p, v, (lo, hi) in zip(names, best, bounds)}
        return Fit(cand, params, "simulation: minimum training gap", float(min(values.min(), objective(best))),
                   self._with(cand, params))

    def _moment_start(self, cand, subset):
        """Rough starting values from the measured and the current model's readings on the condition rows."""
        kr = self.kr
        rows = subset.idx[subset.scored]
        mask = self.condition_rows(cand.condition)[rows]
        sim = (self._current_train if subset is self.train else self.raw(self.model, subset, self.seed_fit))
        sim = sim[subset.scored][mask]
        meas, tr = kr.measured[rows][mask], kr.true_range[rows][mask]
        ok_m, ok_s = np.isfinite(meas) & (meas < kr.max_range), np.isfinite(sim) & (sim < kr.max_range)
        if ok_m.sum() < 10 or ok_s.sum() < 10:
            return {}
        rm, rs = meas[ok_m] - tr[ok_m], sim[ok_s] - tr[ok_s]
        if cand.name == "bias":
            return {"b": float(np.median(rm) - np.median(rs))}
        if cand.name == "scale":
            pos_m, pos_s = tr[ok_m] > 0.1, tr[ok_s] > 0.1
            if pos_m.sum() < 10 or pos_s.sum() < 10:
                return {}
            return {"k": float(np.median(meas[ok_m][pos_m] / tr[ok_m][pos_m])
                               / np.median(sim[ok_s][pos_s] / tr[ok_s][pos_s]))}
        if cand.name == "dropout":
            below = tr < kr.max_range
            lost_m = np.mean(~np.isfinite(meas[below]) | (meas[below] >= kr.max_range)) if below.any() else 0.0
            lost_s = np.mean(~np.isfinite(sim[below]) | (sim[below] >= kr.max_range)) if below.any() else 0.0
            return {"p": float(np.clip((lost_m - lost_s) / max(1 - lost_s, 1e-9), 0, 1)), "p_per_m": 0.0}
        if cand.name == "quantization":
            return {"step": lattice_step(meas[ok_m])}
        if cand.name == "latency":
            rate = kr.range_rate[rows][mask]
            tm, _ = lag_estimate(rm, rate[ok_m])
            ts, _ = lag_estimate(rs, rate[ok_s])
            return {"tau": float(np.clip(tm - ts, 0, 1))} if np.isfinite(tm - ts) else {}
        return {}

    # ---- per vehicle
    def _fit_per_vehicle(self, cand, subset):
        """A value per vehicle from the medians of its readings (module docstring); vehicles with too few readings
        inside the range limits get the identity."""
        kr, effect = self.kr, PER_VEHICLE[cand.name]
        sim = self._current_train if subset is self.train else self.raw(self.model, subset, self.seed_fit)
        rows = subset.idx[subset.scored]
        meas, sim, tr, vehicle = kr.measured[rows], sim[subset.scored], kr.true_range[rows], kr.vehicle[rows]
        (param,) = models.effect_params(effect)
        lo, hi = PARAM_BOUNDS[(effect, param)]
        params, built = {}, []
        for v in np.unique(vehicle):
            mine = (vehicle == v) & (tr > kr.min_range) & (tr < kr.max_range)
            m, s = mine & kr.inside(meas), mine & kr.inside(sim)
            if min(m.sum(), s.sum()) < MIN_VEHICLE_ROWS:
                value = 0.0 if effect == "bias" else 1.0
            elif effect == "bias":
                value = float(np.median(meas[m] - tr[m]) - np.median(sim[s] - tr[s]))
            else:
                value = float(np.median(meas[m] / tr[m]) / np.median(sim[s] / tr[s]))
            value = float(np.clip(value, lo, hi))
            params[f"vehicle {v:g}"] = value
            built.append(models.Effect(effect, {param: value}, f"ctx_vehicle == {v:g}"))
        return Fit(cand, params, f"per vehicle: {'difference' if effect == 'bias' else 'ratio'} of the medians of its "
                   "measured and simulated readings", float("nan"), add_effects(self.model, kr.kind, built),
                   built=built)

    # ---- bias curve
    def _fit_curve(self, cand, subset, knots=None):
        """A bias that follows cand.over: knots at quantiles of it (or `knots`), each knot's bias the difference of
        the median measured and simulated residuals of the rows nearest it (module docstring)."""
        kr = self.kr
        sim = self._current_train if subset is self.train else self.raw(self.model, subset, self.seed_fit)
        rows = subset.idx[subset.scored]
        meas, sim, tr = kr.measured[rows], sim[subset.scored], kr.true_range[rows]
        u = variable(kr, cand.over)[rows]
        usable = np.isfinite(u) & (tr > kr.min_range) & (tr < kr.max_range)
        if knots is None:
            knots = np.unique(np.quantile(u[usable], CURVE_QUANTILES)) if usable.any() else []
        knots = np.asarray(knots, dtype=float)
        if knots.size < 2:
            raise ValueError(f"{cand.over} takes too few distinct values for a curve")
        nearest = np.abs(u[:, None] - knots[None, :]).argmin(axis=1)
        lo, hi = PARAM_BOUNDS[("bias", "b")]
        b = []
        for i in range(knots.size):
            mine = usable & (nearest == i)
            m, s = mine & kr.inside(meas), mine & kr.inside(sim)
            b.append(float(np.clip(np.median(meas[m] - tr[m]) - np.median(sim[s] - tr[s]), lo, hi))
                     if min(m.sum(), s.sum()) >= MIN_SUMMARY_ROWS else 0.0)
        effect = models.Effect("bias_curve", {}, cand.condition, curve=models.BiasCurve(cand.over, knots.tolist(), b))
        params = {f"b at {k:.4g}": v for k, v in zip(knots, b)}
        return Fit(cand, params, f"difference of the median residuals of the rows nearest each of {knots.size} "
                   f"knots of {cand.over}", float("nan"), add_effects(self.model, kr.kind, [effect]), built=[effect])

    # ---- maximum simulated likelihood
    def _mle_data(self, cand, blocks=None):
        """(y, z, valid, block) for the likelihood: readings y of training rows under the condition, strictly
        inside the range limits, and S_DRAWS current-chain outputs z per row (valid: z usable)."""
        if self._draws is None:
            self._draws = np.array([self.raw(self.model, self.train, self.seed_fit + 100 + s)
                                    for s in range(S_DRAWS)])
        kr, sub = self.kr, self.train
        pos = np.flatnonzero(sub.scored)
        rows = sub.idx[pos]
        y, tr = kr.measured[rows], kr.true_range[rows]
        lo, hi = kr.min_range, kr.max_range
        keep = self.condition_rows(cand.condition)[rows] & np.isfinite(y) & (y > lo) & (y < hi) & (tr > lo) & (tr < hi)
        z = self._draws[:, pos]
        valid = np.isfinite(z) & (z > lo) & (z < hi)
        keep &= valid.sum(axis=0) >= S_DRAWS // 2
        sel = np.flatnonzero(keep)
        if sel.size > MLE_ROWS:
            sel = np.sort(self.rng.choice(sel, MLE_ROWS, replace=False))
        if sel.size < 30:
            raise ValueError(f"only {sel.size} usable readings under {cand.condition or 'no condition'}")
        return y[sel], z[:, sel], valid[:, sel], kr.block[rows[sel]]

    def _fit_mle(self, cand, data, start=None):
        y, z, valid, _ = data
        names = models.effect_params(cand.name)
        positive = [PARAM_BOUNDS[(cand.name, p)][0] >= 0 for p in names]
        start = start or _mle_start(cand.name, y, z)
        log_uniform = math.log(EPS / (self.kr.max_range - self.kr.min_range))
        log_keep = math.log1p(-EPS) - np.log(valid.sum(axis=0))

        def unpack(u):
            return {p: float(math.exp(min(v, 5.0)) if pos else v) for p, v, pos in zip(names, u, positive)}

        def neg_loglik(u):
            lp = models.effect_logpdf(cand.name, unpack(u), z, y[None, :])
            lp[~valid] = -np.inf
            top = lp.max(axis=0)           # log-sum-exp over the draws, safe where every draw has density 0
            finite = np.isfinite(top)
            lse = np.full(top.shape, -np.inf)
            lse[finite] = top[finite] + np.log(np.exp(lp[:, finite] - top[finite]).sum(axis=0))
            ll = np.logaddexp(lse + log_keep, log_uniform)
            return -float(np.mean(ll))

        u0 = [math.log(max(start[p], 1e-4)) if pos else start[p] for p, pos in zip(names, positive)]
        res = optimize.minimize(neg_loglik, u0, method="Nelder-Mead",
                                options={"maxfev": 50 * len(names), "xatol": 1e-3, "fatol": 1e-6})
        params = unpack(res.x)
        return Fit(cand, params, f"maximum simulated likelihood ({S_DRAWS} chain draws per reading)",
                   float(res.fun), self._with(cand, params))

    # ---- mixture
    def _fit_gmm(self, cand, components=GMM_COMPONENTS):
        from sklearn.mixture import GaussianMixture
        kr, sub = self.kr, self.train
        rows = sub.idx[sub.scored]
        y, tr = kr.measured[rows], kr.true_range[rows]
        keep = np.flatnonzero(self.condition_rows(cand.condition)[rows] & np.isfinite(y) & (y > kr.min_range)
                              & (y < kr.max_range) & (tr < kr.max_range))
        if keep.size < 50:
            raise ValueError(f"only {keep.size} usable readings for a mixture")
        if keep.size > GMM_ROWS:
            keep = self.rng.choice(keep, GMM_ROWS, replace=False)
        data = np.column_stack([tr[keep], y[keep]])
        best = None
        for k in components:
            g = GaussianMixture(k, covariance_type="full", random_state=self.seed_fit % 2**32,
                                reg_covar=1e-6).fit(data)
            bic = g.bic(data)
            if best is None or bic < best[0]:
                best = (bic, g)
        g = best[1]
        mixture = models.Mixture(g.weights_, g.means_, g.covariances_)
        params = {"components": float(g.n_components)}
        return Fit(cand, params, "maximum likelihood (EM, scikit-learn), components by BIC", float(best[0]),
                   self._with(cand, {}, mixture), mixture=mixture)

    def mixture_summary(self, fit):
        """What a fitted mixture does to a reading, in numbers a person can read: the excess over the true range
        (reading - true range) of the fitted model's simulated readings on the training rows where it acts,
        overall and per true-range bin: n, mean, median and spread (half the 16-84 % interquantile range, the
        standard deviation for a normal law) [m]. Sets fit.summary."""
        rows = self.train.idx[self.train.scored]
        excess = self.raw(fit.model, self.train, self.seed_fit)[self.train.scored] - self.kr.true_range[rows]
        acts = self.mask_of(fit.candidate)[rows] & np.isfinite(excess)
        view = next((v for v in self.views if v.name == "true_range"), None)
        parts = [(fit.candidate.condition or "all rows", acts)]
        if view is not None:
            parts += [(label, acts & (view.code[rows] == b)) for b, label in enumerate(view.labels)]
        fit.summary = []
        for label, m in parts:
            if m.sum() >= MIN_SUMMARY_ROWS:
                q16, q50, q84 = np.quantile(excess[m], [0.16, 0.5, 0.84])
                fit.summary.append({"condition": label, "n": int(m.sum()), "excess_mean": float(excess[m].mean()),
                                    "excess_median": float(q50), "excess_spread": float((q84 - q16) / 2)})
        return fit

    # ---- several effects together
    def fit_jointly(self, fits):
        """The effects of `fits` (effects of the library with numeric parameters, appended in order on top of this
        fitter's model) fitted together: the parameters minimising the training gap, from their fitted values,
        by Nelder-Mead within the search ranges (each fitted alone took on part of the others'); scored like
        fit(). A list of Fits (each with the model of all of them), or None when one cannot be fitted so."""
        if any(not jointly_fittable(f) for f in fits):
            return None
        slots = [(i, p) for i, f in enumerate(fits) for p in f.params]
        bounds = [PARAM_BOUNDS[(fits[i].candidate.name, p)] for i, p in slots]
        firing = any(f.candidate.name in FIRING_EFFECTS for f in fits)
        seeds = range(self.seed_fit, self.seed_fit + (FIRING_SEEDS if firing else 1))

        def unpack(theta):
            params = [dict() for _ in fits]
            for (i, p), v, (lo, hi) in zip(slots, np.atleast_1d(theta), bounds):
                params[i][p] = float(np.clip(v, lo, hi))
            return params

        def build(params):
            effects = [models.Effect(f.candidate.name, ps, f.candidate.condition) for f, ps in zip(fits, params)]
            return add_effects(self.model, self.kr.kind, effects)

        def objective(theta):
            model = build(unpack(theta))
            return float(np.mean([self.train_eval.gap(self.readings(model, self.train, s)) for s in seeds]))

        start = np.clip([fits[i].params[p] for i, p in slots], *np.transpose(bounds))
        res = optimize.minimize(objective, start, method="Nelder-Mead", bounds=bounds,
                                options={"maxfev": JOINT_EVALUATIONS * len(slots), "xatol": 1e-4, "fatol": 1e-7})
        params = unpack(res.x if res.fun <= objective(start) else start)
        model = build(params)
        gap = self.score(model)
        return [Fit(f.candidate, ps, "simulation: minimum training gap, fitted together with "
                    + ", ".join(g.candidate.label for g in fits if g is not f), float(res.fun), model,
                    heldout_gap=gap) for f, ps in zip(fits, params)]

    # ---- shape
    def mirrored(self, fit):
        """Why a fit's error has the mirror shape of the measured one where it acts, "" when it has not
        (shape.mirror_reason; once a fit: the check simulates)."""
        if id(fit) not in self._mirrored:
            self._mirrored[id(fit)] = (fit, mirror_reason(self, fit))
        return self._mirrored[id(fit)][1]

    # ---- the gain test and refits near a fit
    def gain_test(self, fit, start_gap, against=None, alpha=GAIN_ALPHA):
        """selection.GainTest (at level alpha) of a fit against the current model (or against another fit):
        held-out gaps with GAIN_SEEDS paired seeds."""
        seeds = [self.seed_fit + 500 + i for i in range(GAIN_SEEDS)]
        if against is not None:
            base = self._seed_gaps(against.model, seeds)
        else:
            if self._gain_current is None:
                self._gain_current = self._seed_gaps(self.model, seeds)
            base = self._gain_current
        diff = base - self._seed_gaps(fit.model, seeds)
        if np.ptp(diff) == 0:             # a t statistic needs a spread; an exact tie is decided by its sign
            p = 0.0 if diff[0] > 0 else 1.0
        else:
            p = float(stats.ttest_1samp(diff, 0.0, alternative="greater").pvalue)
        return GainTest(float(diff.mean()), p, self.floor_gap, start_gap, alpha)

    def _seed_gaps(self, model, seeds):
        return np.array([self.heldout_eval.gap(self.readings(model, self.heldout, s)) for s in seeds])

    def refit(self, fit):
        """The candidate of `fit` fitted again on this fitter's rows, starting from its parameters (a mixture:
        with its number of components); scored like fit()."""
        cand = fit.candidate
        try:
            if cand.name == "gmm":
                new = self._fit_gmm(cand, components=(int(fit.params["components"]),))
            elif cand.name in PER_VEHICLE:
                new = self._fit_per_vehicle(cand, self.train)
            elif cand.name == "bias_curve":
                new = self._fit_curve(cand, self.train)
            elif models.effect_has_logpdf(cand.name):
                new = self._fit_mle(cand, self._mle_data(cand), start=fit.params)
            else:
                new = self._fit_simulated(cand, self.train, self.train_eval, start=fit.params, local=True)
        except (models.ModelError, ValueError, np.linalg.LinAlgError) as err:
            return Fit(cand, {}, "not fitted", float("nan"), note=str(err))
        new.heldout_gap = self.score(new.model)
        return new

    # ---- confidence intervals
    def bootstrap_ci(self, fit, progress=None):
        """95 % percentile intervals of the fitted parameters from refits on training blocks drawn with
        replacement; sets fit.ci (nothing for gmm)."""
        cand = fit.candidate
        if cand.name == "gmm" or not fit.params:
            return fit
        estimates = []
        if _by_likelihood(cand):
            y, z, valid, block = self._mle_data(cand)
            ids = np.unique(block)
            for _ in range(BOOT_MLE):
                pick = self.rng.choice(ids, len(ids), replace=True)
                sel = np.concatenate([np.flatnonzero(block == b) for b in pick])
                f = self._fit_mle(cand, (y[sel], z[:, sel], valid[:, sel], block[sel]), start=fit.params)
                estimates.append([f.params[p] for p in fit.params])
                if progress:
                    progress.update()
        else:
            ids = np.unique(self.kr.block[self.train.idx[self.train.scored]])
            for b in range(BOOT_SIM):
                subset = sample_blocks(self.kr, "train", 0, self.rng, blocks=self.rng.choice(ids, len(ids)))
                if cand.name in PER_VEHICLE:
                    f = self._fit_per_vehicle(cand, subset)
                elif cand.name == "bias_curve":
                    f = self._fit_curve(cand, subset, knots=fit.built[0].curve.at)
                else:
                    evaluator = GapEvaluator(self.kr, self.views, subset)
                    # other seeds too, so the interval includes the simulation noise of the objective
                    f = self._fit_simulated(cand, subset, evaluator, start=fit.params, seed=self.seed_fit + 1000 + b,
                                            local=True)
                estimates.append([f.params.get(p, np.nan) for p in fit.params])
                if progress:
                    progress.update()
        est = np.array(estimates)
        fit.ci = {p: (float(np.nanpercentile(est[:, j], 2.5)), float(np.nanpercentile(est[:, j], 97.5)))
                  for j, p in enumerate(fit.params)}
        return fit

    def bootstrap_count(self, fit):
        """Refits bootstrap_ci will run (for the progress display)."""
        if fit.candidate.name == "gmm" or not fit.params:
            return 0
        return BOOT_MLE if _by_likelihood(fit.candidate) else BOOT_SIM


def jointly_fittable(fit):
    """Whether fit_jointly can refit it: a library effect whose parameters are all numbers with a search range."""
    return (fit.built is None and fit.candidate.name != "gmm" and bool(fit.params)
            and all((fit.candidate.name, p) in PARAM_BOUNDS for p in fit.params))


def _by_likelihood(cand):
    """Whether a candidate is fitted by maximum simulated likelihood (an effect of the library with a density)."""
    return cand.name not in PER_VEHICLE and models.effect_has_logpdf(cand.name)


def _bootstrap_blocks(kr, rng):
    """Training blocks drawn with replacement until they hold FIT_ROWS rows (or as many as there are)."""
    ids, counts = np.unique(kr.block[~kr.heldout], return_counts=True)
    draws = rng.integers(0, ids.size, size=ids.size)
    enough = np.searchsorted(np.cumsum(counts[draws]), FIT_ROWS) + 1
    return ids[draws[:enough]]


def _grid(effect, param, bounds, n, start):
    """Grid over the search range, plus the start value; a step size also gets a fine grid within +-LATTICE_SPAN
    of its start (the gap of readings against a lattice of another step is rugged in the step)."""
    lo, hi = bounds
    g = np.geomspace(lo, hi, n) if (effect, param) in LOG_GRID else np.linspace(lo, hi, n)
    if start is not None and np.isfinite(start) and lo <= start <= hi:
        g = np.append(g, start)
        if (effect, param) in LOG_GRID:
            g = np.append(g, start * np.linspace(1 - LATTICE_SPAN, 1 + LATTICE_SPAN, 21))
    return np.unique(np.clip(g, lo, hi))


def _local_grid(effect, param, bounds, n, start):
    """A grid of n points within +-LOCAL_SPAN of `start` (relative, at least LOCAL_SPAN of the search range)."""
    lo, hi = bounds
    width = max(LOCAL_SPAN * abs(start), LOCAL_SPAN * (hi - lo) / 4)
    if (effect, param) in LOG_GRID:
        width = LATTICE_SPAN * start
    return np.unique(np.clip(np.linspace(start - width, start + width, max(n // 2, 3)), lo, hi))


def lattice_step(readings):
    """The spacing of the values the readings take when they sit on a lattice [m] (the median gap between
    neighbouring distinct values, which is the step when most lattice points are hit); None when the readings
    are not on a lattice (more than one distinct value per LATTICE_MIN_REPEAT readings)."""
    values = np.unique(np.round(readings, 9))
    if values.size < 3 or values.size * LATTICE_MIN_REPEAT > readings.size:
        return None
    return float(np.median(np.diff(values)))


def _mle_start(name, y, z):
    """Starting values from the excess mean and variance of the readings over the chain's draws."""
    zm = np.nanmean(np.where(np.isfinite(z), z, np.nan), axis=0)
    d = y - zm
    excess_var = max(float(np.var(d) - np.nanmean(np.nanvar(np.where(np.isfinite(z), z, np.nan), axis=0))), 1e-6)
    shift = float(np.mean(d))
    if name == "gaussian":
        return {"sigma": math.sqrt(excess_var)}
    if name == "range_noise":
        return {"sigma0": math.sqrt(excess_var), "sigma1": 0.01}
    if name == "rayleigh_short":
        sigma = math.sqrt(excess_var / ((4 - math.pi) / 2))     # Var R = (4 - pi) / 2 sigma^2
        return {"sigma": sigma, "offset": shift + sigma * math.sqrt(math.pi / 2)}   # E R = sigma sqrt(pi / 2)
    if name == "nlos_bias":
        return {"mean": max(shift, math.sqrt(excess_var), 1e-3)}   # Exponential: mean = standard deviation
    raise ValueError(f"no starting values for effect '{name}'")
