"""How stable a named effect is: would another split of the data, other training blocks and other seeds
name the same one?

The winner of a round and its strongest contenders (the best candidate of each other explanation,
candidates.same_explanation, up to CONTENDERS in all; a mixture set aside stays set aside) are fitted again
on REPLICATES replicates. A replicate draws a new held-out set of blocks (as another SEED would), resamples
the remaining training blocks with replacement (a block bootstrap), and simulates with new seeds; each
contender is refitted from its estimate (fitting.KindFitter.refit) and scored on the replicate's held-out
blocks, and the selection rule's pool and simplicity preference (selection.py) picks one. The winner's share
of the replicates is its stability; below STABLE_SHARE the data cannot tell it from the contenders that won
the other replicates, and the report names them.
"""
import dataclasses
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from finken.discrepancy.candidates import same_explanation
from finken.discrepancy.dataset import HELDOUT_FRACTION
from finken.discrepancy.fitting import KindFitter, add_effects
from finken.discrepancy.selection import choose

#: Replicates; contenders refitted in each (the winner included).
REPLICATES, CONTENDERS = 10, 4
#: Share of replicates below which a name is reported as not told apart from its rivals.
STABLE_SHARE = 0.8


@dataclass
class Stability:
    label: str                   # the winner's candidate label
    share: float                 # share of replicates that chose it
    replicates: int
    rivals: dict = field(default_factory=dict)   # label -> replicates that chose it instead

    @property
    def stable(self):
        return self.share >= STABLE_SHARE

    def text(self):
        head = f"{self.label}: chosen in {self.share:.0%} of {self.replicates} resamples"
        if self.stable:
            return head
        others = ", ".join(f"{k} ({v})" for k, v in sorted(self.rivals.items(), key=lambda kv: -kv[1]))
        return f"{head}; the data cannot tell it from {others}"


def contenders(sel, mask_of):
    """The winner and the best fit of each other explanation in the pool it came from (CONTENDERS in all)."""
    out = [sel.winner]
    for f in sel.ranking:
        if len(out) == CONTENDERS:
            break
        if not np.isfinite(f.heldout_gap) or (sel.mixture_set_aside and f.candidate.name == "gmm"):
            continue
        if not any(same_explanation(f.candidate, c.candidate, mask_of) for c in out):
            out.append(f)
    return out


def _replicate_rows(kr, rng):
    """KindRows with a new held-out set of blocks (the row and block caches shared)."""
    ids = np.unique(kr.block)
    n_out = int(np.clip(round(HELDOUT_FRACTION * len(ids)), 1, max(len(ids) - 1, 1)))
    held = rng.permutation(ids)[:n_out]
    replica = dataclasses.replace(kr, heldout=np.isin(kr.block, held))
    replica._by_block = kr._by_block
    return replica


def stability(sel, kr, views, model, rng, mask_of, progress=None):
    """Stability of sel.winner, the winner of `kr`'s candidates against the current `model`."""
    rivals = contenders(sel, mask_of)
    chosen = Counter()
    for _ in range(REPLICATES):
        rows, seed = _replicate_rows(kr, rng), int(rng.integers(2**31))
        fitter = KindFitter(rows, views, model, seed, rng, bootstrap=True)

        def gap_on_top(winner, fit):
            on_top = add_effects(model, kr.kind, winner.effects())
            return KindFitter(rows, views, on_top, seed, rng, bootstrap=True).refit(fit).heldout_gap

        fits = [fitter.refit(f) for f in rivals]
        pick = choose(fits, fitter.current_gap, fitter.floor_gap, gap_on_top)
        chosen[pick.candidate.label if pick is not None else "nothing"] += 1
        if progress:
            progress.update()
    label = sel.winner.candidate.label
    return Stability(label, chosen[label] / REPLICATES, REPLICATES,
                     {k: v for k, v in chosen.items() if k != label})
