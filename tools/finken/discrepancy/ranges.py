"""Before any fit: what the log says about each sensor's range.

- Rows beyond the model's range (true range or reading outside [min_range, max_range] of the kind's chain)
  are counted per sensor, up front: a model whose range ends at 2.5 m cannot be compared with readings at
  12 m, and the gap it shows there is not a missing error effect. Glitches (finken.discrepancy.glitches) are no
  readings of the range: they count nowhere here.
- The range of each kind's chain is then fitted from the readings (unless fixed). When readings go beyond the
  model's maximum, the maximum is the largest reading plus RANGE_HEADROOM of it: the largest reading of one log
  is where that flight happened to stop, not where the sensor does (a held-out flight, or this log's held-out
  blocks, may go farther). When the sensor clamps below the model's maximum (at least CLAMP_SHARE of the readings
  pile up at their largest value), that value. The same for the minimum (a clamp, or the smallest reading minus
  RANGE_HEADROOM of it, never below 0). The output model keeps the fitted range.
- True ranges far beyond any sensor of the kind (more than UNIT_HINT_FACTOR times the model's maximum range)
  are said: usually a unit error (see --unit).
- A sensor that never reported (no reading on any row) is left out, and said; so is a kind with too few rows
  to decide anything (MIN_DECIDE_ROWS).
"""
import copy
from dataclasses import dataclass

import numpy as np

from finken.discrepancy.dataset import sensor_kind

#: True ranges above this multiple of the model's maximum range are said to be a likely unit error [factor].
UNIT_HINT_FACTOR = 1000.0
#: Room a fitted range leaves beyond the extreme reading seen [fraction of that reading].
RANGE_HEADROOM = 0.1
#: Share of a sensor's readings at its top (or bottom) value that marks a clamp there.
CLAMP_SHARE = 0.01
#: Fewest rows of a kind with readings to fit and score anything (two sets of blocks, each bin >= 30 rows).
MIN_DECIDE_ROWS = 200


@dataclass
class SensorRange:
    """What the log shows of one sensor (a `sensor` value of the log) against the model's range."""
    sensor: str
    kind: str
    rows: int
    readings: int               # rows with a reading
    true_beyond: int            # rows whose true range lies outside the model's range
    readings_beyond: int        # rows whose reading lies outside the model's range


@dataclass
class KindRange:
    """A kind's range: the model's, the one the workflow uses, and how it was chosen."""
    kind: str
    min_in: float
    max_in: float
    min_out: float
    max_out: float
    source: str                 # 'model', 'fitted' or 'given'
    rows_affected: int          # rows with a true range or reading outside the model's range

    @property
    def changed(self):
        return (self.min_in, self.max_in) != (self.min_out, self.max_out)


def rows_of(log):
    """{kind: bool mask of its rows} (dataset.sensor_kind, for arrays)."""
    ranging = log.sensor == "ranging"
    return {"ranging": ranging, "sonar": ~ranging}


def unit_notes(log, model):
    """Lines saying which kinds have true ranges above UNIT_HINT_FACTOR x the model's maximum range."""
    notes, kind_rows = [], rows_of(log)
    for kind, chain in model.chains.items():
        far = log.true_range[kind_rows[kind]]
        if far.size and far.max() > UNIT_HINT_FACTOR * chain.max_range:
            notes.append(f"{kind}: true ranges up to {far.max():g} m, more than {UNIT_HINT_FACTOR:g} times the "
                         f"model's maximum range ({chain.max_range:g} m): a unit error? (see --unit)")
    return notes


def sensor_ranges(log, model, glitch=None):
    """SensorRange of every sensor in the log (in sensor-name order) against its kind's chain; `glitch`: True on
    the rows whose reading is a glitch (they hold no reading of the range)."""
    out = []
    for sensor in np.unique(log.sensor):
        kind = sensor_kind(sensor)
        chain = model.chains.get(kind)
        rows = log.sensor == sensor
        meas, tr = log.measured[rows], log.true_range[rows]
        has = np.isfinite(meas) & (True if glitch is None else ~glitch[rows])
        lo, hi = (chain.min_range, chain.max_range) if chain else (-np.inf, np.inf)
        out.append(SensorRange(str(sensor), kind, int(rows.sum()), int(has.sum()),
                               int(np.sum((tr > hi) | (tr < lo))),
                               int(np.sum(has & ((meas > hi) | (meas < lo))))))
    return out


