"""The offset between a copter's clock and the motion capture's: mocap time = record time + offset.

Each copter has a clock of its own (Paparazzi's time since boot), so each gets its own offset. The offset is the one
under which the readings agree best with the true ranges the motion capture gives: the least mean of the squared
error cut at AGREE_M, min(e, AGREE_M)^2 (a truncated quadratic, as in robust regression), so that glitches, the
sensor's own effects and a few wrong poses weigh no more than a reading that merely disagrees; each sensor kind's
median error is taken out first, so that a sensor's constant offset (what calibration is to find) does not push the
errors toward the cut. It is searched
on a grid over the window the user allows (MAX_OFFSET_S either side of zero by default), with a sample of the
copter's readings, then on finer grids around the best. The offset cannot be found when no offset in the window
puts enough readings inside the motion capture's time (no overlap), when the best agrees for too few readings, or
when another offset far from it agrees nearly as well (a copter that hovered: every offset fits).
"""
from dataclasses import dataclass, replace

import numpy as np

from finken.flight.truth import range_log

AGREE_M = 0.15          # a reading agrees with its true range within this [m] (sonar and ranging noise: a few cm)
MAX_OFFSET_S = 600.0    # the default search window: offsets from -10 min to +10 min
#: (step [s], half-width around the previous best [s] or None for the whole window, readings sampled, cut [m]): the
#: coarse stages cut the error wider, so that their cost is smooth over their step (a copter flies ~0.5 m/s)
STAGES = ((1.0, None, 100, 1.0), (0.1, 1.5, 2000, 0.3), (0.01, 0.3, 5000, AGREE_M), (0.002, 0.03, 10000, AGREE_M))
MIN_AGREEING = 0.5      # the best offset must agree for at least half the readings it places
MIN_PLACED = 0.1        # ... and place at least this share of the readings inside the motion capture
RIVAL_APART_S = 1.0     # the best offset at least this far from the best is its rival
INFORMATIVE_MPS = 0.05  # a reading tells offsets apart when its true range changes at least this fast [m/s] ...
MIN_INFORMATIVE = 200   # ... and the fine stages keep to such readings when there are this many
RATE_STEP_S = 0.05      # half the interval of the central difference giving that rate [s]
MAX_RECENTRING = 5      # times a stage's window may move to a best found at its edge
RIVAL_SIGMAS = 3.0      # the rival must agree for significantly fewer readings (see _distinct)


class ClockError(ValueError):
    """No offset can be found for a copter (the message says what was tried)."""


@dataclass
class ClockOffset:
    vehicle: int
    offset_s: float
    agreeing: float      # share of the placed readings within AGREE_M of their true range (each kind's median off)
    placed: int          # readings placed inside the motion capture at the offset
    rival_s: float       # the best offset at least RIVAL_APART_S away (NaN if none placed enough readings)
    rival_agreeing: float  # its share, on the same readings


def estimate_offset(arena, mounts, readings, poses, vehicle, window=(-MAX_OFFSET_S, MAX_OFFSET_S), where=""):
    """The ClockOffset of `vehicle` (its rows of `readings`, on its own clock), searched over `window` [s];
    ClockError naming `where` (the record's file:line) and what was tried."""
    rows = np.flatnonzero(np.asarray(readings.vehicle) == vehicle)
    rows = rows[np.isfinite(np.asarray(readings.measured, float)[rows])]
    rng = np.random.default_rng(vehicle)   # the same sample on every run
    best, scores, n_coarse, pool = None, [], 0, rows
    for n, (step, half, n_sample, cut_m) in enumerate(STAGES):
        if n == 1:   # within a second or so: the finer stages weigh the readings that tell offsets apart
            pool = _informative(arena, mounts, readings, poses, rows, best)
        sample = np.sort(rng.choice(pool, size=min(n_sample, len(pool)), replace=False))
        centre = best
        for _ in range(MAX_RECENTRING):   # a best at the edge of a stage's window: the window moves to it
            lo, hi = window if half is None else (centre - half, centre + half)
            candidates = np.arange(lo, hi + step / 2, step)
            stage = [(_score(arena, mounts, readings, poses, sample, dt, cut_m), dt) for dt in candidates]
            placed_enough = [(s[0], dt) for s, dt in stage if s[2] >= MIN_PLACED * len(sample)]
            scores += placed_enough
            if not placed_enough:
                raise ClockError(f"{where}: vehicle {vehicle}: no clock offset from {window[0]:+g} s to "
                                 f"{window[1]:+g} s puts {MIN_PLACED:.0%} of its readings inside the motion capture's "
                                 "time: the files do not overlap (state the offset with CLOCK_OFFSET= or widen "
                                 "MAX_OFFSET=)")
            best = min(placed_enough)[1]
            n_coarse = n_coarse or len(scores)   # the rival comes from the whole window's stage
            if half is None or lo + step / 2 < best < hi - step / 2:
                break
            centre = best
    _, agreeing, placed = _score(arena, mounts, readings, poses, sample, best)
    rival_s, rival_agreeing, rival_placed = _rival(arena, mounts, readings, poses, sample, scores[:n_coarse], best)
    found = ClockOffset(vehicle, float(best), agreeing, placed, float(rival_s), float(rival_agreeing))
    steps = ", ".join(f"{stage[0]:g} s" for stage in STAGES[1:])
    tried = (f"tried offsets from {window[0]:+g} s to {window[1]:+g} s in steps of {STAGES[0][0]:g} s, then "
             f"{steps} around the best, on up to {STAGES[-1][2]} of its {len(rows)} readings ({len(pool)} of them "
             f"with a true range changing by {INFORMATIVE_MPS:g} m/s or more)")
    if agreeing < MIN_AGREEING:
        raise ClockError(f"{where}: vehicle {vehicle}: no clock offset makes its readings agree with the motion "
                         f"capture: {tried}; the best, {best:+.3f} s, puts {agreeing:.0%} of them within "
                         f"{AGREE_M:g} m of the true range (needs {MIN_AGREEING:.0%}); state it with CLOCK_OFFSET=")
    if rival_placed and not _distinct(agreeing, placed, rival_agreeing, rival_placed):
        raise ClockError(f"{where}: vehicle {vehicle}: the clock offset is ambiguous: {tried}; {best:+.3f} s and "
                         f"{rival_s:+.3f} s agree for {agreeing:.1%} and {rival_agreeing:.1%} of the readings "
                         "(a copter that hardly moved fits any offset); state it with CLOCK_OFFSET=")
    return found


