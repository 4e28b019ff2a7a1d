"""Running the C benchmark programs of tests/bench/ and reading their figures.

Each program prints one JSON object per line on stdout: {"name", "value", "unit", "reps", "min", "max"}
(tests/bench/bench_common.h); its notes go to stderr.
"""
import json
import subprocess
from pathlib import Path


class BenchProgramError(RuntimeError):
    """A benchmark program failed or printed something that is not a figure."""


def run_program(binary: Path, args: list[str], echo_stderr: bool = True) -> list[dict]:
    """Run one program and return its figures in the order printed."""
    cmd = [str(binary), *map(str, args)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise BenchProgramError(f"{' '.join(cmd)}: exit status {proc.returncode}: {proc.stderr.strip()}")
    if echo_stderr and proc.stderr.strip():
        print("    " + proc.stderr.strip().replace("\n", "\n    "))
    figures = []
    for number, line in enumerate(proc.stdout.splitlines(), start=1):
        try:
            figure = json.loads(line)
        except json.JSONDecodeError as err:
            raise BenchProgramError(f"{binary.name}: stdout line {number}: not JSON ({err}): {line!r}") from None
        if not {"name", "value", "unit"} <= figure.keys():
            raise BenchProgramError(f"{binary.name}: stdout line {number}: needs name, value and unit: {line!r}")
        figures.append(figure)
    return figures
