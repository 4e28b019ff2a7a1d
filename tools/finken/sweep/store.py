"""The results of a sweep: OUT/runs.sqlite, one row per run, committed as each run arrives.

Table `runs`: run_key (point key and seed, finken.sweep.points), point_key, seed, status ("done" or "failed"),
error (the failure's message), attempts (tries so far, over every invocation), started (UTC, ISO 8601, on the
worker), finished (UTC, when stored), wall_s (the run's time on its worker [s]), worker (host:pid), then a column
per parameter, named by its key in the sweep file (vehicles, defines.WALL_DETECTOR_WALL_THRESHOLD, ...), and per
metric (make sim's metrics.json flattened: detector_wall_recall, sensor_errors.sonar_front.rmse_m, ...), added as
they first appear. A failed run has no metrics; when it is tried again and succeeds its row is replaced.
SQLite in write-ahead-log mode: a finished run is on disk once record() returns, so Ctrl-C loses none.

    sqlite3 build/sweep/<name>/runs.sqlite "select vehicles, avg(detector_wall_recall) from runs group by vehicles"
    pandas.read_sql("select * from runs", sqlite3.connect("build/sweep/<name>/runs.sqlite"))
"""
import sqlite3
from datetime import datetime, timezone

BOOKKEEPING = (("run_key", "TEXT PRIMARY KEY"), ("point_key", "TEXT NOT NULL"), ("seed", "INTEGER NOT NULL"),
               ("status", "TEXT NOT NULL"), ("error", "TEXT"), ("attempts", "INTEGER NOT NULL"),
               ("started", "TEXT"), ("finished", "TEXT"), ("wall_s", "REAL"), ("worker", "TEXT"))


class RunStore:
    """The runs table of one sweep's OUT folder (created on first use)."""

    def __init__(self, path):
        self.db = sqlite3.connect(path)
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute(f"CREATE TABLE IF NOT EXISTS runs ({', '.join(f'{n} {t}' for n, t in BOOKKEEPING)})")
        self.db.commit()
        self.columns = [row[1] for row in self.db.execute("PRAGMA table_info(runs)")]

    def close(self):
        self.db.close()

    def states(self):
        """{run_key: (status, attempts)} of every stored run."""
        return {key: (status, attempts) for key, status, attempts in
                self.db.execute("SELECT run_key, status, attempts FROM runs")}

    def record(self, run_key, point, seed, attempts, result=None, error=None):
        """Store one run: done with `result` (finken.sweep.worker.run's), or failed with the text `error`.
        point: finken.sweep.points.Point."""
        row = {"run_key": run_key, "point_key": point.key, "seed": seed, "attempts": attempts,
               "finished": datetime.now(timezone.utc).isoformat(timespec="seconds"), **point.values}
        if result is None:
            row.update(status="failed", error=error)
        else:
            row.update(status="done", started=result["started"], wall_s=result["wall_s"], worker=result["worker"],
                       **result["metrics"])
        self._add_columns(row)
        names = ", ".join(_quoted(name) for name in row)
        with self.db:
            self.db.execute(f"INSERT OR REPLACE INTO runs ({names}) VALUES ({', '.join('?' * len(row))})",
                            list(row.values()))

    def rows(self, run_keys=None):
        """Every stored run as a dict (only those of `run_keys` when given)."""
        cursor = self.db.execute("SELECT * FROM runs ORDER BY rowid")
        names = [d[0] for d in cursor.description]
        rows = (dict(zip(names, values)) for values in cursor)
        return [row for row in rows if run_keys is None or row["run_key"] in run_keys]

    def _add_columns(self, row):
        for name, value in row.items():
            if name not in self.columns:
                kind = "TEXT" if isinstance(value, str) else "INTEGER" if isinstance(value, int) else "REAL"
                self.db.execute(f"ALTER TABLE runs ADD COLUMN {_quoted(name)} {kind}")
                self.columns.append(name)


def _quoted(name):
    return '"' + name.replace('"', '""') + '"'
