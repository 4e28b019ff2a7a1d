#!/usr/bin/env python3
"""Convert a can-utils `candump -l` log of ranging frames into a range log (shared/spec/range-log.md).

    python tools/candump_to_rangelog.py LOG --poses POSES.csv -o OUT.csv [--interface can0]
                                        [--time-offset S] [--max-pose-gap S]
                                        [--id-base 0x300] [--nb-nodes 64] [--range-max-mm 60000]

The range-log format requires a ground truth, and a CAN log carries none: it comes from a motion-capture
poses file (t, vehicle, x, y, z, yaw; t on the log's clock after --time-offset). Readings without a pose at
their time are left out and counted. The summary goes to stderr; the exit status is 1 with one message naming
the file (and line) on bad input. Frames are parsed and decoded by the C code the Linux driver runs
(libfinken_can.so, built by `make build`; FINKEN_CAN_LIB overrides its path).
"""
import argparse
import sys

try:
    from finken.can.candump import CandumpError, read_candump
    from finken.can.candump_rangelog import ConversionError, convert
    from finken.cli_types import integer, real
    from finken.run_logs import read_poses
    from finken.can.ranging_frame import Layout
    from finken.rangelog import RangeLogError, write_range_log
except ImportError as err:  # the C codec library not built yet (finken.can._native says how), or a missing package
    sys.exit(f"candump_to_rangelog: {err}")

LAYOUT_FIELD_MAX = 65535   # the layout's fields are uint16 (struct ranging_can_layout); the C check does the rest


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", help="candump -l log")
    parser.add_argument("--poses", required=True,
                        help="motion-capture poses (t, vehicle, x, y, z, yaw): the ground truth the range log needs")
    parser.add_argument("-o", "--output", required=True, help="range log to write (CSV)")
    parser.add_argument("--interface", help="use only frames logged on this interface (default: all)")
    parser.add_argument("--time-offset", type=real(), default=0.0, help="added to log times to get pose times [s]")
    parser.add_argument("--max-pose-gap", type=real(0, inf_ok=True), default=0.1,
                        help="longest gap between two poses to interpolate across [s] (default 0.1; inf: any)")
    parser.add_argument("--id-base", type=integer(0, LAYOUT_FIELD_MAX, hex_ok=True), default=Layout.id_base,
                        help="CAN id of node 0 (default 0x300)")
    parser.add_argument("--nb-nodes", type=integer(0, LAYOUT_FIELD_MAX), default=Layout.nb_nodes,
                        help="number of node ids (default 64)")
    parser.add_argument("--range-max-mm", type=integer(0, LAYOUT_FIELD_MAX), default=Layout.range_max_mm,
                        help="largest valid range [mm] (default 60000)")
    args = parser.parse_args(argv)
    layout = Layout(args.id_base, args.nb_nodes, args.range_max_mm)
    try:
        layout.check()
        frames = read_candump(args.log)
        poses = read_poses(args.poses)
        log, summary = convert(frames, poses, layout, args.interface, args.time_offset, args.max_pose_gap,
                               path=args.log)
        write_range_log(args.output, log)
    except (CandumpError, RangeLogError, ConversionError, ValueError, OSError) as err:
        print(f"candump_to_rangelog: {err}", file=sys.stderr)
        return 1
    for line in summary.lines():
        print(line, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
