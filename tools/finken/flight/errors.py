"""The error of the flight readers (records, mocap and the formats they read): an input file they cannot use."""


class FlightInputError(ValueError):
    """A file a reader cannot use: `file:line: reason`, or `file:line: column 'x': reason` (line 1 is the header;
    without a line, `file: reason`), as finken.rangelog.RangeLogError words it. Attributes path, line, column,
    reason."""

    def __init__(self, path, line, reason, column=None):
        self.path, self.line, self.column, self.reason = str(path), line, column, reason
        where = f"{self.path}:{line}" if line else self.path
        what = f" column '{column}':" if column else ""
        super().__init__(f"{where}:{what} {reason}")
