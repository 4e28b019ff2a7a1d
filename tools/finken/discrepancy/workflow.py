"""The discrepancy workflow: replay, localize, name and fit, add, repeat (shared/spec/discrepancy-report.md).

First the glitches (glitches.py: negative, zero, infinite or absurd readings) are counted; they stay out of
everything below, which is about the continuous error, and the model's glitch effect is set at the end when the
log's glitch rate is not the model's. Then (ranges.py) sensors that never reported, or kinds with too few rows,
are left out and said; rows beyond the model's range are counted and each kind's range is fitted from the
readings (unless given). Then round r (r = 1, 2, ...):
  1. replay: the measured log's true ranges and context, stream by stream in time order, through the current
     model (finken.models.simulate), twice with different seeds;
  2. localize (localize.py): per condition the gap, the noise floor and the tests, Holm-corrected together;
     if no condition stands above the noise floor, stop;
  3. for each sensor kind with such a condition: fit every candidate effect on training blocks and score it
     on held-out blocks (fitting.py), apply the selection rule and its gain test (selection.py); add the
     winner, with bootstrap confidence intervals and its stability over resamples (stability.py);
  4. if nothing was added, stop (the disagreement is reported as unexplained), else next round.
Finally the input model, the model with the fitted ranges and the output model are compared with the measured
readings on all held-out rows: the gap of the continuous error, and the glitch rates apart.
"""
import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from finken.models import condition_columns
from finken.discrepancy import glitches, progress
from finken.discrepancy.candidates import GENERALIZES, Candidate, enumerate_candidates
from finken.discrepancy.condition_search import both
from finken.discrepancy.conditions import build_views
from finken.discrepancy.dataset import prepare, sample_blocks, simulate_subset
from finken.discrepancy.fitting import KindFitter, add_effects
from finken.discrepancy.gap import METRIC, MIN_ROWS, GapEvaluator, combine
from finken.discrepancy.localize import decide, test_kind
from finken.discrepancy.pairs import two_at_once
from finken.discrepancy.ranges import fit_ranges, left_out, sensor_ranges, unit_notes
from finken.discrepancy.selection import GAIN_ALPHA, Selection, select
from finken.discrepancy.stability import REPLICATES, Stability, stability

#: Most effects added to one kind's chain in one run.
MAX_EFFECTS_PER_KIND = 4
#: Rows per kind used to localize, and to report the held-out gaps (whole time blocks drawn at random beyond
#: that; 300 000 rows resolve a gap to about 0.2 % of the residual spread, 200 000 to 0.25 %: the report's
#: figures keep a two-million-row log under 500 MB).
LOCALIZE_ROWS, REPORT_ROWS = 300000, 200000
#: Best single-column candidates whose conditions are tried together with another column's.
TWO_COLUMN_SEEDS = 3
#: Probabilities at which residual quantiles are kept for the QQ plots.
QQ_PROBS = np.linspace(0.005, 0.995, 100)
#: Histograms of the error per condition: bins between these quantiles of the kind's measured values.
HIST_BINS, HIST_SPAN = 40, (0.005, 0.995)


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
    stability: object = None              # stability.Stability
    undecided: object = None              # a fitting.Fit the data cannot tell from it (a tie: selection.py)
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
    glitch_rates: dict = None   # glitches per row: measured, before (input model), after (output model)
    hist: dict = None      # error histogram: "edges" [m], and densities [1/m] of measured, before, after


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
    sensors: list = field(default_factory=list)   # ranges.SensorRange per sensor of the log
    ranges: dict = field(default_factory=dict)    # kind -> ranges.KindRange
    range_gap_reduction: float = 0.0              # fraction of gap_before the fitted ranges removed
    notes: list = field(default_factory=list)     # sensors left out and why
    glitch_counts: dict = field(default_factory=dict)   # "kinds", "sensors", "streams": [glitches.Count]
    glitch_tests: list = field(default_factory=list)    # glitches.RateTest per kind
    elapsed_s: float = 0.0


def sim_seed(seed, *keys):
    """A simulator seed derived from the run's seed and a purpose (reproducible, distinct per purpose)."""
    return int(np.random.SeedSequence([int(seed), *keys]).generate_state(1, dtype=np.uint64)[0] >> 1)


