"""The arena's walls drawn on Paparazzi's GCS, whatever the arena: SHAPE messages (pprzlink's ground class, which
PprzGCS and the legacy GCS draw) on the ground's Ivy bus.

Run as a program beside a swarm (a helper of `make paparazzi-sim GCS=1` and of `make paparazzi-check`'s ground
step): it sends the walls at rest of `--arena` as a polygon and each interior obstacle as a filled circle or
polygon, placed by the flight plan's origin (`--flight-plan`: its lat0 and lon0; the flight plan's frame is the
arena's, finken_world.h), every `--period` seconds, so that a GCS started later draws them too, until it is stopped.
"""
import argparse
import math
import signal
import sys
import threading

from lxml import etree

WGS84_A = 6378137.0                       # semi-major axis [m]
WGS84_E2 = 6.69437999014e-3               # first eccentricity squared
SHAPE_ID = 1                              # the walls' polygon; the obstacles' shapes are 2, 3, ...
LINE_COLOUR, FILL_COLOUR = "cyan", "cyan"  # no aircraft of the GCS's default palette is cyan
CIRCLE, POLYGON, CREATE, TRANSPARENT, MEDIUM_FILL = 0, 1, 0, 0, 2


def lat_lon_of_enu(east_m, north_m, lat0_deg, lon0_deg):
    """Latitude and longitude [deg] of a point east_m, north_m [m] from (lat0, lon0) on the WGS84 ellipsoid, by the
    radii of curvature there (a flat earth over the few metres of an arena, exact to well under a millimetre):
    meridian M = a (1 - e^2) / (1 - e^2 sin^2 lat)^1.5, prime vertical N = a / (1 - e^2 sin^2 lat)^0.5,
    dlat = north / M, dlon = east / (N cos lat)."""
    lat0 = math.radians(lat0_deg)
    w = 1.0 - WGS84_E2 * math.sin(lat0) ** 2
    meridian, prime_vertical = WGS84_A * (1.0 - WGS84_E2) / w ** 1.5, WGS84_A / math.sqrt(w)
    return (lat0_deg + math.degrees(north_m / meridian),
            lon0_deg + math.degrees(east_m / (prime_vertical * math.cos(lat0))))


def flight_plan_origin(path):
    """(lat0, lon0) [deg] of a flight plan XML, or of the one in Paparazzi's dump of it (var/aircrafts/<name>/
    flight_plan.xml); ValueError naming the file when it has none."""
    root = etree.parse(str(path)).getroot()
    plan = root if root.tag == "flight_plan" else root.find("flight_plan")
    try:
        return float(plan.get("lat0")), float(plan.get("lon0"))
    except (AttributeError, TypeError, ValueError):
        raise ValueError(f"{path}:{root.sourceline}: no flight plan with numeric lat0 and lon0") from None


def shape_message(shape_id, opacity, shape, points, lat0_deg, lon0_deg, radius_m, name):
    """The Ivy text of a ground SHAPE message (pprzlink's messages.xml) through `points` (n, 2) [m east, north of
    the origin]."""
    lat_lon = [lat_lon_of_enu(x, y, lat0_deg, lon0_deg) for x, y in points]
    lats = ",".join(str(round(lat * 1e7)) for lat, _ in lat_lon)
    lons = ",".join(str(round(lon * 1e7)) for _, lon in lat_lon)
    return (f"ground SHAPE {shape_id} {LINE_COLOUR} {FILL_COLOUR} {opacity} {shape} {CREATE} {lats} {lons} "
            f"{radius_m} {name}")


def walls_message(polygon, lat0_deg, lon0_deg, name="Arena"):
    """The Ivy text of the ground SHAPE message drawing `polygon` (n, 2) [m east, north of the origin]."""
    return shape_message(SHAPE_ID, TRANSPARENT, POLYGON, polygon, lat0_deg, lon0_deg, 0.0, name)


def obstacle_messages(obstacles, lat0_deg, lon0_deg):
    """The Ivy texts of one filled SHAPE per obstacle (finken.flight.truth.Obstacle), ids after the walls': a circle
    as a SHAPE circle, a polygon as a SHAPE polygon."""
    messages = []
    for k, obstacle in enumerate(obstacles, start=1):
        if obstacle.circle is not None:
            x, y, radius_m = obstacle.circle
            shape, points = CIRCLE, [(x, y)]
        else:
            shape, points, radius_m = POLYGON, obstacle.outline, 0.0
        messages.append(shape_message(SHAPE_ID + k, MEDIUM_FILL, shape, points, lat0_deg, lon0_deg, radius_m,
                                      f"Obstacle{k}"))
    return messages


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bus", required=True, help="the ground segment's Ivy bus")
    ap.add_argument("--arena", required=True, help="arena XML (conf/arena/)")
    ap.add_argument("--flight-plan", required=True, help="the aircraft's flight plan XML (its lat0 and lon0)")
    ap.add_argument("--period", type=float, default=2.0, help="seconds between two sendings")
    args = ap.parse_args(argv)
    from finken.flight.truth import ArenaError, ArenaTruth
    try:
        with ArenaTruth(args.arena) as arena:
            polygon, obstacles = arena.outline(), arena.obstacles()
        origin = flight_plan_origin(args.flight_plan)
        messages = [walls_message(polygon, *origin), *obstacle_messages(obstacles, *origin)]
    except (ArenaError, ValueError, OSError, etree.XMLSyntaxError) as err:
        print(f"arena_shapes: {err}", file=sys.stderr, flush=True)
        return 2
    from ivy.ivy import IvyServer
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    ivy = IvyServer("finken_arena_shapes", "finken_arena_shapes READY")
    ivy.start(args.bus)
    print(f"arena_shapes: the walls of {args.arena} ({len(polygon)} corners) and {len(obstacles)} obstacle(s) every "
          f"{args.period:g} s", flush=True)
    try:
        while True:
            for message in messages:
                ivy.send_msg(message)
            if stop.wait(args.period):
                break
    finally:
        ivy.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