def _rival(arena, mounts, readings, poses, sample, coarse, best, tries=5):
    """(offset, share agreeing, readings placed) of the best offset of the coarse stage at least RIVAL_APART_S from
    `best` that places MIN_PLACED of `sample` (the final readings), scored on them; (NaN, NaN, 0) if none of the
    `tries` best does."""
    far = sorted((cost, dt) for cost, dt in coarse if abs(dt - best) >= RIVAL_APART_S)
    for _, dt in far[:tries]:
        _, agreeing, placed = _score(arena, mounts, readings, poses, sample, dt)
        if placed >= MIN_PLACED * len(sample):
            return dt, agreeing, placed
    return np.nan, np.nan, 0


def _informative(arena, mounts, readings, poses, rows, offset_s):
    """The rows whose true range changes at INFORMATIVE_MPS or more around offset_s (a central difference), if there
    are MIN_INFORMATIVE of them, else all rows: where the copters hover, most readings fit any offset alike, and a
    sample of all readings would hold too few of those that tell offsets apart."""
    ranges = []
    for shift in (-RATE_STEP_S, RATE_STEP_S):
        part = on_clock(readings, rows, offset_s + shift)
        ranges.append(range_log(arena, mounts, part, poses, context=False).true_range)
    rate = np.abs(ranges[1] - ranges[0]) / (2 * RATE_STEP_S)
    moving = rows[rate >= INFORMATIVE_MPS]   # NaN (a copter unseen) is not
    return moving if len(moving) >= MIN_INFORMATIVE else rows


def _distinct(agreeing, placed, rival_agreeing, rival_placed):
    """Whether the rival offset agrees for significantly fewer readings than the best: the two shares differ by more
    than RIVAL_SIGMAS standard deviations of their difference, sqrt(p_b (1 - p_b) / n_b + p_r (1 - p_r) / n_r) (two
    binomial proportions; a floor of one reading's worth keeps it above zero when both shares are 0 or 1). Most
    readings (a wall far away, the floor below) agree at any offset, so a large share alone cannot tell."""
    variance = sum(max(p * (1 - p), 1.0 / n) / n for p, n in ((agreeing, placed), (rival_agreeing, rival_placed)))
    return agreeing - rival_agreeing > RIVAL_SIGMAS * np.sqrt(variance)


def _score(arena, mounts, readings, poses, sample, offset_s, cut_m=AGREE_M):
    """(mean squared error cut at cut_m [m^2] over the sample, a reading the motion capture cannot place counting as
    cut_m^2, so that an offset placing only a quiet sliver of the flight cannot look best; share of the placed
    readings within AGREE_M of their true range; readings placed) at this offset."""
    everything = range_log(arena, mounts, on_clock(readings, sample, offset_s), poses, context=False)
    placed = np.isfinite(everything.true_range)   # range_log leaves the rows the motion capture did not see NaN
    if not placed.any():
        return cut_m ** 2, 0.0, 0
    truth = everything.select(placed)
    error = truth.measured - truth.true_range
    for kind in (truth.sensor == "ranging", truth.sensor != "ranging"):   # each kind's own offset taken out
        if kind.any():
            error[kind] -= np.median(error[kind])
    error = np.abs(error)
    cost = (np.sum(np.minimum(error, cut_m) ** 2) + (len(sample) - placed.sum()) * cut_m ** 2) / len(sample)
    return float(cost), float(np.mean(error <= AGREE_M)), int(placed.sum())


def seen_by_mocap(poses, records):
    """Rows of `records` (on the motion capture's clock) whose copter, and ranging peer, the motion capture saw at
    the row's time."""
    seen = np.ones(len(records.t), bool)
    for ids in (records.vehicle, records.peer):
        for v in np.unique(ids[ids >= 0]):
            rows = np.flatnonzero(ids == v)
            seen[rows] &= poses.at(int(v), records.t[rows])[2]
    return seen


def on_clock(records, rows, offset_s):
    """The rows of `records` (finken.flight.records.Records) with their times moved onto the motion capture's clock:
    offset_s, one number or one per row."""
    picked = records.select(rows)
    return replace(picked, t=picked.t + offset_s)
