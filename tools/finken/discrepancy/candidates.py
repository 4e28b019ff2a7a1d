"""Candidate effects: every effect of the library (finken.models.EFFECT_NAMES), unconditional or under the
condition each `ctx_` column of the log offers (condition_search.py); a bias that follows the true range or a
continuous ctx_ column smoothly (bias_curve, one candidate per variable); and, where the log has several vehicles,
effects with a value per vehicle (PER_VEHICLE: each copter's sensor unit its own offset or scale); with the search
range of each parameter and the relations between candidates that the selection rule needs (which candidates are
versions of one explanation). Glitches are not searched (models.EFFECT_NAMES leaves them and bias curves out): the
workflow sets them apart (glitches.py)."""
from dataclasses import dataclass

import numpy as np

from finken import models
from finken.discrepancy.condition_search import terms

#: Search range of each parameter when fitting [unit of the parameter]: wide enough for a real sensor's
#: error (sonar and ranging work over 0-3 m), narrow enough that a grid over it resolves an effect.
PARAM_BOUNDS = {
    ("bias", "b"): (-1.0, 1.0),                      # m
    ("scale", "k"): (0.5, 1.5),                      # measured / true
    ("gaussian", "sigma"): (0.0, 1.0),               # m
    ("range_noise", "sigma0"): (0.0, 0.5),           # m
    ("range_noise", "sigma1"): (0.0, 0.5),           # m/m
    ("rayleigh_short", "sigma"): (0.0, 1.0),         # m
    ("rayleigh_short", "offset"): (-0.5, 1.5),       # m
    ("crosstalk", "p"): (0.0, 1.0),
    ("dropout", "p"): (0.0, 1.0),
    ("dropout", "p_per_m"): (-0.3, 0.3),             # 1/m
    ("outlier", "p"): (0.0, 0.5),
    ("quantization", "step"): (0.002, 0.5),          # m
    ("latency", "tau"): (0.0, 1.0),                  # s
    ("nlos_bias", "mean"): (0.0, 1.0),               # m
}
#: Parameters searched on a logarithmic grid (their effect scales with their size).
LOG_GRID = {("quantization", "step")}
#: Effects that contain another as a special case (range_noise with sigma1 = 0 is gaussian; rayleigh_short with
#: sigma -> 0 is a bias of +offset; a mixture can take the shape of any additive or multiplicative error).
GENERALIZES = {
    "bias_per_vehicle": {"bias"},
    "bias_curve": {"bias", "scale"},
    "scale_per_vehicle": {"scale"},
    "range_noise": {"gaussian"},
    "rayleigh_short": {"bias"},
    "gmm": {"bias", "scale", "gaussian", "range_noise", "rayleigh_short", "nlos_bias"},
}
#: Candidates with a value per vehicle: the library effect each adds, once per vehicle under "ctx_vehicle == id".
PER_VEHICLE = {"bias_per_vehicle": "bias", "scale_per_vehicle": "scale"}
#: Fewest rows every vehicle needs for the per-vehicle candidates to be tried.
MIN_VEHICLE_ROWS = 30
#: Knots of a fitted bias curve (at these quantiles of its variable), and the distinct values a ctx_ column needs
#: to carry one (fewer: it is a flag or a count, which conditions handle).
CURVE_QUANTILES, CURVE_MIN_LEVELS = (0.05, 0.275, 0.5, 0.725, 0.95), 12
#: A condition column non-zero on at least this fraction of a kind's rows is the same as no condition.
SAME_MASK_FRACTION = 0.98
#: ctx_ column without which cross-talk never fires in log replay (finken.models.simulate).
CROSSTALK_CTX = "ctx_facing_sonars"


@dataclass(frozen=True)
class Candidate:
    kind: str                 # 'sonar' or 'ranging'
    name: str                 # effect name
    condition: str = None     # ctx_ column the effect depends on, None: everywhere
    over: str = None          # bias_curve: its variable, "true_range" or a ctx_ column

    @property
    def label(self):
        return (f"{self.kind}: {self.name}" + (f" over {self.over}" if self.over else "")
                + (f" | {self.condition}" if self.condition else ""))


