"""The wall detector in a crowd: the last part of `make sim`.

After make sim's main pair of runs, the detector-on host flies again, same seed and duration, with 8 copters in
SwarmLab (conf/arena/swarmlab.xml) and with 16 in SwarmLab scaled to the same floor area per copter
(conf/arena/swarmlab_16.xml), then with 4 and 8 in each example arena that is no rectangle (EXAMPLE_ARENAS: an L
with a reentrant corner, SwarmLab with a pillar). For each, and for the main run, the per-reading classification of the wall detector
and of the single-reading baseline (the baseline_class column of the same detections.csv) with make sim's code
(finken.sim_report.detector_metrics.run_classification); a table, and the key "crowd" of metrics.json with the
targets of these runs (finken.sim_report.targets):

    "crowd": {"4_swarmlab": {"copters": 4, "arena": "conf/arena/swarmlab.xml", "logs": ".",
                             "detector_wall_recall": ..., "detector_copter_as_wall": ...,
                             "baseline_wall_recall": ..., "baseline_copter_as_wall": ...,
                             "wall_echoes": ..., "copter_echoes": ...},
              "8_swarmlab": {...}, "16_swarmlab_16": {...}, "4_swarmlab_l": {...}, ...,
              "targets": {"wall_recall_at_least_0.99_at_4": true, "wall_recall_beats_baseline_at_4": true, ...,
                          "wall_recall_at_least_0.90_at_8": true, "copter_as_wall_at_most_0.05_at_8": true, ...}}

A crowd run whose swarm size and arena are those of the main run is not flown again: its figures are the main
run's (logs "."). Every other option of the main run (seed, duration, sensor model, ...) is passed on unchanged.
"""
import json
import os
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from finken.atomic_output import atomic_output
from finken.run_logs import read_detections
from finken.sim_report.detector_metrics import run_classification
from finken.sim_report.detector_report import json_safe

#: the example arenas that are no rectangle, each flown with 4 and 8 copters
EXAMPLE_ARENAS = ("conf/arena/swarmlab_l.xml", "conf/arena/swarmlab_pillar.xml")
#: (copters, arena, logs folder in OUT) of the crowd runs: 8 in SwarmLab, 16 at the same floor area per copter
#: (1.5 m^2), then the example arenas
CROWD = ((8, "conf/arena/swarmlab.xml", "crowd_8"), (16, "conf/arena/swarmlab_16.xml", "crowd_16"),
         *((n, arena, f"crowd_{n}_{Path(arena).stem}") for arena in EXAMPLE_ARENAS for n in (4, 8)))
#: the host's options that a crowd run sets itself
OWN_OPTIONS = ("--vehicles", "--arena", "--out")
#: the figures of a row, in metrics.json and in the table
FIGURES = ("detector_wall_recall", "baseline_wall_recall", "detector_copter_as_wall", "baseline_copter_as_wall")


@dataclass
class HostArgs:
    """make sim's host options split: the swarm size and arena (None: the airframe's), and the rest as given."""
    vehicles: int
    arena: str | None
    rest: list


def split_host_args(args):
    """HostArgs of the host's command-line options `args` (make sim's SIM_ARGS). ValueError for an option
    without its value or a --vehicles that is not a whole number."""
    vehicles, arena, rest = 4, None, []
    items = iter(args)
    for item in items:
        name, eq, inline = item.partition("=")
        if name not in OWN_OPTIONS:
            rest.append(item)
            continue
        value = inline if eq else next(items, None)
        if value is None:
            raise ValueError(f"{name} without a value")
        if name == "--vehicles":
            if not value.isdigit():
                raise ValueError(f"--vehicles {value}: expected a whole number")
            vehicles = int(value)
        elif name == "--arena":
            arena = value
    return HostArgs(vehicles, arena, rest)


def row_key(copters, arena):
    """The key of a run in metrics.json's "crowd": copters and the arena file's stem, e.g. 8_swarmlab."""
    return f"{copters}_{Path(arena).stem}"


def same_arena(a, b):
    return os.path.realpath(a) == os.path.realpath(b)


def row_from_detections(copters, arena, logs, detections_csv):
    """The figures of one detector-on run from its detections.csv (make sim's per-reading classification)."""
    scores = run_classification(read_detections(detections_csv))
    return _row(copters, arena, logs, scores)


def row_from_metrics(copters, arena, metrics):
    """The figures of make sim's main run from its metrics.json (the detector-on run's classification; a score
    JSON holds as null, with nothing to compute it from, is NaN again)."""
    scores = {who: {k: float("nan") if v is None else v for k, v in s.items()}
              for who, s in metrics["classification"]["on"].items()}
    return _row(copters, arena, ".", scores)


def _row(copters, arena, logs, scores):
    row = {"copters": copters, "arena": str(arena), "logs": str(logs)}
    for who in ("detector", "baseline"):
        row[f"{who}_wall_recall"] = scores[who]["wall_recall"]
        row[f"{who}_copter_as_wall"] = scores[who]["copter_as_wall"]
    row["wall_echoes"] = scores["detector"]["walls"]
    row["copter_echoes"] = scores["detector"]["copters"]
    return row


def format_crowd_table(rows):
    """The rows as fixed-width text."""
    header = f"{'copters':>7}  {'arena':<28} {'detector':>9} {'baseline':>9}   {'detector':>9} {'baseline':>9}"
    lines = [f"{'':<37} {'wall recall':^19}   {'copter echoes labelled wall'}", header, "-" * len(header)]
    for row in rows:
        arena = Path(row["arena"]).name + (" (main run)" if row["logs"] == "." else "")
        values = " ".join(f"{row[k]:>9.3f}" for k in FIGURES[:2]) + "   " + \
            " ".join(f"{row[k]:>9.3f}" for k in FIGURES[2:])
        lines.append(f"{row['copters']:>7}  {arena:<28} {values}")
    lines.append("detector-on runs; baseline: the single-reading check on the same readings")
    return "\n".join(lines)


def fly_crowd(host, out, host_args, main_arena):
    """Fly the crowd runs that are not the main run with `host` into their folders of `out` (CROWD); returns the rows
    of the main run (first) and of each crowd run. RuntimeError when a host run fails."""
    out = Path(out)
    metrics = json.loads((out / "metrics.json").read_text())
    rows = [row_from_metrics(host_args.vehicles, main_arena, metrics)]
    for copters, arena, folder in CROWD:
        if copters == host_args.vehicles and same_arena(arena, main_arena):
            print(f"  {copters} copters in {arena}: the main run")
            continue
        logs = out / folder
        command = [str(host), *host_args.rest, "--vehicles", str(copters), "--arena", arena, "--quiet",
                   "--out", str(logs)]
        t0 = time.perf_counter()
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{' '.join(command)}: exit status {done.returncode}: "
                               f"{(done.stderr.strip() or done.stdout.strip())[-2000:]}")
        print(f"  {copters} copters in {arena} -> {logs} ({time.perf_counter() - t0:.1f} s)")
        rows.append(row_from_detections(copters, arena, folder, logs / "detections.csv"))
    return rows


def add_to_metrics(metrics_json, rows, targets):
    """Add the key "crowd" to metrics.json, every other key as it was."""
    metrics = json.loads(Path(metrics_json).read_text())
    metrics["crowd"] = {**{row_key(r["copters"], r["arena"]): r for r in rows}, "targets": targets}
    with atomic_output(metrics_json) as f:
        json.dump(json_safe(metrics), f, indent=2)
