"""A lab's flight to a range log: the copters' records and the motion capture's poses, each copter's clock put on the
motion capture's, the readings the motion capture saw ray-cast against the arena (finken.flight.truth).

Refused, with file:line and nothing written (FlightInputError, ClockError): a vehicle or ranging peer with no body in
the motion capture; clocks whose offset cannot be found. Readings where the motion capture lost a copter (or its
peer), or before or after its samples, are left out and counted; so are the samples of a body that jumped
(finken.flight.mocap).
"""
from dataclasses import dataclass, field

import numpy as np

from finken.flight.clock import AGREE_M, MAX_OFFSET_S, estimate_offset, on_clock, seen_by_mocap
from finken.flight.errors import FlightInputError
from finken.flight.truth import SonarTiming, range_log
from finken.rangelog_columns import parse_items


@dataclass
class VehicleReport:
    vehicle: int
    readings: int
    offset_s: float
    offset_stated: bool
    agreeing: float = np.nan   # share of the readings within AGREE_M of their true range at the offset
    left_out: int = 0          # readings where the motion capture did not see the copter or its peer


@dataclass
class FlightReport:
    vehicles: list = field(default_factory=list)
    written: int = 0

    def lines(self):
        """What the terminal shows."""
        out = []
        for r in self.vehicles:
            how = "stated" if r.offset_stated else (f"estimated: {r.agreeing:.0%} of its readings agree within "
                                                    f"{AGREE_M:g} m, each sensor's median error aside")
            out.append(f"vehicle {r.vehicle}: {r.readings} readings, clock offset {r.offset_s:+.3f} s ({how}), "
                       f"{r.left_out} left out where the motion capture lost it or its peer")
        return out


def parse_offsets(text):
    """CLOCK_OFFSET text: one number for every copter ('0.25') or per vehicle ('1=0.25,2=-1.5') -> {vehicle: s}
    (key None: every copter); ValueError naming the item."""
    text = text.strip()
    if not text:
        return {}
    if "=" not in text:
        return {None: _seconds(text)}
    try:
        items = parse_items(text, "seconds", "vehicle", "vehicle")
    except ValueError as err:
        raise ValueError(f"clock offset {err}") from None
    offsets = {}
    for name, value in items:
        if not name.isdigit():
            raise ValueError(f"clock offset '{name}={value}': expected vehicle=seconds")
        offsets[int(name)] = _seconds(value)
    return offsets


def _seconds(text):
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"clock offset '{text.strip()}' is not a number of seconds") from None
    if not np.isfinite(value):
        raise ValueError(f"clock offset '{text.strip()}' is not finite")
    return value


def flight_range_log(arena, mounts, records, poses, offsets=None, max_offset_s=MAX_OFFSET_S, timing=SonarTiming(),
                     progress=None):
    """(RangeLog, FlightReport) of `records` (finken.flight.records.Records) with `poses` (finken.flight.mocap.Poses)
    in `arena` (truth.ArenaTruth). `offsets` {vehicle or None: s} states clock offsets; the others are estimated
    within +-max_offset_s."""
    offsets = offsets or {}
    vehicle = records.vehicle
    _check_bodies(records, poses)
    report = FlightReport()
    offset_of_row = np.zeros(len(records))
    for v in np.unique(vehicle):
        rows = vehicle == v
        first_line = int(records.line[rows][0])
        stated = v in offsets or None in offsets
        entry = VehicleReport(int(v), int(rows.sum()), offsets.get(v, offsets.get(None, np.nan)), stated)
        if not stated:
            found = estimate_offset(arena, mounts, records, poses, int(v), (-max_offset_s, max_offset_s),
                                    where=f"{records.path}:{first_line}")
            entry.offset_s, entry.agreeing = found.offset_s, found.agreeing
        offset_of_row[rows] = entry.offset_s
        report.vehicles.append(entry)
    moved = on_clock(records, np.arange(len(records)), offset_of_row)
    seen = seen_by_mocap(poses, moved)
    for entry in report.vehicles:
        entry.left_out = int(((vehicle == entry.vehicle) & ~seen).sum())
    kept = moved.select(seen)
    log = range_log(arena, mounts, kept, poses, timing, progress=progress)
    report.written = len(log)
    return log, report


def _check_bodies(records, poses):
    """Every vehicle and ranging peer has a body in the motion capture (FlightInputError at its first row)."""
    known = set(int(v) for v in poses.vehicles)
    line = records.line
    for role, ids in (("vehicle", records.vehicle), ("ranging peer", records.peer)):
        valid = ids >= 0
        for v in np.unique(ids[valid]):
            if v not in known:
                first = int(line[valid & (ids == v)][0])
                raise FlightInputError(records.path, first,
                                       f"{role} {v} has no body in the motion capture {poses.path} (its bodies give "
                                       f"vehicles {', '.join(map(str, sorted(known))) or 'none'}; map a body to it "
                                       "with BODIES=name=id)")
