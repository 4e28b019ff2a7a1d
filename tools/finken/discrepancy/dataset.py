"""The rows of a range log grouped by sensor kind, with what the workflow derives from them.

Per kind (`sonar`: every `sonar_*` sensor, `ranging`): the rows in file order, their stream, the true-range
rate of change (a time-series property), the time block each row falls in and the split of the blocks into
training and held-out sets. Blocks are contiguous time intervals shared by all kinds, so a held-out block is a
stretch of flight the fit never saw (splitting rows at random would leak neighbouring, correlated readings).
When the log is read with a grouping column (a recording id: SPLIT_BY), each recording is a block instead, so
that held-out data are whole recordings the fit never saw.
"""
from dataclasses import dataclass, field

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
#: (the C stream state remembers 128 readings: 6.4 s at 20 Hz); at most the shortest block.
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
    t: np.ndarray            # [s]
    true_range: np.ndarray   # [m]
    measured: np.ndarray     # [m], NaN = no reading
    sensor: np.ndarray       # sensor names
    stream: np.ndarray       # stream id (vehicle, sensor, peer) of the log
    ctx: dict                # ctx_ columns
    range_rate: np.ndarray   # d true_range / dt within the stream [m/s]
    block: np.ndarray        # time block id (or recording id)
    heldout: np.ndarray      # True for rows of held-out blocks
    min_range: float         # [m]
    max_range: float         # [m]
    vehicle: np.ndarray = None   # the copter carrying the sensor (the log's `vehicle`: ctx_vehicle in the model)
    glitch: np.ndarray = None    # glitch type code of each measured reading (finken.discrepancy.glitches; 0: none)
    glitch_limit: float = float("inf")   # a reading farther than this is absurd [m] (glitches.absurd_limit)
    by_recording: bool = False   # blocks are recordings: no history is simulated across their starts
    _by_block: tuple = field(default=None, init=False, repr=False)   # (row order by block, block ids, starts)

    @property
    def n(self):
        return len(self.t)

    def block_rows(self, b):
        """Row positions of block `b`, in file order (sorted once, then found by binary search)."""
        if self._by_block is None:
            order = np.argsort(self.block, kind="stable").astype(np.int32)
            ids, starts = np.unique(self.block[order], return_index=True)
            self._by_block = (order, ids, np.r_[starts, order.size])
        order, ids, starts = self._by_block
        i = int(np.searchsorted(ids, b))
        return order[starts[i]:starts[i + 1]] if i < ids.size and ids[i] == b else order[:0]

    def reading(self, measured):
        """Readings for distances between distributions: a missing reading counts as the maximum range [m]."""
        return np.where(np.isnan(measured), self.max_range, measured)

    def inside(self, readings):
        """Readings strictly inside the range limits (no missing reading, no value the chain clamped)."""
        return np.isfinite(readings) & (readings > self.min_range) & (readings < self.max_range)

    def ctx_of(self, idx):
        """The context columns of rows `idx` for the simulator: the log's ctx_ columns and ctx_vehicle."""
        ctx = {k: v[idx] for k, v in self.ctx.items()}
        if self.vehicle is not None:
            ctx["ctx_vehicle"] = self.vehicle[idx]
        return ctx


@dataclass
class Subset:
    """Rows of a kind to simulate together: `idx` into the KindRows arrays, a stream id per row for the
    simulator (one per stream and block, so no history crosses a gap), which rows count (False for warm-up rows)
    and which of them score the continuous error (`scored`: those whose measured reading is no glitch)."""
    idx: np.ndarray
    sim_stream: np.ndarray
    counted: np.ndarray
    scored: np.ndarray

    @property
    def n_scored(self):
        return int(self.scored.sum())


def range_rate(t, true_range, stream):
    """Central-difference rate of change of the true range within each stream [m/s] (one-sided at a stream's
    ends, 0 where undefined). Rows of a stream are in time order in the file, so a stable sort by stream puts
    each stream's rows in time order; positions are int32 to keep a two-million-row log small."""
    n = len(t)
    rate = np.zeros(n)
    if n < 2:
        return rate
    order = np.argsort(stream, kind="stable").astype(np.int32)
    ends = np.flatnonzero(stream[order][1:] != stream[order][:-1]).astype(np.int32)   # last row of a stream
    nxt = np.arange(1, n + 1, dtype=np.int32)
    nxt[-1] = n - 1
    nxt[ends] = ends
    prev = np.arange(-1, n - 1, dtype=np.int32)
    prev[0] = 0
    prev[ends + 1] = ends + 1
    dt = t[order[nxt]] - t[order[prev]]
    dx = true_range[order[nxt]] - true_range[order[prev]]
    rate[order] = np.divide(dx, dt, out=np.zeros(n), where=dt > 0)
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


