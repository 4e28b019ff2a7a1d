"""Range logs: read, validate and write the measured-data CSV format of `shared/spec/range-log.md`.

One reader for every tool (simulator summary, wall-detector metrics, discrepancy workflow). A file that breaks
the spec is rejected with `RangeLogError` naming the file, the line (1 = header) and the column.

Reading policy for messy lab data (documented in the README):
- columns in any order; surrounding spaces in names and values are ignored; a UTF-8 byte-order mark is
  ignored; blank lines are skipped; CRLF line ends are accepted; quoted fields are accepted;
- numbers are ASCII decimal (finken.text_numbers: no `1_5`, no digits of other scripts); ids (`vehicle`,
  `peer`) are whole numbers from 0 to text_numbers.MAX_ID;
- an empty field, or NaN written out (`nan`, `NaN`), means "no value" in `measured`, `peer` and `ctx_`
  columns; `t`, `vehicle`, `sensor` and `true_range` must hold a value;
- `peer` is another copter's id on a `ranging` row (required, not the row's own vehicle) and empty on sonar rows;
- rejected: a missing required column, a duplicated column, a row with the wrong number of fields, text or an
  infinity in a numeric column, a `vehicle`/`peer` that is not an id, a peer breaking the rule above, an
  unknown `sensor`, a negative range, and a stream (`vehicle`, `sensor`, `peer`) whose `t` goes backwards
  (equal times are accepted).

Speed: a file without quote characters is split with str methods, its numbers checked column-wise by one
regular-expression search (text_numbers.parse_column) and converted by numpy (about 5 s per million rows of
6 numeric columns, 1 s of it the check); files with quotes go through the `csv` module (slower).
"""
import csv
import io
from dataclasses import dataclass, field

import numpy as np

from finken.atomic_output import atomic_output
from finken.text_numbers import MAX_ID, SPACES, ColumnError, is_id, parse_column

REQUIRED_COLUMNS = ("t", "vehicle", "sensor", "peer", "true_range", "measured")
SENSOR_NAMES = ("sonar_front", "sonar_right", "sonar_back", "sonar_left", "sonar_down", "ranging")
CTX_PREFIX = "ctx_"


class RangeLogError(ValueError):
    """A range log that breaks the spec: `file:line: column 'x': reason` (line 1 is the header)."""

    def __init__(self, path, line, column, reason):
        self.path, self.line, self.column, self.reason = str(path), line, column, reason
        where = f"{self.path}:{line}" if line else self.path
        what = f" column '{column}':" if column else ""
        super().__init__(f"{where}:{what} {reason}")


@dataclass
class RangeLog:
    """A range log in memory; one entry per row, in file order. Units: s, m."""
    path: str
    t: np.ndarray            # time of the reading [s]
    vehicle: np.ndarray      # copter id (float holding an integer)
    sensor: np.ndarray       # sensor name (str), one of SENSOR_NAMES
    peer: np.ndarray         # other copter's id for ranging, NaN if empty
    true_range: np.ndarray   # ground-truth range [m]
    measured: np.ndarray     # reported range [m], NaN when the sensor reported nothing
    ctx: dict = field(default_factory=dict)    # every ctx_ column, float (NaN if empty)
    extra: dict = field(default_factory=dict)  # every other column, str

    def __len__(self):
        return len(self.t)

    def select(self, rows):
        """A new RangeLog with the rows given by an index array or boolean mask, in that order."""
        return RangeLog(self.path, self.t[rows], self.vehicle[rows], self.sensor[rows], self.peer[rows],
                        self.true_range[rows], self.measured[rows],
                        {k: v[rows] for k, v in self.ctx.items()}, {k: v[rows] for k, v in self.extra.items()})


def stream_ids(log):
    """Integer id per row of its stream (`vehicle`, `sensor`, `peer`), numbered in sorted key order."""
    if len(log) == 0:
        return np.zeros(0, dtype=np.int64)
    sensor_code = np.full(len(log), len(SENSOR_NAMES), dtype=np.int64)
    for code, name in enumerate(SENSOR_NAMES):
        sensor_code[log.sensor == name] = code
    _, vehicle_code = np.unique(log.vehicle, return_inverse=True)
    peer_values, peer_code = np.unique(np.where(np.isnan(log.peer), -np.inf, log.peer), return_inverse=True)
    key = (vehicle_code.astype(np.int64) * (len(SENSOR_NAMES) + 1) + sensor_code) * len(peer_values) + peer_code
    _, ids = np.unique(key, return_inverse=True)
    return ids.reshape(-1).astype(np.int64)


