"""Which candidate, if any, to add: the rule and its margins.

All candidates of a kind are ranked by their held-out gap (lower is better). With the margin
    delta = max(MARGIN_FLOOR x noise floor of the held-out gap, MARGIN_GAP x current held-out gap),
- the *winner* is the simplest candidate (fewest fitted quantities, candidates.complexity) whose held-out gap is
  within delta of the best one, so that a more general effect (range_noise, a mixture, a condition that holds
  almost everywhere) is chosen only when it does better than its special case by the margin;
- the *runner-up* is the best candidate that is not a version of the winner's explanation
  (candidates.same_explanation) and competes with it: a candidate that still lowers the gap by delta once the
  winner has been added explains another part of the disagreement (two missing effects), so it is no rival and
  the next one is taken (at most COMPLEMENT_CHECKS such refits);
- the winner is added when its held-out gap is more than delta below the current model's and more than delta
  below the runner-up's; otherwise nothing is added and the reason is reported.
"""
from dataclasses import dataclass, field

import numpy as np

from finken.discrepancy.candidates import complexity, same_explanation

#: Margin factors (module docstring): multiples of the noise floor of the held-out gap and of the current gap.
MARGIN_FLOOR, MARGIN_GAP = 0.25, 0.02
#: Candidates checked for being complementary to the winner (one refit each).
COMPLEMENT_CHECKS = 3


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
    added: bool = False
    reason: str = ""

    @property
    def margin_over_current(self):
        return self.current_gap - self.winner.heldout_gap if self.winner else float("nan")

    @property
    def margin_over_runner_up(self):
        if self.winner is None or self.runner_up is None:
            return float("nan")
        return self.runner_up.heldout_gap - self.winner.heldout_gap


def select(kind, fits, current_gap, floor_gap, mask_of, gap_on_top):
    """Apply the rule to the fits of one kind. `mask_of(candidate)`: rows where it acts
    (candidates.effective_mask). `gap_on_top(winner, fit)` returns the held-out gap of `fit`'s
    candidate refitted with `winner` already added (for the complementarity check)."""
    ranking = sorted(fits, key=lambda f: (not np.isfinite(f.heldout_gap), f.heldout_gap))
    delta = max(MARGIN_FLOOR * floor_gap, MARGIN_GAP * current_gap)
    sel = Selection(kind, ranking, current_gap, floor_gap, delta)
    valid = [f for f in ranking if np.isfinite(f.heldout_gap)]
    if not valid:
        sel.reason = "no candidate could be fitted"
        return sel
    best = valid[0].heldout_gap
    pool = [f for f in valid if f.heldout_gap <= best + delta]
    sel.winner = min(pool, key=lambda f: (complexity(f.candidate, f.params), f.heldout_gap))
    rivals = [f for f in valid if f is not sel.winner
              and not same_explanation(f.candidate, sel.winner.candidate, mask_of)]
    checks = 0
    for rival in rivals:
        if rival.heldout_gap - sel.winner.heldout_gap >= delta or checks >= COMPLEMENT_CHECKS:
            sel.runner_up = rival
            break
        checks += 1
        on_top = gap_on_top(sel.winner, rival)
        if on_top <= sel.winner.heldout_gap - delta:
            sel.complementary.append((rival, on_top))
            continue
        sel.runner_up = rival
        break
    if not sel.margin_over_current > delta:
        sel.reason = (f"{sel.winner.candidate.label} lowers the held-out gap by {sel.margin_over_current:.4g} m, "
                      f"less than the margin {delta:.4g} m")
    elif sel.runner_up is not None and not sel.margin_over_runner_up > delta:
        sel.reason = (f"{sel.winner.candidate.label} beats the runner-up {sel.runner_up.candidate.label} by "
                      f"{sel.margin_over_runner_up:.4g} m only, less than the margin {delta:.4g} m")
    else:
        sel.added = True
        rival = (f"beats the runner-up {sel.runner_up.candidate.label} by {sel.margin_over_runner_up:.4g} m"
                 if sel.runner_up is not None else "has no rival")
        sel.reason = (f"{sel.winner.candidate.label} lowers the held-out gap by {sel.margin_over_current:.4g} m and "
                      f"{rival} (margin {delta:.4g} m)")
    return sel
