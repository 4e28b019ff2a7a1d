"""The GCS's picture (tools/finken/paparazzi/gcs_view.py): where PprzGCS's map and the arena's walls are on a
screenshot (synthetic screens drawn as PprzGCS draws them: a grey map with buttons inside it, a light side pane, cyan
walls under aircraft icons), what is missing named, and a virtual display started and stopped."""
import shutil
import subprocess

import numpy as np
import pytest

from finken.paparazzi.gcs_view import map_box, picture_problem, virtual_display, walls_centre

GREY, LIGHT, CYAN, RED = (64, 64, 64), (239, 239, 239), (0, 255, 255), (255, 0, 0)


def screen():
    rgb = np.zeros((1000, 1600, 3), int)
    rgb[:] = LIGHT
    rgb[75:968, 10:1130] = GREY                       # the map
    rgb[80:480, 15:100] = (40, 90, 200)               # its buttons, inside it
    rgb[600:620, 1200:1500] = GREY                    # a grey patch in the side pane, not the map
    return rgb


def test_the_map_is_the_largest_grey_patch():
    assert map_box(screen()) == (10, 75, 1130, 968)


def test_the_walls_centre_is_the_centre_of_the_cyan_lines_even_under_icons():
    rgb = screen()
    x0, y0, x1, y1 = 400, 300, 770, 790               # the walls' rectangle
    for y in (y0, y1):
        rgb[y:y + 3, x0:x1 + 3] = CYAN
    for x in (x0, x1):
        rgb[y0:y1 + 3, x:x + 3] = CYAN
    rgb[280:330, 380:430] = RED                        # an aircraft over a corner
    rgb[40:60, 1300:1400] = CYAN                       # cyan outside the map does not count
    assert walls_centre(rgb, map_box(rgb)) == (586, 546)
    assert walls_centre(screen(), map_box(screen())) is None


def test_what_is_missing_is_named(tmp_path):
    assert "no pprzgcs on the PATH" in picture_problem({"PATH": str(tmp_path)})
    (tmp_path / "pprzgcs").write_text("#!/bin/sh\n")
    (tmp_path / "pprzgcs").chmod(0o755)
    assert "missing Xvfb (xvfb), xdotool (xdotool), import (imagemagick)" in picture_problem({"PATH": str(tmp_path)})


@pytest.mark.skipif(not shutil.which("Xvfb") or not shutil.which("xdpyinfo"), reason="needs Xvfb and xdpyinfo")
def test_a_virtual_display_starts_and_stops(tmp_path):
    with virtual_display(tmp_path / "xvfb.log") as display:
        info = subprocess.run(["xdpyinfo", "-display", display], capture_output=True, text=True, timeout=30)
        assert info.returncode == 0 and "1600x1000 pixels" in info.stdout
    assert subprocess.run(["xdpyinfo", "-display", display], capture_output=True, timeout=30).returncode != 0
