"""Range logs: read, validate and write the measured-data CSV format of `shared/spec/range-log.md`.

One reader for every tool (simulator summary, wall-detector metrics, discrepancy workflow). A file that breaks
the spec is rejected with `RangeLogError` naming the file, the line (1 = header) and the column.

Reading policy for messy lab data (documented in docs/calibration.md, "Range logs"):
- columns in any order; surrounding spaces in names and values are ignored; a UTF-8 byte-order mark is
  ignored; blank lines are skipped; CRLF line ends are accepted; quoted fields are accepted;
- numbers are ASCII decimal (finken.text_numbers: no `1_5`, no digits of other scripts); ids (`vehicle`,
  `peer`) are whole numbers from 0 to text_numbers.MAX_ID;
- an empty field, or NaN written out (`nan`, `NaN`), means "no value" in `measured`, `peer` and `ctx_`
  columns; `t`, `vehicle`, `sensor` and `true_range` must hold a value;
- `measured` is what the sensor reported, whatever it is: a negative, zero, infinite (`inf`, `-inf`) or absurd
  reading is a glitch of the sensor, kept as it is (finken.discrepancy.glitches counts and models them);
- `peer` is another copter's id on a `ranging` row (required, not the row's own vehicle) and empty on sonar rows;
- rejected: a missing required column, a duplicated column, a row with the wrong number of fields, text in a
  numeric column, an infinity in a numeric column other than `measured`, a `vehicle`/`peer` that is not an id, a
  peer breaking the rule above, an unknown `sensor`, a negative `true_range`, and a stream (`vehicle`, `sensor`,
  `peer`) whose `t` goes backwards (equal times are accepted);
- a file with several faults gets the error the first failing check gives in this order, at its first line:
  not UTF-8, malformed CSV, field count, header, values of t, vehicle, peer, true_range, measured, sensor,
  peer rule, negative true range, ctx_ values, time order (so the chunks a file is read in never change it).

A lab's own CSV is read as is with options (finken.rangelog_columns; parse_column_map and parse_fill read
their command-line text): `columns` {spec name: file column} reads a file column as that spec column (a
`ctx_` name makes it a context column); `unit` "cm" or "mm" divides true_range and measured; `fill` {spec
name: text} gives a required column the file lacks one value for every row (checked as a file value, in
`unit`; an error names the option); `group` names a file column whose value identifies a recording: it is
part of every stream, so each recording may start again at t = 0 (RangeLog.group, group_names). Each row
keeps its file line (RangeLog.line).

Memory and speed: the file is read in chunks of `chunk_bytes` (1 MiB) cut at line ends, after a first pass
that only checks UTF-8 and looks for quote characters. A chunk is split with str methods (by the `csv`
module if the file holds a quote anywhere), its numbers checked and converted column-wise
(text_numbers.parse_column) into columns allocated once for the file's line count; the time order carries
the last row of each stream from chunk to chunk. Peak memory is the result (8 bytes a value; `sensor` holds
the SENSOR_NAMES strs themselves, dtype object) plus about 30 MB: 190 MB over the interpreter for 2 million
rows of 9 columns, read in 2.3 s on one core (7 s with quotes).
"""
import codecs
import csv
import io
import os
from dataclasses import dataclass, field
from itertools import repeat

import numpy as np

from finken.atomic_output import atomic_output
from finken.rangelog_columns import (CTX_PREFIX, REQUIRED_COLUMNS, SENSOR_NAMES, UNITS, check_column_map,
                                     check_fill, parse_column_map, parse_fill)
from finken.text_numbers import MAX_ID, SPACES, ColumnError, is_id, parse_column

__all__ = ["CTX_PREFIX", "REQUIRED_COLUMNS", "SENSOR_NAMES", "UNITS", "RangeLog", "RangeLogError",
           "parse_column_map", "parse_fill", "read_range_log", "stream_ids", "write_range_log"]

