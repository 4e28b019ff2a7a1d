"""Which candidate, if any, to add: the rule and its margins.

All candidates of a kind are ranked by their held-out gap (lower is better). With the margin
    delta = max(MARGIN_FLOOR x noise floor of the held-out gap, MARGIN_GAP x current held-out gap),
- a *mixture* (gmm) may be named only when no library explanation comes within delta of it: neither the best
  library candidate alone nor with a second effect of the library (each, without condition, best first)
  refitted on top of it (a two-effect explanation); otherwise the mixture leaves the pool, so a named effect means
  something (nlos_bias, not "components = 6");
- the *winner* is the simplest candidate of the pool (fewest fitted quantities, candidates.complexity) whose
  held-out gap is within delta of the pool's best, so that a more general effect (range_noise, a condition
  that holds almost everywhere) is chosen only when it does better than its special case by the margin;
- the *runner-up* is the best candidate that is not a version of the winner's explanation
  (candidates.same_explanation) and competes with it: a candidate that still lowers the gap by delta once the
  winner has been added explains another part of the disagreement (two missing effects), so it is no rival and
  the next one is taken (at most COMPLEMENT_CHECKS such refits);
- the winner is added when its held-out gap is more than delta below the current model's and its gain passes the
  gain test (GainTest). When the runner-up comes within delta of it, the two explanations tie: the data cannot
  tell them apart, the report names both as undecided, and the model carries the winner (the simpler, or the
  better of two equally simple ones); a tie never hands the choice to a mixture. The gain test is a paired
  one-sided t-test over
  GAIN_SEEDS simulation seeds (gap of the current model minus the winner's, same seeds and rows) at level
  GAIN_ALPHA, a gain above the noise floor (smaller gains cannot be told from the difference two simulations
  of one model show), and at least MIN_GAIN_SHARE of the kind's gap at the start of the workflow (an effect
  that removes a sliver of the disagreement only patches the fit of another one). Otherwise nothing is added
  and the reason is reported.
"""
from dataclasses import dataclass, field

import numpy as np

from finken.discrepancy.candidates import complexity, same_explanation

#: Margin factors (module docstring): multiples of the noise floor of the held-out gap and of the current gap.
MARGIN_FLOOR, MARGIN_GAP = 0.25, 0.02
#: Candidates checked for being complementary to the winner (one refit each).
COMPLEMENT_CHECKS = 3
#: Gain test: simulation seeds, one-sided level, least share of the kind's starting gap.
GAIN_SEEDS, GAIN_ALPHA, MIN_GAIN_SHARE = 12, 0.01, 0.05


@dataclass
class GainTest:
    """The gain test of a winner (module docstring)."""
    gain: float            # mean over seeds of (current gap - winner's gap) [m]
    p: float               # one-sided paired t-test p-value
    floor: float           # noise floor of the held-out gap [m]
    start_gap: float       # the kind's held-out gap at the start of the workflow [m]
    alpha: float = GAIN_ALPHA   # level (lower when the tested fit was chosen among several: Bonferroni)

    @property
    def passed(self):
        return self.p < self.alpha and self.gain > self.floor and self.gain >= MIN_GAIN_SHARE * self.start_gap

    def reason(self):
        if self.p >= self.alpha:
            return f"its gain over {GAIN_SEEDS} seeds is not significant (p = {self.p:.2g} >= {self.alpha:.2g})"
        if self.gain <= self.floor:
            return f"its gain {self.gain:.4g} m is not above the noise floor {self.floor:.4g} m"
        return (f"its gain {self.gain:.4g} m is {self.gain / self.start_gap:.1%} of the gap at the start "
                f"({self.start_gap:.4g} m), less than {MIN_GAIN_SHARE:.0%}")


@dataclass
class Selection:
    kind: str
    ranking: list                      # fitting.Fit, best held-out gap first (not fitted ones last)
    current_gap: float                 # held-out gap of the current model [m]
    floor_gap: float                   # held-out gap between two simulations of the current model [m]
    margin: float                      # delta [m]
    winner: object = None              # Fit chosen (added when `added`)
    runner_up: object = None           # Fit it had to beat
    complementary: list = field(default_factory=list)   # (Fit, gap once added on top of the winner)
    mirrored: list = field(default_factory=list)        # (Fit, why): set aside for a shape opposite the data's
    undecided: object = None           # the runner-up when it ties with the winner (within the margin)
    partner: object = None             # a second effect named with the winner, fitted together with it
    partner_undecided: object = None   # another second effect that ties with the partner
    mixture_set_aside: str = ""        # why the best mixture left the pool, if it did
    gain_test: GainTest = None
    added: bool = False
    reason: str = ""
    stability: object = None           # stability.Stability of the winner, when added

    @property
    def margin_over_current(self):
        return self.current_gap - self.winner.heldout_gap if self.winner else float("nan")

    def reason_not_added(self, gain_test):
        """Set and return why the winner is not added ("" when it is): the margins, then the gain test."""
        label = self.winner.candidate.label
        if not self.margin_over_current > self.margin:
            self.reason = (f"{label} lowers the held-out gap by {self.margin_over_current:.4g} m, less than the "
                           f"margin {self.margin:.4g} m")
        elif gain_test is not None:
            self.gain_test = gain_test(self.winner)
            if not self.gain_test.passed:
                self.reason = f"{label} fails the gain test: {self.gain_test.reason()}"
        return self.reason

    @property
    def margin_over_runner_up(self):
        if self.winner is None or self.runner_up is None:
            return float("nan")
        return self.runner_up.heldout_gap - self.winner.heldout_gap


