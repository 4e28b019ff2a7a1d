"""What a swarm run shows of its shared arena: who ranged whom, copter echoes, cross-talk, walls bulging toward
the copters that pass them, and the wall detector's scores. The same figures for a run of our host and for one of
Paparazzi's NPS processes sharing a world (make paparazzi-check), so that the two can be compared.
"""
import itertools
from dataclasses import dataclass, field

import numpy as np

from finken.rangelog import read_range_log
from finken.run_logs import read_detections, read_poses
from finken.sim_report.arena_plot import read_walls
from finken.sim_report.detector_metrics import run_classification

HORIZONTAL_SONARS = ("sonar_front", "sonar_right", "sonar_back", "sonar_left")
# a plate bulges by more than this [deg] (the walls' maximum amplitude is 30 deg in the SwarmLab arena)
BULGE_DEG = 5.0
# a bulge is toward a copter when one is this close to the plate's midpoint [m] (the walls' threshold is 1 m)
BULGE_REACH_M = 1.0


@dataclass
class SwarmFigures:
    aircraft: list
    pairs_not_ranged: list                 # ordered (vehicle, peer) pairs without a single distance
    copter_echoes: int                     # horizontal sonar readings whose first hit was a copter
    crosstalk_readings: int                # horizontal sonar readings that heard a facing sonar's pulse
    bulges: int                            # wall snapshots with a plate bulged more than BULGE_DEG
    bulges_toward_a_copter: int            # of those, with a copter within BULGE_REACH_M of the plate
    detector: dict = field(default_factory=dict)   # detector scores over the detections from `from_s` on

    def as_dict(self):
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def _nearest_copter_m(poses, t, x, y):
    """Distance from (x, y) to the nearest copter at the pose rows closest in time to t."""
    nearest_t = poses["t"][np.argmin(np.abs(poses["t"] - t))]
    rows = np.abs(poses["t"] - nearest_t) <= 0.05
    return float(np.min(np.hypot(poses["x"][rows] - x, poses["y"][rows] - y)))


def swarm_figures(run_dir, from_s=0.0):
    """The figures of the run in run_dir (readings.csv, poses.csv, walls.csv, detections.csv)."""
    readings = read_range_log(f"{run_dir}/readings.csv")
    poses = read_poses(f"{run_dir}/poses.csv")
    walls = read_walls(f"{run_dir}/walls.csv")
    aircraft = sorted(int(v) for v in np.unique(poses["vehicle"]))

    ranging = (readings.sensor == "ranging") & np.isfinite(readings.measured)
    ranged = set(zip(readings.vehicle[ranging].astype(int), readings.peer[ranging].astype(int)))
    pairs_not_ranged = [pair for pair in itertools.permutations(aircraft, 2) if pair not in ranged]

    horizontal = np.isin(readings.sensor, HORIZONTAL_SONARS)
    copter_echoes = int(np.sum(horizontal & (readings.ctx.get("ctx_target_copter", 0.0) == 1.0)))
    crosstalk = int(np.sum(horizontal & (readings.ctx.get("ctx_facing_sonars", 0.0) > 0.0)))

    bulged = np.flatnonzero(walls["angle_deg"] > BULGE_DEG)
    toward = sum(_nearest_copter_m(poses, walls["t"][i], 0.5 * (walls["x0"][i] + walls["x1"][i]),
                                   0.5 * (walls["y0"][i] + walls["y1"][i])) <= BULGE_REACH_M for i in bulged)

    detections = read_detections(f"{run_dir}/detections.csv")
    later = np.asarray(detections["t"]) >= from_s
    scores = run_classification({k: np.asarray(v)[later] for k, v in detections.items()})["detector"]
    return SwarmFigures(aircraft, pairs_not_ranged, copter_echoes, crosstalk, int(bulged.size), int(toward), scores)


def compare_detectors(ours, host, tolerance=0.05, scores=("wall_recall", "copter_as_wall")):
    """The scores of `ours` more than `tolerance` away from the host's: {name: (ours, host)}."""
    return {name: (ours.detector[name], host.detector[name]) for name in scores
            if not abs(ours.detector[name] - host.detector[name]) <= tolerance}


def problems(figures):
    """What a shared arena must show and this run does not (empty when it shows everything)."""
    found = []
    if len(figures.aircraft) < 2:
        found.append(f"only aircraft {figures.aircraft} in the poses")
    if figures.pairs_not_ranged:
        found.append(f"pairs never ranged: {figures.pairs_not_ranged}")
    if figures.copter_echoes == 0:
        found.append("no sonar echo from a copter")
    if figures.crosstalk_readings == 0:
        found.append("no sonar heard a facing sonar's pulse (cross-talk)")
    if figures.bulges_toward_a_copter == 0:
        found.append(f"no plate bulged more than {BULGE_DEG} deg with a copter within {BULGE_REACH_M} m")
    return found