CHUNK_BYTES = 1 << 20
_PRESCAN_BYTES = 1 << 20
_SENSOR_CODE = {name: code for code, name in enumerate(SENSOR_NAMES)}
_SENSOR_OBJECTS = np.array(SENSOR_NAMES, dtype=object)
#: (name, optional, integer), in the order they are checked; every value finite but a reading's (a glitch may be
#: infinite)
_NUMERIC = (("t", False, False), ("vehicle", False, True), ("peer", True, True), ("true_range", False, False),
            ("measured", True, False))


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
    sensor: np.ndarray       # sensor name (str), one of SENSOR_NAMES (read: dtype object, the SENSOR_NAMES strs)
    peer: np.ndarray         # other copter's id for ranging, NaN if empty
    true_range: np.ndarray   # ground-truth range [m]
    measured: np.ndarray     # reported range [m], NaN when the sensor reported nothing
    ctx: dict = field(default_factory=dict)    # every ctx_ column, float (NaN if empty)
    extra: dict = field(default_factory=dict)  # every other column, str
    line: np.ndarray = None          # int64: the row's line in its file (1 = header); None if not read from one
    group: np.ndarray = None         # int64: the row's recording, an index into group_names (read with group=)
    group_names: np.ndarray = None   # str: each recording's value of the group column, in order of appearance

    def __len__(self):
        return len(self.t)

    def select(self, rows):
        """A new RangeLog with the rows given by an index array or boolean mask, in that order."""
        return RangeLog(self.path, self.t[rows], self.vehicle[rows], self.sensor[rows], self.peer[rows],
                        self.true_range[rows], self.measured[rows],
                        {k: v[rows] for k, v in self.ctx.items()}, {k: v[rows] for k, v in self.extra.items()},
                        None if self.line is None else self.line[rows],
                        None if self.group is None else self.group[rows], self.group_names)


def stream_ids(log):
    """Integer id per row of its stream (`vehicle`, `sensor`, `peer`, and the recording when the log was read
    with `group`), numbered in sorted key order."""
    if len(log) == 0:
        return np.zeros(0, dtype=np.int64)
    sensor_code = np.full(len(log), len(SENSOR_NAMES), dtype=np.int64)
    for code, name in enumerate(SENSOR_NAMES):
        sensor_code[log.sensor == name] = code
    _, vehicle_code = np.unique(log.vehicle, return_inverse=True)
    peer_values, peer_code = np.unique(np.where(np.isnan(log.peer), -np.inf, log.peer), return_inverse=True)
    key = (vehicle_code.astype(np.int64) * (len(SENSOR_NAMES) + 1) + sensor_code) * len(peer_values) + peer_code
    _, ids = np.unique(key, return_inverse=True)
    group = getattr(log, "group", None)
    if group is not None:
        _, ids = np.unique(ids.reshape(-1).astype(np.int64) * (int(group.max()) + 1) + group, return_inverse=True)
    return ids.reshape(-1).astype(np.int64)


def read_range_log(path, columns=None, unit="m", fill=None, group=None, progress=None, chunk_bytes=CHUNK_BYTES):
    """Read and validate the range log at `path`; return a RangeLog or raise RangeLogError.

    columns: {spec name: the file's column name} (a file column read as that spec column; `ctx_` names make
      context columns); unit: "m", "cm" or "mm", the unit of true_range and measured in the file (and in
      `fill`); fill: {spec name: value text} for columns the file lacks, one value for every row; group: the
      name of a file column whose value identifies a recording (part of the stream key);
    progress: a callable progress(bytes_done, bytes_total), called after each chunk of the file;
    chunk_bytes: how much of the file is read and checked at a time."""
    path = str(path)
    reader = _Reader(path, columns, unit, fill, group)
    try:
        f = open(path, "rb")
    except OSError as err:
        raise RangeLogError(path, None, None, f"cannot read: {err.strerror or err}")
    with f:
        try:
            if not f.seekable():   # a pipe: read twice from memory
                f = io.BytesIO(f.read())
            total = f.seek(0, os.SEEK_END)
            f.seek(0)
            quoted, max_rows = _prescan(path, f)
            reader.reserve(max_rows)
            f.seek(0)
            for done, rows in (_quoted_rows if quoted else _plain_rows)(path, f, max(1, int(chunk_bytes))):
                reader.add(rows)
                if reader.first.rank == _FIELD_COUNT and not quoted:
                    break   # nothing later in a file without quotes can come before it
                if progress is not None:
                    progress(done, total)
        except OSError as err:
            raise RangeLogError(path, None, None, f"cannot read: {err.strerror or err}")
    return reader.finish()