def read_range_log(path):
    """Read and validate the range log at `path`; return a RangeLog or raise RangeLogError."""
    path = str(path)
    try:
        with open(path, "r", encoding="utf-8", newline="") as f:
            text = f.read()
    except OSError as err:
        raise RangeLogError(path, None, None, f"cannot read: {err.strerror or err}")
    except UnicodeDecodeError as err:
        raise RangeLogError(path, None, None, f"not UTF-8 text: {err.reason} at byte {err.start}")
    header, line_of_row, columns = _split_fields(path, text)
    return _build_log(path, header, line_of_row, columns)


def _split_fields(path, text):
    """Header names, the line number of each data row, and the fields as one list of str per column."""
    text = text.lstrip("\ufeff")
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    if '"' in text:
        records = []
        reader = csv.reader(io.StringIO(text))
        try:
            for fields in reader:
                records.append((reader.line_num - (sum(f.count("\n") for f in fields)), fields))
        except csv.Error as err:
            raise RangeLogError(path, reader.line_num, None, f"malformed CSV: {err}")
        records = [(n, fs) for n, fs in records if any(f.strip() for f in fs)]
        numbers = [n for n, _ in records]
        rows = [fs for _, fs in records]
    else:
        lines = text.split("\n")
        numbers = [i + 1 for i, line in enumerate(lines) if line.strip()]
        rows = None
        lines = [lines[n - 1] for n in numbers] if len(numbers) != len(lines) else lines
    if not numbers:
        raise RangeLogError(path, None, None, "empty file: expected a header row with " + ", ".join(REQUIRED_COLUMNS))
    header = [h.strip() for h in (rows[0] if rows is not None else lines[0].split(","))]
    width = len(header)
    body = rows[1:] if rows is not None else lines[1:]
    if rows is not None:
        counts = np.fromiter((len(r) for r in body), dtype=np.int64, count=len(body))
    else:
        counts = np.fromiter((line.count(",") for line in body), dtype=np.int64, count=len(body)) + 1
    bad = np.flatnonzero(counts != width)
    if bad.size:
        i = int(bad[0])
        column = header[counts[i]] if counts[i] < width else None
        raise RangeLogError(path, numbers[i + 1], column, f"expected {width} fields as in the header, found {counts[i]}")
    if rows is not None:
        columns = [list(c) for c in zip(*body)] if body else [[] for _ in header]
    else:
        flat = ",".join(body).split(",") if body else []
        columns = [flat[j::width] for j in range(width)]
    return header, np.asarray(numbers[1:], dtype=np.int64), columns


def _build_log(path, header, line_of_row, columns):
    seen = {}
    for j, name in enumerate(header):
        if name == "":
            raise RangeLogError(path, 1, None, f"header field {j + 1} is empty")
        if name in seen:
            raise RangeLogError(path, 1, name, "duplicated column")
        seen[name] = j
    for name in REQUIRED_COLUMNS:
        if name not in seen:
            raise RangeLogError(path, 1, name, "missing required column (required: " + ", ".join(REQUIRED_COLUMNS) + ")")

    def numeric(name, optional, integer=False):
        return _to_float(path, name, columns[seen[name]], line_of_row, optional, integer)

    t = numeric("t", optional=False)
    vehicle = numeric("vehicle", optional=False, integer=True)
    peer = numeric("peer", optional=True, integer=True)
    true_range = numeric("true_range", optional=False)
    measured = numeric("measured", optional=True)
    sensor = np.strings.strip(np.asarray(columns[seen["sensor"]], dtype=str)) if line_of_row.size else np.zeros(0, str)
    unknown = ~np.isin(sensor, SENSOR_NAMES)
    if unknown.any():
        i = int(np.flatnonzero(unknown)[0])
        raise RangeLogError(path, int(line_of_row[i]), "sensor",
                            f"unknown sensor '{sensor[i]}' (expected one of: {', '.join(SENSOR_NAMES)})")
    _check_peers(path, vehicle, sensor, peer, line_of_row)
    for name, values in (("true_range", true_range), ("measured", measured)):
        negative = values < 0
        if negative.any():
            i = int(np.flatnonzero(negative)[0])
            raise RangeLogError(path, int(line_of_row[i]), name, f"negative range {values[i]:g} m")
    ctx = {name: numeric(name, optional=True) for name in header if name.startswith(CTX_PREFIX)}
    extra = {name: np.asarray(columns[j], dtype=str) for j, name in enumerate(header)
             if name not in REQUIRED_COLUMNS and not name.startswith(CTX_PREFIX)}
    log = RangeLog(path, t, vehicle, sensor, peer, true_range, measured, ctx, extra)
    _check_time_order(log, line_of_row)
    return log


