"""The per-aircraft logs finken_world writes in FINKEN_WORLD_OUT, merged into the files of one swarm run.

Each NPS process (one aircraft) writes <kind>_<ac_id>.csv for the kinds readings (range-log format,
shared/spec/range-log.md), poses (t,vehicle,x,y,z,yaw), detections (the wall detector's decisions) and walls (wall
segment snapshots, written only by the aircraft that owns the walls at the time; ownership passes on when it dies).
All are CSV with one header line, the same for every aircraft, and times in the world's common time base in
column `t`. The merge writes <kind>.csv: one header and the rows of every aircraft ordered by time (rows of equal
time by aircraft id, each aircraft's in its own order).

Bad input stops nothing silently: a missing file, or one without even its header line, is reported; a file whose
last row lacks its newline (the process died mid-write) loses that row with a warning naming file and line; a
header different from the first aircraft's or a row that is not a row of that header is a MergeError naming file
and line, and that kind is not merged. The merged file is written to a temporary file and renamed, so an earlier
run's file is replaced whole or kept whole.
"""
import csv
import io
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

KINDS = ("readings", "poses", "detections", "walls")


class MergeError(ValueError):
    pass


@dataclass
class MergeResult:
    kind: str
    path: Path                     # the merged file (written when `written`)
    rows: int = 0
    written: bool = False
    missing: list = field(default_factory=list)    # source files that do not exist
    empty: list = field(default_factory=list)      # source files without even a header line
    warnings: list = field(default_factory=list)   # "file:line: ..." of rows left out

    @property
    def complete(self):
        """Written, with the rows of every aircraft (an aircraft may have written its header only)."""
        return self.written and not self.missing and not self.empty


def raw_path(raw_dir, kind, ac_id):
    return Path(raw_dir) / f"{kind}_{ac_id}.csv"


def _complete_lines(path, warnings):
    """The text of `path` without a torn last line (no newline at the end: left out with a warning)."""
    text = Path(path).read_text(encoding="utf-8", errors="replace")
    if text and not text.endswith("\n"):
        cut = text.rfind("\n") + 1
        warnings.append(f"{path}:{text.count(chr(10)) + 1}: torn last row (no newline at the end), left out: "
                        f"{text[cut:][:80]!r}")
        text = text[:cut]
    return text


def _rows_of(path, ac_id, header, warnings):
    """(header, [(t, ac_id, fields)]) of one aircraft's file; `header` is the first file's (None for the first).
    A file without a header line gives (None, [])."""
    reader = csv.reader(io.StringIO(_complete_lines(path, warnings)))
    own_header = next(reader, None)
    if own_header is None:
        return None, []
    if header is not None and own_header != header:
        raise MergeError(f"{path}:1: header {','.join(own_header)!r} differs from the other aircraft's "
                         f"{','.join(header)!r}")
    if "t" not in own_header:
        raise MergeError(f"{path}:1: no column 't' in the header {','.join(own_header)!r}")
    t_col, width = own_header.index("t"), len(own_header)
    rows = []
    for fields in reader:
        if len(fields) != width:
            raise MergeError(f"{path}:{reader.line_num}: {len(fields)} fields, the header has {width}")
        try:
            t = float(fields[t_col])
        except ValueError:
            t = math.nan
        if not math.isfinite(t):
            raise MergeError(f"{path}:{reader.line_num}: column t is {fields[t_col]!r}, not a time in seconds")
        rows.append((t, ac_id, fields))
    return own_header, rows


def write_atomically(path, header, rows):
    """Write the CSV `path` (header, then the field lists of `rows`) through a temporary file in the same folder
    renamed over it: a reader, or an error half-way, never sees a half-written file. Returns the row count."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    count = 0
    try:
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            writer = csv.writer(f, lineterminator="\n")
            writer.writerow(header)
            for fields in rows:
                writer.writerow(fields)
                count += 1
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return count


def merge_kind(kind, raw_dir, ac_ids, out_dir):
    """Merge <kind>_<id>.csv of the aircraft `ac_ids` in raw_dir into out_dir/<kind>.csv. Returns a MergeResult
    (not written when no file of the kind has a header line); raises MergeError when the files do not fit
    together."""
    result = MergeResult(kind, Path(out_dir) / f"{kind}.csv")
    header, rows = None, []
    for ac_id in sorted(ac_ids):
        source = raw_path(raw_dir, kind, ac_id)
        if not source.is_file():
            result.missing.append(source)
            continue
        own_header, own = _rows_of(source, ac_id, header, result.warnings)
        if own_header is None:
            result.empty.append(source)
        header, rows = header or own_header, rows + own
    if header is None:
        return result
    rows.sort(key=lambda row: (row[0], row[1]))   # stable: each aircraft's rows keep their order
    result.rows = write_atomically(result.path, header, (fields for _, _, fields in rows))
    result.written = True
    return result


def merge_all(raw_dir, ac_ids, out_dir):
    """Merge every kind; a kind whose files do not fit together gives its MergeError instead of a result (the
    other kinds are merged all the same). Returns {kind: MergeResult or MergeError}."""
    outcome = {}
    for kind in KINDS:
        try:
            outcome[kind] = merge_kind(kind, raw_dir, ac_ids, out_dir)
        except (MergeError, OSError) as err:
            outcome[kind] = err if isinstance(err, MergeError) else MergeError(f"{kind}: {err}")
    return outcome


def newest_time(path, tail_bytes=4096):
    """The time of the last complete row of a log being written (None when it has none yet or cannot be read):
    for a progress display, from the header's `t` column and the file's tail."""
    try:
        with open(path, "rb") as f:
            header = f.readline().decode("utf-8", "replace").rstrip("\n").split(",")
            if "t" not in header:
                return None
            size = f.seek(0, os.SEEK_END)
            f.seek(max(0, size - tail_bytes))
            tail = f.read().decode("utf-8", "replace")
    except OSError:
        return None
    lines = tail.split("\n")[:-1]   # the piece after the last newline is a row being written
    for line in reversed(lines[1:] if size > tail_bytes else lines):   # a tail's first line may be cut
        fields = line.split(",")
        if len(fields) == len(header):
            try:
                return float(fields[header.index("t")])
            except ValueError:
                return None
    return None
