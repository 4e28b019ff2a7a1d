"""Run one of tools/*.py as a user would: a subprocess with the test environment, optionally with every file it
writes limited in size (a write beyond the limit fails with EFBIG, "File too large", as on a full disk)."""
import os
import resource
import subprocess
import sys
from pathlib import Path

TOOLS = Path(__file__).resolve().parents[2] / "tools"


def run_tool(name, *args, max_file_bytes=None):
    """CompletedProcess of tools/<name> with `args` (text output captured)."""
    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (max_file_bytes, max_file_bytes))  # Python ignores SIGXFSZ

    env = dict(os.environ, PYTHONPATH=str(TOOLS), MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(TOOLS / name), *map(str, args)], capture_output=True, text=True,
                          env=env, preexec_fn=limit_file_size if max_file_bytes else None)
