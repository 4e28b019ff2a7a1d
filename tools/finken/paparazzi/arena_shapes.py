"""The arena's walls drawn on Paparazzi's GCS, whatever the arena: SHAPE messages (pprzlink's ground class, which
PprzGCS and the legacy GCS draw) on the ground's Ivy bus.

Run as a program beside a swarm (a helper of `make paparazzi-sim GCS=1` and of `make paparazzi-check`'s ground
step): it sends the walls at rest of `--arena` as a polygon, placed by the flight plan's origin (`--flight-plan`: its
lat0 and lon0; the flight plan's frame is the arena's, finken_world.h), every `--period` seconds, so that a GCS
started later draws them too, until it is stopped.
"""
import argparse
import math
import signal
import sys
import threading

from lxml import etree

WGS84_A = 6378137.0                       # semi-major axis [m]
WGS84_E2 = 6.69437999014e-3               # first eccentricity squared
SHAPE_ID = 1                              # the walls' polygon
LINE_COLOUR, FILL_COLOUR = "cyan", "cyan"  # no aircraft of the GCS's default palette is cyan
POLYGON, CREATE, TRANSPARENT = 1, 0, 0


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


def walls_message(polygon, lat0_deg, lon0_deg, name="Arena"):
    """The Ivy text of the ground SHAPE message drawing `polygon` (n, 2) [m east, north of the origin]."""
    points = [lat_lon_of_enu(x, y, lat0_deg, lon0_deg) for x, y in polygon]
    lats = ",".join(str(round(lat * 1e7)) for lat, _ in points)
    lons = ",".join(str(round(lon * 1e7)) for _, lon in points)
    return (f"ground SHAPE {SHAPE_ID} {LINE_COLOUR} {FILL_COLOUR} {TRANSPARENT} {POLYGON} {CREATE} {lats} {lons} "
            f"0.0 {name}")


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
            polygon = arena.outline()
        message = walls_message(polygon, *flight_plan_origin(args.flight_plan))
    except (ArenaError, ValueError, OSError, etree.XMLSyntaxError) as err:
        print(f"arena_shapes: {err}", file=sys.stderr, flush=True)
        return 2
    from ivy.ivy import IvyServer
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    ivy = IvyServer("finken_arena_shapes", "finken_arena_shapes READY")
    ivy.start(args.bus)
    print(f"arena_shapes: the walls of {args.arena} ({len(polygon)} corners) every {args.period:g} s", flush=True)
    try:
        while True:
            ivy.send_msg(message)
            if stop.wait(args.period):
                break
    finally:
        ivy.stop()
    return 0


if __name__ == "__main__":
    sys.exit(main())