def calibrate(log, model, seed=1, show_progress=False, max_range=None):
    """Run the workflow on a RangeLog against a SensorModel; returns a CalibrationResult. max_range: {kind:
    maximum range [m]} to keep instead of fitting it."""
    start = time.perf_counter()
    model = model.for_log(log.ctx)   # effects may be conditioned on any ctx_ column of the log
    limits = glitches.limits(log, model)
    code = glitches.classify_log(log, limits)
    sensors = sensor_ranges(log, model, code > 0)
    leave, notes = left_out(sensors)
    notes = unit_notes(log, model) + notes
    for n in notes:
        progress.note(n, show_progress)
    keep = ~np.isin(log.sensor, sorted(leave))
    used = log.select(keep) if leave else log
    if len(used) == 0:
        return _undecided(log, model, seed, sensors, notes, start)
    counts = glitches.counts(used, code[keep])
    ranged, ranges = fit_ranges(used, glitches.continuous(model), max_range, code[keep] > 0)
    kinds = prepare(used, ranged, seed, limits)
    path = log.path
    del log, used     # the rows live on split by kind: a caller that handed the log over frees its memory
    views = {k: build_views(kr) for k, kr in kinds.items()}
    kind_no = {k: i for i, k in enumerate(kinds)}
    current, effects, rounds, start_gap = ranged, [], [], {}
    active = set(kinds)
    while True:
        r = len(rounds) + 1
        with progress.bar(len(kinds), f"round {r}: localizing", show_progress, unit="kind") as bar:
            rnd = Round(r, _localize(kinds, views, current, seed, r, bar))
        rounds.append(rnd)
        flagged = sorted({t.kind for t in rnd.tests if t.significant} & active)
        if not flagged:
            break
        added = []
        for kind in flagged:
            if sum(e.fit.candidate.kind == kind for e in effects) >= MAX_EFFECTS_PER_KIND:
                active.discard(kind)
                continue
            sel = _fit_kind(kinds[kind], views[kind], current, sim_seed(seed, r, kind_no[kind]), rnd, start_gap,
                            show_progress)
            rnd.selections[kind] = sel
            if sel.added:
                added.append(AddedEffect(sel.winner, r, sel.stability, sel.undecided))
                if sel.partner is not None:
                    added.append(AddedEffect(sel.partner, r, undecided=sel.partner_undecided))
            else:
                active.discard(kind)
        if not added:
            break
        for a in added:
            current = add_effects(current, a.fit.candidate.kind, a.fit.effects())
            progress.note(f"round {r}: added {a.fit.candidate.label} {a.fit.params}"
                          + (f" ({a.stability.text()})" if a.stability else ""), show_progress)
        effects += added
    tests = [glitches.test_kind(kr, model, sim_seed(seed, 0, kind_no[kind], 11)) for kind, kr in kinds.items()]
    model_out = current
    for test in tests:
        kept = test.effects_after(model)
        if kept:
            model_out = glitches.with_glitches(model_out, test.kind, kept)
    for line in glitches.describe(counts["kinds"], tests):
        progress.note(line, show_progress)
    result = _evaluate(path, kinds, views, model, ranged, model_out, effects, rounds, seed)
    result.sensors, result.ranges, result.notes = sensors, ranges, notes
    result.glitch_counts, result.glitch_tests = counts, tests
    result.verdict = _verdict(effects, rounds, ranges, notes, tests)
    result.elapsed_s = time.perf_counter() - start
    return result


def _undecided(log, model, seed, sensors, notes, start):
    """The result when no sensor is left to calibrate: nothing measured, nothing decided."""
    verdict = "Nothing could be decided: " + "; ".join(notes) + "."
    return CalibrationResult(log.path, model, model, seed, 0.0, 0.0, 0.0, METRIC, [], [], [], [], verdict, {},
                             sensors, {}, 0.0, notes, elapsed_s=time.perf_counter() - start)


def _localize(kinds, views, model, seed, r, bar):
    tests = []
    for i, (kind, kr) in enumerate(kinds.items()):
        rng = np.random.default_rng(sim_seed(seed, r, i, 7))
        subset = sample_blocks(kr, None, LOCALIZE_ROWS, rng)
        sim = [simulate_subset(model, kr, subset, sim_seed(seed, r, i, s)) for s in (1, 2)]
        tests += test_kind(kr, views[kind], subset, sim[0], sim[1], rng)
        bar.update()
    return decide(tests)


