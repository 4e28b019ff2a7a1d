"""The command-line options that say how to read a lab's own range log, shared by tools/calibrate.py and
tools/evaluate.py, and the reading itself with a progress bar.

    --columns measured=rng,true_range=real_rng,ctx_nlos=NLOS   the file's names of the spec's columns
    --fill sensor=ranging,vehicle=1,peer=2                     spec columns the file does not have
    --unit mm                                                  true_range and measured in mm (m, cm, mm)
    --split-by recording                                       a recording id column: rows of one recording
                                                               are one stream, held out together
"""
import argparse

from finken.cli_types import real
from finken.discrepancy import progress
from finken.discrepancy.dataset import KINDS
from finken.rangelog import parse_column_map, parse_fill, read_range_log

UNITS = ("m", "cm", "mm")


def add_arguments(ap):
    """Add the reading options to an argparse parser."""
    ap.add_argument("--columns", type=_checked(parse_column_map), default=None, metavar="SPEC=FILE,...",
                    help="the file's names of spec columns, e.g. measured=rng,true_range=real_rng,ctx_nlos=NLOS")
    ap.add_argument("--fill", type=_checked(parse_fill), default=None, metavar="SPEC=VALUE,...",
                    help="spec columns the file lacks, one value for every row, e.g. sensor=ranging,vehicle=1,peer=2")
    ap.add_argument("--unit", choices=UNITS, default="m", help="unit of true_range and measured in the file (m)")
    ap.add_argument("--split-by", default=None, metavar="COLUMN",
                    help="a column naming the recording of each row: held-out data are whole recordings, and each "
                         "recording is its own stream (it may start again at t = 0)")


def _checked(parse):
    """An argparse type from a parser that raises ValueError."""
    def convert(text):
        try:
            return parse(text)
        except ValueError as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    convert.__name__ = parse.__name__
    return convert


def parse_max_range(text):
    """--max-range: one number for every kind ({'*': m}) or kind=number pairs ({'ranging': m, ...}) [m]."""
    out = {}
    for part in text.split(","):
        kind, _, value = part.rpartition("=")
        kind = kind.strip() or "*"
        if kind != "*" and kind not in KINDS:
            raise argparse.ArgumentTypeError(f"'{kind}' is not a sensor kind (expected {' or '.join(KINDS)})")
        out[kind] = real(0.0, low_open=True)(value)
    return out


def add_max_range(ap):
    """Add --max-range (calibrate only: evaluate takes the models as they are)."""
    ap.add_argument("--max-range", type=parse_max_range, default=None, metavar="M|KIND=M,...",
                    help="keep this maximum range [m] (for every kind, or per kind: ranging=15,sonar=3) instead of "
                         "fitting it from the readings")


def expand_max_range(fixed, kinds):
    """{kind: m} for the given kinds from parse_max_range's result (None: nothing fixed)."""
    if not fixed:
        return {}
    return {k: fixed.get(k, fixed.get("*")) for k in kinds if k in fixed or "*" in fixed}


def read_log(path, args, show_progress):
    """Read the range log with the options of add_arguments, with a progress bar of bytes read."""
    with progress.bar(None, "reading", show_progress, unit="B") as bar:
        def advance(done, total):
            bar.total = total
            bar.update(done - bar.n)

        return read_range_log(path, columns=args.columns, unit=args.unit, fill=args.fill, group=args.split_by,
                              progress=advance)
