"""A sweep's runs on Dask (dask.distributed): a LocalCluster on this machine, or the scheduler of a running cluster.

dask_client(scheduler, workers): without a scheduler, a LocalCluster of `workers` worker processes (default: one per
usable core), one thread each, as each run is one single-threaded host at a time; with one (tcp://host:8786), a
client of it, refused at once with SchedulerUnreachable when it cannot be reached, and with WorkerCodeMismatch when
the scheduler (it unpickles the tasks) or a worker runs other code than ours (tools/finken compared by content) or
none: nothing is started then.

execute(): scatters the runs' files (each once), submits every pending run (finken.sweep.worker.run), stores each as
it arrives (finken.sweep.store), tries a failed run once more, and shows a progress bar (runs, done, failed, ETA).
"""
import hashlib
import io
import logging
import os
import sys
import tarfile
import uuid
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from finken.sweep import worker
from finken.sweep.points import run_key

#: seconds to wait for a scheduler before giving up (default)
CONNECT_TIMEOUT_S = 10.0
#: tries of a run per invocation: a failed run is tried once more
TRIES = 2
#: the finken package: what a worker must run the same
CODE_DIR = Path(__file__).resolve().parents[1]


class SchedulerUnreachable(RuntimeError):
    """The scheduler given cannot be reached."""


class WorkerCodeMismatch(RuntimeError):
    """The scheduler or a worker of the cluster runs other code than this checkout, or cannot import it."""


@dataclass
class Pending:
    """A run to fly: its point, seed and the tries stored so far (over every invocation)."""
    point: object
    seed: int
    attempts: int


@dataclass
class Outcome:
    """Runs stored as done and as failed (after their last try), and tries made again."""
    done: int = 0
    failed: int = 0
    retried: int = 0


def pending_runs(runs, states):
    """Pending runs of `runs` ([(point, seed)]) not done according to `states` (RunStore.states()), and the number
    of runs done before."""
    pending = []
    for point, seed in runs:
        status, attempts = states.get(run_key(point, seed), (None, 0))
        if status != "done":
            pending.append(Pending(point, seed, attempts))
    return pending, len(runs) - len(pending)


def code_fingerprint():
    """SHA-256 of the finken package's modules (every *.py under it): what a worker runs."""
    digest = hashlib.sha256()
    for path in sorted(CODE_DIR.rglob("*.py")):
        digest.update(str(path.relative_to(CODE_DIR)).encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()


@contextmanager
def dask_client(scheduler=None, workers=None, timeout_s=CONNECT_TIMEOUT_S):
    """A dask.distributed Client (module docstring), closed with its LocalCluster on leaving."""
    from distributed import Client, LocalCluster
    if scheduler is None:
        with LocalCluster(n_workers=workers or len(os.sched_getaffinity(0)), threads_per_worker=1, processes=True,
                          dashboard_address=None, silence_logs=logging.CRITICAL) as cluster, Client(cluster) as client:
            yield client
        return
    try:
        client = Client(scheduler, timeout=f"{timeout_s}s")
    except (OSError, TimeoutError) as err:
        raise SchedulerUnreachable(f"cannot reach the Dask scheduler at {scheduler} within {timeout_s:g} s "
                                   f"({err}); start one with `dask scheduler` (docs/sweeps.md)") from None
    with client:
        _check_code(client, scheduler)
        yield client


def _check_code(client, scheduler):
    """Raise WorkerCodeMismatch unless the scheduler (which reads the tasks) and every worker run our code."""
    ours = code_fingerprint()
    try:
        theirs = {"the scheduler": client.run_on_scheduler(code_fingerprint),
                  **{f"worker {w}": digest for w, digest in client.run(code_fingerprint).items()}}
    except Exception as err:   # anything the remote side raised: it cannot import or run the finken package
        raise WorkerCodeMismatch(f"the cluster of {scheduler} cannot run the finken package ({type(err).__name__}: "
                                 f"{err}): start its scheduler and workers with PYTHONPATH=<checkout>/tools "
                                 "(docs/sweeps.md)") from None
    other = sorted(name for name, digest in theirs.items() if digest != ours)
    if other:
        raise WorkerCodeMismatch(f"{', '.join(other)} (cluster at {scheduler}): other code than {CODE_DIR}; start "
                                 "the scheduler and workers from a checkout of the same commit (docs/sweeps.md)")


def execute(client, pending, inputs, store, keep_logs, logs_dir, progress=True):
    """Fly every Pending run on the client's workers; store each as it arrives. inputs: {point key: {name: Blob}}
    (finken.sweep.hosts.prepare_inputs). Returns an Outcome. Ctrl-C (KeyboardInterrupt) leaves every run stored so
    far in the store."""
    from distributed import as_completed
    from tqdm import tqdm
    blobs = {blob.digest: blob for files in inputs.values() for blob in files.values()}
    scattered = client.scatter({f"sweep-file-{d}": blob for d, blob in blobs.items()}, hash=False)
    token = uuid.uuid4().hex[:8]
    running = {}

    def submit(run, tries):
        files = {name: scattered[f"sweep-file-{blob.digest}"] for name, blob in inputs[run.point.key].items()}
        task = {"run_key": run_key(run.point, run.seed), "seed": run.seed, "keep_logs": keep_logs,
                "vehicles": run.point.values["vehicles"], "duration": run.point.values["duration"]}
        future = client.submit(worker.run, task, files, key=f"sweep-run-{task['run_key']}-{tries}-{token}",
                               pure=False)
        running[future.key] = (run, tries)
        return future

    futures = as_completed([submit(run, 0) for run in pending])
    outcome = Outcome()
    tty = sys.stderr.isatty()
    with tqdm(total=len(pending), unit="run", disable=not progress, file=sys.stderr, dynamic_ncols=True,
              mininterval=0.5 if tty else 10.0, desc="runs") as bar:
        for future in futures:
            run, tries = running.pop(future.key)
            run.attempts += 1
            key = run_key(run.point, run.seed)
            if future.status == "finished":
                result = future.result()
                if result["logs"]:
                    _unpack(result["logs"], logs_dir)
                store.record(key, run.point, run.seed, run.attempts, result=result)
                outcome.done += 1
            else:
                store.record(key, run.point, run.seed, run.attempts, error=_error_text(future))
                if tries + 1 < TRIES:
                    futures.add(submit(run, tries + 1))
                    outcome.retried += 1
                else:
                    outcome.failed += 1
            future.release()
            bar.set_postfix(done=outcome.done, failed=outcome.failed, refresh=False)
            bar.update(outcome.done + outcome.failed - bar.n)
    return outcome


def _error_text(future):
    if future.cancelled():
        return "cancelled (the cluster lost the run)"
    error = future.exception()
    return f"{type(error).__name__}: {error}"


def _unpack(logs, logs_dir):
    """Extract a run's logs (finken.sweep.worker's gzipped tar of OUT-like folder <run_key>/) into logs_dir."""
    logs_dir.mkdir(parents=True, exist_ok=True)
    with tarfile.open(fileobj=io.BytesIO(logs), mode="r:gz") as tar:
        tar.extractall(logs_dir, filter="data")
