"""Wall-detector and swarm metrics: pure functions over arrays (numpy), no I/O.

Classification is judged per reading against the simulator's ground truth (`ctx_target_copter`: the sonar's
boresight really hit a copter), on echoes only (readings below the sonar maximum, class not "none"), for the
sequence detector and the single-reading baseline side by side. Swarm behaviour is judged from poses: the
fraction of time copters spend near a wall and the swarm's cohesion.
"""
import numpy as np

#: A copter centre closer than this to a wall counts as "near the wall" [m].
NEAR_WALL_M = 0.5


def classification_scores(target_copter, labels):
    """Scores of one classifier over echoes.

    target_copter: bool array, True where the reading's ray really hit a copter.
    labels: str array of the classifier's classes ("wall", "copter", "unknown") for the same readings.
    Returns a dict of fractions (NaN where the denominator is 0) and counts:
      wall_recall        walls labelled wall / walls
      wall_precision     walls labelled wall / readings labelled wall
      copter_recall      copters labelled copter / copters
      copter_precision   copters labelled copter / readings labelled copter
      copter_as_wall     copters labelled wall / copters
      undecided          readings labelled unknown / readings
      walls, copters     numbers of wall and copter echoes
    """
    truth_copter = np.asarray(target_copter, dtype=bool)
    labels = np.asarray(labels, dtype=str)
    said_wall = labels == "wall"
    said_copter = labels == "copter"
    walls = ~truth_copter

    def ratio(num, den):
        return float(num) / float(den) if den else float("nan")

    return {
        "wall_recall": ratio(np.sum(said_wall & walls), np.sum(walls)),
        "wall_precision": ratio(np.sum(said_wall & walls), np.sum(said_wall)),
        "copter_recall": ratio(np.sum(said_copter & truth_copter), np.sum(truth_copter)),
        "copter_precision": ratio(np.sum(said_copter & truth_copter), np.sum(said_copter)),
        "copter_as_wall": ratio(np.sum(said_wall & truth_copter), np.sum(truth_copter)),
        "undecided": ratio(np.sum(labels == "unknown"), labels.size),
        "walls": int(np.sum(walls)),
        "copters": int(np.sum(truth_copter)),
    }


def distance_to_polygon(xy, polygon):
    """Distance [m] from each point of xy (n x 2) to the nearest edge of the closed polygon (k x 2 corners;
    a repeated first corner at the end is allowed)."""
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    corners = np.asarray(polygon, dtype=float).reshape(-1, 2)
    if np.allclose(corners[0], corners[-1]):
        corners = corners[:-1]
    a = corners
    b = np.roll(corners, -1, axis=0)
    ab = b - a
    # projection of every point on every edge, clamped to the segment
    ap = xy[:, None, :] - a[None, :, :]
    s = np.clip(np.sum(ap * ab[None], axis=2) / np.sum(ab * ab, axis=1)[None], 0.0, 1.0)
    nearest = a[None] + s[..., None] * ab[None]
    return np.min(np.linalg.norm(xy[:, None, :] - nearest, axis=2), axis=1)


def _time_weights(t, vehicle):
    """Duration [s] each pose sample stands for: the time to the same vehicle's next sample (the last
    sample of a vehicle gets that vehicle's median interval)."""
    t = np.asarray(t, dtype=float)
    vehicle = np.asarray(vehicle)
    weights = np.zeros(t.size)
    for v in np.unique(vehicle):
        rows = np.flatnonzero(vehicle == v)
        rows = rows[np.argsort(t[rows], kind="stable")]
        dt = np.diff(t[rows])
        if dt.size:
            weights[rows[:-1]] = dt
            weights[rows[-1]] = np.median(dt)
    return weights


def near_wall_fraction(t, vehicle, xy, polygon, within_m=NEAR_WALL_M):
    """Fraction (0-1) of the copters' flight time spent with the centre within `within_m` of a wall,
    time-weighted per vehicle and pooled over vehicles."""
    weights = _time_weights(t, vehicle)
    total = weights.sum()
    if total <= 0:
        return float("nan")
    near = distance_to_polygon(xy, polygon) < within_m
    return float(weights[near].sum() / total)


def cohesion(t, vehicle, xy):
    """Swarm cohesion [m]: the mean distance of the copters to their centroid, averaged over the sample
    times at which every vehicle has a pose (each time weighted by the interval to the next one)."""
    t = np.asarray(t, dtype=float)
    xy = np.asarray(xy, dtype=float).reshape(-1, 2)
    vehicles = np.unique(vehicle)
    times, index = np.unique(t, return_inverse=True)
    counts = np.bincount(index, minlength=times.size)
    complete = counts == vehicles.size
    if not complete.any():
        return float("nan")
    centroid = np.stack([np.bincount(index, xy[:, k], times.size) for k in (0, 1)], axis=1) / counts[:, None]
    spread = np.bincount(index, np.linalg.norm(xy - centroid[index], axis=1), times.size) / counts
    times, spread = times[complete], spread[complete]
    if times.size == 1:
        return float(spread[0])
    weights = np.append(np.diff(times), np.median(np.diff(times)))
    return float(np.sum(spread * weights) / np.sum(weights))


