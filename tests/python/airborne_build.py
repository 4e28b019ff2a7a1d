"""Compiler flags and calls shared by the tests that compile airborne code outside the Makefile."""
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def airborne_flags(build_dir, arch="sim"):
    """The Makefile's include flags for a module source built for `arch` (sim or linux): -Isw/airborne/arch/<arch>
    and AIRBORNE_INC (paths relative to the repository; the generated ABI header in build_dir/gen)."""
    return [f"-Isw/airborne/arch/{arch}", "-DPPRZ_HOST_MULTI_VEHICLE", "-Isw/airborne", "-Isim/pprz",
            f"-I{Path(build_dir) / 'gen'}", "-Isw/simulator/nps"]


def compile_or_fail(what, cmd, cwd=REPO):
    """Run a compiler; on failure, fail the test with the command and the compiler's messages."""
    result = subprocess.run(list(map(str, cmd)), cwd=cwd, capture_output=True, text=True)
    assert result.returncode == 0, f"{what} failed:\n$ {' '.join(map(str, cmd))}\n{result.stdout}{result.stderr}"


def require_abi_header(build_dir):
    generated = Path(build_dir) / "gen" / "abi_messages.h"
    assert generated.is_file(), f"{generated} is missing: run make build"
