"""The arena's interior obstacles in the Python tools: read through libfinken_nps (finken.flight.truth.ArenaTruth
.obstacles: file order, counter-clockwise, circles as regular polygons, polygons of any size), drawn on make sim's
trajectory plot (finken.sim_report.swarm_plot, through tools/sim_report.py --arena / --airframe) and sent to the GCS
as SHAPE messages (finken.paparazzi.arena_shapes); the plot's near-wall margin of a non-convex arena."""
import math

import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.path import Path as MplPath

import sim_report
from finken.flight.truth import ArenaTruth
from finken.paparazzi.arena_shapes import SHAPE_ID, lat_lon_of_enu, obstacle_messages
from finken.sim_report import swarm_plot
from test_sim_report import _run_folder

ARENA = """<?xml version="1.0"?>
<arena name="obstacles" flightHeight="0.6" wallHeight="2.0">
  <polygon>
    <point x="0" y="0"/><point x="3" y="0"/><point x="3" y="4"/><point x="0" y="4"/><point x="0" y="0"/>
  </polygon>
  <walls numSegments="20" segmentMass="40" jointForce="15" threshold="1" friction="3" maxAmplitude="30"
         PID_P="1" PID_I="2" PID_D="1" hingeHeight="1.0" curtainMass="3" frictionVelocity="0.15"/>
  <copters radius="0.2" height="0.15"/>
  <sonars beamHalfAngle="15" range="3.0" offset="0"/>
  {obstacles}
</arena>
"""
TABLE_CW = [(1.0, 1.0), (1.0, 1.8), (2.2, 1.8), (2.2, 1.0)]    # a table, given clockwise
CIRCLE = '<obstacle height="3"><circle x="2.5" y="3" radius="0.25"/></obstacle>'
L_CORNERS = np.array([(0, 0), (4, 0), (4, 1.5), (2, 1.5), (2, 4.5), (0, 4.5), (0, 0)], float)
POSES = {"t": np.array([0.0, 1.0]), "vehicle": np.array([1.0, 1.0]), "x": np.array([0.5, 0.6]),
         "y": np.array([0.5, 0.7])}


def polygon_xml(corners, height):
    points = "".join(f'<point x="{x}" y="{y}"/>' for x, y in [*corners, corners[0]])
    return f'<obstacle height="{height}"><polygon>{points}</polygon></obstacle>'


def arena_file(tmp_path, *obstacles):
    path = tmp_path / "arena.xml"
    path.write_text(ARENA.format(obstacles="\n  ".join(obstacles)))
    return path


def signed_area(outline):
    x, y = outline.T
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def test_the_pillar_as_48_corners_on_its_circle(repo):
    with ArenaTruth(repo / "conf/arena/swarmlab_pillar.xml") as arena:
        (outline, height, circle), = arena.obstacles()
    assert outline.shape == (48, 2)
    assert np.hypot(*(outline - (1.1, 2.5)).T) == pytest.approx(np.full(48, 0.2), abs=1e-12)
    assert len(np.unique(np.round(np.arctan2(*(outline - (1.1, 2.5)).T[::-1]), 9))) == 48   # 48 distinct corners
    assert signed_area(outline) > 0
    assert height == 3.0 and circle == (1.1, 2.5, 0.2)


def test_obstacles_in_file_order_polygons_counter_clockwise_and_whole(tmp_path):
    angles = np.linspace(0, 2 * math.pi, 60, endpoint=False)
    sixty = [(0.5 + 0.3 * math.cos(a), 3.0 + 0.3 * math.sin(a)) for a in angles]    # more corners than a circle's
    path = arena_file(tmp_path, polygon_xml(TABLE_CW, 0.75), CIRCLE, polygon_xml(sixty, 1.5))
    with ArenaTruth(path) as arena:
        (table, table_h, no_circle), (circle, circle_h, centre_radius), (many, many_h, _) = arena.obstacles()
        diameter = arena.obstacles(circle_corners=2)[1].outline
    assert (table_h, circle_h, many_h) == (0.75, 3.0, 1.5)
    assert signed_area(table) > 0
    start = int(np.flatnonzero((table == TABLE_CW[0]).all(axis=1))[0])
    assert np.roll(table, -start, axis=0).tolist() == [list(p) for p in [TABLE_CW[0], *TABLE_CW[:0:-1]]]
    assert circle.shape == (48, 2) and np.hypot(*(circle - (2.5, 3)).T) == pytest.approx(np.full(48, 0.25))
    assert many.shape == (60, 2) and sorted(map(tuple, many.tolist())) == sorted(sixty)
    assert diameter.mean(axis=0) == pytest.approx([2.5, 3.0]) and math.dist(*diameter) == pytest.approx(0.5)
    assert no_circle is None and centre_radius == (2.5, 3.0, 0.25)


def test_an_arena_without_obstacles_has_none(repo):
    with ArenaTruth(repo / "conf/arena/swarmlab.xml") as arena:
        assert arena.obstacles() == []


def drawn_figure(monkeypatch, *args, **kwargs):
    """plot_trajectories' figure, kept when it closes it."""
    closed = []
    monkeypatch.setattr(plt, "close", closed.append)
    swarm_plot.plot_trajectories(*args, **kwargs)
    return closed[0]


