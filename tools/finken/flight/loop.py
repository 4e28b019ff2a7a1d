"""The loop closed on a simulated flight: the copters' records and their true poses, written by the simulator as a
lab's flight would give them, through `make rangelog` and the calibration workflow.

- hidden_model: a sensor model with one effect the calibration does not start from;
- flight_files: the recorder's files of every aircraft as one record, the poses as the motion capture;
- truth_agreement: how well the true ranges computed from the poses agree with the simulator's own, and why they
  differ where they do, row by row (the recorder writes the simulator's readings in the same order); and how many
  readings each marks as hearing another sonar's pulse (ctx_crosstalk_path > 0).
"""
from dataclasses import dataclass

import numpy as np
from lxml import etree
from scipy.spatial.transform import Rotation

from finken.atomic_output import atomic_output

AGREE_M = 0.01           # a computed true range agrees with the simulator's within this [m]
TILT_DEG = 2.0           # a copter tilted more than this: its sonars' rays leave the simulator's level ones


def hidden_model(base_path, out_path, kind, effect):
    """Write the model at base_path with `effect` ({attribute: value}, "name" included) appended to its `kind`
    chain ("sonar" or "ranging") to out_path; relative mixture files are made absolute so that the copy loads
    anywhere. Returns out_path."""
    tree = etree.parse(str(base_path))
    for element in tree.iter("effect"):
        mixture = element.get("mixture")
        if mixture and not mixture.startswith("/"):
            element.set("mixture", str((base_path.parent / mixture).resolve()))
    chain = tree.getroot().find(kind)
    indent = chain.text                       # the newline and indentation before each effect
    last = chain[-1] if len(chain) else None
    added = etree.SubElement(chain, "effect", {k: str(v) for k, v in effect.items()})
    if last is not None:
        added.tail, last.tail = last.tail, indent
    with atomic_output(out_path) as f:
        f.write(etree.tostring(tree, encoding="unicode", xml_declaration=False))
    return out_path


def flight_files(raw_dir, ids, out_dir):
    """(record path, motion-capture path): the aircraft's record_<id>.csv one after the other, and their
    poses_<id>.csv, in out_dir."""
    paths = {}
    for kind in ("record", "poses"):
        paths[kind] = out_dir / f"{kind}.csv"
        with atomic_output(paths[kind]) as out:
            for n, ac_id in enumerate(ids):
                lines = (raw_dir / f"{kind}_{ac_id}.csv").read_text().splitlines(keepends=True)
                out.writelines(lines if n == 0 else lines[1:])
    return paths["record"], paths["poses"]


@dataclass
class TruthAgreement:
    rows: int
    agreeing: dict        # sensor kind ("sonar", "ranging") -> share within AGREE_M
    reasons: dict         # reason -> share of all rows that differ for it
    target_agreeing: float  # sonar rows whose first hit (copter or not) is the simulator's
    heard: dict           # "computed", "simulator", "both" -> sonar rows that hear another sonar's pulse

    def lines(self):
        out = [f"computed true ranges within {AGREE_M * 100:g} cm of the simulator's own: " +
               ", ".join(f"{k} {v:.1%}" for k, v in self.agreeing.items()) +
               f" of {self.rows} readings; sonar first hit (copter or not) the same in {self.target_agreeing:.1%}"]
        out += [f"  differ: {share:.1%} of the readings where {reason}" for reason, share in self.reasons.items()]
        out += [f"cross-talk context (another sonar's pulse heard): {self.heard['computed']} readings computed, "
                f"{self.heard['simulator']} in the simulator's log, {self.heard['both']} in both (the trigger offsets "
                f"come from the records' times and the estimated clock offsets, a few ms off)"]
        return out


REASONS = ("two copters were closer than their bodies allow at the poses' times (the world's contacts push them apart "
           "within a step; a pose row is up to a step early)",
           f"the copter was tilted more than {TILT_DEG:g} deg (the simulator keeps its sonars level)",
           "the simulator's curtain had bulged toward the copter (the arena file holds the walls at rest)",
           "none of these (pose samples cutting a turn short, a clock offset a few ms off)")


