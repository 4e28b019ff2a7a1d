"""A small CSV with a header row, its cells kept as text until a column is asked for: Table and read_table, as the
flight readers use them (finken.flight.records for the recorder's decisions CSV, finken.flight.mocap for a plain
motion-capture CSV and our poses.csv).

Numbers follow finken.text_numbers; ids are whole numbers from 0 to MAX_ID, as in a range log.
Errors: FlightInputError, `file:line: column 'x': reason` (line 1 = the header).
"""
import csv
import io
from dataclasses import dataclass

import numpy as np

from finken.flight.errors import FlightInputError
from finken.text_numbers import MAX_ID, SPACES, ColumnError, is_id, parse_column

__all__ = ["Table", "read_table"]


@dataclass
class Table:
    """A CSV's data rows: `columns` {name: list of str, stripped}, each row's `line`, the header's line."""
    path: str
    header: list
    columns: dict
    line: np.ndarray
    header_line: int = 1

    def __len__(self):
        return len(self.line)

    def fail(self, i, column, reason):
        """Raise FlightInputError for data row i (0-based) in `column`."""
        raise FlightInputError(self.path, int(self.line[i]), reason, column)

    def numbers(self, name, finite, rows=None):
        """Column `name` as float64 (empty or nan: NaN); with `finite`, every value must be a finite number."""
        texts = self.columns[name] if rows is None else [self.columns[name][i] for i in rows]
        try:
            values = parse_column(texts)
        except ColumnError as err:
            self.fail(err.index if rows is None else rows[err.index], name, err.reason)
        if finite and not np.isfinite(values).all():
            i = int(np.flatnonzero(~np.isfinite(values))[0])
            what = "empty" if texts[i] == "" else f"'{texts[i]}'"
            self.fail(i if rows is None else rows[i], name, f"{what}: a finite number is required here")
        return values

    def ids(self, name):
        """Column `name` as int64 ids (whole numbers from 0 to MAX_ID, as in a range log)."""
        values = self.numbers(name, finite=True)
        bad = ~is_id(values)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            self.fail(i, name, f"'{self.columns[name][i]}' is not an integer id from 0 to {MAX_ID}")
        return values.astype(np.int64)


def read_table(path, required, optional=()):
    """A CSV with a header row as a Table: the `required` columns (FlightInputError at the header if one is
    missing) and those of `optional` that are there. A UTF-8 byte-order mark, CRLF, quoted fields, blank lines and
    spaces around names and values are accepted; every row must have the header's number of fields."""
    path = str(path)
    try:
        with open(path, encoding="utf-8-sig", newline="") as f:
            text = f.read()
    except (OSError, UnicodeDecodeError) as err:
        raise FlightInputError(path, None, f"cannot read: {err}") from None
    reader = csv.reader(io.StringIO(text))
    header, header_line, rows, lines = None, None, [], []
    try:
        for fields in reader:
            if not any(cell.strip(SPACES) for cell in fields):
                continue
            if header is None:
                header, header_line = [cell.strip(SPACES) for cell in fields], reader.line_num
                continue
            if len(fields) != len(header):
                raise FlightInputError(path, reader.line_num,
                                       f"expected {len(header)} fields as in the header, found {len(fields)}")
            rows.append(fields)
            lines.append(reader.line_num)
    except csv.Error as err:
        raise FlightInputError(path, reader.line_num, f"malformed CSV: {err}") from None
    if header is None:
        raise FlightInputError(path, None, "empty file: expected a header row with " + ", ".join(required))
    for j, name in enumerate(header):
        if name in header[:j]:
            raise FlightInputError(path, header_line, "duplicated column", name)
    for name in required:
        if name not in header:
            raise FlightInputError(path, header_line, "missing column (required: " + ", ".join(required) + ")",
                                   name)
    wanted = [name for name in list(required) + list(optional) if name in header]
    columns = {name: [row[header.index(name)].strip(SPACES) for row in rows] for name in wanted}
    return Table(path, header, columns, np.asarray(lines, dtype=np.int64), header_line)
