#!/usr/bin/env python3
"""Monte-Carlo sweeps on Dask: make sim's runs over parameter points and seeds, their metrics in one store.

    tools/sweep.py conf/sweeps/<name>.yaml [--out build/sweep/<name>] [--scheduler tcp://host:8786]
                   [--connect-timeout S] [--workers N] [--quiet]

Checks the sweep file (finken.sweep.spec; nothing runs if it is refused), builds the hosts its points need (make
host), flies every run not yet done in OUT/runs.sqlite on a Dask LocalCluster of one worker per core, or on the
cluster of --scheduler, storing each run as it arrives, then writes OUT/points.csv, OUT/plots/ and OUT/summary.html.
`make sweep SWEEP=... [SCHEDULER=...] [OUT=...]` runs this. docs/sweeps.md.

Exit status: 0 every run done; 1 some runs failed after their second try (summary.html lists them), the scheduler
cannot be reached, a host does not build, or an output cannot be written; 2 a bad sweep file or option; 130 on
Ctrl-C (every finished run is stored: the same command goes on from there).
"""
import argparse
import os
import sys
from contextlib import ExitStack
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from finken.atomic_output import WriteError  # noqa: E402
from finken.cli_types import integer, real  # noqa: E402
from finken.sweep.engine import (CONNECT_TIMEOUT_S, SchedulerUnreachable, WorkerCodeMismatch,  # noqa: E402
                                 dask_client, execute, pending_runs)
from finken.sweep.hosts import HostBuildError, prepare_inputs  # noqa: E402
from finken.sweep.points import run_key  # noqa: E402
from finken.sweep.report import write_report  # noqa: E402
from finken.sweep.spec import load_sweep  # noqa: E402
from finken.sweep.store import RunStore  # noqa: E402
from finken.sweep.yaml_lines import SweepFileError  # noqa: E402


def default_out(name):
    return Path(os.environ.get("FINKEN_BUILD") or Path(__file__).resolve().parent.parent / "build") / "sweep" / name


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sweep", type=Path, help="sweep file (YAML), e.g. conf/sweeps/sonar_noise.yaml")
    ap.add_argument("--out", type=Path, help="output folder (default build/sweep/<sweep file name>)")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (tcp://host:8786); default: a "
                                        "LocalCluster on this machine")
    ap.add_argument("--workers", type=integer(1, 1024), help="LocalCluster workers (default: one per usable core)")
    ap.add_argument("--connect-timeout", type=real(0.0, low_open=True), default=CONNECT_TIMEOUT_S, metavar="S",
                    help=f"seconds to wait for --scheduler (default {CONNECT_TIMEOUT_S:g})")
    ap.add_argument("--quiet", action="store_true", help="no progress bar")
    args = ap.parse_args(argv)
    if args.scheduler and args.workers:
        ap.error("--workers sizes the LocalCluster; a --scheduler's cluster has its own workers")
    try:
        sweep = load_sweep(args.sweep)
    except SweepFileError as err:
        print(f"sweep: {err}", file=sys.stderr)
        return 2
    except OSError as err:
        print(f"sweep: {args.sweep}: cannot read: {err.strerror}", file=sys.stderr)
        return 2
    out = args.out or default_out(sweep.name)
    try:
        return run(sweep, out, args)
    except (SchedulerUnreachable, WorkerCodeMismatch, HostBuildError, WriteError) as err:
        print(f"sweep: {err}", file=sys.stderr)
        return 1
    except OSError as err:
        print(f"sweep: {out}: {err}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print(f"\nsweep: interrupted; every finished run is in {out / 'runs.sqlite'}: run the same command again to "
              "go on", file=sys.stderr)
        return 130


def run(sweep, out, args):
    """Fly the sweep's pending runs and write the report; the exit status."""
    with ExitStack() as stack:
        client = stack.enter_context(dask_client(args.scheduler, timeout_s=args.connect_timeout)) \
            if args.scheduler else None
        out.mkdir(parents=True, exist_ok=True)
        store = RunStore(out / "runs.sqlite")
        stack.callback(store.close)
        pending, skipped = pending_runs(sweep.runs, store.states())
        print(f"sweep {sweep.name}: {len(sweep.points)} points x {len(sweep.seeds)} seeds = {len(sweep.runs)} runs; "
              f"{skipped} done before, {len(pending)} to fly")
        note = f"{skipped} runs done before, nothing to fly"
        if pending:
            inputs = prepare_inputs(sweep, list({run.point.key: run.point for run in pending}.values()))
            client = client or stack.enter_context(dask_client(None, args.workers))
            print(f"on {len(client.scheduler_info()['workers'])} Dask workers ({client.scheduler.address})")
            outcome = execute(client, pending, inputs, store, sweep.keep_logs, out / "logs", not args.quiet)
            note = (f"{outcome.done} runs done, {outcome.failed} failed after a second try, {outcome.retried} tried "
                    f"again, {skipped} done before")
        paths, table = write_report(sweep, store, out / "runs.sqlite", out, note)
        states = store.states()
    failed = sum(states.get(run_key(point, seed), ("",))[0] == "failed" for point, seed in sweep.runs)
    print(f"{note}\n{table}\nwrote {', '.join(str(p) for p in paths)}")
    if failed:
        print(f"sweep: {failed} runs failed: see {out / 'summary.html'}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