def _to_float(path, name, strings, line_of_row, optional, integer):
    """Column `name` as float64 (text_numbers' grammar: ASCII decimal); empty or NaN fields become NaN where
    `optional`, else are errors; infinities are errors; with `integer`, every value must be an id."""
    text = np.strings.strip(np.asarray(strings, dtype=str), SPACES) if len(strings) else np.zeros(0, dtype=str)
    try:
        values = parse_column(text)
    except ColumnError as err:
        raise RangeLogError(path, int(line_of_row[err.index]), name, err.reason) from None
    empty = np.isnan(values)
    if empty.any() and not optional:
        i = int(np.flatnonzero(empty)[0])
        what = "empty" if text[i] == "" else f"'{text[i]}'"
        raise RangeLogError(path, int(line_of_row[i]), name, f"{what}: a number is required here")
    bad = np.isinf(values)
    if integer:
        bad |= ~empty & ~is_id(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        expected = f"an integer id from 0 to {MAX_ID}" if integer else "a finite number"
        raise RangeLogError(path, int(line_of_row[i]), name, f"'{text[i]}' is not {expected}")
    return values


def _check_peers(path, vehicle, sensor, peer, line_of_row):
    """The spec's `peer`: the other copter's id on a ranging row, empty on a sonar row."""
    ranging = sensor == "ranging"
    rules = ((ranging & np.isnan(peer), lambda i: "no value: a ranging row needs the id of the other copter"),
             (~ranging & ~np.isnan(peer), lambda i: f"{peer[i]:g} on a {sensor[i]} row: sonar rows have no peer"),
             (peer == vehicle, lambda i: f"{peer[i]:g} is the row's own vehicle: the peer is another copter"))
    for rows, reason in rules:
        if rows.any():
            i = int(np.flatnonzero(rows)[0])
            raise RangeLogError(path, int(line_of_row[i]), "peer", reason(i))


def _check_time_order(log, line_of_row):
    """Reject the first row (in file order) whose time is earlier than the previous row of its stream."""
    if len(log) < 2:
        return
    ids = stream_ids(log)
    order = np.lexsort((np.arange(len(log)), ids))
    same_stream = ids[order][1:] == ids[order][:-1]
    backwards = same_stream & (np.diff(log.t[order]) < 0)
    if backwards.any():
        positions = np.flatnonzero(backwards)
        later = order[positions + 1]
        k = int(np.argmin(later))
        row, previous = int(later[k]), int(order[positions[k]])
        peer = "" if np.isnan(log.peer[row]) else f", peer {log.peer[row]:g}"
        raise RangeLogError(log.path, int(line_of_row[row]), "t",
                            f"t = {log.t[row]:g} s goes back in time from t = {log.t[previous]:g} s on line "
                            f"{int(line_of_row[previous])} of the same stream (vehicle {log.vehicle[row]:g}, "
                            f"sensor {log.sensor[row]}{peer})")


def write_range_log(path, log):
    """Write `log` as a range-log CSV: required columns, then ctx_ columns, then the other columns."""
    names = list(REQUIRED_COLUMNS) + list(log.ctx) + list(log.extra)
    columns = [_format_float(log.t), _format_int(log.vehicle), log.sensor.astype(str).tolist(),
               _format_int(log.peer), _format_float(log.true_range), _format_float(log.measured)]
    columns += [_format_float(v) for v in log.ctx.values()]
    columns += [np.asarray(v, dtype=str).tolist() for v in log.extra.values()]
    with atomic_output(path, newline="") as f:
        writer = csv.writer(f, lineterminator="\n")
        writer.writerow(names)
        writer.writerows(zip(*columns))


def _format_float(values):
    """Shortest round-trip text of each value, '' for NaN."""
    return ["" if v != v else repr(v) for v in np.asarray(values, dtype=np.float64).tolist()]


def _format_int(values):
    return ["" if v != v else str(int(v)) for v in np.asarray(values, dtype=np.float64).tolist()]
