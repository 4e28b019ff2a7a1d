"""Shared fixtures: paths of the repository and of the build the Makefile made."""
import os
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "tools"))


@pytest.fixture
def repo():
    return REPO


@pytest.fixture
def build_dir():
    return Path(os.environ.get("FINKEN_BUILD", REPO / "build"))


@pytest.fixture
def arena_native():
    """(ffi, lib): the arena functions of libfinken_nps.so through cffi (declarations in nps_arena.cdef)."""
    import cffi
    lib_path = Path(os.environ.get("FINKEN_LIB", REPO / "build" / "lib" / "libfinken_nps.so"))
    assert lib_path.is_file(), f"{lib_path} is missing: run make build"
    ffi = cffi.FFI()
    ffi.cdef((REPO / "sw" / "simulator" / "nps" / "nps_arena.cdef").read_text())
    return ffi, ffi.dlopen(str(lib_path))