def _fit_kind(kr, views, model, seed, rnd, start_gap, show_progress):
    """Fit, select and (when added) bound and test the stability of a kind's winner; `start_gap` {kind: the
    kind's held-out gap in its first round} is filled on first use."""
    def make_fitter(m):
        return KindFitter(kr, views, m, seed, np.random.default_rng(seed))

    fitter = make_fitter(model)
    start_gap.setdefault(kr.kind, fitter.current_gap)
    candidates, rnd.skipped[kr.kind] = enumerate_candidates(kr, fitter.side_conditions())
    if min(fitter.train_eval.n, fitter.heldout_eval.n) < MIN_ROWS:
        return Selection(kr.kind, [], fitter.current_gap, fitter.floor_gap, float("nan"),
                         reason=f"too few rows to fit and score ({fitter.train_eval.n} in training blocks, "
                                f"{fitter.heldout_eval.n} held out; at least {MIN_ROWS} each)")
    fits = []
    with progress.bar(len(candidates), f"round {rnd.number} {kr.kind}: fitting candidates", show_progress) as b:
        for cand in candidates:
            fits.append(fitter.fit(cand))
            b.update()

    on_top = {}     # a fitter per winner (candidate and parameters) that rivals are refitted on top of

    def fitter_on_top(fit):
        key = (fit.candidate, tuple(sorted(fit.params.items())))
        if key not in on_top:
            on_top[key] = make_fitter(add_effects(model, kr.kind, fit.effects()))
        return on_top[key]

    def gap_on_top(winner, rival):
        """The held-out gap of the two explanations together: the rival refitted on top of the winner, and both
        fitted together from there (each fitted alone took on part of the other's), the winner under its condition
        and without it (alone it may have needed the condition only to keep off the rows of the rival's part);
        the best of these."""
        pair = fitter_on_top(winner).fit(rival.candidate)
        if not np.isfinite(pair.heldout_gap):
            return pair.heldout_gap
        gaps = [pair.heldout_gap]
        for first in {winner.candidate, dataclasses.replace(winner.candidate, condition=None)}:
            alone = winner if first == winner.candidate else fitter.fit(first)
            together = fitter.fit_jointly([alone, pair]) if np.isfinite(alone.heldout_gap) else None
            if together is not None:
                gaps.append(together[0].heldout_gap)
        return min(gaps)

    one_column = fits
    two_columns = _two_column_fits(fitter, one_column)
    fits = one_column + two_columns

    def gain_test(winner, against=None):
        return fitter.gain_test(winner, start_gap[kr.kind], against=against)

    sel = select(kr.kind, fits, fitter.current_gap, fitter.floor_gap, fitter.mask_of, gap_on_top, gain_test,
                 fitter.mirrored)
    if sel.winner is not None and not _second_column_pays(fitter, sel.winner, one_column, len(two_columns),
                                                          start_gap[kr.kind]):
        sel = select(kr.kind, one_column, fitter.current_gap, fitter.floor_gap, fitter.mask_of, gap_on_top,
                     gain_test, fitter.mirrored)
    two_at_once(sel, fitter, gain_test)
    if sel.added and sel.partner is None:   # a pair is fitted and tested together, not one by one
        with progress.bar(REPLICATES, f"round {rnd.number} {kr.kind}: stability of {sel.winner.candidate.label}",
                          show_progress) as b:
            sel.stability = stability(sel, kr, views, model, np.random.default_rng(seed + 7), fitter.mask_of, b)
        _follow_the_resamples(sel, fits, fitter, start_gap[kr.kind])
        label = sel.winner.candidate.label
        with progress.bar(fitter.bootstrap_count(sel.winner), f"round {rnd.number} {kr.kind}: bootstrap {label}",
                          show_progress) as b:
            fitter.bootstrap_ci(sel.winner, b)
        if sel.winner.candidate.name == "gmm":
            fitter.mixture_summary(sel.winner)
    return sel


def _follow_the_resamples(sel, fits, fitter, start_gap):
    """When most resamples chose one rival over the winner of this split, name that rival instead (the choice
    of most resamples depends less on one split of the data), if it passes the gain test too."""
    stab = sel.stability
    if not stab.rivals:
        return
    label, count = max(stab.rivals.items(), key=lambda kv: kv[1])
    chosen = {f.candidate.label: f for f in fits}
    if count <= stab.share * stab.replicates or label not in chosen:
        return
    rival = chosen[label]
    test = fitter.gain_test(rival, start_gap)
    if not test.passed:
        return
    others = {k: v for k, v in stab.rivals.items() if k != label}
    others[stab.label] = round(stab.share * stab.replicates)
    sel.reason += (f"; most resamples ({count} of {stab.replicates}) chose {label} instead of "
                   f"{sel.winner.candidate.label}, which is named")
    sel.winner, sel.gain_test = rival, test
    sel.stability = Stability(label, count / stab.replicates, stab.replicates, others)