def test_obstacles_drawn_grey_and_labelled_once(repo, tmp_path, monkeypatch):
    with ArenaTruth(arena_file(tmp_path, polygon_xml(TABLE_CW, 0.75), CIRCLE)) as arena:
        obstacles = arena.obstacles()
    png = tmp_path / "t.png"
    fig = drawn_figure(monkeypatch, [("off", POSES), ("on", POSES)], [(0, 0), (3, 0), (3, 4), (0, 4)], png,
                       obstacles=obstacles)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for ax in fig.axes:
        grey = [p for p in ax.patches if p.get_facecolor()[:3] == matplotlib.colors.to_rgb("grey")]
        assert sorted(len(p.get_xy()) for p in grey) == [4 + 1, 48 + 1]     # closed: the first corner again
    assert [t.get_text() for t in fig.axes[0].get_legend().get_texts()].count("obstacle") == 1
    plain = drawn_figure(monkeypatch, [("on", POSES)], [(0, 0), (3, 0), (3, 4), (0, 4)], tmp_path / "p.png")
    assert len(plain.axes[0].patches) == 0
    assert "obstacle" not in [t.get_text() for t in plain.axes[0].get_legend().get_texts()]


def boundary_dist(points, closed):
    a, ab = closed[:-1], np.diff(closed, axis=0)
    along = np.clip(np.sum((points[:, None] - a) * ab, axis=2) / np.sum(ab * ab, axis=1), 0, 1)
    return np.linalg.norm(points[:, None] - (a + along[..., None] * ab), axis=2).min(axis=1)


@pytest.mark.parametrize("corners", [L_CORNERS, L_CORNERS[::-1]], ids=["counter-clockwise", "clockwise"])
def test_near_wall_margin_of_an_l_at_the_distance_all_round(corners):
    fig, ax = plt.subplots()
    swarm_plot._near_wall_margin(ax, corners, 0.5)
    margin = np.vstack([line.get_xydata() for line in ax.lines] +
                       [path.vertices for c in ax.collections for path in c.get_paths()])
    plt.close(fig)
    assert MplPath(corners).contains_points(margin).all()
    assert boundary_dist(margin, corners) == pytest.approx(np.full(len(margin), 0.5), abs=0.02)
    # drawn all round: near every point 0.5 m inside the walls, the arc round the reentrant corner (2, 1.5) included
    for point in [(0.5, 0.5), (3.5, 1.0), (1.0, 4.0), (1.5, 2.5), (3.0, 1.0), (2 - 0.5 ** 1.5, 1.5 - 0.5 ** 1.5)]:
        assert np.hypot(*(margin - point).T).min() < 0.02


def test_sim_report_draws_the_arenas_obstacles(repo, tmp_path, monkeypatch):
    drawn, plot, drawn_in_arena, arena_plot = [], swarm_plot.plot_trajectories, [], sim_report.plot_arena

    def recorded(*args, obstacles, **kwargs):
        drawn.append(obstacles)
        return plot(*args, obstacles=obstacles, **kwargs)

    def recorded_in_arena(*args, obstacles, **kwargs):
        drawn_in_arena.append(obstacles)
        return arena_plot(*args, obstacles=obstacles, **kwargs)

    monkeypatch.setattr(swarm_plot, "plot_trajectories", recorded)
    monkeypatch.setattr(sim_report, "plot_arena", recorded_in_arena)
    monkeypatch.chdir(repo)   # the airframe names its arena from the repository
    _run_folder(tmp_path / "on", with_readings=True)
    _run_folder(tmp_path / "on" / "detector_off", with_readings=False)
    argv = ["--on", str(tmp_path / "on"), "--off", str(tmp_path / "on" / "detector_off")]
    airframe = ["--airframe", str(repo / "conf/airframes/finken_nps.xml")]
    pillar = ["--arena", str(repo / "conf/arena/swarmlab_pillar.xml")]
    for options in ([], airframe, pillar, airframe + pillar):
        assert sim_report.main(argv + options) == 0
    assert [len(obstacles) for obstacles in drawn] == [0, 0, 1, 1]   # the airframe's arena is swarmlab.xml
    assert [len(obstacles) for obstacles in drawn_in_arena] == [0, 0, 1, 1]
    assert drawn[2][0][1] == 3.0
    assert sim_report.main(argv + ["--arena", str(tmp_path / "missing.xml")]) == 1


def test_one_shape_message_per_obstacle(tmp_path):
    with ArenaTruth(arena_file(tmp_path, polygon_xml(TABLE_CW, 0.75), CIRCLE)) as arena:
        table, circle = obstacle_messages(arena.obstacles(), 52.1395, 11.6456)
    table, circle = table.split(), circle.split()
    assert table[:8] == ["ground", "SHAPE", str(SHAPE_ID + 1), "cyan", "cyan", "2", "1", "0"]   # a filled polygon
    lats, lons = [list(map(int, f.split(","))) for f in table[8:10]]
    expected = [lat_lon_of_enu(x, y, 52.1395, 11.6456) for x, y in TABLE_CW]
    assert sorted(zip(lats, lons)) == sorted((round(la * 1e7), round(lo * 1e7)) for la, lo in expected)
    assert table[10:] == ["0.0", "Obstacle1"]
    assert circle[:8] == ["ground", "SHAPE", str(SHAPE_ID + 2), "cyan", "cyan", "2", "0", "0"]   # a filled circle
    lat, lon = lat_lon_of_enu(2.5, 3.0, 52.1395, 11.6456)
    assert circle[8:10] == [str(round(lat * 1e7)), str(round(lon * 1e7))]
    assert float(circle[10]) == pytest.approx(0.25) and circle[11] == "Obstacle2"