# ------------------------------------------------------------------ the file's text, chunk by chunk

def _prescan(path, f):
    """Check that the whole file is UTF-8 (RangeLogError naming the byte otherwise); (whether it holds a
    quote, how many lines it has at most)."""
    decoder = codecs.getincrementaldecoder("utf-8")()
    quoted, offset, breaks = False, 0, 0
    while True:
        data = f.read(_PRESCAN_BYTES)
        pending = len(decoder.getstate()[0])
        if not data or not data.isascii() or pending:
            try:
                decoder.decode(data, final=not data)
            except UnicodeDecodeError as err:
                raise RangeLogError(path, None, None,
                                    f"not UTF-8 text: {err.reason} at byte {offset - pending + err.start}")
        if not data:
            return quoted, breaks + 1
        quoted = quoted or b'"' in data
        breaks += data.count(b"\n") + data.count(b"\r")
        offset += len(data)


def _byte_chunks(f, chunk_bytes):
    """(bytes, offset of their end) pieces of the file, each cut after a line end ("\\n", or a "\\r" known not
    to be followed by "\\n") unless it is the file's last piece."""
    pending, done = [], 0
    while True:
        data = f.read(chunk_bytes)
        done += len(data)
        if not data:
            if pending:
                yield b"".join(pending), done
            return
        cut = max(data.rfind(b"\n"), data.rfind(b"\r", 0, len(data) - 1)) + 1
        if cut == 0:
            pending.append(data)
            continue
        pending.append(data[:cut])
        yield b"".join(pending), done - (len(data) - cut)
        pending = [data[cut:]] if cut < len(data) else []


def _decode(path, data, first):
    """A chunk as text: a leading byte-order mark of the file dropped, line ends made "\\n"."""
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:   # the file changed since _prescan
        raise RangeLogError(path, None, None, f"not UTF-8 text: {err.reason}")
    if first:
        text = text.lstrip("\ufeff")
    if "\r" in text:
        text = text.replace("\r\n", "\n").replace("\r", "\n")
    return text


class _PlainRows:
    """The non-blank lines of a chunk without quotes: `numbers` (their lines in the file), `counts` (fields
    per line), and the text (kept whole when no line was blank)."""

    def __init__(self, numbers, counts, text, lines):
        self.numbers, self.counts, self.text, self.lines = numbers, counts, text, lines

    def take_header(self):
        self.numbers, self.counts = self.numbers[1:], self.counts[1:]
        if self.lines is not None:
            return self.lines.pop(0).split(",")
        first, _, self.text = self.text.partition("\n")
        return first.split(",")

    def columns(self, width):
        """The fields as one list of str per column (all lines have `width` fields)."""
        if not len(self.numbers):
            return [[] for _ in range(width)]
        if self.text is not None:
            flat = self.text.replace("\n", ",").split(",")
            if self.text.endswith("\n"):
                flat.pop()
        else:
            flat = ",".join(self.lines).split(",")
        self.text = self.lines = None
        return [flat[j::width] for j in range(width)]


