"""Score sensor models on a measured range log without fitting anything (`make evaluate`, tools/evaluate.py).

Each model replays the log's true ranges and context (finken.models.simulate) SEEDS times. Its gap is the
workflow's metric (gap.METRIC) between the measured and the simulated readings, the mean over the simulations,
on all rows of the log (whole time blocks up to workflow.REPORT_ROWS rows per kind for bigger logs, drawn as
the workflow draws its held-out rows). Every model sees the same rows and the same simulator seeds, so the
comparison is paired (common random numbers): the same model given twice scores identically. A model's noise
floor is the gap between two of its own simulations on those rows, the mean over every pair of the SEEDS.
The gap is that of the continuous error, as in the workflow: rows whose measured reading is a glitch are not
scored (glitches.py; one rule for every model: the first model's range decides what is absurd) and each model is
simulated without its glitch effects; its glitch rate on the same rows is reported apart, beside the log's.
"""
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np

from finken.discrepancy import glitches, progress
from finken.discrepancy.conditions import build_views
from finken.discrepancy.dataset import KINDS, IncompatibleInputError, prepare, sample_blocks, simulate_subset
from finken.discrepancy.gap import METRIC, GapEvaluator, combine
from finken.discrepancy.ranges import sensor_ranges
from finken.discrepancy.workflow import REPORT_ROWS, sim_seed

#: Simulations per model (each model gets the same simulator seeds).
SEEDS = 3
#: First key of this tool's simulator seeds (workflow.sim_seed), beyond the workflow's round numbers.
SEED_PURPOSE = 1000


@dataclass
class ConditionScore:
    kind: str          # sonar | ranging
    view: str          # conditioning variable (conditions.View.name)
    label: str         # the condition (bin) described
    n: int             # rows scored in it
    gap: float         # [m], mean over the simulations
    floor: float       # [m]


@dataclass
class ModelScore:
    name: str          # the model as given (its path)
    model: object      # finken.models.SensorModel
    gap: float = float("nan")
    floor: float = float("nan")
    conditions: list = field(default_factory=list)     # ConditionScore, same conditions for every model
    beyond_range: list = field(default_factory=list)   # ranges.SensorRange per sensor of the log
    glitch_rate: dict = field(default_factory=dict)    # kind -> glitches per row of its simulations

    @property
    def ratio(self):
        return self.gap / self.floor if self.floor > 0 else float("inf")


@dataclass
class Evaluation:
    measured_path: str
    seed: int
    metric: str
    rows: dict         # kind -> (rows of the log, rows scored)
    scores: list       # ModelScore, in the order given
    glitch_rate: dict = field(default_factory=dict)    # kind -> glitches per row of the log on the same rows

    def best(self):
        """The ModelScore(s) of the lowest gap (several when tied)."""
        low = min(s.gap for s in self.scores)
        return [s for s in self.scores if s.gap == low]


def evaluate(log, named_models, seed=1, show_progress=False):
    """Score each (name, SensorModel) of `named_models` on the RangeLog `log`; returns an Evaluation. Raises
    IncompatibleInputError (naming the model) before any simulation when a model cannot replay the log."""
    scores, prepared = [], []
    limits = glitches.limits(log, named_models[0][1])
    glitch = glitches.classify_log(log, limits) > 0
    for name, model in named_models:
        try:
            prepared.append(prepare(log, model, seed, limits))
        except IncompatibleInputError as err:
            raise IncompatibleInputError(f"{err} (model {name})") from None
        scores.append(ModelScore(name, model, beyond_range=sensor_ranges(log, model, glitch)))
    parts = [([], []) for _ in scores]     # per model: (gap, rows) and (floor, rows) per kind
    rows, measured_rate = {}, {}
    with progress.bar(len(scores) * len(prepared[0]) * SEEDS, "simulating", show_progress, unit="sim") as bar:
        for kind, first in prepared[0].items():   # rows, blocks and views do not depend on the model
            i = KINDS.index(kind)
            sub = sample_blocks(first, None, REPORT_ROWS, np.random.default_rng(sim_seed(seed, SEED_PURPOSE, i, 0)))
            views = build_views(first)
            seeds = [sim_seed(seed, SEED_PURPOSE, i, s) for s in range(1, SEEDS + 1)]
            rows[kind] = (first.n, sub.n_scored)
            measured_rate[kind] = float(np.mean(first.glitch[sub.idx[sub.counted]] > 0))
            for score, kinds, (gaps, floors) in zip(scores, prepared, parts):
                gap, floor, n, conds = _score_kind(kinds[kind], views, sub, score.model, seeds, bar)
                gaps.append((gap, n))
                floors.append((floor, n))
                score.conditions += conds
                full = simulate_subset(score.model, kinds[kind], sub, seeds[0])[sub.counted]
                score.glitch_rate[kind] = float(np.mean(glitches.classify(full, first.glitch_limit) > 0))
    for score, (gaps, floors) in zip(scores, parts):
        score.gap, score.floor = combine(gaps), combine(floors)
    return Evaluation(log.path, seed, METRIC, rows, scores, measured_rate)


def _score_kind(kr, views, sub, model, seeds, bar):
    """(gap, floor, rows scored, [ConditionScore]) of one model on one kind's subset."""
    evaluator = GapEvaluator(kr, views, sub)
    sims, model = [], glitches.continuous(model)
    for s in seeds:
        sims.append(kr.reading(simulate_subset(model, kr, sub, s)))
        bar.update()
    gaps = np.mean([evaluator.bin_gaps(s) for s in sims], axis=0)
    floors = np.mean([evaluator.with_reference(a[sub.scored]).bin_gaps(b) for a, b in combinations(sims, 2)],
                     axis=0)
    conds = [ConditionScore(kr.kind, views[vi].name, views[vi].labels[b], int(pos.size), float(g), float(f))
             for (vi, b, pos, _), g, f in zip(evaluator.bins, gaps, floors)]
    return evaluator.overall(gaps), evaluator.overall(floors), evaluator.n, conds

