"""Turn a candump log of ranging frames into a range log (shared/spec/range-log.md).

Each valid ranging frame becomes one row: `vehicle` = the node that measured, `sensor` = ranging, `peer` = the
peer id, `measured` = range [m]; extra columns `ctx_quality_pct` (the unit's confidence [%]) and `seq`.
Frames that are not valid ranging frames are counted by reason (the C driver's own decoder and verdicts,
through finken.can.ranging_frame); a repeated sequence number of a node on an interface (a duplicate frame) is
dropped and counted.

Ground truth: the spec requires `true_range`, and a CAN log has none, so it comes from a motion-capture poses
file (t, vehicle, x, y, z, yaw): the distance between the two copters' positions, each interpolated linearly
at the reading's time (the pose origins stand for the antennas: an antenna offset from the tracked origin
adds up to twice that offset to the error attributed to the sensor). A reading outside a copter's tracked time
span, or between two poses further apart than `max_pose_gap_s` (tracking lost), gets no truth and is left out
(counted); if none is left, the conversion fails with a message saying why. Log times plus `time_offset_s`
must be on the poses' clock.
"""
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from finken.can.ranging_frame import Layout, decode
from finken.rangelog import RangeLog


class ConversionError(ValueError):
    """The log and the poses give no usable range log."""


@dataclass
class Summary:
    """What the conversion did (counts of frames and readings)."""
    frames: int = 0                                  # frames in the log (after the interface filter)
    other_interfaces: int = 0                        # frames on other interfaces, skipped
    rejected: Counter = field(default_factory=Counter)  # invalid frames by reason
    duplicates: int = 0                              # repeated sequence numbers, dropped
    readings: int = 0                                # valid ranging readings
    no_truth: int = 0                                # readings left out: no pose at their time
    untracked: tuple = ()                            # vehicle ids without any pose
    written: int = 0                                 # rows written

    def lines(self):
        """Human-readable lines."""
        out = [f"{self.frames} frames, {self.readings} ranging readings, {self.written} rows written"]
        if self.other_interfaces:
            out.append(f"{self.other_interfaces} frames on other interfaces skipped")
        for reason, n in sorted(self.rejected.items()):
            out.append(f"{n} frames rejected: {reason}")
        if self.duplicates:
            out.append(f"{self.duplicates} duplicate frames dropped")
        if self.no_truth:
            out.append(f"{self.no_truth} readings without ground truth left out (no pose at their time)")
        if self.untracked:
            out.append("no poses for vehicle " + ", ".join(str(v) for v in self.untracked))
        return out


def ranging_readings(frames, layout=Layout(), ifname=None):
    """Valid, non-duplicate ranging readings of `frames` as arrays (t [s], node, peer, range_m [m],
    quality_pct [%], seq) and a Summary."""
    layout.check()
    summary = Summary()
    last_seq = {}
    rows = []
    for frame in frames:
        if ifname is not None and frame.ifname != ifname:
            summary.other_interfaces += 1
            continue
        summary.frames += 1
        msg, reason = decode(frame, layout)
        if msg is None:
            summary.rejected[reason] += 1
            continue
        key = (frame.ifname, msg.node)
        if last_seq.get(key) == msg.seq:
            summary.duplicates += 1
            continue
        last_seq[key] = msg.seq
        rows.append((frame.time_us, msg.node, msg.peer, msg.range_mm, msg.quality_pct, msg.seq))
    summary.readings = len(rows)
    table = np.array(rows, dtype=np.int64).reshape(-1, 6)
    readings = {
        "t": table[:, 0] / 1e6, "node": table[:, 1], "peer": table[:, 2], "range_m": table[:, 3] / 1000.0,
        "quality_pct": table[:, 4], "seq": table[:, 5],
    }
    return readings, summary


def positions_at(poses, vehicle, t, max_pose_gap_s):
    """Position (n x 3 [m]) of `vehicle` at times `t` [s] by linear interpolation of its poses; NaN rows where
    it has no pose, where t is outside its tracked span, or where the two poses around t are further apart
    than max_pose_gap_s (unless t is a pose time)."""
    t = np.asarray(t, dtype=np.float64)
    out = np.full((len(t), 3), np.nan)
    mine = poses["vehicle"] == vehicle
    if not np.any(mine):
        return out
    order = np.argsort(poses["t"][mine], kind="stable")
    pt = poses["t"][mine][order]
    if len(pt) == 1:
        i0 = i1 = np.zeros(len(t), dtype=np.intp)
    else:
        i1 = np.clip(np.searchsorted(pt, t, side="right"), 1, len(pt) - 1)
        i0 = i1 - 1
    on_sample = (pt[i0] == t) | (pt[i1] == t)
    ok = (t >= pt[0]) & (t <= pt[-1]) & (on_sample | (pt[i1] - pt[i0] <= max_pose_gap_s))
    for axis, name in enumerate(("x", "y", "z")):
        out[ok, axis] = np.interp(t[ok], pt, poses[name][mine][order])
    return out


def convert(frames, poses, layout=Layout(), ifname=None, time_offset_s=0.0, max_pose_gap_s=0.1, path="candump"):
    """A RangeLog of the ranging readings in `frames` with true ranges from `poses` (dict of arrays t [s],
    vehicle, x, y, z [m]), and a Summary. Raises ConversionError if no reading gets a ground truth."""
    readings, summary = ranging_readings(frames, layout, ifname)
    t = readings["t"] + time_offset_s
    vehicles = np.unique(np.concatenate([readings["node"], readings["peer"]]))
    tracked = set(np.unique(poses["vehicle"]).astype(np.int64).tolist())
    summary.untracked = tuple(int(v) for v in vehicles if int(v) not in tracked)
    node_xyz = np.full((len(t), 3), np.nan)
    peer_xyz = np.full((len(t), 3), np.nan)
    for v in vehicles:
        for ids, xyz in ((readings["node"], node_xyz), (readings["peer"], peer_xyz)):
            rows = ids == v
            if np.any(rows):
                xyz[rows] = positions_at(poses, v, t[rows], max_pose_gap_s)
    true_range = np.linalg.norm(node_xyz - peer_xyz, axis=1)
    keep = np.isfinite(true_range)
    summary.no_truth = int(np.count_nonzero(~keep))
    summary.written = int(np.count_nonzero(keep))
    if summary.readings == 0:
        raise ConversionError(f"{path}: no valid ranging frame (" + "; ".join(summary.lines()) + ")")
    if summary.written == 0:
        raise ConversionError(f"{path}: no reading has a ground truth: the poses cover none of the reading times "
                              f"(check --time-offset and the vehicle ids; " + "; ".join(summary.lines()) + ")")
    order = np.argsort(t[keep], kind="stable")
    rows = np.flatnonzero(keep)[order]
    n = len(rows)
    log = RangeLog(
        path=str(path), t=t[rows], vehicle=readings["node"][rows].astype(np.float64),
        sensor=np.full(n, "ranging", dtype=object), peer=readings["peer"][rows].astype(np.float64),
        true_range=true_range[rows], measured=readings["range_m"][rows],
        ctx={"ctx_quality_pct": readings["quality_pct"][rows].astype(np.float64)},
        extra={"seq": readings["seq"][rows].astype(str)},
    )
    return log, summary