def _plain_rows(path, f, chunk_bytes):
    """(bytes done, _PlainRows) for each chunk of a file without quote characters."""
    next_line = 1
    for k, (data, done) in enumerate(_byte_chunks(f, chunk_bytes)):
        text = _decode(path, data, k == 0)
        del data
        lines = text.split("\n")
        if text.endswith("\n"):
            lines.pop()
        numbers = np.arange(next_line, next_line + len(lines), dtype=np.int64)
        next_line += len(lines)
        counts = np.fromiter(map(str.count, lines, repeat(",")), dtype=np.int64, count=len(lines)) + 1
        blank = [i for i in np.flatnonzero(counts == 1).tolist() if not lines[i].strip()]
        if blank:
            keep = np.ones(len(lines), dtype=bool)
            keep[blank] = False
            yield done, _PlainRows(numbers[keep], counts[keep], None, [s for s, k in zip(lines, keep) if k])
        else:
            del lines
            yield done, _PlainRows(numbers, counts, text, None)


class _QuotedRows:
    """Non-blank records read by the csv module: `numbers` (each record's first line), `counts`, the fields."""

    def __init__(self, records):
        self.numbers = np.fromiter((n for n, _ in records), dtype=np.int64, count=len(records))
        self.counts = np.fromiter((len(fs) for _, fs in records), dtype=np.int64, count=len(records))
        self.records = [fs for _, fs in records]

    def take_header(self):
        self.numbers, self.counts = self.numbers[1:], self.counts[1:]
        return self.records.pop(0)

    def columns(self, width):
        columns = [list(c) for c in zip(*self.records)] if self.records else [[] for _ in range(width)]
        self.records = None
        return columns


def _quoted_rows(path, f, chunk_bytes):
    """(bytes done, _QuotedRows) for about each chunk of a file holding quotes (a record may span chunks)."""
    state = {"done": 0, "chunks": 0}

    def lines():
        for k, (data, done) in enumerate(_byte_chunks(f, chunk_bytes)):
            state["done"], state["chunks"] = done, state["chunks"] + 1
            yield from io.StringIO(_decode(path, data, k == 0))

    reader = csv.reader(lines())
    records, seen = [], 0
    try:
        for fields in reader:
            if any(f.strip() for f in fields):
                records.append((reader.line_num - sum(f.count("\n") for f in fields), fields))
            if state["chunks"] != seen:
                seen = state["chunks"]
                yield state["done"], _QuotedRows(records)
                records = []
    except csv.Error as err:
        raise RangeLogError(path, reader.line_num, None, f"malformed CSV: {err}")
    yield state["done"], _QuotedRows(records)


# ------------------------------------------------------------------ checks

_FIELD_COUNT, _HEADER = (0,), (1,)   # ranks of the checks (tuples, compared in order); see _Reader.add


class _FirstError:
    """The error a reader of the whole file reports: the first check (lowest rank) that fails, at its first
    line. Chunks are checked in file order, so the first error offered for a rank is the one kept."""

    def __init__(self):
        self.rank, self.error = None, None

    def open(self, rank):
        """True while a failure of check `rank` would still be reported."""
        return self.rank is None or rank < self.rank

    def offer(self, rank, error):
        if self.open(rank):
            self.rank, self.error = rank, error


class _Problem(Exception):
    """A field that fails a check: its index in the column, which check of the column (`sub`), the reason."""

    def __init__(self, index, sub, reason):
        super().__init__(reason)
        self.index, self.sub, self.reason = index, sub, reason