def _fit_limit(readings, model_value, top):
    """The range limit the readings show: beyond the model's, the extreme reading with RANGE_HEADROOM; inside it,
    the extreme reading when at least CLAMP_SHARE of the readings sit there (a clamp); else the model's value."""
    if readings.size == 0:
        return model_value
    extreme = float(readings.max() if top else readings.min())
    beyond = extreme > model_value if top else extreme < model_value
    if beyond:
        return extreme * (1 + RANGE_HEADROOM) if top else max(extreme * (1 - RANGE_HEADROOM), 0.0)
    clamped = np.mean(readings == extreme) >= CLAMP_SHARE and extreme != model_value
    return extreme if clamped and readings.size >= MIN_DECIDE_ROWS else model_value


def fit_ranges(log, model, fixed_max=None, glitch=None):
    """(model with fitted ranges, {kind: KindRange}). fixed_max: {kind: max range [m]} that the data must not
    change (the user's --max-range); `glitch`: True on the rows whose reading is a glitch (not fitted from)."""
    fixed_max = fixed_max or {}
    out, ranges = model, {}
    kind_rows = rows_of(log)
    for kind, chain in model.chains.items():
        rows = kind_rows[kind]
        if not rows.any():
            continue
        meas, tr = log.measured[rows], log.true_range[rows]
        if glitch is not None:
            meas = np.where(glitch[rows], np.nan, meas)
        readings = meas[np.isfinite(meas)]
        lo, hi = chain.min_range, chain.max_range
        affected = int(np.sum((tr > hi) | (tr < lo) | (np.isfinite(meas) & ((meas > hi) | (meas < lo)))))
        new_lo = _fit_limit(readings, lo, top=False)
        if kind in fixed_max:
            new_hi, source = float(fixed_max[kind]), "given"
        else:
            new_hi = _fit_limit(readings, hi, top=True)
            source = "fitted" if (new_lo, new_hi) != (lo, hi) else "model"
        if new_lo >= new_hi:
            new_lo = lo if lo < new_hi else 0.0
        ranges[kind] = KindRange(kind, lo, hi, new_lo, new_hi, source, affected)
        if (new_lo, new_hi) != (lo, hi):
            out = _with_range(out, kind, new_lo, new_hi)
    return out, ranges


def _with_range(model, kind, min_range, max_range):
    """A copy of the model whose `kind` chain has this range (validated by the C loader)."""
    model = copy.deepcopy(model)
    model.source = None
    model.chains[kind].min_range, model.chains[kind].max_range = float(min_range), float(max_range)
    model.native()
    return model


def describe(sensors, model):
    """Lines for the terminal, before any fit: the rows beyond the model's range per sensor, the sensors left
    out (left_out)."""
    lines = []
    for s in sensors:
        if s.true_beyond or s.readings_beyond:
            c = model.chains[s.kind]
            lines.append(f"{s.sensor}: {s.true_beyond} of {s.rows} true ranges and {s.readings_beyond} of "
                         f"{s.readings} readings lie outside the model's range [{c.min_range:g}, {c.max_range:g}] m; "
                         "the range will be fitted from the readings unless --max-range is given")
    return lines + left_out(sensors)[1]


def left_out(sensors):
    """(sensor names to leave out, notes): sensors that never reported, and the sensors of a kind with fewer
    than MIN_DECIDE_ROWS readings in all (too few to decide anything about it)."""
    out, notes = set(), []
    for s in sensors:
        if s.readings == 0:
            out.add(s.sensor)
            notes.append(f"{s.sensor} never reported: no reading on any of its {s.rows} rows (measured empty); "
                         "left out")
    for kind in sorted({s.kind for s in sensors}):
        of_kind = [s for s in sensors if s.kind == kind and s.sensor not in out]
        readings = sum(s.readings for s in of_kind)
        if of_kind and readings < MIN_DECIDE_ROWS:
            out |= {s.sensor for s in of_kind}
            notes.append(f"{kind}: {readings} rows with a reading, too few to decide (at least {MIN_DECIDE_ROWS}); "
                         "left out")
    return out, notes