def _two_column_fits(fitter, fits):
    """Fits of the TWO_COLUMN_SEEDS best library candidates under one column's condition, and of the effects
    each generalizes, under that condition and another column's together (the rule's simplicity preference
    keeps one column unless two do better by the margin)."""
    ranked = sorted((f for f in fits if np.isfinite(f.heldout_gap) and f.candidate.name != "gmm"
                     and f.candidate.condition and " and " not in f.candidate.condition),
                    key=lambda f: f.heldout_gap)[:TWO_COLUMN_SEEDS]
    others = {f.candidate.condition for f in fits if f.candidate.condition and " and " not in f.candidate.condition}
    tried, out = set(), []
    for seed_fit in ranked:
        first = seed_fit.candidate.condition
        column = condition_columns(first)[0]
        for other in sorted(c for c in others if condition_columns(c)[0] != column):
            for effect in [seed_fit.candidate.name, *sorted(GENERALIZES.get(seed_fit.candidate.name, ()))]:
                cand = Candidate(seed_fit.candidate.kind, effect, both(first, other))
                if cand not in tried and fitter.mask_of(cand).any():
                    tried.add(cand)
                    out.append(fitter.fit(cand))
    return out


def _second_column_pays(fitter, winner, one_column, tried, start_gap):
    """Whether a winner under two columns passes the gain test against the best candidate under its first
    column alone (True for a winner under one column or none): a second column must earn its place as an
    effect does, not by a chance win of a noisy objective. It was chosen among `tried` two-column fits, so its
    test is at level GAIN_ALPHA / tried (Bonferroni)."""
    condition = winner.candidate.condition
    if not condition or " and " not in condition:
        return True
    first = condition.split(" and ")[0]
    parents = [f for f in one_column if f.candidate.condition == first and np.isfinite(f.heldout_gap)]
    if not parents:
        return True
    parent = min(parents, key=lambda f: f.heldout_gap)
    return fitter.gain_test(winner, start_gap, against=parent, alpha=GAIN_ALPHA / max(tried, 1)).passed


def _evaluate(path, kinds, views, model_in, ranged, model_out, effects, rounds, seed):
    """Held-out gaps of the continuous error of the input model, the model with fitted ranges, the output model,
    the models in between and the noise floor; the glitch rates of the log and of the input and output models."""
    stages = [glitches.continuous(model_in), ranged]
    for e in effects:
        stages.append(add_effects(stages[-1], e.fit.candidate.kind, e.fit.effects()))
    stage_gaps = [[] for _ in stages]
    floor_parts, conditions, rows = [], [], {}
    for i, (kind, kr) in enumerate(kinds.items()):
        rng = np.random.default_rng(sim_seed(seed, 0, i, 9))
        sub = sample_blocks(kr, "heldout", REPORT_ROWS, rng)
        rows[kind] = (kr.n, sub.n_scored)
        evaluator = GapEvaluator(kr, views[kind], sub)

        def readings(m, s):
            return kr.reading(simulate_subset(m, kr, sub, sim_seed(seed, 0, i, s)))

        sims = [readings(m, 1) for m in stages]
        for j, s in enumerate(sims):
            stage_gaps[j].append((evaluator.gap(s), evaluator.n))
        after2 = readings(stages[-1], 2)
        counted = sub.idx[sub.counted]
        glitch_codes = {"measured": kr.glitch[counted]}
        for name, m in (("before", model_in), ("after", model_out)):
            glitch_codes[name] = glitches.classify(simulate_subset(m, kr, sub, sim_seed(seed, 0, i, 3))[sub.counted],
                                                   kr.glitch_limit)
        floor_eval = evaluator.with_reference(after2[sub.scored])
        floor_bins = floor_eval.bin_gaps(sims[-1])
        floor_parts.append((floor_eval.overall(floor_bins), floor_eval.n))
        before_bins, after_bins = evaluator.bin_gaps(sims[0]), evaluator.bin_gaps(sims[-1])
        tr = kr.true_range[sub.idx[sub.scored]]
        edges = {q: np.linspace(*np.quantile(evaluator.reference[q], HIST_SPAN), HIST_BINS + 1)
                 for q in ("residual", "reading")} if evaluator.n else {}
        for k, (vi, b, pos, _) in enumerate(evaluator.bins):
            view = views[kind][vi]
            values = {"measured": evaluator.reference[view.quantity][pos]}
            for name, s in (("before", sims[0]), ("after", sims[-1])):
                vals = s[sub.scored][pos]
                values[name] = vals - tr[pos] if view.quantity == "residual" else vals
            qq = {name: np.quantile(v, QQ_PROBS) for name, v in values.items()}
            hist = {"edges": edges[view.quantity], **{name: _density(v, edges[view.quantity])
                                                       for name, v in values.items()}}
            in_bin = view.code[counted] == b
            rates = {name: float(np.mean(c[in_bin] > 0)) if in_bin.any() else 0.0
                     for name, c in glitch_codes.items()}
            conditions.append(ConditionGap(kind, view.name, view.labels[b], int(pos.size), float(before_bins[k]),
                                           float(after_bins[k]), float(floor_bins[k]), qq, rates, hist))
    gaps = [combine(g) for g in stage_gaps]

    def reduction(j):      # of stage j + 1 over stage j
        return (gaps[j] - gaps[j + 1]) / gaps[0] if gaps[0] > 0 else 0.0

    for j, e in enumerate(effects, start=1):
        e.gap_reduction = reduction(j)
    result = CalibrationResult(path, model_in, model_out, seed, gaps[0], gaps[-1], combine(floor_parts),
                               METRIC, effects, conditions, rounds, rounds[-1].tests, "", rows)
    result.range_gap_reduction = reduction(0)
    return result


