"""The host programs and input files of a sweep's runs, prepared where the sweep starts.

Each run flies make sim's two hosts: the airframe built with the point's defines, and the same with
SWARM_USE_WALL_DETECTOR=FALSE. make builds them (`make host`): a point without defines uses make sim's builds
(build/host/<airframe> and <airframe>_detector_off), each set of defines its own, <airframe>_sweep_<hash> and
<airframe>_sweep_<hash>_detector_off, built once without profile-guided optimisation (HOST_PGO=0: one compilation,
a few seconds; the logs are the same bytes, tests/python/test_host.py). The programs, the arena and the sensor model
of a run travel with its task as Blobs (finken.sweep.worker), so that a worker needs no build of its own.
"""
import hashlib
import os
import subprocess
from dataclasses import dataclass
from pathlib import Path

from finken.conf.airframe_modules import REPO_ROOT

DETECTOR_OFF = {"SWARM_USE_WALL_DETECTOR": "FALSE"}


class HostBuildError(RuntimeError):
    """make could not build a host."""


@dataclass(frozen=True)
class Blob:
    """A file's bytes and their SHA-256 (hex), under which a worker keeps it."""
    data: bytes
    digest: str

    @classmethod
    def of(cls, data):
        return cls(data, hashlib.sha256(data).hexdigest())


def point_defines(point):
    """{NAME: C text} of a point's defines: true/false as TRUE/FALSE, a float with its decimal point."""
    defines = {}
    for key, value in point.values.items():
        if key.startswith("defines."):
            if isinstance(value, bool):
                value = "TRUE" if value else "FALSE"
            defines[key.split(".", 1)[1]] = repr(value) if isinstance(value, float) else str(value)
    return defines


def build_host(airframe, defines, detector=True):
    """Path of the host of `airframe` with `defines` ({NAME: text}), built by make if needed; detector=False: the
    swarm ignores the wall detector (make sim's second run). Raises HostBuildError with make's output."""
    build = Path(os.environ.get("FINKEN_BUILD") or REPO_ROOT / "build").resolve()
    # make sim's spelling of the default folder, so that both share make's dependency files
    build_arg = "build" if build == (REPO_ROOT / "build").resolve() else str(build)
    text = " ".join(f"{name}={value}" for name, value in sorted(defines.items()))
    variant = f"_sweep_{hashlib.sha256(text.encode()).hexdigest()[:10]}" if defines else ""
    if not detector:
        variant += "_detector_off"
        text = " ".join(filter(None, (text, *(f"{n}={v}" for n, v in DETECTOR_OFF.items()))))
    command = ["make", "--no-print-directory", "host", f"BUILD={build_arg}", f"AIRFRAME={airframe}",
               f"HOST_VARIANT={variant}", f"HOST_DEFINES={text}", *(["HOST_PGO=0"] if defines else [])]
    done = subprocess.run(command, cwd=REPO_ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        errors = [line for line in (done.stdout + done.stderr).splitlines() if "error" in line.lower()]
        raise HostBuildError(f"make host with {text or 'the airframe as it is'} failed (exit status "
                             f"{done.returncode}):\n  " + "\n  ".join(errors[-8:] or done.stderr.splitlines()[-8:]))
    return build / "host" / f"{Path(airframe).stem}{variant}" / "nps_host"


def prepare_inputs(sweep, points, note=print):
    """{point key: {"host_on", "host_off", "arena", "model": Blob}} of the points (of the sweep); builds the hosts
    they need (`note` tells which). Raises HostBuildError, OSError."""
    hosts, files, inputs = {}, {}, {}
    for point in points:
        defines = point_defines(point)
        name = " ".join(f"{k}={v}" for k, v in sorted(defines.items()))
        if name not in hosts:
            note(f"host {name or 'of the airframe as it is'}: make host")
            hosts[name] = [Blob.of(build_host(sweep.airframe, defines, detector).read_bytes())
                           for detector in (True, False)]
        arena = point.values["arena"]
        if arena not in files:
            files[arena] = Blob.of(Path(arena).read_bytes())
        model = sweep.models[point.key]
        if model not in files:
            files[model] = Blob.of(model.encode())
        inputs[point.key] = {"host_on": hosts[name][0], "host_off": hosts[name][1], "arena": files[arena],
                             "model": files[model]}
    return inputs
