"""OptiTrack Motive's CSV export of a take, read: each rigid body's position and quaternion, frame by frame, as
exported (finken.flight.mocap turns them into the arena frame).

Format version 1.2x-1.3x:
- line 1, the metadata as key,value pairs: "Format Version", ..., "Rotation Type", "Length Units", "Coordinate
  Space";
- the rows Type, Name, ID (and Parent in later versions; the label in a leading column), the component row
  (Rotation, Position, Mean Marker Error, ...) and the axis row `Frame, Time (Seconds)[, TimeCode], X, Y, Z, W, ...`;
- one row per frame, each with the axis row's number of fields. An empty cell: the body was lost in that frame
  (NaN here).
Only "Rigid Body" columns are read: Rotation X, Y, Z, W (a quaternion, scalar last) and Position X, Y, Z; markers,
rigid-body markers, bones and the error/quality columns are skipped. A "Rotation Type" other than Quaternion (Euler
XYZ, ...) and a "Coordinate Space" other than Global are refused.

Units: the positions are kept in the export's "Length Units" (Meters, Centimeters or Millimeters: MotiveExport.unit
"m", "cm" or "mm"), or in the unit the caller names. Axes: as exported; Motive's frame is y-up by default, which
finken.flight.mocap turns z-up (its `up`, "y" for Motive unless told).
Errors: FlightInputError, `file:line: reason`.
"""
import csv
from dataclasses import dataclass

import numpy as np

from finken.flight.errors import FlightInputError
from finken.text_numbers import ColumnError, parse_column

__all__ = ["MotiveExport", "read_motive"]

MOTIVE_UNITS = {"meters": "m", "centimeters": "cm", "millimeters": "mm"}   # "Length Units" to our unit names
_AXES = ("X", "Y", "Z", "W")


@dataclass
class MotiveExport:
    """The rigid bodies of a Motive export: one time and line per frame, shared by every body."""
    t: np.ndarray             # (n,) [s], the "Time (Seconds)" column
    line: np.ndarray          # (n,) int64: each frame's line
    name_line: int            # the Name row's line, where the bodies are named
    bodies: dict              # {rigid body name: (pos (n, 3) [unit], quat (n, 4) scalar last)}, NaN where lost
    unit: str                 # the positions' unit: "m", "cm" or "mm"


def read_motive(path, unit=None):
    """The rigid bodies of the Motive CSV export at `path`, as a MotiveExport. `unit` ("m", "cm" or "mm"): the
    positions' unit, instead of the export's "Length Units". Raises FlightInputError."""
    try:
        f = open(path, encoding="utf-8-sig", newline="")
    except OSError as err:
        raise FlightInputError(path, None, f"cannot read: {err.strerror or err}") from None
    with f:
        reader = csv.reader(f)
        try:
            meta_row = next(reader, [])
            meta = {meta_row[i].strip(): meta_row[i + 1].strip() for i in range(0, len(meta_row) - 1, 2)}
            if not meta_row or meta_row[0].strip() != "Format Version":
                raise FlightInputError(path, 1, "not a Motive CSV export: the first line must start with "
                                       "'Format Version'")
            unit = _motive_units(path, meta, unit)
            header, axis, axis_line = [], None, None
            for row in reader:
                if row and row[0].strip() == "Frame":
                    axis, axis_line = [c.strip() for c in row], reader.line_num
                    break
                if any(c.strip() for c in row):
                    header.append((reader.line_num, [c.strip() for c in row]))
                if len(header) > 20:
                    break
            if axis is None:
                raise FlightInputError(path, reader.line_num, "malformed Motive header: no 'Frame,Time (Seconds),"
                                       "...' row after the Type, Name, ID and Rotation/Position rows")
            columns, t_column, name_line = _motive_columns(path, header, axis, axis_line)
            wanted = sorted({j for cols in columns.values() for j in cols.values()} | {t_column})
            texts = {j: [] for j in wanted}
            lines = []
            for row in reader:
                if not any(c.strip() for c in row):
                    continue
                if len(row) != len(axis):
                    raise FlightInputError(path, reader.line_num, f"expected {len(axis)} fields as in the header "
                                           f"(line {axis_line}), found {len(row)}")
                for j in wanted:
                    texts[j].append(row[j].strip())
                lines.append(reader.line_num)
        except csv.Error as err:
            raise FlightInputError(path, reader.line_num, f"malformed CSV: {err}") from None
        except UnicodeDecodeError as err:
            raise FlightInputError(path, None, f"not UTF-8 text: {err.reason}") from None
    lines = np.asarray(lines, dtype=np.int64)
    numbers = {}
    for j in wanted:
        try:
            numbers[j] = parse_column(texts[j])
        except ColumnError as err:
            raise FlightInputError(path, int(lines[err.index]), err.reason, axis[j] if j == t_column else
                                   f"{axis[j]} (column {j + 1})") from None
    t = numbers[t_column]
    if not np.isfinite(t).all():
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise FlightInputError(path, int(lines[i]), "a frame needs its time", axis[t_column])
    bodies = {name: (np.column_stack([numbers[cols[("Position", a)]] for a in "XYZ"]),
                     np.column_stack([numbers[cols[("Rotation", a)]] for a in "XYZW"]))
              for name, cols in columns.items()}
    return MotiveExport(t, lines, name_line, bodies, unit)