def blocks_of(log):
    """Block id per row: the recording (the log's grouping column) when it has one, else the time block."""
    group = getattr(log, "group", None)
    return (np.asarray(group, dtype=np.int64), True) if group is not None else (time_blocks(log.t)[0], False)


def check_compatible(log, model):
    """{kind: rows of the log} for the kinds present in `log`; raises IncompatibleInputError when the log has no
    rows, or the model lacks the chain of a kind the log has or conditions it on a column the log lacks."""
    if len(log) == 0:
        raise IncompatibleInputError(f"{log.path}: the log has no rows")
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
        out[kind] = rows
    return out


def prepare(log, model, seed, glitch_limits=None):
    """{kind: KindRows} for the kinds present in `log` (check_compatible first). glitch_limits: {kind: the
    reading beyond which a reading is absurd [m]} (default: glitches.absurd_limit of the model and the log)."""
    from finken.discrepancy import glitches
    kinds = check_compatible(log, model)
    streams = stream_ids(log)
    block, by_recording = blocks_of(log)
    heldout = split_blocks(block, seed)
    out = {}
    for kind, rows in kinds.items():
        chain = model.chains[kind]
        t, tr = log.t[rows], log.true_range[rows]
        st, blk = streams[rows].astype(np.int32), block[rows].astype(np.int32)     # 4 bytes a row: big logs
        limit = (glitch_limits or {}).get(kind) or glitches.absurd_limit(chain.max_range, tr)
        measured = log.measured[rows]
        out[kind] = KindRows(kind, t, tr, measured, log.sensor[rows], st,
                             {k: v[rows] for k, v in log.ctx.items()}, range_rate(t, tr, st), blk,
                             heldout[rows], float(chain.min_range), float(chain.max_range),
                             log.vehicle[rows], glitches.classify(measured, limit), limit,
                             by_recording)
    return out


def simulate_subset(model, kr, subset, seed):
    """Simulated measurements (NaN = none) of a Subset's rows of one kind by `model` [m]."""
    idx = subset.idx
    return models.simulate(model, kr.kind, kr.t[idx], kr.true_range[idx], subset.sim_stream, kr.ctx_of(idx), seed)


def whole(kr):
    """A Subset of all rows of a kind, streams unbroken."""
    idx = np.arange(kr.n)
    return _subset(kr, idx, kr.stream.copy(), np.ones(kr.n, bool))


def _subset(kr, idx, sim_stream, counted):
    """The Subset of these rows: the counted ones score unless their measured reading is a glitch."""
    glitch = kr.glitch[idx] > 0 if kr.glitch is not None else np.zeros(len(idx), bool)
    return Subset(idx, sim_stream, counted, counted & ~glitch)


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
        rows = kr.block_rows(b)
        rows = rows[mask[rows]]
        if rows.size == 0:
            continue
        # consecutive blocks form one segment (one simulator stream per sensor stream): fewer generators to
        # seed, no warm-up needed in between; a repeated block (bootstrap) starts a new segment
        contiguous = previous is not None and b == previous + 1 and not kr.by_recording
        previous = b
        if not contiguous:
            segment += 1
        if contiguous or kr.by_recording:     # a recording starts without history
            warm = np.zeros(0, dtype=np.int64)
        else:
            start = kr.t[rows].min()
            before = kr.block_rows(b - 1)           # WARMUP_S is within one block (BLOCK_S_RANGE)
            warm = before[kr.t[before] >= start - WARMUP_S]
        both = np.r_[warm, rows]
        parts.append(both)
        streams.append(kr.stream[both].astype(np.int64) + segment * n_streams)
        scored.append(np.r_[np.zeros(warm.size, bool), np.ones(rows.size, bool)])
    if not parts:
        return _subset(kr, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, bool))
    idx, sim_stream, sc = np.concatenate(parts), np.concatenate(streams), np.concatenate(scored)
    order = np.lexsort((idx, sim_stream))
    return _subset(kr, idx[order], sim_stream[order], sc[order])
