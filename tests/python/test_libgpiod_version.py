"""The sonar GPIO driver (sw/airborne/arch/linux/modules/sonar/sonar_gpiod.c) is written for libgpiod 1.x: built
against libgpiod 2.x's gpiod.h it stops with one message naming the version found and what to do, and the
libgpiod 1.x header of this machine builds it."""
import subprocess

import pytest

SOURCE = "sw/airborne/arch/linux/modules/sonar/sonar_gpiod.c"
FLAGS = ["-std=gnu99", "-Wall", "-Wextra", "-Werror", "-fsyntax-only", "-Isw/airborne/arch/linux", "-Isw/airborne"]


def compile_sonar_gpiod(repo, *include_dirs):
    return subprocess.run(["gcc", *FLAGS, *[f"-I{d}" for d in include_dirs], SOURCE], cwd=repo,
                          capture_output=True, text=True)


def test_libgpiod_2_is_refused_with_one_clear_message(repo):
    result = compile_sonar_gpiod(repo, "tests/data/libgpiod2")
    assert result.returncode != 0
    errors = [line for line in result.stderr.splitlines() if "error:" in line]
    assert len(errors) == 1, result.stderr  # ours, not a page of errors about the 1.x API
    assert "#error" in errors[0]
    assert "found libgpiod 2.x" in errors[0]
    assert "needs libgpiod 1.x" in errors[0]
    assert "Install libgpiod 1.6" in errors[0]


def test_libgpiod_1_builds(repo):
    probe = subprocess.run(["gcc", "-E", "-dM", "-include", "gpiod.h", "-x", "c", "/dev/null"],
                           capture_output=True, text=True)
    if "GPIOD_LINE_BULK_MAX_LINES" not in probe.stdout:
        pytest.skip("this machine's gpiod.h is not libgpiod 1.x")
    result = compile_sonar_gpiod(repo)
    assert result.returncode == 0, result.stderr
