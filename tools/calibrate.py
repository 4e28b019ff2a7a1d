#!/usr/bin/env python3
"""Discrepancy workflow (shared/spec/discrepancy-report.md): compare a measured range log with the sensor
model's replay of it, name and fit the missing effects, write OUT/report.json, OUT/report.html, OUT/model.xml.

    tools/calibrate.py --measured LOG.csv --model MODEL.xml --out DIR [--seed N] [--force] [--max-range M]
                       [--columns SPEC=FILE,...] [--fill SPEC=VALUE,...] [--unit mm] [--split-by COLUMN]

`make calibrate MEASURED=... MODEL=... OUT=... [SEED=] [FORCE=1] [MAX_RANGE=] [COLUMNS=] [FILL=] [UNIT=]
[SPLIT_BY=]` runs this. A sensor's glitches (negative, zero, infinite or absurd readings) are data: counted,
reported and modelled, never refused. Exit status: 0 done, 2 bad input (an option, a log breaking the spec, a
model that does not load, OUT already holding a report without --force), 1 when an output cannot be written
(each output replaces its old file only when complete).
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from finken import models  # noqa: E402
from finken.atomic_output import WriteError  # noqa: E402
from finken.cli_types import SEED_MAX, integer  # noqa: E402
from finken.discrepancy import glitches, log_options  # noqa: E402
from finken.discrepancy.dataset import IncompatibleInputError, check_compatible  # noqa: E402
from finken.discrepancy.ranges import describe, sensor_ranges  # noqa: E402
from finken.discrepancy.report import OutputExistsError, check_output_dir, write_outputs  # noqa: E402
from finken.discrepancy.workflow import calibrate  # noqa: E402
from finken.rangelog import RangeLogError  # noqa: E402

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--measured", required=True, help="measured range log (CSV, shared/spec/range-log.md)")
    ap.add_argument("--model", required=True, help="sensor model file to start from (e.g. "
                    "conf/sensor_models/gaussian_only.xml)")
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--seed", type=integer(0, SEED_MAX), default=1,
                    help=f"seed of every random choice, 0 to {SEED_MAX} as the simulator's (default 1)")
    ap.add_argument("--force", action="store_true", help="overwrite a report already in --out")
    ap.add_argument("--quiet", action="store_true", help="no progress display")
    log_options.add_max_range(ap)
    log_options.add_arguments(ap)
    args = ap.parse_args(argv)
    try:
        check_output_dir(args.out, args.force)
        log = log_options.read_log(args.measured, args, show_progress=not args.quiet)
        model = models.SensorModel.load(args.model, log_columns=log.ctx)   # conditions on the log's columns
        check_compatible(log, model)       # the log's sensor kinds must have chains in the model
    except (OutputExistsError, NotADirectoryError, models.ModelError, RangeLogError, IncompatibleInputError) as err:
        print(f"calibrate: {err}", file=sys.stderr)
        return 2
    code = glitches.classify_log(log, glitches.limits(log, model))
    for line in describe(sensor_ranges(log, model, code > 0), model) + glitches.describe(
            glitches.counts(log, code)["kinds"], []):
        print(line)
    fixed = log_options.expand_max_range(args.max_range, model.chains)
    handed_over = [log]       # held only by the workflow, which frees it once split by sensor kind (big logs)
    del log
    result = calibrate(handed_over.pop(), model, seed=args.seed, show_progress=not args.quiet, max_range=fixed)
    try:
        out = write_outputs(args.out, result, force=args.force)
    except WriteError as err:
        print(f"calibrate: {err}", file=sys.stderr)
        return 1
    for e in result.effects:
        if e.stability is not None and not e.stability.stable:
            print(f"unstable name: {e.stability.text()}")
    print(result.verdict)
    print(f"gap before {result.gap_before:.4g} m, after {result.gap_after:.4g} m, noise floor "
          f"{result.gap_floor:.4g} m ({result.elapsed_s:.0f} s)")
    print(f"wrote {out / 'report.json'}, {out / 'report.html'}, {out / 'model.xml'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