def _motive_units(path, meta, unit):
    """The positions' unit: `unit`, else the metadata's "Length Units"; a rotation other than quaternions or a
    coordinate space other than Global refused."""
    rotation = meta.get("Rotation Type")
    if rotation is not None and rotation.lower() != "quaternion":
        raise FlightInputError(path, 1, f"Rotation Type '{rotation}': only quaternions are read (export again with "
                               "Rotation Type Quaternion: Euler angles depend on an order and axes the export "
                               "does not fully state)")
    space = meta.get("Coordinate Space")
    if space is not None and space.lower() != "global":
        raise FlightInputError(path, 1, f"Coordinate Space '{space}': only Global coordinates are read")
    if unit is not None:
        return unit
    length = meta.get("Length Units")
    if length is None:
        raise FlightInputError(path, 1, "no 'Length Units' in the metadata: give the unit (m, cm or mm)")
    if length.lower() not in MOTIVE_UNITS:
        raise FlightInputError(path, 1, f"Length Units '{length}': expected Meters, Centimeters or Millimeters")
    return MOTIVE_UNITS[length.lower()]


def _motive_columns(path, header, axis, axis_line):
    """({rigid body name: {(Rotation|Position, X|Y|Z|W): column}}, the time column, the Name row's line)."""
    lead = next((j for j, a in enumerate(axis) if a in _AXES), None)
    if lead is None:
        raise FlightInputError(path, axis_line, "malformed Motive header: no X, Y, Z columns in the axis row")
    if "Time (Seconds)" not in axis[:lead]:
        raise FlightInputError(path, axis_line, "malformed Motive header: no 'Time (Seconds)' column")
    rows = {}
    for number, cells in header:
        cells = cells + [""] * (len(axis) - len(cells))
        label = next((c for c in cells[:lead] if c), "")
        if label == "" and any(c in ("Rotation", "Position") for c in cells[lead:]):
            label = "components"
        rows.setdefault(label, (number, cells))
    for label, what in (("Type", "',Type,' row (Rigid Body, Marker, ...)"), ("Name", "',Name,' row"),
                        ("components", "',,Rotation,...,Position,...' row")):
        if label not in rows:
            raise FlightInputError(path, axis_line, f"malformed Motive header: no {what} above the 'Frame' row")
    types, names, components = rows["Type"][1], rows["Name"][1], rows["components"][1]
    columns = {}
    for j in range(lead, len(axis)):
        if types[j] != "Rigid Body" or components[j] not in ("Rotation", "Position"):
            continue
        key = (components[j], axis[j])
        body = columns.setdefault(names[j], {})
        if key in body or axis[j] not in _AXES:
            raise FlightInputError(path, axis_line, f"malformed Motive header: rigid body '{names[j]}' has "
                                   f"{' '.join(key)} in column {j + 1} " + ("twice" if key in body else
                                                                              "(expected X, Y, Z or W)"))
        body[key] = j
    if not columns:
        found = sorted({t for t in types[lead:] if t})
        raise FlightInputError(path, rows["Type"][0], "no 'Rigid Body' columns (types found: "
                               + (", ".join(found) or "none") + ")")
    for name, body in columns.items():
        missing = [" ".join(k) for k in [("Rotation", a) for a in "XYZW"] + [("Position", a) for a in "XYZ"]
                   if k not in body]
        if missing:
            extra = " (no W: Euler angles? export with Rotation Type Quaternion)" if ("Rotation", "W") not in body \
                and ("Rotation", "X") in body else ""
            raise FlightInputError(path, axis_line, f"malformed Motive header: rigid body '{name}' lacks "
                                   + ", ".join(missing) + extra)
    return columns, axis[:lead].index("Time (Seconds)"), rows["Name"][0]