def select(kind, fits, current_gap, floor_gap, mask_of, gap_on_top, gain_test=None, mirrored=None):
    """Apply the rule to the fits of one kind. `mask_of(candidate)`: rows where it acts
    (candidates.effective_mask). `gap_on_top(winner, fit)` returns the held-out gap of `fit`'s
    candidate refitted with `winner` already added (for the complementarity and the two-effect checks).
    `gain_test(winner)` returns its GainTest (None: no gain test). `mirrored(fit)` says why a fit's error has
    the mirror shape of the measured one ("" when not; None: no check): such a winner leaves the pool."""
    sel = _ranked(kind, fits, current_gap, floor_gap)
    valid = [f for f in sel.ranking if np.isfinite(f.heldout_gap)]
    if mirrored is not None:
        valid = _without_mirrored_leaders(sel, valid, mirrored)
    if not valid:
        sel.reason = "no candidate could be fitted"
        return sel
    pool = _pool(sel, valid, gap_on_top)
    sel.winner = _simplest(pool, sel.margin)
    while mirrored is not None and (why := mirrored(sel.winner)):
        sel.mirrored.append((sel.winner, why))
        pool = [f for f in pool if f is not sel.winner]
        if not pool:
            sel.winner, sel.reason = None, f"no candidate left: {why}"
            return sel
        sel.winner = _simplest(pool, sel.margin)
    _runner_up(sel, pool, mask_of, gap_on_top)
    if sel.reason_not_added(gain_test):
        return sel
    sel.added = True
    if sel.runner_up is not None and not sel.margin_over_runner_up > sel.margin:
        sel.undecided = sel.runner_up
        rival = (f"ties with {sel.runner_up.candidate.label} ({sel.margin_over_runner_up:.4g} m behind): undecided "
                 f"between the two, the model carries {sel.winner.candidate.label}")
    elif sel.runner_up is not None:
        rival = f"beats the runner-up {sel.runner_up.candidate.label} by {sel.margin_over_runner_up:.4g} m"
    else:
        rival = "has no rival"
    sel.reason = (f"{sel.winner.candidate.label} lowers the held-out gap by {sel.margin_over_current:.4g} m and "
                  f"{rival} (margin {sel.margin:.4g} m)")
    return sel


def choose(fits, current_gap, floor_gap, gap_on_top):
    """The winner the rule would pick among `fits` (pool and simplicity, no margins or tests); None when none
    could be fitted."""
    sel = _ranked(None, fits, current_gap, floor_gap)
    valid = [f for f in sel.ranking if np.isfinite(f.heldout_gap)]
    return _simplest(_pool(sel, valid, gap_on_top), sel.margin) if valid else None


def _ranked(kind, fits, current_gap, floor_gap):
    ranking = sorted(fits, key=lambda f: (not np.isfinite(f.heldout_gap), f.heldout_gap))
    return Selection(kind, ranking, current_gap, floor_gap, max(MARGIN_FLOOR * floor_gap, MARGIN_GAP * current_gap))


def _simplest(pool, margin):
    """The simplest candidate within `margin` of the pool's best held-out gap."""
    best = pool[0].heldout_gap
    return min((f for f in pool if f.heldout_gap <= best + margin),
               key=lambda f: (complexity(f.candidate, f.params), f.heldout_gap))


def _without_mirrored_leaders(sel, valid, mirrored):
    """`valid` without the library candidates ranked before the best one whose shape is no mirror of the data's
    (those set aside in sel.mirrored): the pool's test of the mixtures then starts from a fit that may be named."""
    out = list(valid)
    for f in [f for f in valid if not is_mixture(f)]:
        why = mirrored(f)
        if not why:
            break
        sel.mirrored.append((f, why))
        out.remove(f)
    return out


def is_mixture(fit):
    return fit.candidate.name == "gmm"


def _pool(sel, valid, gap_on_top):
    """The candidates the winner may come from: all, or all but the mixtures when a library explanation of
    one or two effects comes close to the best mixture (module docstring); sets sel.mixture_set_aside."""
    library = [f for f in valid if not is_mixture(f)]
    mixtures = [f for f in valid if is_mixture(f)]
    if not mixtures or not library or library[0].heldout_gap <= mixtures[0].heldout_gap:
        return library or valid
    mix, lib = mixtures[0], library[0]
    if lib.heldout_gap - mix.heldout_gap <= sel.margin:
        sel.mixture_set_aside = (f"{lib.candidate.label} comes within the margin {sel.margin:.4g} m of "
                                 f"{mix.candidate.label} ({lib.heldout_gap:.4g} vs {mix.heldout_gap:.4g} m)")
        return library
    seconds = [f for f in library[1:] if f.candidate.condition is None and f.candidate.name != lib.candidate.name]
    for second in seconds:
        pair = gap_on_top(lib, second)
        if pair - mix.heldout_gap <= sel.margin:
            sel.mixture_set_aside = (f"{lib.candidate.label} with {second.candidate.label} on top comes within "
                                     f"the margin {sel.margin:.4g} m of {mix.candidate.label} ({pair:.4g} vs "
                                     f"{mix.heldout_gap:.4g} m)")
            return library
    return valid


def _runner_up(sel, pool, mask_of, gap_on_top):
    """Set sel.runner_up and sel.complementary (module docstring); mixtures set aside are no rivals."""
    rivals = [f for f in pool if f is not sel.winner
              and not same_explanation(f.candidate, sel.winner.candidate, mask_of)]
    checks = 0
    for rival in rivals:
        if rival.heldout_gap - sel.winner.heldout_gap >= sel.margin or checks >= COMPLEMENT_CHECKS:
            sel.runner_up = rival
            return
        checks += 1
        on_top = gap_on_top(sel.winner, rival)
        if on_top <= sel.winner.heldout_gap - sel.margin:
            sel.complementary.append((rival, on_top))
            continue
        sel.runner_up = rival
        return
