#!/usr/bin/env python3
"""The wall detector in a crowd, and the targets: the last part of `make sim` (finken.sim_report.crowd, .targets).

Flies the detector-on host, with make sim's other options, at 8 copters in SwarmLab, at 16 in
conf/arena/swarmlab_16.xml (into OUT/crowd_8, OUT/crowd_16) and at 4 and 8 in the example arenas that are no
rectangle (OUT/crowd_<n>_<arena>; finken.sim_report.crowd.CROWD), not again when the main run is one of them; prints
wall recall and copter echoes labelled wall of the detector and the baseline next to the main run's, then every
target the project keeps with its figure, what the figure is compared with and whether it is met; adds the runs and
their targets to OUT/metrics.json as "crowd". Run after tools/sim_report.py. Exit status 3 when a target is missed
(the table says which), 1 on bad logs or an output not written.

Usage: sim_crowd.py --out build/sim --host build/host/finken_nps/nps_host --airframe conf/airframes/finken_nps.xml
                    -- --vehicles 4 --seed 1 --duration 180 [--arena FILE] [--sensor-model M] ...
"""
import argparse
import json
import sys
from pathlib import Path

from finken.conf.airframe import airframe_arena
from finken.sim_report.crowd import add_to_metrics, fly_crowd, format_crowd_table, split_host_args
from finken.sim_report.targets import cohesion_target, detector_targets, format_targets


#: exit status when a target the project keeps is missed (every output is written all the same)
TARGET_MISSED = 3


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    own, host = (argv[:argv.index("--")], argv[argv.index("--") + 1:]) if "--" in argv else (argv, [])
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], allow_abbrev=False)
    parser.add_argument("--out", required=True, type=Path, help="make sim's OUT (with the main run's metrics.json)")
    parser.add_argument("--host", required=True, type=Path, help="the detector-on host (make host)")
    parser.add_argument("--airframe", required=True, help="its airframe (the default arena)")
    args = parser.parse_args(own)
    try:
        host_args = split_host_args(host)
        main_arena = host_args.arena or airframe_arena(args.airframe)
        print("\n== The wall detector in a crowd: detector-on runs, same seed and duration")
        rows = fly_crowd(args.host, args.out, host_args, main_arena)
        print("\nWall detector in a crowd (per-reading classification)")
        print(format_crowd_table(rows))
        crowd_targets = [target for row in rows for target in detector_targets(row)]
        main_run = json.loads((args.out / "metrics.json").read_text())
        targets = crowd_targets + [cohesion_target(main_run, rows[0])]
        print()
        print(format_targets(targets))
        add_to_metrics(args.out / "metrics.json", rows,
                       {key: met for target in crowd_targets for key, met in target.checks.items()})
    except (ValueError, RuntimeError, OSError) as err:   # ValueError: bad logs or airframe; OSError: not written
        print(f"error: {err}", file=sys.stderr)
        return 1
    print(f"  wrote {args.out / 'metrics.json'} (key crowd)")
    return 0 if all(target.met for target in targets) else TARGET_MISSED


if __name__ == "__main__":
    sys.exit(main())
