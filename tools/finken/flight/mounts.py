"""What the airframe says of the sonars for a lab's flight: where they sit on the copter (the mounts the flight is
ray-cast from; body frame: x forward, y left, z up, from the copter's centre [m]) and when they listen.

The FINken's five sonars point front, right, back, left and down. The airframe may state where they sit, in a
section with the prefix SONAR_ARRAY_:
- MOUNT_OFFSET: every sonar this far from the centre along its boresight [m];
- <FRONT|RIGHT|BACK|LEFT|DOWN>_MOUNT_X, _Y, _Z: one sonar's position, overriding the offset for that sonar [m].
Without them the sonars sit where the simulator puts them: the arena file's <sonars offset> along each boresight.
When a sonar listens (sonar_timing): SONAR_ARRAY_READ_DELAY slots of the ring's round robin after its trigger, each
slot 1 / (5 SONAR_ARRAY_RATE) s, and SONAR_ARRAY_SPEED_OF_SOUND; the sonar_array module's defaults unless the
airframe sets them (anywhere: a section, the firmware, the module's own defines).
"""
from dataclasses import dataclass

import numpy as np

from finken.conf.airframe import read_airframe
from finken.flight.truth import SonarTiming
from finken.xml_errors import XmlInputError

#: Range-log sensor name -> unit boresight in the body frame (x forward, y left, z up).
BORESIGHTS = {
    "sonar_front": (1.0, 0.0, 0.0),
    "sonar_right": (0.0, -1.0, 0.0),
    "sonar_back": (-1.0, 0.0, 0.0),
    "sonar_left": (0.0, 1.0, 0.0),
    "sonar_down": (0.0, 0.0, -1.0),
}
PREFIX = "SONAR_ARRAY_"
SONARS_IN_RING = 5
#: the sonar_array module's defaults (sw/airborne/modules/sonar/sonar_array.h)
TIMING_DEFAULTS = {"SONAR_ARRAY_READ_DELAY": 2.0, "SONAR_ARRAY_RATE": 20.0, "SONAR_ARRAY_SPEED_OF_SOUND": 343.0}


@dataclass
class SonarMounts:
    """Each sonar's position and unit boresight in the body frame [m], and where they were taken from."""
    position: dict      # sensor name -> np.array(3)
    boresight: dict     # sensor name -> np.array(3)
    source: str         # "airframe <path>" or "arena <sonars offset>"


def sonar_mounts(airframe_path, arena_offset_m):
    """The mounts stated by the airframe (see the module docstring), else the arena's offset along the boresights.
    XmlInputError (file:line) for a define that is not a number."""
    defines = {d.name: d for d in _airframe(airframe_path).section_defines
               if d.name.startswith(PREFIX)}
    offset_m, stated = arena_offset_m, False
    if PREFIX + "MOUNT_OFFSET" in defines:
        offset_m, stated = _number(airframe_path, defines[PREFIX + "MOUNT_OFFSET"]), True
    position, boresight = {}, {}
    for name, axis in BORESIGHTS.items():
        boresight[name] = np.array(axis)
        position[name] = offset_m * boresight[name]
        key = PREFIX + name.removeprefix("sonar_").upper() + "_MOUNT_"
        for k, coord in enumerate("XYZ"):
            if key + coord in defines:
                position[name][k], stated = _number(airframe_path, defines[key + coord]), True
    source = f"airframe {airframe_path}" if stated else f"the arena's <sonars offset> ({arena_offset_m:g} m)"
    return SonarMounts(position, boresight, source)


def sonar_timing(airframe_path):
    """The SonarTiming the airframe gives the ring (see the module docstring); XmlInputError for a value that is not
    a number."""
    frame = _airframe(airframe_path)
    stated = {d.name: d for d in frame.section_defines + frame.defines +
              [d for m in frame.modules for d in m.defines] if d.name in TIMING_DEFAULTS}
    value = {name: _number(airframe_path, stated[name]) if name in stated else default
             for name, default in TIMING_DEFAULTS.items()}
    slot_s = 1.0 / (SONARS_IN_RING * value["SONAR_ARRAY_RATE"])
    return SonarTiming(value["SONAR_ARRAY_READ_DELAY"] * slot_s, value["SONAR_ARRAY_SPEED_OF_SOUND"])


def _airframe(airframe_path):
    """The airframe with its NPS target, else its autopilot's (a lab's airframe may have no simulation target)."""
    try:
        return read_airframe(airframe_path, target="nps")
    except XmlInputError:
        return read_airframe(airframe_path, target="ap")


def _number(path, define):
    try:
        return float(define.value)
    except (TypeError, ValueError):
        raise XmlInputError(path, define.line, f"{define.name}: '{define.value}' is not a number") from None
