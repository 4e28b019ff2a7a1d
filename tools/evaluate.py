#!/usr/bin/env python3
"""Score sensor models on a measured range log without fitting anything: each model's gap (the discrepancy
workflow's metric), noise floor and gap per condition, on the same rows and simulator seeds for every model;
writes OUT/evaluate.json and OUT/evaluate.html.

    tools/evaluate.py --measured LOG.csv --model A.xml [--model B.xml ...] --out DIR [--seed N] [--force] [--quiet]
                      [--columns SPEC=FILE,...] [--fill SPEC=VALUE,...] [--unit mm] [--split-by COLUMN]

`make evaluate MEASURED=... MODEL=... [MODEL2=... MODEL9=] OUT=... [SEED=] [FORCE=1]` runs this. Exit status:
0 done, 2 bad input (an option, a log breaking the spec, a model that does not load or lacks a chain the log
needs, OUT already holding an evaluation without --force), 1 when an output cannot be written.
"""
import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from finken import models  # noqa: E402
from finken.atomic_output import WriteError  # noqa: E402
from finken.cli_types import SEED_MAX, integer  # noqa: E402
from finken.discrepancy import log_options  # noqa: E402
from finken.discrepancy.dataset import IncompatibleInputError  # noqa: E402
from finken.discrepancy.evaluate import evaluate  # noqa: E402
from finken.discrepancy.evaluate_output import check_output_dir, write_outputs  # noqa: E402
from finken.discrepancy.report import OutputExistsError  # noqa: E402
from finken.rangelog import RangeLogError  # noqa: E402


def summary_lines(ev):
    """One line per model (gap, floor, rows beyond its range), then the best model."""
    lines = []
    for s in ev.scores:
        beyond = sum(max(b.true_beyond, b.readings_beyond) for b in s.beyond_range)
        note = f"; about {beyond} rows outside its range" if beyond else ""
        glitch = ", ".join(f"{k} {r:.3%} (log {ev.glitch_rate[k]:.3%})" for k, r in s.glitch_rate.items())
        lines.append(f"{s.name}: gap {s.gap:.4g} m, noise floor {s.floor:.4g} m (gap/floor {s.ratio:.3g}); glitch "
                     f"rate {glitch}{note}")
    best = ev.best()
    tied = f" (tied with {', '.join(s.name for s in best[1:])})" if len(best) > 1 else ""
    lines.append(f"best: {best[0].name}{tied}")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--measured", required=True, help="measured range log (CSV, shared/spec/range-log.md)")
    ap.add_argument("--model", required=True, action="append",
                    help="sensor model file to score; repeat for each model to compare")
    ap.add_argument("--out", required=True, help="output folder")
    ap.add_argument("--seed", type=integer(0, SEED_MAX), default=1,
                    help=f"seed of every random choice, 0 to {SEED_MAX} as the simulator's (default 1)")
    ap.add_argument("--force", action="store_true", help="overwrite an evaluation already in --out")
    ap.add_argument("--quiet", action="store_true", help="no progress display")
    log_options.add_arguments(ap)
    args = ap.parse_args(argv)
    try:
        check_output_dir(args.out, args.force)
        log = log_options.read_log(args.measured, args, show_progress=not args.quiet)
        named = [(path, models.SensorModel.load(path, log_columns=log.ctx)) for path in args.model]
        ev = evaluate(log, named, seed=args.seed, show_progress=not args.quiet)   # checks every model first
    except (OutputExistsError, NotADirectoryError, models.ModelError, RangeLogError, IncompatibleInputError) as err:
        print(f"evaluate: {err}", file=sys.stderr)
        return 2
    try:
        out = write_outputs(args.out, ev, force=args.force)
    except WriteError as err:
        print(f"evaluate: {err}", file=sys.stderr)
        return 1
    print("\n".join(summary_lines(ev)))
    print(f"wrote {out / 'evaluate.json'}, {out / 'evaluate.html'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
