"""tools/finken/sim_report/arena_plot.py: reading the wall snapshots, choosing what each panel shows, the drawn
deflection, the PNG from the command line, and the loop from the C wall model through its CSV to the plot."""
import math
from pathlib import Path

import numpy as np
import pytest

from finken.sim_report import arena_plot

HEADER = "t,wall,segment,x0,y0,x1,y1,nx,ny,angle_deg,disp_flight_m,disp_bottom_m,target_deg,driven\n"
# hinge at 1 m, flight at 0.6 m: displacement at flight height 0.4 tan(angle), bottom edge sin(angle)
ROWS = [
    (0.0, 0, 0, 0.0, 0.0, 1.5, 0.0, 0.0, 1.0, 0.0),
    (0.0, 0, 1, 1.5, 0.0, 3.0, 0.0, 0.0, 1.0, 0.0),
    (0.0, 1, 0, 3.0, 0.0, 3.0, 4.0, -1.0, 0.0, 0.0),
    (1.0, 0, 0, 0.0, 0.0, 1.5, 0.0, 0.0, 1.0, 30.0),
    (1.0, 0, 1, 1.5, 0.0, 3.0, 0.0, 0.0, 1.0, 10.0),
    (1.0, 1, 0, 3.0, 0.0, 3.0, 4.0, -1.0, 0.0, 0.0),
]


def write_walls(path, rows=ROWS):
    with open(path, "w") as f:
        f.write(HEADER)
        for t, w, s, x0, y0, x1, y1, nx, ny, deg in rows:
            rad = math.radians(deg)
            f.write(f"{t},{w},{s},{x0},{y0},{x1},{y1},{nx},{ny},{deg},{0.4 * math.tan(rad)},{math.sin(rad)},{deg},"
                    f"{int(deg > 0)}\n")
    return path


def write_poses(path):
    with open(path, "w") as f:
        f.write("t,vehicle,x,y,z,yaw\n")
        for t in (0.0, 0.5, 1.0):
            f.write(f"{t},0,{1.0 + t},0.5,0.6,{-math.pi / 2}\n")
            f.write(f"{t},1,2.5,{2.0 + t},0.6,0.0\n")
    return path


def write_readings(path):
    with open(path, "w") as f:
        f.write("t,vehicle,sensor,peer,true_range,measured\n")
        f.write("0.9,0,sonar_front,,0.42,0.40\n")
        f.write("0.95,0,sonar_front,,0.41,\n")   # the later reading wins; no echo
        f.write("0.2,1,sonar_right,,1.0,0.9\n")   # too old for t = 1 with a 0.5 s window
        f.write("0.9,1,sonar_down,,0.6,0.6\n")    # not drawn
    return path


def test_read_walls_and_pick_snapshots(tmp_path):
    walls = arena_plot.read_walls(write_walls(tmp_path / "walls.csv"))
    assert walls["t"].shape == (6,)
    snap = arena_plot.snapshot_at(walls, 0.7)          # the last snapshot at or before 0.7 s is at 0 s
    assert np.all(snap["t"] == 0.0) and snap["t"].size == 3
    snap = arena_plot.snapshot_at(walls, 5.0)
    assert np.all(snap["t"] == 1.0)
    assert np.all(arena_plot.snapshot_at(walls, -1.0)["t"] == 0.0)  # before the first: the first


def test_displaced_segments_move_inward_by_the_exaggerated_displacement(tmp_path):
    snap = arena_plot.snapshot_at(arena_plot.read_walls(write_walls(tmp_path / "walls.csv")), 1.0)
    seg = arena_plot.displaced_segments(snap, 3.0)
    # segment 0 of wall 0 (y = 0, inward +y) at 30 deg: 3 x 0.4 tan 30 deg = 0.69282 m north
    north = 1.2 * math.tan(math.radians(30))
    assert seg[0] == pytest.approx(np.array([[0.0, north], [1.5, north]]))
    assert seg[1, 0, 1] == pytest.approx(1.2 * math.tan(math.radians(10)))
    assert seg[2] == pytest.approx(np.array([[3.0, 0.0], [3.0, 4.0]]))  # at rest


