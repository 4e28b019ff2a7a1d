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