def _column_numbers(texts, optional, integer, infinite=False):
    """Fields (list of str) as float64 (text_numbers' grammar); empty or NaN fields become NaN where
    `optional`, else are errors; infinities are errors unless `infinite`; with `integer`, every value must be an
    id.
    Raises _Problem: sub 0 text, 1 no value, 2 infinity or not an id (each over the whole column first)."""
    blob = ",".join(texts)
    if " " in blob or "\t" in blob:
        texts = [s.strip(SPACES) for s in texts]
    try:
        values = parse_column(texts)
    except ColumnError as err:
        raise _Problem(err.index, 0, err.reason) from None
    empty = np.isnan(values)
    if not optional and empty.any():
        i = int(np.flatnonzero(empty)[0])
        what = "empty" if texts[i] == "" else f"'{texts[i]}'"
        raise _Problem(i, 1, f"{what}: a number is required here")
    bad = np.isinf(values) if not infinite else np.zeros(values.shape, bool)
    if integer:
        bad |= ~empty & ~is_id(values)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        expected = f"an integer id from 0 to {MAX_ID}" if integer else "a finite number"
        raise _Problem(i, 2, f"'{texts[i]}' is not {expected}")
    return values


def _sensor_codes(texts):
    """Index into SENSOR_NAMES of each field (surrounding white space ignored); _Problem for another name."""
    codes = np.fromiter(map(_SENSOR_CODE.get, texts, repeat(-1)), dtype=np.int8, count=len(texts))
    if (codes < 0).any():
        texts = [s.strip() for s in texts]
        codes = np.fromiter(map(_SENSOR_CODE.get, texts, repeat(-1)), dtype=np.int8, count=len(texts))
        if (codes < 0).any():
            i = int(np.flatnonzero(codes < 0)[0])
            raise _Problem(i, 0, f"unknown sensor '{texts[i]}' (expected one of: {', '.join(SENSOR_NAMES)})")
    return codes


# The spec's `peer`: the other copter's id on a ranging row, empty on a sonar row. (columns needed, rows
# breaking the rule, reason for row i)
_PEER_RULES = (
    (("sensor", "peer"), lambda v, c, p: (c == _SENSOR_CODE["ranging"]) & np.isnan(p),
     lambda i, v, c, p: "no value: a ranging row needs the id of the other copter"),
    (("sensor", "peer"), lambda v, c, p: (c != _SENSOR_CODE["ranging"]) & ~np.isnan(p),
     lambda i, v, c, p: f"{p[i]:g} on a {SENSOR_NAMES[c[i]]} row: sonar rows have no peer"),
    (("vehicle", "peer"), lambda v, c, p: p == v,
     lambda i, v, c, p: f"{p[i]:g} is the row's own vehicle: the peer is another copter"),
)


def _stream_order(vehicle, code, peer, group):
    """Rows sorted by stream (stable: file order within a stream) and, for each sorted row after the first,
    whether it is in the stream of the one before."""
    peer = np.where(np.isnan(peer), 0, peer + 1).astype(np.int64)
    vehicle = vehicle.astype(np.int64)
    spans = [int(vehicle.max()) + 1, len(SENSOR_NAMES), int(peer.max()) + 1, int(group.max()) + 1]
    if float(np.prod(np.asarray(spans, dtype=np.float64))) < 2.0**62:
        key = ((vehicle * spans[1] + code) * spans[2] + peer) * spans[3] + group
        order = np.argsort(key, kind="stable")
        key = key[order]
        return order, key[1:] == key[:-1]
    order = np.lexsort((group, peer, code, vehicle))
    same = np.ones(len(order) - 1, dtype=bool)
    for k in (vehicle, code, peer, group):
        k = k[order]
        same &= k[1:] == k[:-1]
    return order, same


