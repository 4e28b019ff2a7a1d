"""The discrepancy workflow: replay, localize, name and fit, add, repeat (shared/spec/discrepancy-report.md).

Round r (r = 1, 2, ...):
  1. replay: the measured log's true ranges and context, stream by stream in time order, through the current
     model (finken.models.simulate), twice with different seeds;
  2. localize (localize.py): per condition the gap, the noise floor and the tests, Holm-corrected together;
     if no condition stands above the noise floor, stop;
  3. for each sensor kind with such a condition: fit every candidate effect on training blocks and score it
     on held-out blocks (fitting.py), apply the selection rule (selection.py); add the winner, with bootstrap
     confidence intervals;
  4. if nothing was added, stop (the disagreement is reported as unexplained), else next round.
Finally the input and output models are compared with the measured readings on all held-out rows.
"""
import time
from dataclasses import dataclass, field

import numpy as np

from finken import models
from finken.discrepancy import progress
from finken.discrepancy.candidates import enumerate_candidates
from finken.discrepancy.conditions import build_views
from finken.discrepancy.dataset import prepare, sample_blocks
from finken.discrepancy.fitting import KindFitter
from finken.discrepancy.gap import METRIC, MIN_ROWS, GapEvaluator, combine
from finken.discrepancy.localize import decide, test_kind
from finken.discrepancy.selection import Selection, select

#: Most effects added to one kind's chain in one run.
MAX_EFFECTS_PER_KIND = 4
#: Rows per kind used to localize, and to report the held-out gaps (whole time blocks drawn at random beyond
#: that; 300 000 rows resolve a gap to about 0.2 % of the residual spread).
LOCALIZE_ROWS = REPORT_ROWS = 300000
#: Probabilities at which residual quantiles are kept for the QQ plots.
QQ_PROBS = np.linspace(0.005, 0.995, 100)


@dataclass
class Round:
    number: int
    tests: list                                       # localize.ConditionTest of the model at the round's start
    selections: dict = field(default_factory=dict)    # kind -> selection.Selection
    skipped: dict = field(default_factory=dict)       # kind -> [(candidate label, reason)]


@dataclass
class AddedEffect:
    fit: object            # fitting.Fit, with confidence intervals
    round: int
    gap_reduction: float = float("nan")   # fraction of gap_before this effect removed (held-out)


@dataclass
class ConditionGap:
    kind: str
    view: str
    label: str
    n: int
    gap_before: float
    gap_after: float
    floor: float
    qq: dict = None        # residual (or reading) quantiles at QQ_PROBS: measured, before, after


@dataclass
class CalibrationResult:
    measured_path: str
    model_in: object
    model_out: object
    seed: int
    gap_before: float
    gap_after: float
    gap_floor: float
    metric: str
    effects: list
    conditions: list
    rounds: list
    final_tests: list
    verdict: str
    rows: dict             # kind -> (rows, held-out rows)
    elapsed_s: float = 0.0


def sim_seed(seed, *keys):
    """A simulator seed derived from the run's seed and a purpose (reproducible, distinct per purpose)."""
    return int(np.random.SeedSequence([int(seed), *keys]).generate_state(1, dtype=np.uint64)[0] >> 1)


def calibrate(log, model, seed=1, show_progress=False):
    """Run the workflow on a RangeLog against a SensorModel; returns a CalibrationResult."""
    start = time.perf_counter()
    model = model.for_log(log.ctx)   # effects may be conditioned on any ctx_ column of the log
    kinds = prepare(log, model, seed)
    views = {k: build_views(kr) for k, kr in kinds.items()}
    kind_no = {k: i for i, k in enumerate(kinds)}
    current, effects, rounds = model, [], []
    active = set(kinds)
    while True:
        r = len(rounds) + 1
        progress.note(f"round {r}: localizing", show_progress)
        rnd = Round(r, _localize(kinds, views, current, seed, r))
        rounds.append(rnd)
        flagged = sorted({t.kind for t in rnd.tests if t.significant} & active)
        if not flagged:
            break
        added = []
        for kind in flagged:
            if sum(e.fit.candidate.kind == kind for e in effects) >= MAX_EFFECTS_PER_KIND:
                active.discard(kind)
                continue
            sel = _fit_kind(kinds[kind], views[kind], current, sim_seed(seed, r, kind_no[kind]), rnd, show_progress)
            rnd.selections[kind] = sel
            if sel.added:
                added.append(AddedEffect(sel.winner, r))
            else:
                active.discard(kind)
        if not added:
            break
        for a in added:
            current = current.with_effect(a.fit.candidate.kind, a.fit.effect())
            progress.note(f"round {r}: added {a.fit.candidate.label} {a.fit.params}", show_progress)
        effects += added
    result = _evaluate(log, kinds, views, model, current, effects, rounds, seed)
    result.elapsed_s = time.perf_counter() - start
    return result


def _localize(kinds, views, model, seed, r):
    tests = []
    for i, (kind, kr) in enumerate(kinds.items()):
        rng = np.random.default_rng(sim_seed(seed, r, i, 7))
        subset = sample_blocks(kr, None, LOCALIZE_ROWS, rng)
        sim = [models.simulate(model, kind, kr.t[subset.idx], kr.true_range[subset.idx], subset.sim_stream,
                               {k: v[subset.idx] for k, v in kr.ctx.items()}, sim_seed(seed, r, i, s))
               for s in (1, 2)]
        tests += test_kind(kr, views[kind], subset, sim[0], sim[1], rng)
    return decide(tests)