def run_classification(detections):
    """Detector and baseline scores over the echoes (detector_class not "none") of one run's detections
    (dict of arrays target_copter, detector_class, baseline_class, as finken.run_logs.read_detections)."""
    echo = np.asarray(detections["detector_class"]) != "none"
    truth = np.asarray(detections["target_copter"])[echo]
    return {"detector": classification_scores(truth, np.asarray(detections["detector_class"])[echo]),
            "baseline": classification_scores(truth, np.asarray(detections["baseline_class"])[echo])}


def summarize(runs, polygon):
    """make sim's wall-detector and swarm metrics as a flat dict (fractions 0-1, metres), plus the full score sets.

    runs: {"off": run, "on": run}, each run a dict with "detections" (see run_classification) and "poses"
    (dict of arrays t [s], vehicle, x [m], y [m]) of the detector-off and detector-on simulations.
    polygon: arena corners (k x 2) [m].
    The classification keys come from the detector-on run, where the swarm acts on the detector's
    verdicts; the same figures of the detector-off run (the detector judging while the swarm ignores it) are
    given with the suffix _off_run.
    """
    metrics = {}
    scores = {run: run_classification(runs[run]["detections"]) for run in ("on", "off")}
    for run, suffix in (("on", ""), ("off", "_off_run")):
        for who in ("detector", "baseline"):
            metrics[f"{who}_wall_recall{suffix}"] = scores[run][who]["wall_recall"]
            metrics[f"{who}_copter_as_wall{suffix}"] = scores[run][who]["copter_as_wall"]
    for run in ("off", "on"):
        poses = runs[run]["poses"]
        xy = np.column_stack([poses["x"], poses["y"]])
        metrics[f"near_wall_fraction_{run}"] = near_wall_fraction(poses["t"], poses["vehicle"], xy, polygon)
        metrics[f"cohesion_{run}"] = cohesion(poses["t"], poses["vehicle"], xy)
    metrics["classification"] = scores
    return metrics


def beats_baseline(figures):
    """Whether the detector beats the single-reading baseline on the same readings: a higher wall recall and a lower
    share of copter echoes labelled wall. figures: a dict with detector_/baseline_ wall_recall and copter_as_wall
    (the metrics of summarize, or a row of finken.sim_report.crowd)."""
    return {"wall_recall_beats_baseline": bool(figures["detector_wall_recall"] > figures["baseline_wall_recall"]),
            "copter_as_wall_beats_baseline":
            bool(figures["detector_copter_as_wall"] < figures["baseline_copter_as_wall"])}


def targets_met(metrics):
    """The targets every run keeps, whatever its size, each True/False: the detector beats the baseline (detector-on
    run), and the swarm holds together tighter with the detector than without it (lower cohesion). The bounds kept
    at given swarm sizes: finken.sim_report.targets."""
    return {**beats_baseline(metrics),
            "cohesion_tighter_with_detector": bool(metrics["cohesion_on"] < metrics["cohesion_off"])}


def format_table(metrics):
    """The metrics as a fixed-width text table."""
    rows = [("wall recall", "wall_recall"), ("wall precision", "wall_precision"),
            ("copter recall", "copter_recall"), ("copter precision", "copter_precision"),
            ("copter echoes labelled wall", "copter_as_wall"), ("undecided (unknown)", "undecided")]
    cls = metrics["classification"]
    header = f"{'per-reading classification':<30} {'detector':>9} {'baseline':>9}   {'detector':>9} {'baseline':>9}"
    lines = [f"{'':<30} {'detector-on run':>19}   {'detector-off run':>19}", header, "-" * len(header)]
    for label, key in rows:
        values = [cls[run][who][key] for run in ("on", "off") for who in ("detector", "baseline")]
        lines.append(f"{label:<30} {values[0]:>9.3f} {values[1]:>9.3f}   {values[2]:>9.3f} {values[3]:>9.3f}")
    for run in ("on", "off"):
        d = cls[run]["detector"]
        lines.append(f"echoes judged, detector-{run} run: {d['walls']} from walls, {d['copters']} from copters")
    lines += ["baseline: an echo within eps (0.286 m) of a ranging distance is a copter, else a wall", "",
              f"{'swarm':<30} {'det. off':>9} {'det. on':>9}", "-" * 50,
              f"{'time within 0.5 m of a wall':<30} {metrics['near_wall_fraction_off']:>9.3f} "
              f"{metrics['near_wall_fraction_on']:>9.3f}",
              f"{'cohesion [m]':<30} {metrics['cohesion_off']:>9.3f} {metrics['cohesion_on']:>9.3f}",
              "cohesion: the copters' mean distance to their centroid"]
    return "\n".join(lines)
