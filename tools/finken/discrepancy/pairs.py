"""Two effects named at once: when no single candidate explains a kind's disagreement, the best pair of library
effects fitted together (fitting.KindFitter.fit_jointly) may be named in one round (workflow.py)."""
import dataclasses

import numpy as np

from finken.discrepancy.candidates import complexity
from finken.discrepancy.fitting import jointly_fittable

#: Pairs are tried when the best single effect leaves more than this many noise floors of gap; the best
#: explanations tried as the first of the two.
PAIR_SEARCH_FLOORS, PAIR_FIRSTS = 2.0, 2


def two_at_once(sel, fitter, gain_test):
    """Name two effects at once when together they explain the disagreement better, by the margin, than the
    round's winner and than each of them alone: two effects fitted one after the other each take on part of the
    other's error (a latency grows over a tail of short readings, an excess path shrinks to sit on an offset), so
    the second is then found wrong or not at all.

    Tried when no single candidate brings the gap down to PAIR_SEARCH_FLOORS noise floors: the PAIR_FIRSTS best
    library explanations (each also without its condition) with every other effect of the library that lowers
    the gap alone, without condition, fitted together (fitting.KindFitter.fit_jointly). The simplest pair within
    the margin of the best one is named when it beats each of its members fitted alone the same way by the margin,
    passes the gain test against each of them and against the current model, and is no mirror of the data's
    shape. Sets sel.winner and sel.partner; a pair within the margin that shares one of its effects and differs in
    the other ties with it: that other is the undecided rival of the one it replaces (sel.undecided of the winner,
    sel.partner_undecided of the partner)."""
    singles = [f for f in sel.ranking if np.isfinite(f.heldout_gap) and jointly_fittable(f)]
    if not singles or singles[0].heldout_gap <= PAIR_SEARCH_FLOORS * sel.floor_gap:
        return
    firsts = []
    for f in singles:
        if len(firsts) < PAIR_FIRSTS and all(f.candidate.name != g.candidate.name for g in firsts) \
                and not fitter.mirrored(f):
            firsts.append(f)
    plain = {dataclasses.replace(f.candidate, condition=None) for f in firsts if f.candidate.condition}
    firsts += [f for f in singles if f.candidate in plain]
    seconds = [f for f in singles if f.candidate.condition is None and f.heldout_gap < sel.current_gap]
    pairs = [pair for first in firsts for second in seconds if second.candidate.name != first.candidate.name
             if (pair := fitter.fit_jointly([first, second])) is not None and np.isfinite(pair[0].heldout_gap)]
    if not pairs:
        return
    margin = sel.margin

    def cost(pair):
        return sum(complexity(f.candidate, f.params) for f in pair)
    lowest = min(p[0].heldout_gap for p in pairs)     # the simplest pair within the margin of the best one
    near = [p for p in pairs if p[0].heldout_gap <= lowest + margin]
    best = min(near, key=lambda p: (cost(p), p[0].heldout_gap))
    gap = best[0].heldout_gap
    # each member must earn its place: the pair passes the gain test against each of them alone, fitted the same
    # way (a joint fit of one), as a second column must against one (workflow._second_column_pays)
    alone = [fitter.fit_jointly([f]) for f in best]
    if any(a is None or not gap < a[0].heldout_gap - margin or not gain_test(best[1], against=a[0]).passed
           for a in alone) or fitter.mirrored(best[1]) or (sel.added and gap >= sel.winner.heldout_gap - margin):
        return
    test = gain_test(best[1])
    if not test.passed:
        return
    sel.winner, sel.partner, sel.runner_up, sel.gain_test, sel.added = *best, None, test, True
    sel.undecided = sel.partner_undecided = None
    mine = {f.candidate for f in best}
    for other in near:     # a pair within the margin that shares one effect and differs in the other: a tie
        theirs = [f for f in other if f.candidate not in mine]
        if other is best or len(theirs) != 1:
            continue
        if best[0].candidate in {f.candidate for f in other}:
            sel.partner_undecided = sel.partner_undecided or theirs[0]
        else:
            sel.undecided = sel.undecided or theirs[0]
    sel.reason = (f"{best[0].candidate.label} and {best[1].candidate.label} fitted together lower the held-out gap "
                  f"by {sel.current_gap - gap:.4g} m, more than either alone or any single effect by the margin "
                  f"{margin:.4g} m")