def test_auto_exaggeration():
    walls = {"x0": np.array([0.0]), "x1": np.array([3.0]), "y0": np.array([0.0]), "y1": np.array([4.0]),
             "disp_flight_m": np.array([0.02])}
    assert arena_plot.auto_exaggeration(walls) == 10.0       # 8 % of 4 m / 0.02 m = 16, capped at 10
    walls["disp_flight_m"] = np.array([0.08])
    assert arena_plot.auto_exaggeration(walls) == pytest.approx(4.0)
    walls["disp_flight_m"] = np.array([0.5])
    assert arena_plot.auto_exaggeration(walls) == 1.0       # large deflections at true scale
    walls["disp_flight_m"] = np.array([0.0])
    assert arena_plot.auto_exaggeration(walls) == 1.0


def test_poses_and_readings_at_a_time(tmp_path):
    from finken.run_logs import read_poses
    from finken.rangelog import read_range_log
    poses = arena_plot.poses_at(read_poses(write_poses(tmp_path / "poses.csv")), 0.7)
    assert poses[0] == pytest.approx((1.5, 0.5, 0.6, -math.pi / 2))
    assert poses[1] == pytest.approx((2.5, 2.5, 0.6, 0.0))
    shown = arena_plot.readings_at(read_range_log(write_readings(tmp_path / "readings.csv")), 1.0, 0.5)
    assert set(shown) == {(0, "sonar_front")}
    true_range, measured = shown[(0, "sonar_front")]
    assert true_range == 0.41 and math.isnan(measured)


@pytest.mark.parametrize("text, where, what", [
    ("t,wall\n0,1\n", ":1: column 'segment'", "missing"),
    (HEADER + "0,0,0,0,0,1,0,0,1,abc,0,0,0,0\n", ":2: column 'angle_deg'", "'abc' is not a finite number"),
    (HEADER + "0,0,0,0,0,1,0,0,1\n", ":2:", "expected 14 fields"),
    ("", "", "empty file"),
])
def test_bad_walls_file_names_line_and_column(tmp_path, text, where, what):
    path = tmp_path / "walls.csv"
    path.write_text(text)
    with pytest.raises(arena_plot.ArenaPlotError) as err:
        arena_plot.read_walls(path)
    assert f"{path}{where}" in str(err.value) and what in str(err.value)


@pytest.mark.parametrize("row, where, what", [
    ("0,0,0,0,0,1_5,0,0,1,0,0,0,0,0", ":2: column 'x1'", "'1_5' is not a finite number"),
    ("0,0,0,0,0,1,0,0,1,\u0665,0,0,0,0", ":2: column 'angle_deg'", "is not a finite number"),
    ("0,-1,0,0,0,1,0,0,1,0,0,0,0,0", ":2: column 'wall'", "'-1' is not an integer from 0 to 2147483647"),
    ("0,0,1e300,0,0,1,0,0,1,0,0,0,0,0", ":2: column 'segment'", "'1e300' is not an integer from 0"),
])
def test_walls_numbers_and_ids_as_in_a_range_log(tmp_path, row, where, what):
    path = tmp_path / "walls.csv"
    path.write_text(HEADER + row + "\n", encoding="utf-8")
    with pytest.raises(arena_plot.ArenaPlotError) as err:
        arena_plot.read_walls(path)
    assert f"{path}{where}: " in str(err.value) and what in str(err.value)


@pytest.mark.parametrize("option, value", [("--radius", "-0.2"), ("--radius", "nan"), ("--exaggerate", "0"),
                                           ("--exaggerate", "inf")])
def test_cli_refuses_meaningless_sizes(tmp_path, capsys, option, value):
    with pytest.raises(SystemExit) as done:
        arena_plot.main(["--walls", "w.csv", "--poses", "p.csv", "-o", str(tmp_path / "a.png"), option, value])
    assert done.value.code == 2
    assert f"argument {option}: '{value}' is not a finite number > 0" in capsys.readouterr().err


def test_times_are_ascii_numbers():
    assert arena_plot.parse_times("0, 1.5,2e1") == [0.0, 1.5, 20.0]
    for text in ("1_0", "\u0661", "nan", ""):
        with pytest.raises(arena_plot.ArenaPlotError, match="expected comma-separated times"):
            arena_plot.parse_times(text)


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="no /dev/full")
def test_cli_reports_a_png_it_cannot_write(tmp_path, capsys):
    status = arena_plot.main(["--walls", str(write_walls(tmp_path / "walls.csv")),
                              "--poses", str(write_poses(tmp_path / "poses.csv")), "-o", "/dev/full"])
    assert status == 1
    assert capsys.readouterr().err.strip() == "arena_plot: /dev/full: cannot write: No space left on device"


