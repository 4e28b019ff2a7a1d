"""The arena's walls on the GCS (tools/finken/paparazzi/arena_shapes.py): the SHAPE message of the SwarmLab arena
placed by the flight plan's origin, its latitudes and longitudes against an exact conversion through ECEF, and a
flight plan without an origin refused naming the file."""
import math

import numpy as np
import pytest

from finken.paparazzi.arena_shapes import flight_plan_origin, lat_lon_of_enu, walls_message

A, E2 = 6378137.0, 6.69437999014e-3


def ecef(lat, lon, h=0.0):
    lat, lon = math.radians(lat), math.radians(lon)
    n = A / math.sqrt(1 - E2 * math.sin(lat) ** 2)
    return np.array([(n + h) * math.cos(lat) * math.cos(lon), (n + h) * math.cos(lat) * math.sin(lon),
                     (n * (1 - E2) + h) * math.sin(lat)])


def geodetic(p):
    """Latitude, longitude [deg] of an ECEF point, by fixed-point iteration on the latitude."""
    lon = math.atan2(p[1], p[0])
    r = math.hypot(p[0], p[1])
    lat = math.atan2(p[2], r * (1 - E2))
    for _ in range(20):
        n = A / math.sqrt(1 - E2 * math.sin(lat) ** 2)
        h = r / math.cos(lat) - n
        lat = math.atan2(p[2], r * (1 - E2 * n / (n + h)))
    return math.degrees(lat), math.degrees(lon)


def exact(east, north, lat0, lon0):
    """The point east, north [m] of (lat0, lon0) in the local tangent plane, as Paparazzi's server places positions
    (ecef_of_ned), back to latitude and longitude."""
    la, lo = math.radians(lat0), math.radians(lon0)
    e = np.array([-math.sin(lo), math.cos(lo), 0.0])
    n = np.array([-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)])
    return geodetic(ecef(lat0, lon0) + east * e + north * n)


@pytest.mark.parametrize("lat0, lon0", [(52.1395, 11.6456), (-33.9, 151.2), (0.0, 0.0), (69.6, 18.9)])
def test_points_within_a_millimetre_of_the_local_tangent_plane(lat0, lon0):
    for east, north in [(0, 0), (3, 0), (3, 4), (0, 4), (-10, 25)]:
        lat, lon = lat_lon_of_enu(east, north, lat0, lon0)
        lat_x, lon_x = exact(east, north, lat0, lon0)
        metres = math.hypot((lat - lat_x) * 111e3, (lon - lon_x) * 111e3 * math.cos(math.radians(lat0)))
        assert metres < 1e-3     # 0.1 mm at 27 m from the origin, at 70 deg north


def test_the_swarmlab_walls_as_a_shape_message():
    msg = walls_message(np.array([[0, 0], [3, 0], [3, 4], [0, 4]]), 52.1395, 11.6456)
    fields = msg.split()
    assert fields[:8] == ["ground", "SHAPE", "1", "cyan", "cyan", "0", "1", "0"]
    lats, lons = [list(map(int, f.split(","))) for f in fields[8:10]]
    assert lats[0] == 521395000 and lons[0] == 116456000
    # 4 m north: 4 / 111.3 km of latitude; 3 m east: 3 / (111.3 km cos 52.14 deg) of longitude, in 1e-7 deg
    assert lats[2] - lats[0] == pytest.approx(4 / 111_300 * 1e7, rel=2e-3)
    assert lons[1] - lons[0] == pytest.approx(3 / (111_300 * math.cos(math.radians(52.1395))) * 1e7, rel=3e-3)
    assert fields[10:] == ["0.0", "Arena"]


def test_origin_from_a_flight_plan_or_paparazzis_dump_of_it(tmp_path):
    plan = tmp_path / "plan.xml"
    plan.write_text('<flight_plan lat0="52.1" lon0="11.6" name="x"/>')
    assert flight_plan_origin(plan) == (52.1, 11.6)
    dump = tmp_path / "dump.xml"
    dump.write_text('<dump>\n  <flight_plan lat0="-33.9" lon0="151.2"/>\n</dump>')
    assert flight_plan_origin(dump) == (-33.9, 151.2)
    bad = tmp_path / "bad.xml"
    bad.write_text('<flight_plan name="no origin"/>')
    with pytest.raises(ValueError, match=r"bad.xml:1: no flight plan with numeric lat0 and lon0"):
        flight_plan_origin(bad)
