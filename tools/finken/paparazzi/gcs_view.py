"""A picture of the swarm in Paparazzi's GCS (PprzGCS) on a virtual display: `make paparazzi-check`'s ground step runs
PprzGCS beside link and server (ground_check.py), and ground_commands.py takes the picture while the swarm flies,
before it sends its commands.

There is no network for map tiles: PprzGCS gets a settings file of its own (a scratch XDG folder) with
`default_tiles=none`, so its map is the flight plan's sectors (the arena's walls) and the aircraft on grey.
"""
import os
import shutil
import subprocess
import time
from contextlib import contextmanager
from pathlib import Path

import numpy as np
from PIL import Image
from scipy import ndimage

SCREEN = (1600, 1000)       # PprzGCS's default layout is this size
# X programs the picture needs, and the Debian package of each (make installs them: PAPARAZZI_PACKAGES)
X_TOOLS = {"Xvfb": "xvfb", "xdotool": "xdotool", "import": "imagemagick"}
SETTINGS = """[General]
aircraft_default_color=red

[map]
default_tiles=none
"""
# Where to look: PprzGCS loads a flight plan at zoom level 17, "c" centres its map on the selected aircraft, and the
# wheel zooms half a level about the pointer (mapwidget.cpp, map2d.cpp).
FLIGHT_PLAN_ZOOM = 17
NEAR_ZOOM = 20              # about the aircraft: the 3 x 4 m arena some 30 x 45 px, its walls found on the screen
ZOOM = 23.5                 # then about the walls' centre: the arena some 370 x 490 px


def picture_problem(env):
    """Why the GCS's picture cannot be taken here (None when it can)."""
    path = env.get("PATH")
    if not shutil.which("pprzgcs", path=path):
        return "no pprzgcs on the PATH (PprzGCS: docs/paparazzi.md, \"Watch the swarm live\")"
    missing = [f"{tool} ({package})" for tool, package in X_TOOLS.items() if not shutil.which(tool, path=path)]
    if missing:
        return f"missing {', '.join(missing)}: apt-get install {' '.join(sorted(set(X_TOOLS.values())))}"
    return None


@contextmanager
def virtual_display(log):
    """An Xvfb server of SCREEN's size for the block: yields its DISPLAY (":N", the first free number, which Xvfb
    writes once it accepts clients); stopped after it. Its output goes to the file `log`."""
    read_fd, write_fd = os.pipe()
    with open(log, "w") as out:
        xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write_fd), "-screen", "0", f"{SCREEN[0]}x{SCREEN[1]}x24",
                                 "-nolisten", "tcp"], pass_fds=(write_fd,), stdout=out, stderr=subprocess.STDOUT)
    os.close(write_fd)
    with os.fdopen(read_fd) as answer:
        number = answer.readline().strip()
    try:
        if not number:
            raise RuntimeError(f"Xvfb did not start (its output: {log})")
        yield f":{number}"
    finally:
        xvfb.terminate()
        try:
            xvfb.wait(10)
        except subprocess.TimeoutExpired:
            xvfb.kill()
            xvfb.wait()


def gcs_env(env, display, scratch):
    """The environment of PprzGCS on `display`, its settings and caches in the folder `scratch`."""
    scratch = Path(scratch)
    settings = scratch / "data/pprzgcs/settings.conf"
    settings.parent.mkdir(parents=True, exist_ok=True)
    settings.write_text(SETTINGS)
    return dict(env, DISPLAY=display, XDG_DATA_HOME=str(scratch / "data"), XDG_CONFIG_HOME=str(scratch / "config"),
                XDG_CACHE_HOME=str(scratch / "cache"))


def _xdotool(*args):
    subprocess.run(["xdotool", *map(str, args)], check=True, capture_output=True, timeout=30)


def _screen(png):
    return np.asarray(Image.open(png).convert("RGB")).astype(int)


def map_box(rgb):
    """(x0, y0, x1, y1) [px] of PprzGCS's map on a screenshot: the largest patch of the screen's commonest colour,
    the map's background when there are no tiles (its buttons sit inside the box)."""
    packed = (rgb[:, :, 0] << 16) | (rgb[:, :, 1] << 8) | rgb[:, :, 2]
    colours, counts = np.unique(packed, return_counts=True)
    labels, _ = ndimage.label(packed == colours[counts.argmax()])
    largest = np.bincount(labels.ravel())[1:].argmax() + 1
    ys, xs = np.nonzero(labels == largest)
    return xs.min(), ys.min(), xs.max() + 1, ys.max() + 1


def walls_centre(rgb, box):
    """The centre (x, y) [px] of the walls' drawing (arena_shapes.py: cyan lines) inside the map's box, or None."""
    x0, y0, x1, y1 = box
    r, g, b = (rgb[y0:y1, x0:x1, k] for k in range(3))
    ys, xs = np.nonzero((r < 80) & (g > 180) & (b > 180))
    if len(xs) == 0:
        return None
    return x0 + (xs.min() + xs.max() + 1) // 2, y0 + (ys.min() + ys.max() + 1) // 2


def _zoom(at, levels):
    _xdotool("mousemove", *at)
    for _ in range(round(2 * levels)):
        _xdotool("click", 4)       # wheel up: half a zoom level about the pointer
        time.sleep(0.15)


def _screenshot(path):
    subprocess.run(["import", "-window", "root", str(path)], check=True, capture_output=True, timeout=60)


def take_picture(path):
    """Zoom PprzGCS's map (on $DISPLAY) onto the arena and write the screen to `path` (PNG). Raises RuntimeError
    naming what failed. The map is centred on the selected aircraft (inside the arena) and zoomed about it until the
    walls show (arena_shapes.py draws them), then zoomed about the walls' centre."""
    try:
        window = subprocess.run(["xdotool", "search", "--sync", "--onlyvisible", "--class", "pprzgcs"], check=True,
                                capture_output=True, text=True, timeout=30).stdout.split()[0]
        _xdotool("windowfocus", "--sync", window)
        _screenshot(path)
        box = map_box(_screen(path))
        centre = ((box[0] + box[2]) // 2, (box[1] + box[3]) // 2)
        _xdotool("mousemove", *centre)
        _xdotool("key", "c")
        _zoom(centre, NEAR_ZOOM - FLIGHT_PLAN_ZOOM)
        _screenshot(path)
        walls = walls_centre(_screen(path), box)
        _zoom(walls or centre, ZOOM - NEAR_ZOOM)
        _xdotool("mousemove", 0, 0)    # no hover highlight in the picture
        time.sleep(1.0)                # a telemetry period: the aircraft redrawn
        _screenshot(path)
    except (subprocess.CalledProcessError, subprocess.TimeoutExpired) as err:
        detail = getattr(err, "stderr", b"") or b""
        if isinstance(detail, bytes):
            detail = detail.decode(errors="replace")
        raise RuntimeError(f"the GCS picture failed: {' '.join(err.cmd)}: {detail.strip()}")