def _fit_kind(kr, views, model, seed, rnd, show_progress):
    def make_fitter(m):
        return KindFitter(kr, views, m, seed, np.random.default_rng(seed))

    fitter = make_fitter(model)
    candidates, rnd.skipped[kr.kind] = enumerate_candidates(kr)
    if min(fitter.train_eval.n, fitter.heldout_eval.n) < MIN_ROWS:
        return Selection(kr.kind, [], fitter.current_gap, fitter.floor_gap, float("nan"),
                         reason=f"too few rows to fit and score ({fitter.train_eval.n} in training blocks, "
                                f"{fitter.heldout_eval.n} held out; at least {MIN_ROWS} each)")
    fits = []
    with progress.bar(len(candidates), f"round {rnd.number} {kr.kind}: fitting candidates", show_progress) as b:
        for cand in candidates:
            fits.append(fitter.fit(cand))
            b.update()

    def gap_on_top(winner, rival):
        return make_fitter(model.with_effect(kr.kind, winner.effect())).fit(rival.candidate).heldout_gap

    sel = select(kr.kind, fits, fitter.current_gap, fitter.floor_gap, fitter.mask_of, gap_on_top)
    if sel.added:
        with progress.bar(fitter.bootstrap_count(sel.winner), f"round {rnd.number} {kr.kind}: bootstrap "
                          f"{sel.winner.candidate.label}", show_progress) as b:
            fitter.bootstrap_ci(sel.winner, b)
    return sel


def _evaluate(log, kinds, views, model_in, model_out, effects, rounds, seed):
    """Held-out gaps of the input model, the output model, the models in between and the noise floor."""
    stages = [model_in]
    for e in effects:
        stages.append(stages[-1].with_effect(e.fit.candidate.kind, e.fit.effect()))
    stage_gaps = [[] for _ in stages]
    floor_parts, conditions, rows = [], [], {}
    for i, (kind, kr) in enumerate(kinds.items()):
        rng = np.random.default_rng(sim_seed(seed, 0, i, 9))
        sub = sample_blocks(kr, "heldout", REPORT_ROWS, rng)
        rows[kind] = (kr.n, sub.n_scored)
        evaluator = GapEvaluator(kr, views[kind], sub)

        def readings(m, s):
            raw = models.simulate(m, kind, kr.t[sub.idx], kr.true_range[sub.idx], sub.sim_stream,
                                  {k: v[sub.idx] for k, v in kr.ctx.items()}, sim_seed(seed, 0, i, s))
            return kr.reading(raw)

        sims = [readings(m, 1) for m in stages]
        for j, s in enumerate(sims):
            stage_gaps[j].append((evaluator.gap(s), evaluator.n))
        after2 = readings(model_out, 2)
        floor_eval = GapEvaluator(kr, views[kind], sub, after2[sub.scored])
        floor_bins = floor_eval.bin_gaps(sims[-1])
        floor_parts.append((floor_eval.overall(floor_bins), floor_eval.n))
        before_bins, after_bins = evaluator.bin_gaps(sims[0]), evaluator.bin_gaps(sims[-1])
        tr = kr.true_range[sub.idx[sub.scored]]
        for k, (vi, b, pos, _) in enumerate(evaluator.bins):
            view = views[kind][vi]
            qq = {"measured": np.quantile(evaluator.reference[view.quantity][pos], QQ_PROBS)}
            for name, s in (("before", sims[0]), ("after", sims[-1])):
                vals = s[sub.scored][pos]
                qq[name] = np.quantile(vals - tr[pos] if view.quantity == "residual" else vals, QQ_PROBS)
            conditions.append(ConditionGap(kind, view.name, view.labels[b], int(pos.size), float(before_bins[k]),
                                           float(after_bins[k]), float(floor_bins[k]), qq))
    gaps = [combine(g) for g in stage_gaps]
    for j, e in enumerate(effects):
        e.gap_reduction = (gaps[j] - gaps[j + 1]) / gaps[0] if gaps[0] > 0 else 0.0
    return CalibrationResult(log.path, model_in, model_out, seed, gaps[0], gaps[-1], combine(floor_parts), METRIC,
                             effects, conditions, rounds, rounds[-1].tests, _verdict(effects, rounds), rows)


def _verdict(effects, rounds):
    last = rounds[-1]
    standing = [t for t in last.tests if t.significant]
    if not effects and not standing:
        return ("Nothing is missing: no condition's gap stands above the noise floor of the input model, "
                "so no effect was added.")
    added = "; ".join(e.fit.candidate.label for e in effects)
    head = f"Added {len(effects)} effect(s): {added}." if effects else "No effect was added."
    if not standing:
        return head + " No condition's gap stands above the noise floor any more."
    reasons = " ".join(f"{k}: {s.reason}." for k, s in last.selections.items() if not s.added)
    kinds = sorted({t.kind for t in standing})
    return (head + f" {len(standing)} condition(s) of {', '.join(kinds)} still stand above the noise floor; "
            f"no candidate met the selection rule. {reasons}").strip()