class _Reader:
    """Checks the chunks of one file in order and keeps their columns; finish() gives the RangeLog."""

    def __init__(self, path, columns, unit, fill, group):
        self.path = path
        try:
            self.column_map, fill = check_column_map(columns), check_fill(fill)
            if unit not in UNITS:
                raise ValueError(f"unit: '{unit}' is not one of {', '.join(UNITS)}")
            if group is not None and (not isinstance(group, str) or not group.strip()):
                raise ValueError(f"group: {group!r} is not a column name")
        except ValueError as err:
            raise RangeLogError(path, None, None, str(err)) from None
        self.unit, self.scale = unit, UNITS[unit]
        self.group_column = group.strip() if group is not None else None
        self.fill = {name: self._fill_value(name, text) for name, text in fill.items()}
        self._check_filled_peers(fill)
        self.first = _FirstError()
        self.header = None
        self.capacity = self.rows = 0
        self.kept, self.extra = {}, {}   # the columns so far: arrays of `capacity` rows (`rows` used); lists
        self.carry = None             # last row of every stream so far: (vehicle, code, peer, group, t, line)
        self.group_codes = {}

    def reserve(self, max_rows):
        """Room for `max_rows` rows in every column kept (pages never written take no memory)."""
        self.capacity = max_rows

    # -------------------------------------------------------------- options
    def _fill_value(self, name, text):
        """The value of a filled column (a float, or a sensor's index), checked as a file value would be."""
        try:
            if name == "sensor":
                return int(_sensor_codes([text])[0])
            optional, integer = next(((o, i) for n, o, i in _NUMERIC if n == name), (True, False))
            value = float(_column_numbers([text], optional, integer, infinite=name == "measured")[0])
        except _Problem as problem:
            raise RangeLogError(self.path, None, name, f"fill option {name}='{text}': {problem.reason}") from None
        if name in ("true_range", "measured"):
            if name == "true_range" and value < 0:
                raise RangeLogError(self.path, None, name,
                                    f"fill option {name}='{text}': negative range {value:g} {self.unit}")
            value /= self.scale
        return value

    def _check_filled_peers(self, fill):
        """The peer rule on filled values alone (a rule on a file column is checked on its rows)."""
        for needs, rows, reason in _PEER_RULES:
            if all(name in self.fill for name in needs):
                v, c, p = (np.array([self.fill.get(n, 0)], dtype=np.float64) for n in ("vehicle", "sensor", "peer"))
                c = c.astype(np.int64)
                if rows(v, c, p)[0]:
                    given = ", ".join(f"{n}='{fill[n]}'" for n in needs)
                    raise RangeLogError(self.path, None, "peer", f"fill option {given}: {reason(0, v, c, p)}")

    # -------------------------------------------------------------- header
    def _set_header(self, fields):
        names = [h.strip() for h in fields]
        self.header, self.width = names, len(names)
        error = self._read_header(names)
        if error is not None:
            self.first.offer(_HEADER, RangeLogError(self.path, 1, *error))

    def _read_header(self, names):
        """Where each spec column is in the file (self.index, ctx_columns, extra_columns, group_index); or
        (column, reason) of the first fault of the header and of the options that name its columns."""
        seen = set()
        for j, name in enumerate(names):
            if name == "":
                return None, f"header field {j + 1} is empty"
            if name in seen:
                return name, "duplicated column"
            seen.add(name)
        role = list(names)   # the spec name each file column is read as
        for spec, column in self.column_map.items():
            if column not in seen:
                return column, f"not in the header (given for '{spec}' by the columns option)"
            role[names.index(column)] = spec
        for spec, column in self.column_map.items():
            if role.count(spec) > 1:
                return spec, f"is in the header and also given by the columns option (as column '{column}')"
        for name in self.fill:
            if name in role:
                return name, "is in the file and given by the fill option too"
        for name in REQUIRED_COLUMNS:
            if name not in role and name not in self.fill:
                return name, "missing required column (required: " + ", ".join(REQUIRED_COLUMNS) + ")"
        if self.group_column is not None and self.group_column not in seen:
            return self.group_column, "not in the header (named by the group option)"
        self.index = {spec: j for j, spec in enumerate(role) if spec in REQUIRED_COLUMNS}
        self.ctx_columns = [(j, spec) for j, spec in enumerate(role) if spec.startswith(CTX_PREFIX)]
        self.ctx_columns += [(None, name) for name in self.fill if name.startswith(CTX_PREFIX)]
        self.extra_columns = [(j, spec) for j, spec in enumerate(role)
                              if spec not in REQUIRED_COLUMNS and not spec.startswith(CTX_PREFIX)]
        self.group_index = None if self.group_column is None else names.index(self.group_column)
        return None

    # -------------------------------------------------------------- rows
    def add(self, rows):
        """Check the rows of one chunk; keep their columns while no error has been found."""
        if self.header is None:
            if not len(rows.numbers):
                return
            self._set_header(rows.take_header())
        lines, counts = rows.numbers, rows.counts
        bad = np.flatnonzero(counts != self.width)
        if bad.size and self.first.open(_FIELD_COUNT):
            i = int(bad[0])
            column = self.header[counts[i]] if counts[i] < self.width else None
            reason = f"expected {self.width} fields as in the header, found {counts[i]}"
            self.first.offer(_FIELD_COUNT, RangeLogError(self.path, int(lines[i]), column, reason))
        if not self.first.open(_HEADER) or not len(lines):
            return
        columns = rows.columns(self.width)
        n = len(lines)
        values = {}
        for k, (name, optional, integer) in enumerate(_NUMERIC):
            if name in self.fill:
                values[name] = np.full(n, self.fill[name])
                continue
            values[name] = self._numbers((2, k), name, columns[self.index[name]], lines, optional, integer,
                                         infinite=name == "measured")
            if values[name] is None:
                return
        if "sensor" in self.fill:
            codes = np.full(n, self.fill["sensor"], dtype=np.int8)
        else:
            codes = self._checked((3,), "sensor", lines, _sensor_codes, columns[self.index["sensor"]])
            if codes is None:
                return
        vehicle, peer = values["vehicle"], values["peer"]
        for r, (_, rule, reason) in enumerate(_PEER_RULES):
            if not self._rule((4, r), "peer", lines, rule(vehicle, codes, peer),
                              lambda i: reason(i, vehicle, codes, peer)):
                return
        v = values["true_range"]
        if "true_range" not in self.fill and not self._rule((5,), "true_range", lines, v < 0,
                                                             lambda i: f"negative range {v[i]:g} {self.unit}"):
            return
        for name in ("true_range", "measured"):
            if name not in self.fill and self.scale != 1:
                values[name] = values[name] / self.scale
        ctx = {}
        for i, (j, name) in enumerate(self.ctx_columns):
            if j is None:
                ctx[name] = np.full(n, self.fill[name])
            else:
                ctx[name] = self._numbers((6, i), name, columns[j], lines, True, False)
                if ctx[name] is None:
                    return
        group = np.zeros(n, dtype=np.int64)
        if self.group_index is not None:
            codes_of = self.group_codes
            group = np.fromiter((codes_of.setdefault(s.strip(), len(codes_of)) for s in columns[self.group_index]),
                                dtype=np.int64, count=n)
        self._check_time(values["t"], vehicle, codes, peer, group, lines)
        if self.first.error is None:
            if self.rows + n > self.capacity:   # the file grew since _prescan
                self.capacity = 2 * (self.rows + n)
                for column in self.kept.values():
                    column.resize(self.capacity, refcheck=False)
            kept = [(name, v) for name, v in values.items()] + [("sensor", codes), (("line",), lines)]
            kept += [(("group",), group)] + [(("ctx", name), v) for name, v in ctx.items()]
            for key, v in kept:
                if key not in self.kept:
                    self.kept[key] = np.empty(self.capacity, dtype=v.dtype)
                self.kept[key][self.rows:self.rows + n] = v
            for j, name in self.extra_columns:
                self.extra.setdefault(name, []).append(np.asarray(columns[j], dtype=str))
            self.rows += n

    def _checked(self, rank, name, lines, check, *args):
        """check(*args), or None after offering its _Problem (at sub-rank problem.sub) as the row's error."""
        if not self.first.open(rank + (0,)):
            return None
        try:
            return check(*args)
        except _Problem as problem:
            self.first.offer(rank + (problem.sub,), RangeLogError(self.path, int(lines[problem.index]), name,
                                                                   problem.reason))
            return None

    def _numbers(self, rank, name, texts, lines, optional, integer, infinite=False):
        return self._checked(rank, name, lines, _column_numbers, texts, optional, integer, infinite)

    def _rule(self, rank, name, lines, broken, reason):
        """False if the check `rank` is no longer reported or fails here (offering the first broken row)."""
        if not self.first.open(rank):
            return False
        if broken.any():
            i = int(np.flatnonzero(broken)[0])
            self.first.offer(rank, RangeLogError(self.path, int(lines[i]), name, reason(i)))
            return False
        return True

    def _check_time(self, t, vehicle, codes, peer, group, lines):
        """Offer the first row (in file order) whose time is earlier than the previous row of its stream, the
        stream's rows of earlier chunks included (through self.carry, the last row of each stream)."""
        rank = (7,)
        if not self.first.open(rank):
            return
        arrays = (vehicle, codes.astype(np.int64), peer, group, t, lines)
        if self.carry is not None:
            arrays = tuple(np.concatenate((c, a)) for c, a in zip(self.carry, arrays))
        vehicle, codes, peer, group, t, lines = arrays
        order, same = _stream_order(vehicle, codes, peer, group)
        t_sorted = t[order]
        backwards = same & (t_sorted[1:] < t_sorted[:-1])
        if backwards.any():
            positions = np.flatnonzero(backwards)
            later = order[positions + 1]
            k = int(np.argmin(lines[later]))
            row, previous = int(later[k]), int(order[positions[k]])
            where = f"vehicle {vehicle[row]:g}, sensor {SENSOR_NAMES[codes[row]]}"
            if not np.isnan(peer[row]):
                where += f", peer {peer[row]:g}"
            if self.group_index is not None:
                where += f", {self.group_column} '{list(self.group_codes)[group[row]]}'"
            self.first.offer(rank, RangeLogError(
                self.path, int(lines[row]), "t", f"t = {t[row]:g} s goes back in time from t = {t[previous]:g} s "
                f"on line {int(lines[previous])} of the same stream ({where})"))
            return
        last = order[np.append(~same, True)]
        self.carry = tuple(a[last] for a in arrays)

    # -------------------------------------------------------------- result
    def finish(self):
        if self.first.error is not None:
            raise self.first.error
        if self.header is None:
            raise RangeLogError(self.path, None, None,
                                "empty file: expected a header row with " + ", ".join(REQUIRED_COLUMNS))
        def take(key, dtype):
            column = self.kept.pop(key, None)
            if column is None:
                return np.zeros(0, dtype=dtype)
            column.resize(self.rows, refcheck=False)   # shrinks in place
            return column

        t, vehicle, peer, true_range, measured = (take(name, np.float64) for name, _, _ in _NUMERIC)
        sensor = _SENSOR_OBJECTS[take("sensor", np.int8)]
        ctx = {name: take(("ctx", name), np.float64) for _, name in self.ctx_columns}
        extra = {name: np.concatenate(self.extra.pop(name, [np.zeros(0, dtype=str)])) for _, name in self.extra_columns}
        line = take(("line",), np.int64)
        group = take(("group",), np.int64) if self.group_index is not None else None
        names = np.array(list(self.group_codes), dtype=str) if self.group_index is not None else None
        return RangeLog(self.path, t, vehicle, sensor, peer, true_range, measured, ctx, extra, line, group, names)


def write_range_log(path, log):
    """Write `log` as a range-log CSV: required columns, then ctx_ columns, then the other columns."""
    names = list(REQUIRED_COLUMNS) + list(log.ctx) + list(log.extra)
    columns = [_format_float(log.t), _format_int(log.vehicle), np.asarray(log.sensor).astype(str).tolist(),
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