def test_cli_writes_a_png(tmp_path):
    out = tmp_path / "arena.png"
    status = arena_plot.main(["--walls", str(write_walls(tmp_path / "walls.csv")),
                              "--poses", str(write_poses(tmp_path / "poses.csv")),
                              "--readings", str(write_readings(tmp_path / "readings.csv")),
                              "--times", "0,1", "-o", str(out)])
    assert status == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 10000


def test_cli_reports_bad_input(tmp_path, capsys):
    status = arena_plot.main(["--walls", str(tmp_path / "missing.csv"), "--poses", "x", "-o", str(tmp_path / "a.png")])
    assert status == 2
    assert "missing.csv: cannot read" in capsys.readouterr().err
    status = arena_plot.main(["--walls", str(write_walls(tmp_path / "walls.csv")),
                              "--poses", str(write_poses(tmp_path / "poses.csv")), "--times", "1,x",
                              "-o", str(tmp_path / "a.png")])
    assert status == 2


def test_c_wall_model_through_its_csv(tmp_path, repo, arena_native):
    """The C model writes walls.csv; the plot reads back the plate that the copter pulled."""
    ffi, lib = arena_native
    err = ffi.new("char[]", 512)
    arena = lib.nps_arena_load(str(repo / "conf" / "arena" / "swarmlab.xml").encode(), err, 512)
    assert arena != ffi.NULL, ffi.string(err).decode()
    try:
        copter = ffi.new("struct nps_arena_copter *", {"id": 5, "pos_m": [1.575, 0.75, 0.6], "yaw_rad": 0.0,
                                                        "radius_m": 0.2, "height_m": 0.15})
        assert lib.nps_arena_set_copters(arena, copter, 1) == 0
        path = tmp_path / "walls.csv"
        for k in range(0, 30 * 512 + 1):
            assert lib.nps_arena_walls_step(arena, k / 512.0) == 0
            if k % (10 * 512) == 0:
                assert lib.nps_arena_snapshot_file(arena, str(path).encode(), 1, err, 512) == 0, ffi.string(err)
    finally:
        lib.nps_arena_free(arena)
    walls = arena_plot.read_walls(path)
    assert sorted(np.unique(walls["t"])) == [0.0, 10.0, 20.0, 30.0]
    last = arena_plot.snapshot_at(walls, 30.0)
    assert last["t"].size == 80
    pulled = (last["wall"] == 0) & (last["segment"] == 10)      # x in [1.5, 1.65], 0.75 m from the copter
    assert last["target_deg"][pulled][0] == pytest.approx(lib.nps_walls_amplitude_deg(0.75, 1.0, 30.0))
    assert last["angle_deg"][pulled][0] == pytest.approx(24.421875, abs=0.01)   # settled (test_walls.c)
    assert last["disp_flight_m"][pulled][0] == pytest.approx(0.4 * math.tan(math.radians(last["angle_deg"][pulled][0])))
    far = last["wall"] == 2                                      # 3.25 m away: at rest
    assert np.all(last["angle_deg"][far] == 0.0) and np.all(last["driven"][far] == 0)


def test_cdef_mirrors_the_headers(repo):
    """Every declaration in nps_arena.cdef appears, whitespace aside, in the C headers it mirrors."""
    import re
    nps = repo / "sw" / "simulator" / "nps"
    headers = " ".join((nps / h).read_text() for h in ("nps_arena.h", "nps_walls.h", "nps_arena_snapshot.h"))
    headers = re.sub(r"\s+", " ", re.sub(r"/\*.*?\*/", " ", headers, flags=re.S))
    headers = re.sub(r"\s*([(),;*])\s*", r"\1", headers)
    cdef = re.sub(r"/\*.*?\*/", " ", (nps / "nps_arena.cdef").read_text(), flags=re.S)
    functions = [line.strip() for line in cdef.splitlines() if line.strip().endswith(");")]
    assert len(functions) == 10
    for declaration in functions:
        assert re.sub(r"\s*([(),;*])\s*", r"\1", declaration) in headers, declaration
    fields = re.search(r"struct nps_arena_copter \{(.*?)\};", headers).group(1)
    assert re.sub(r"\s+", "", fields) == re.sub(r"\s+", "", re.search(r"struct nps_arena_copter \{(.*?)\};", cdef, re.S).group(1))