def condition_mask(kr, condition):
    """Rows of a kind (KindRows) where an effect under `condition` applies (the simulator's rule)."""
    return models.condition_mask(condition, kr.ctx, kr.n)


def effective_mask(kr, cand):
    """Rows where a candidate can change a reading: its condition's rows, and for cross-talk only those with a
    facing sonar (finken.models.simulate never fires it elsewhere)."""
    mask = condition_mask(kr, cand.condition)
    if cand.name == "crosstalk":
        facing = kr.ctx.get(CROSSTALK_CTX)
        mask = mask & (facing > 0) if facing is not None else np.zeros(kr.n, bool)
    return mask


def enumerate_candidates(kr, conditions):
    """(candidates, skipped) for one kind: every effect unconditional and under each of `conditions` (texts),
    except where it cannot act on these rows, or acts on (almost, SAME_MASK_FRACTION) the same rows as a
    candidate of the same effect already listed (it would be the same model); `skipped` lists (label, reason)."""
    out, skipped = [], []
    conditions = [None] + list(conditions)
    for name in models.EFFECT_NAMES:
        kept = []
        for cond in conditions:
            cand = Candidate(kr.kind, name, cond)
            mask = effective_mask(kr, cand)
            if not mask.any():
                why = (f"cross-talk needs rows with {CROSSTALK_CTX} > 0" if name == "crosstalk" and
                       condition_mask(kr, cond).any() else f"{cond} holds on no row")
                skipped.append((cand.label, why))
                continue
            twin = next((c for c, m in kept if np.mean(m == mask) >= SAME_MASK_FRACTION), None)
            if twin is not None:
                skipped.append((cand.label, f"acts on the same rows as {twin.label}"))
                continue
            kept.append((cand, mask))
        out += [c for c, _ in kept]
    out += [Candidate(kr.kind, "bias_curve", over=over) for over in curve_variables(kr)]
    if kr.vehicle is not None:
        vehicles, rows = np.unique(kr.vehicle, return_counts=True)
        if vehicles.size >= 2 and rows.min() >= MIN_VEHICLE_ROWS:
            out += [Candidate(kr.kind, name) for name in PER_VEHICLE]
    return out, skipped


def curve_variables(kr):
    """The variables a bias curve may follow: the true range and every ctx_ column with at least CURVE_MIN_LEVELS
    distinct values."""
    return ["true_range"] + [name for name, values in kr.ctx.items()
                             if np.unique(values[np.isfinite(values)]).size >= CURVE_MIN_LEVELS]


def variable(kr, over):
    """The values of a bias curve's variable on a kind's rows."""
    return kr.true_range if over == "true_range" else kr.ctx[over]


def complexity(cand, params):
    """Number of fitted quantities: parameters (a mixture: 6 per component - 1), plus 1 per term of the
    condition and 1 per cut fitted in it."""
    n = len(params) if cand.name != "gmm" else 6 * int(params.get("components", 1)) - 1
    return n + sum(terms(cand.condition))


def same_explanation(a, b, mask_of):
    """Whether two candidates are versions of one explanation: one effect is (a special case of) the other
    and they act on (almost, SAME_MASK_FRACTION) the same rows or one's rows hold the other's (a condition that
    narrows, or drops, the other's: the simplicity preference chooses between them, they are no rivals).
    `mask_of(candidate)` = effective_mask."""
    if a.kind != b.kind:
        return False
    related = a.name == b.name or a.name in GENERALIZES.get(b.name, ()) or b.name in GENERALIZES.get(a.name, ())
    if not related:
        return False
    ma, mb = mask_of(a), mask_of(b)
    agree = np.mean(ma == mb) if ma.size else 1.0
    nested = not (ma & ~mb).any() or not (mb & ~ma).any()
    return bool(agree >= SAME_MASK_FRACTION or nested)
