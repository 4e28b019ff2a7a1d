"""Pieces of make paparazzi-check that need no Paparazzi tree (the check itself runs when PAPARAZZI_HOME is set)."""
import shutil
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "tools"))
from finken.paparazzi.check import CheckFailed, check_ap_binary  # noqa: E402
from finken.paparazzi.tree import warnings_in_our_files  # noqa: E402

OURS = ["sw/airborne/modules/ranging/ranging_table.c", "sw/simulator/nps/nps_swarm.c"]


def test_warnings_are_found_in_our_files_by_relative_or_absolute_path(tmp_path):
    log = tmp_path / "build.log"
    log.write_text(
        "CC /tree/var/aircrafts/FINKEN_1/ap/modules/ranging/ranging_table.o\n"
        "modules/ranging/ranging_table.c:56:31: warning: cast discards 'const' qualifier [-Wcast-qual]\n"
        "/tree/sw/simulator/nps/nps_swarm.c:10:2: warning: unused variable 'x' [-Wunused-variable]\n"
        "modules/imu/imu.c:12:3: warning: not ours [-Wshadow]\n"
        "/tree/sw/simulator/nps/nps_fdm_jsbsim.cpp:1:1: warning: not ours either\n"
        "modules/ranging/ranging_table.c:70:1: error: an error is not a warning\n")
    found = warnings_in_our_files(log, OURS)
    assert [line.split(":")[0] for line in found] == ["modules/ranging/ranging_table.c",
                                                      "/tree/sw/simulator/nps/nps_swarm.c"]


def test_a_clean_log_has_no_warning(tmp_path):
    log = tmp_path / "build.log"
    log.write_text("CC modules/ranging/ranging_table.o\nLD ap.elf\n")
    assert warnings_in_our_files(log, OURS) == []


@pytest.mark.skipif(shutil.which("readelf") is None, reason="readelf (binutils) is not installed")
def test_a_host_binary_without_our_drivers_is_not_taken_for_the_autopilot():
    with pytest.raises(CheckFailed, match="expected an ARM executable"):
        check_ap_binary(Path(shutil.which("true")).resolve())


def test_the_scratch_tree_is_not_overridden_by_our_makes_command_line(tmp_path, monkeypatch):
    from finken.paparazzi.tree import paparazzi_env
    monkeypatch.setenv("PAPARAZZI_HOME", str(tmp_path / "users_tree"))
    monkeypatch.setenv("MAKEFLAGS", f" -- PAPARAZZI_HOME={tmp_path / 'users_tree'}")
    monkeypatch.setenv("MAKELEVEL", "1")
    env = paparazzi_env(tmp_path / "copy")
    assert env["PAPARAZZI_HOME"] == env["PAPARAZZI_SRC"] == str(tmp_path / "copy")
    assert "MAKEFLAGS" not in env and "MAKELEVEL" not in env


def test_make_test_checks_against_paparazzi_home_else_the_tree_the_last_check_was_given(tmp_path):
    from finken.paparazzi.check import HOME_RECORD, tree_for_tests
    out = tmp_path / "paparazzi"
    assert tree_for_tests(out, {"PAPARAZZI_HOME": "/users/tree"}) == ("/users/tree", None)
    home, why_not = tree_for_tests(out, {})
    assert home is None and why_not.startswith("PAPARAZZI_HOME is not set and") and HOME_RECORD in why_not
    tree = tmp_path / "pprz"
    out.mkdir()
    (out / HOME_RECORD).write_text(f"{tree}\n")
    home, why_not = tree_for_tests(out, {})
    assert home is None and f"{tree} lacks Makefile.ac" in why_not          # gone, or never prepared
    for needed in ("Makefile.ac", "conf/airframes/airframe.dtd", "sw/tools/generators/gen_aircraft.out",
                   "var/include/pprzlink/messages.h"):
        (tree / needed).parent.mkdir(parents=True, exist_ok=True)
        (tree / needed).touch()
    assert tree_for_tests(out, {}) == (str(tree), None)
