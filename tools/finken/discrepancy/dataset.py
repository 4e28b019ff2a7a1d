"""The rows of a range log grouped by sensor kind, with what the workflow derives from them.

Per kind (`sonar`: every `sonar_*` sensor, `ranging`): the rows in file order, their stream, the true-range
rate of change (a time-series property), the time block each row falls in and the split of the blocks into
training and held-out sets. Blocks are contiguous time intervals shared by all kinds, so a held-out block is a
stretch of flight the fit never saw (splitting rows at random would leak neighbouring, correlated readings).
"""
from dataclasses import dataclass

import numpy as np

from finken import models
from finken.rangelog import stream_ids

KINDS = ("sonar", "ranging")

#: Blocks per log aimed at (enough for a block bootstrap of the training half) [count].
TARGET_BLOCKS = 40
#: Shortest and longest time block [s].
BLOCK_S_RANGE = (2.0, 10.0)
#: Fraction of the blocks held out for scoring.
HELDOUT_FRACTION = 0.4
#: History simulated before each block of a subset, so that latency sees earlier true ranges [s]
#: (the C stream state remembers 128 readings: 6.4 s at 20 Hz).
WARMUP_S = 2.0


class IncompatibleInputError(ValueError):
    """The log and the model do not fit together (e.g. ranging rows but no ranging chain)."""


def sensor_kind(sensor_name):
    """'ranging' for the ranging sensor, 'sonar' for every sonar_* sensor."""
    return "ranging" if sensor_name == "ranging" else "sonar"


@dataclass
class KindRows:
    """The rows of one sensor kind (arrays in file order) and the limits of the model's chain for it."""
    kind: str
    index: np.ndarray        # row numbers in the log (0-based)
    t: np.ndarray            # [s]
    true_range: np.ndarray   # [m]
    measured: np.ndarray     # [m], NaN = no reading
    sensor: np.ndarray       # sensor names
    stream: np.ndarray       # stream id (vehicle, sensor, peer) of the log
    ctx: dict                # ctx_ columns
    range_rate: np.ndarray   # d true_range / dt within the stream [m/s]
    block: np.ndarray        # time block id
    heldout: np.ndarray      # True for rows of held-out blocks
    min_range: float         # [m]
    max_range: float         # [m]

    @property
    def n(self):
        return len(self.index)

    def reading(self, measured):
        """Readings for distances between distributions: a missing reading counts as the maximum range [m]."""
        return np.where(np.isnan(measured), self.max_range, measured)


@dataclass
class Subset:
    """Rows of a kind to simulate together: `idx` into the KindRows arrays, a stream id per row for the
    simulator (one per stream and block, so no history crosses a gap) and which rows count in statistics
    (False for warm-up rows)."""
    idx: np.ndarray
    sim_stream: np.ndarray
    scored: np.ndarray

    @property
    def n_scored(self):
        return int(self.scored.sum())


def range_rate(t, true_range, stream):
    """Central-difference rate of change of the true range within each stream [m/s] (0 where undefined)."""
    n = len(t)
    rate = np.zeros(n)
    if n < 2:
        return rate
    order = np.lexsort((np.arange(n), stream))
    ts, xs, ss = t[order], true_range[order], stream[order]
    prev = np.r_[0, np.arange(n - 1)]
    nxt = np.r_[np.arange(1, n), n - 1]
    prev = np.where(ss[prev] == ss, prev, np.arange(n))
    nxt = np.where(ss[nxt] == ss, nxt, np.arange(n))
    dt = ts[nxt] - ts[prev]
    with np.errstate(invalid="ignore", divide="ignore"):
        r = np.where(dt > 0, (xs[nxt] - xs[prev]) / np.where(dt > 0, dt, 1.0), 0.0)
    rate[order] = r
    return rate


def time_blocks(t):
    """Block id per row and the block length [s]: contiguous intervals of equal length from the first time."""
    if len(t) == 0:
        return np.zeros(0, dtype=np.int64), BLOCK_S_RANGE[0]
    t0, span = float(np.min(t)), float(np.ptp(t))
    block_s = float(np.clip(span / TARGET_BLOCKS, *BLOCK_S_RANGE))
    if 0 < span < 2 * block_s:          # a short log still gets two blocks (one to fit, one to score)
        block_s = span / 2 * (1 + 1e-9)
    return np.floor((t - t0) / block_s).astype(np.int64), block_s


