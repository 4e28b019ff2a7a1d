"""One run of a sweep, on a Dask worker: make sim's two host runs for a point and a seed, and their metrics.

run(task, files) writes the task's files (the host with the wall detector and without, the arena, the sensor model:
finken.sweep.hosts.Blob) into the worker's temporary folder, once per content; runs each host with `--threads 1`
into a temporary folder laid out as make sim's OUT (the detector-on run, detector_off/); and turns the logs into
make sim's metrics.json with make sim's code (finken.sim_report.metrics), returned flattened (finken.sweep.metrics).
With keep_logs the folder, with metrics.json and report.txt (make sim's printed tables), comes back as a gzipped
tar.
"""
import contextlib
import io
import json
import os
import socket
import subprocess
import tarfile
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

from finken.sim_report.metrics import sim_metrics
from finken.sweep.metrics import flatten

#: where a worker keeps the files of the tasks, by content
CACHE = Path(tempfile.gettempdir()) / f"finken-sweep-{os.getuid()}"
#: file names of the task's files (the host reads a sensor model as a file when its name ends in .xml)
FILE_NAMES = {"host_on": "nps_host", "host_off": "nps_host", "arena": "arena.xml", "model": "sensor_model.xml"}
#: lines of a failed host's output kept in the error
ERROR_LINES = 4


class RunFailed(RuntimeError):
    """A host exited with an error: which run, the exit status and the host's last lines."""


def run(task, files):
    """Fly the run `task` ({run_key, seed, vehicles, duration, keep_logs}) with `files` ({"host_on", "host_off",
    "arena", "model": Blob}). Returns {metrics, started (UTC, ISO 8601), wall_s, worker, logs (bytes or None)}."""
    started = datetime.now(timezone.utc).isoformat(timespec="seconds")
    t0 = time.perf_counter()
    paths = {name: _cached(blob, FILE_NAMES[name]) for name, blob in files.items()}
    with tempfile.TemporaryDirectory(prefix="finken-sweep-run-") as tmp:
        on = Path(tmp) / task["run_key"]
        _fly(paths["host_on"], task, paths, on, "detector on")
        _fly(paths["host_off"], task, paths, on / "detector_off", "detector off")
        with contextlib.redirect_stdout(io.StringIO()) as tables:
            sim_metrics(on, on / "detector_off")
        metrics = flatten(json.loads((on / "metrics.json").read_text()))
        logs = None
        if task["keep_logs"]:
            (on / "report.txt").write_text(tables.getvalue())
            logs = _tar(on)
    return {"metrics": metrics, "started": started, "wall_s": time.perf_counter() - t0,
            "worker": f"{socket.gethostname()}:{os.getpid()}", "logs": logs}


def _fly(host, task, paths, out, label):
    command = [str(host), "--vehicles", str(task["vehicles"]), "--seed", str(task["seed"]), "--duration",
               repr(float(task["duration"])), "--threads", "1", "--quiet", "--arena", str(paths["arena"]),
               "--sensor-model", str(paths["model"]), "--out", str(out)]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        last = (done.stderr.strip() or done.stdout.strip()).splitlines()[-ERROR_LINES:]
        raise RunFailed(f"{label}: nps_host exited with status {done.returncode}: {' | '.join(last)}")


def _cached(blob, name):
    """The path of `blob` in CACHE, written (executable) if it is not there yet."""
    path = CACHE / f"{blob.digest[:32]}-{name}"
    if not path.is_file():
        CACHE.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(f".{path.name}.{os.getpid()}")
        partial.write_bytes(blob.data)
        partial.chmod(0o755)
        os.replace(partial, path)
    return path


def _tar(folder):
    """The folder as gzipped tar bytes, its files under the folder's name."""
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz", compresslevel=1) as tar:
        tar.add(folder, arcname=folder.name)
    return buffer.getvalue()
