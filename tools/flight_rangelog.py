#!/usr/bin/env python3
"""A lab's flight to a range log: the copters' records of every reading and the motion capture's poses give each
reading its true range (sonar: a ray cast from the sonar's mount against the arena as drawn; ranging: the distance
between the two copters) and the context columns our simulator writes (docs/calibration.md, "A lab's flight").

    tools/flight_rangelog.py --readings RECORD --mocap POSES --arena ARENA.xml --out LOG.csv [--airframe AIRFRAME.xml]
                             [--bodies NAME=ID,...] [--transform yaw=DEG,x=M,y=M,z=M] [--up y|z]
                             [--clock-offset S | --clock-offset ID=S,...] [--max-offset S] [--force]

`make rangelog READINGS=... MOCAP=... ARENA=... OUT=... [AIRFRAME=] [BODIES=] [TRANSFORM=] [CLOCK_OFFSET=]
[MAX_OFFSET=] [FORCE=1]` runs this. RECORD: a CSV of `t, vehicle, sensor, peer, measured` (the range_recorder
module's file) or Paparazzi's server log (.log/.data). POSES: a CSV of `t, body, x, y, z, qx, qy, qz, qw`, our
simulator's poses.csv, an OptiTrack Motive CSV export or Paparazzi's server log. Exit status: 0 written, 2 bad input
(nothing written), 1 when the output cannot be written.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from finken.atomic_output import WriteError  # noqa: E402
from finken.flight.clock import MAX_OFFSET_S, ClockError  # noqa: E402
from finken.flight.errors import FlightInputError  # noqa: E402
from finken.flight.flight_log import flight_range_log, parse_offsets  # noqa: E402
from finken.flight.mocap import FORMATS, read_mocap  # noqa: E402
from finken.flight.mounts import sonar_mounts, sonar_timing  # noqa: E402
from finken.flight.records import read_records  # noqa: E402
from finken.flight.truth import ArenaError, ArenaTruth  # noqa: E402
from finken.progress_line import ProgressLine  # noqa: E402
from finken.rangelog import write_range_log  # noqa: E402
from finken.xml_errors import XmlInputError  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
DEFAULT_AIRFRAME = REPO / "conf/airframes/finken_nps.xml"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--readings", required=True, help="the copters' records (CSV or Paparazzi's .log/.data)")
    ap.add_argument("--decisions", help="the range_recorder's decisions CSV, reported with the readings")
    ap.add_argument("--mocap", required=True, help="motion-capture poses")
    ap.add_argument("--mocap-format", default="auto", choices=("auto",) + tuple(FORMATS))
    ap.add_argument("--arena", required=True, help="the arena file (conf/arena/*.xml)")
    ap.add_argument("--airframe", default=str(DEFAULT_AIRFRAME),
                    help="where the sonars sit (default: the airframe make sim flies)")
    ap.add_argument("--bodies", default="", help="bodies to vehicles: finken1=1,finken2=2 (default: the number at "
                    "the end of each body's name; name=- leaves a body out)")
    ap.add_argument("--transform", default="", help="the motion capture's frame to the arena's: yaw=DEG,x=M,y=M,z=M")
    ap.add_argument("--up", choices=("y", "z"), help="the motion capture's up axis (default: y for Motive, else z)")
    ap.add_argument("--clock-offset", default="", help="mocap time minus record time [s], for every copter or per "
                    "vehicle (1=0.25,2=-1.5); the others are estimated")
    ap.add_argument("--max-offset", type=float, default=MAX_OFFSET_S,
                    help=f"search clock offsets within +- this [s] (default {MAX_OFFSET_S:g})")
    ap.add_argument("--out", required=True, help="the range log to write")
    ap.add_argument("--force", action="store_true", help="replace an existing --out")
    ap.add_argument("--quiet", action="store_true", help="no progress display")
    args = ap.parse_args(argv)
    out = Path(args.out)
    if out.exists() and not args.force:
        print(f"rangelog: {out} exists: give FORCE=1 (--force) to replace it", file=sys.stderr)
        return 2
    try:
        offsets = parse_offsets(args.clock_offset)
        records = read_records(args.readings, decisions=args.decisions)
        poses = read_mocap(args.mocap, fmt=args.mocap_format, bodies=args.bodies or None,
                           transform=args.transform or None, up=args.up)
        with ArenaTruth(args.arena) as arena:
            mounts = sonar_mounts(args.airframe, arena.sonar_offset_m)
            timing = sonar_timing(args.airframe)
            print(f"{args.readings}: {len(records)} readings of vehicles "
                  f"{', '.join(map(str, sorted(set(records.vehicle.tolist()))))}")
            for line in poses.report_lines():
                print(line)
            print(f"sonar mounts: {mounts.source}")
            progress = None if args.quiet else ProgressLine()
            show = None if progress is None else (lambda i, n: progress.show(f"ray casts: {i}/{n} readings"))
            log, report = flight_range_log(arena, mounts, records, poses, offsets, args.max_offset, timing, show)
            if progress is not None:
                progress.done()
    except (FlightInputError, ClockError, ArenaError, XmlInputError, ValueError) as err:
        print(f"rangelog: {err}", file=sys.stderr)
        return 2
    for line in report.lines():
        print(line)
    try:
        write_range_log(out, log)
    except WriteError as err:
        print(f"rangelog: {err}", file=sys.stderr)
        return 1
    print(f"wrote {out}: {report.written} readings")
    return 0


if __name__ == "__main__":
    sys.exit(main())