def split_blocks(block, seed):
    """Held-out mask: a seeded random HELDOUT_FRACTION of the blocks (at least one, never all of them)."""
    ids = np.unique(block)
    rng = np.random.default_rng(seed)
    n_out = int(np.clip(round(HELDOUT_FRACTION * len(ids)), 1, max(len(ids) - 1, 1)))
    held = rng.permutation(ids)[:n_out] if len(ids) > 1 else np.zeros(0, dtype=ids.dtype)
    return np.isin(block, held)


def prepare(log, model, seed):
    """{kind: KindRows} for the kinds present in `log`; raises IncompatibleInputError when the model lacks the
    chain of a kind the log has or conditions it on a column the log does not have, or the log has no rows."""
    if len(log) == 0:
        raise IncompatibleInputError(f"{log.path}: the log has no rows")
    streams = stream_ids(log)
    block, _ = time_blocks(log.t)
    heldout = split_blocks(block, seed)
    is_ranging = log.sensor == "ranging"
    out = {}
    for kind in KINDS:
        rows = np.flatnonzero(is_ranging if kind == "ranging" else ~is_ranging)
        if rows.size == 0:
            continue
        if kind not in model.chains:
            raise IncompatibleInputError(f"{log.path}: the log has {rows.size} {kind} rows but the model has no "
                                         f"{kind} chain")
        try:
            models.check_replay(model, kind, log.ctx)
        except models.ModelError as err:
            raise IncompatibleInputError(f"{log.path}: {err}") from None
        chain = model.chains[kind]
        t, tr, st = log.t[rows], log.true_range[rows], streams[rows]
        out[kind] = KindRows(kind, rows, t, tr, log.measured[rows], log.sensor[rows], st,
                             {k: v[rows] for k, v in log.ctx.items()}, range_rate(t, tr, st), block[rows],
                             heldout[rows], float(chain.min_range), float(chain.max_range))
    return out


def whole(kr):
    """A Subset of all rows of a kind, streams unbroken."""
    idx = np.arange(kr.n)
    return Subset(idx, kr.stream.copy(), np.ones(kr.n, bool))


def _which(kr, which):
    if which is None:
        return np.ones(kr.n, dtype=bool)
    return kr.heldout if which == "heldout" else ~kr.heldout


def sample_blocks(kr, which, max_rows, rng, blocks=None):
    """A Subset of whole time blocks of the rows (which=None), or of the 'train' or 'heldout' rows, in random
    order until `max_rows` rows (all of them if fewer), each preceded by WARMUP_S of unscored history.
    `blocks` (ids, may repeat, as a block bootstrap draws them) overrides the random choice. With which=None
    and at most `max_rows` rows, all rows are returned with their streams unbroken."""
    mask = _which(kr, which)
    if which is None and blocks is None and kr.n <= max_rows:
        return whole(kr)
    if blocks is None:
        ids, counts = np.unique(kr.block[mask], return_counts=True)
        order = rng.permutation(len(ids))
        keep = np.cumsum(counts[order]) - counts[order] < max_rows
        blocks = ids[order][keep]
    parts, streams, scored = [], [], []
    n_streams = int(kr.stream.max()) + 1 if kr.n else 1
    segment, previous = -1, None
    for b in np.sort(np.asarray(blocks)):
        rows = np.flatnonzero((kr.block == b) & mask)
        if rows.size == 0:
            continue
        # consecutive blocks form one segment (one simulator stream per sensor stream): fewer generators to
        # seed, no warm-up needed in between; a repeated block (bootstrap) starts a new segment
        contiguous = previous is not None and b == previous + 1
        previous = b
        if contiguous:
            warm = np.zeros(0, dtype=np.int64)
        else:
            segment += 1
            start = kr.t[rows].min()
            warm = np.flatnonzero((kr.t >= start - WARMUP_S) & (kr.t < start))
        both = np.r_[warm, rows]
        parts.append(both)
        streams.append(kr.stream[both] + segment * n_streams)
        scored.append(np.r_[np.zeros(warm.size, bool), np.ones(rows.size, bool)])
    if not parts:
        return Subset(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, bool))
    idx, sim_stream, sc = np.concatenate(parts), np.concatenate(streams), np.concatenate(scored)
    order = np.lexsort((idx, sim_stream))
    return Subset(idx[order], sim_stream[order], sc[order])