def truth_agreement(log, records, sim_by_vehicle, poses, copter_radius_m):
    """TruthAgreement of `log` (flight_log's RangeLog, rows with their record lines) against the simulator's
    range logs {vehicle: RangeLog}, whose rows the recorder wrote one for one, in order, into `records`."""
    index = np.empty(int(records.line.max()) + 1, int)
    owner = np.empty_like(index)
    for v in np.unique(records.vehicle):
        lines = records.line[records.vehicle == v]
        index[lines], owner[lines] = np.arange(len(lines)), v
    sim_true = np.array([sim_by_vehicle[owner[k]].true_range[index[k]] for k in log.line])
    sim_target = np.array([sim_by_vehicle[owner[k]].ctx["ctx_target_copter"][index[k]] for k in log.line])
    sim_path = np.array([sim_by_vehicle[owner[k]].ctx["ctx_crosstalk_path"][index[k]] for k in log.line])
    differ = np.abs(log.true_range - sim_true) > AGREE_M
    sonar = log.sensor != "ranging"
    reason = np.full(len(log), -1)
    at = _bodies_at(log, poses)
    reason[differ & _in_contact(log, at, copter_radius_m)] = 0
    reason[differ & (reason < 0) & sonar & (_tilt_deg(log, at) > TILT_DEG)] = 1
    bulged = sonar & (sim_true < log.true_range) & (sim_target == 0) & (log.ctx["ctx_target_copter"] == 0)
    reason[differ & (reason < 0) & bulged] = 2
    reason[differ & (reason < 0)] = 3
    kinds = {"sonar": sonar, "ranging": ~sonar}
    heard, sim_heard = sonar & (log.ctx["ctx_crosstalk_path"] > 0), sonar & (sim_path > 0)
    return TruthAgreement(len(log), {k: float(np.mean(~differ[m])) for k, m in kinds.items() if m.any()},
                          {REASONS[r]: float(np.mean(reason == r)) for r in range(len(REASONS)) if np.any(reason == r)},
                          float(np.mean(log.ctx["ctx_target_copter"][sonar] == sim_target[sonar])),
                          {"computed": int(heard.sum()), "simulator": int(sim_heard.sum()),
                           "both": int((heard & sim_heard).sum())})


def _in_contact(log, at, radius_m):
    """Rows at whose time the reading copter is closer than two body radii to another copter (`at`: _bodies_at)."""
    own, _, _ = _own(log, at)
    near = np.zeros(len(log), bool)
    for other, (pos, _, valid) in at.items():
        near |= valid & (log.vehicle != other) & (np.linalg.norm(pos - own, axis=1) < 2 * radius_m)
    return near


def _tilt_deg(log, at):
    """The reading copter's tilt: the angle between its body z axis and the arena's [deg]."""
    _, quat, valid = _own(log, at)
    tilt = np.zeros(len(log))
    up = Rotation.from_quat(quat[valid]).apply([0.0, 0.0, 1.0])
    tilt[valid] = np.degrees(np.arccos(np.clip(up[:, 2], -1.0, 1.0)))
    return tilt


def _bodies_at(log, poses):
    """{vehicle: (pos, quat, valid)} of every body of the motion capture at every row's time."""
    return {int(v): poses.at(int(v), log.t) for v in poses.vehicles}


def _own(log, at):
    """(pos, quat, valid) of each row's own copter, from _bodies_at."""
    pos, quat, valid = np.full((len(log), 3), np.nan), np.full((len(log), 4), np.nan), np.zeros(len(log), bool)
    for v, (p, q, ok) in at.items():
        rows = log.vehicle == v
        pos[rows], quat[rows], valid[rows] = p[rows], q[rows], ok[rows]
    return pos, quat, valid