def _density(values, edges):
    """Histogram of `values` over `edges` as a density [1/unit] of all of them (values beyond the edges count in
    the total, not in a bin); zeros when the edges have no width."""
    width = np.diff(edges)
    if not len(values) or not (width > 0).all():
        return np.zeros(len(edges) - 1)
    return np.histogram(values, edges)[0] / (len(values) * width)


def _verdict(effects, rounds, ranges, notes, glitch_tests=()):
    """One paragraph: the ranges fitted, the glitch effects set, the effects added, what still stands out, the
    sensors left out."""
    fitted = [f"{r.kind} range [{r.min_out:.4g}, {r.max_out:.4g}] m instead of [{r.min_in:.4g}, {r.max_in:.4g}] m "
              f"({r.rows_affected} rows outside the model's range)" for r in ranges.values() if r.changed]
    head = ("Fitted the " + "; the ".join(fitted) + ". ") if fitted else ""
    set_glitches = [f"{g.kind} glitches: {g.measured} of {g.rows} rows ({g.measured / g.rows:.3%}) against "
                    f"{g.model_rate:.3%} in the input model, glitch effect "
                    + (f"p = {g.effect.params['p']:.4g}" if g.effect is not None else "removed")
                    for g in glitch_tests if g.changed]
    head += ("Set the " + "; the ".join(set_glitches) + ". ") if set_glitches else ""
    tail = (" Left out: " + "; ".join(notes) + ".") if notes else ""
    return head + _effects_verdict(effects, rounds) + tail


def _effects_verdict(effects, rounds):
    last = rounds[-1]
    standing = [t for t in last.tests if t.significant]
    if not effects and not standing:
        return ("Nothing is missing: no condition's gap stands above the noise floor of the model, "
                "so no effect was added.")
    added = "; ".join((e.stability.text() if e.stability else e.fit.candidate.label)
                      + (f" ({e.fit.values_text()})" if e.fit.values_text() else "")
                      + (f" (undecided: the data cannot tell it from {e.undecided.candidate.label})"
                         if e.undecided is not None else "") for e in effects)
    head = f"Added {len(effects)} effect(s): {added}." if effects else "No effect was added."
    if not standing:
        return head + " No condition's gap stands above the noise floor any more."
    reasons = " ".join(f"{k}: {s.reason}." for k, s in last.selections.items() if not s.added)
    kinds = sorted({t.kind for t in standing})
    return (head + f" {len(standing)} condition(s) of {', '.join(kinds)} still stand above the noise floor; "
            f"no candidate met the selection rule. {reasons}").strip()
