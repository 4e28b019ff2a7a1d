"""The crash of several Paparazzi NPS processes on one Ivy bus, reproduced (`make paparazzi-ivy-race`).

tests/paparazzi/ivy_two_threads.c does what Paparazzi's nps_ivy.c does (ivy-c called from two threads); several of
it on one bus crash in pcre_exec (a use after free: another process's regexp freed by the Ivy thread while the
sending thread runs it). The same program with one thread (its requests from a timer of the Ivy loop) does not.
Built with AddressSanitizer, the crash report names both sides. Built against the ivy-c that Paparazzi's NPS links
(pkg-config ivy-c, as the tree's Makefile.nps finds it).
"""
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]
SOURCE = REPO / "tests/paparazzi/ivy_two_threads.c"
PROCESSES = 4
SECONDS = 15.0


def build(out_dir, env=os.environ):
    """The reproducer built with AddressSanitizer in out_dir; its path. CalledProcessError names pkg-config's or gcc's
    complaint."""
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "ivy-c"], env=env, capture_output=True, text=True,
                           check=True).stdout.split()
    binary = Path(out_dir) / "ivy_two_threads"
    subprocess.run(["gcc", "-std=gnu99", "-Wall", "-Wextra", "-Werror", "-g", "-O1", "-fsanitize=address",
                    str(SOURCE), "-o", str(binary), *flags, "-lpthread"], env=env, check=True)
    return binary


def run(binary, mode, port, processes=PROCESSES, seconds=SECONDS, env=os.environ):
    """Run `processes` of the reproducer in `mode` ("threads" or "loop") on one bus for `seconds`; the stderr of
    each that crashed (an empty list: none did)."""
    bus = f"127.255.255.255:{port}"
    env = dict(env, ASAN_OPTIONS="detect_leaks=0")
    procs = [subprocess.Popen([str(binary), bus, f"{seconds:g}", mode], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True) for _ in range(processes)]
    crashed = []
    for p in procs:
        _, err = p.communicate(timeout=seconds * 4 + 30)
        if p.returncode != 0:
            crashed.append(err)
    return crashed


def summary(crash):
    """AddressSanitizer's kind of error, the first frames of the bad access and, for a use after free, of the free."""
    error = re.search(r"ERROR: AddressSanitizer: (\S+)", crash)
    frames = re.findall(r"#\d+ 0x[0-9a-f]+ in (\w+)", crash)
    text = f"{error.group(1) if error else 'crash'}: {' <- '.join(frames[:4])}"
    freed = re.search(r"freed by thread (T\d+) here:\s+#0 0x[0-9a-f]+ in \w+ \S+\s+#1 0x[0-9a-f]+ in (\w+)", crash)
    return text + (f"; freed by {freed.group(2)} in thread {freed.group(1)}" if freed else "")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        try:
            binary = build(tmp)
        except (subprocess.CalledProcessError, FileNotFoundError) as err:
            print(f"paparazzi-ivy-race: cannot build the reproducer ({err}): it needs ivy-c (pkg-config ivy-c), as "
                  "Paparazzi's NPS does: source your Paparazzi environment", file=sys.stderr)
            return 2
        port = 30000 + os.getpid() % 10000
        for mode, what in (("threads", "ivy-c from two threads, as nps_ivy.c"), ("loop", "one thread")):
            crashed = run(binary, mode, port)
            print(f"{what}: {len(crashed)} of {PROCESSES} processes on one bus crashed in {SECONDS:g} s")
            for crash in crashed:
                print(f"    {summary(crash)}")
    return 0
