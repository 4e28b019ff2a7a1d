"""Child processes that run side by side, one per aircraft (plus helpers such as a ground station), each with its
output in a log file.

run_fleet starts them, waits for every aircraft to end by itself, and reports each one that exits non-zero or
dies (name and the tail of its log) while the others go on. It stops all of them with SIGTERM (then SIGKILL after a
grace period) when the wall-time limit passes or when this process gets SIGINT (Ctrl-C) or SIGTERM; the children
run in sessions of their own, so a Ctrl-C in the terminal reaches them only as that one SIGTERM. Helpers are
stopped once the aircraft have ended. The command of each child is a parameter: the tests fly small scripts.
"""
import os
import signal
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path


@dataclass
class Member:
    name: str                  # e.g. "FINKEN_2"
    command: list
    log: Path
    env: dict = None
    cwd: Path = None
    helper: bool = False       # not waited for: stopped when the aircraft have ended


@dataclass
class Ended:
    name: str
    returncode: int
    how: str                   # "exit 0", "exit 3", "killed by SIGSEGV", ...
    stopped: str = None        # why we stopped it: "interrupted", "wall-time limit ...", "aircraft ended"
    log_tail: list = field(default_factory=list)
    helper: bool = False

    @property
    def ok(self):
        """Exit 0, or a helper stopped because the aircraft had ended (however it took the SIGTERM)."""
        return self.returncode == 0 or (self.helper and self.stopped == "aircraft ended")


@dataclass
class FleetOutcome:
    ended: list                # Ended of every member, in the order given
    interrupted: str = None    # "SIGINT" / "SIGTERM" when we were told to stop
    timed_out: bool = False
    wall_s: float = 0.0

    def failures(self):
        """Members that ended otherwise than by exit 0."""
        return [e for e in self.ended if not e.ok]


def describe_status(returncode):
    if returncode >= 0:
        return f"exit {returncode}"
    try:
        return f"killed by {signal.Signals(-returncode).name}"
    except ValueError:
        return f"killed by signal {-returncode}"


def log_tail(log, lines=12):
    try:
        return Path(log).read_text(errors="replace").splitlines()[-lines:]
    except OSError as err:
        return [f"(cannot read {log}: {err})"]


class _StopRequest:
    """SIGINT / SIGTERM to us, noted while the fleet runs (the previous handlers are restored afterwards)."""

    def __init__(self):
        self.signal_name = None

    def __enter__(self):
        self.previous = {s: signal.signal(s, self._note) for s in (signal.SIGINT, signal.SIGTERM)}
        return self

    def _note(self, signum, _frame):
        self.signal_name = signal.Signals(signum).name

    def __exit__(self, *exc):
        for s, handler in self.previous.items():
            signal.signal(s, handler)


def _start(member):
    member.log.parent.mkdir(parents=True, exist_ok=True)
    with open(member.log, "w") as log:
        return subprocess.Popen([str(c) for c in member.command], stdout=log, stderr=subprocess.STDOUT,
                                stdin=subprocess.DEVNULL, env=member.env, cwd=member.cwd, start_new_session=True)


def _signal_group(proc, sig):
    """Send `sig` to the child's process group (its session: it and anything it started)."""
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass


def _stop(procs, grace_s):
    """SIGTERM to every running child, SIGKILL to those still running after grace_s; waits for all."""
    running = [p for p in procs if p.poll() is None]
    for p in running:
        _signal_group(p, signal.SIGTERM)
    deadline = time.monotonic() + grace_s
    for p in running:
        try:
            p.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            _signal_group(p, signal.SIGKILL)
            p.wait()
    return running


def _reason_to_stop(flying, signal_name, elapsed_s, wall_limit_s):
    """Why the fleet stops now (None: it flies on)."""
    if not flying:
        return "aircraft ended"
    if signal_name:
        return "interrupted"
    if elapsed_s > wall_limit_s:
        return f"wall-time limit {wall_limit_s:.0f} s"
    return None


def run_fleet(members, wall_limit_s, on_tick=None, on_failure=None, poll_s=0.25, grace_s=15.0):
    """Run `members` until every aircraft (non-helper member) has ended, the wall-time limit passes or we are told
    to stop. on_tick(flying_names, elapsed_s) is called every poll; on_failure(Ended) as soon as a member ends
    otherwise than by exit 0. Returns a FleetOutcome."""
    started = time.monotonic()
    procs, ended = {}, {}
    with _StopRequest() as stop:
        try:
            for m in members:
                procs[m.name] = _start(m)
            while True:
                for m in members:
                    rc = procs[m.name].poll()
                    if rc is not None and m.name not in ended:
                        ended[m.name] = Ended(m.name, rc, describe_status(rc), helper=m.helper)
                        if rc != 0:
                            ended[m.name].log_tail = log_tail(m.log)
                            if on_failure:
                                on_failure(ended[m.name])
                flying = [m.name for m in members if not m.helper and m.name not in ended]
                elapsed = time.monotonic() - started
                reason = _reason_to_stop(flying, stop.signal_name, elapsed, wall_limit_s)
                if reason:
                    break
                if on_tick:
                    on_tick(flying, elapsed)
                time.sleep(poll_s)
        finally:   # also when starting one failed, or on an error in a callback: no child is left running
            stopped = _stop(list(procs.values()), grace_s)
    outcome = FleetOutcome(ended=[], interrupted=stop.signal_name, timed_out=reason.startswith("wall-time"))
    for m in members:
        rc = procs[m.name].returncode
        end = ended.get(m.name) or Ended(m.name, rc, describe_status(rc), helper=m.helper)
        if procs[m.name] in stopped:
            end.stopped = reason
            end.log_tail = log_tail(m.log)
        outcome.ended.append(end)
    outcome.wall_s = time.monotonic() - started
    return outcome
