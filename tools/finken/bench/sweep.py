"""Stage sweep of `make bench`: how fast the Dask sweep engine flies runs, on 1 worker and on 2, and what it costs
per run beyond the run itself.

The runs are make sim's pair (finken.sweep.worker) of 4 copters for 60 s simulated, seeds 1..runs, on a LocalCluster
of 1 worker, then of 2, for each repetition, each into a fresh store. The hosts are built, every worker has imported
the worker's code and the clock starts when the runs are submitted (it covers scattering the files, submitting,
running and storing every run) and stops when the last is stored: what a long sweep spends per run.

  sweep_runs_per_min_1, _2   runs per minute with 1 and with 2 workers (median over the repetitions)
  sweep_run_s_1, _2          a run's own time on its worker with 1 and with 2 workers (median over every run) [s]:
                             the second is longer when the two runs compete for the machine
  sweep_overhead_pct         100 (wall time per run with 1 worker - the mean of the runs' own times) / that mean,
                             median over the repetitions [%]
  sweep_busy_2               the share of the wall time the 2 workers spend in runs: sum of the runs' own times /
                             (2 x wall time), median over the repetitions (1: the engine never keeps a worker
                             waiting); sweep_speedup_2_1 is about 2 x sweep_busy_2 x sweep_run_s_1 / sweep_run_s_2
  cpu_parallel_2_1           measured just before each 2-worker sweep: how much faster two processes of a busy loop
                             get through their work than one (2 when both cores are free, less while other programs
                             use them): what the machine gave a second worker at that time
and, derived by finken.bench.report, sweep_speedup_2_1 (2 workers against 1).
"""
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from finken.sweep.engine import dask_client, execute, pending_runs
from finken.sweep.hosts import prepare_inputs
from finken.sweep.spec import load_sweep
from finken.sweep.store import RunStore

#: the runs: make sim's copters for a minute
SWEEP_YAML = """description: make bench, stage sweep
airframe: {airframe}
vehicles: 4
duration: 60
seeds: {runs}
"""
WORKERS = (1, 2)
#: the busy loop of cpu_parallel_2_1 (about half a second on the development machine)
BUSY_LOOP = "for _ in range(15_000_000): pass"


def _import_worker_code():
    """Run on every worker before the clock starts: the first task would otherwise pay the imports."""
    import finken.sweep.worker  # noqa: F401
    return True


def _parallel_capacity():
    """2 x (time of one busy loop alone) / (time of two at once): cpu_parallel_2_1 of one repetition."""
    def loops(count):
        t0 = time.perf_counter()
        procs = [subprocess.Popen([sys.executable, "-c", BUSY_LOOP]) for _ in range(count)]
        for proc in procs:
            proc.wait()
        return time.perf_counter() - t0
    return 2.0 * loops(1) / loops(2)


def _timed_sweep(sweep, inputs, workers, folder):
    """(wall time [s] from submitting to the last run stored, the runs' own times [s]) on `workers` workers."""
    store = RunStore(folder / f"runs_{workers}.sqlite")
    try:
        pending, _ = pending_runs(sweep.runs, store.states())
        with dask_client(None, workers) as client:
            client.run(_import_worker_code)
            t0 = time.perf_counter()
            outcome = execute(client, pending, inputs, store, False, folder / "logs", progress=False)
            wall_s = time.perf_counter() - t0
        if outcome.failed:
            raise RuntimeError(f"bench sweep: {outcome.failed} runs failed: {store.rows()[0].get('error')}")
        return wall_s, [row["wall_s"] for row in store.rows()]
    finally:
        store.close()


def sweep_figures(airframe, work, reps, runs):
    """The stage's figures (module docstring): `reps` repetitions of `runs` runs on each number of workers."""
    work.mkdir(parents=True, exist_ok=True)
    spec = work / "bench_sweep.yaml"
    spec.write_text(SWEEP_YAML.format(airframe=airframe, runs=runs))
    sweep = load_sweep(spec)
    inputs = prepare_inputs(sweep, sweep.points, note=lambda text: None)
    per_min = {w: [] for w in WORKERS}
    own_s = {w: [] for w in WORKERS}
    overhead, busy, capacity = [], [], []
    for rep in range(reps):
        for workers in WORKERS:
            if workers == 2:
                capacity.append(_parallel_capacity())
            with tempfile.TemporaryDirectory(prefix="finken_bench_sweep_") as folder:
                wall_s, run_s = _timed_sweep(sweep, inputs, workers, Path(folder))
            per_min[workers].append(60.0 * runs / wall_s)
            own_s[workers] += run_s
            if workers == 1:
                overhead.append(100.0 * (wall_s / runs - statistics.fmean(run_s)) / statistics.fmean(run_s))
            else:
                busy.append(sum(run_s) / (workers * wall_s))
            print(f"    sweep, {workers} worker(s), repetition {rep + 1}: {runs} runs in {wall_s:.1f} s "
                  f"({per_min[workers][-1]:.0f} runs/min)", flush=True)
    return [*(_figure(f"sweep_runs_per_min_{w}", per_min[w], "1/min") for w in WORKERS),
            *(_figure(f"sweep_run_s_{w}", own_s[w], "s") for w in WORKERS),
            _figure("sweep_overhead_pct", overhead, "%"), _figure("sweep_busy_2", busy, "x"),
            _figure("cpu_parallel_2_1", capacity, "x")]


def _figure(name, values, unit):
    values = sorted(values)
    return {"name": name, "value": statistics.median(values), "unit": unit, "reps": len(values),
            "min": values[0], "max": values[-1]}
