"""The copter's records of every sensor reading, as a lab brings them home: read, checked, never written.

Two forms, told apart by the file:
- a CSV in the range-log columns without the truth: `t, vehicle, sensor, peer, measured` (../shared/spec/
  range-log.md; a `true_range` column, if there, is read and ignored). It is read by finken.rangelog.read_range_log,
  so every check and error of a range log holds (file:line: column 'x': reason; an unknown sensor is named).
- Paparazzi's server log: the pair `<name>.log`/`<name>.data`, either file given (finken.flight.server_log reads
  it and describes the format). Messages of our recorder module:
    FINKEN_RANGE_READING (195): stamp uint32 [us], sensor uint8 (0 front, 1 right, 2 back, 3 left, 4 down,
      5 ranging), peer uint16 (ranging peer's aircraft id; 65535 on sonar rows), measured float [m] (nan: none)
    FINKEN_WALL_DECISION (194): stamp uint32 [us], sonar uint8 (0-3), detector_class uint8 (0 unknown, 1 wall,
      2 copter, 3 no echo), confidence float, measured float [m], baseline_class uint8
  Field positions come from the .log's definitions; a message it does not define (or a .data without its .log) is
  read with server_log.BUILTIN_MESSAGES, said in `definitions`.
  `stamp` is the copter's clock, which wraps at 2^32 us (71.6 min): per aircraft, over both messages in file
  order, a stamp falling by more than half of that (2^31 us) from the aircraft's previous one is a wrap (and one
  rising by more than half, a late record from before the wrap); then a stream (vehicle, sensor, peer) whose time
  goes back is refused (a smaller fall: a copter that restarted; the message says so). t = unwrapped stamp / 1e6
  [s]; t_log keeps the .data's own time of each record (the server's clock).
- the recorder's decisions CSV (read_decisions, through finken.flight.csv_table): `t, vehicle, sensor, measured,
  detector_class, confidence, baseline_class`; classes by name (finken.run_logs.CLASS_NAMES: unknown, wall,
  copter, none = no echo) or code.

A reading's value (`measured`) is kept as the sensor gave it: negative, zero, infinite or absurd, it is data.
Errors: FlightInputError, `file:line: reason` (the .data's line; the .log's for a definition).
"""
import csv
from dataclasses import dataclass

import numpy as np

from finken.flight.csv_table import read_table
from finken.flight.errors import FlightInputError
from finken.flight.server_log import ServerLog
from finken.rangelog import RangeLogError, read_range_log
from finken.rangelog_columns import SENSOR_NAMES
from finken.run_logs import CLASS_NAMES

__all__ = ["DECISION_COLUMNS", "Decisions", "Records", "read_decisions", "read_records"]

RANGE_MESSAGE, DECISION_MESSAGE = "FINKEN_RANGE_READING", "FINKEN_WALL_DECISION"
NO_PEER = 65535              # the peer field of a sonar row
STAMP_WRAP = 2**32           # the copter's uint32 microsecond clock wraps here
DECISION_COLUMNS = ("t", "vehicle", "sensor", "measured", "detector_class", "confidence", "baseline_class")
_RESTART_HINT = ("; the stamp fell by less than half the clock's range, so it is no wrap: did the copter restart? "
                 "split the log there")


# ------------------------------------------------------------------ the records

@dataclass
class Decisions:
    """The wall detector's decisions: one entry per decision, in file order. Units: s, m."""
    path: str
    t: np.ndarray               # [s], the copter's clock (unwrapped stamp / 1e6 in a server log)
    vehicle: np.ndarray         # int64
    sensor: np.ndarray          # str (dtype object): sonar_front, sonar_right, sonar_back or sonar_left
    measured: np.ndarray        # the reading decided on [m]
    detector_class: np.ndarray  # str (dtype object): unknown, wall, copter or none (no echo)
    confidence: np.ndarray      # the detector's confidence
    baseline_class: np.ndarray  # str (dtype object), as detector_class
    line: np.ndarray            # int64: the decision's line in its file

    def __len__(self):
        return len(self.t)


@dataclass
class Records:
    """The copter's records of its sensor readings: one entry per reading, in file order. Units: s, m."""
    path: str                 # the file read (the .data of a server log)
    t: np.ndarray             # time of the reading [s] on the copter's clock
    vehicle: np.ndarray       # int64: the copter that read
    sensor: np.ndarray        # str (dtype object, the SENSOR_NAMES strs)
    peer: np.ndarray          # int64: the ranging peer's id; -1 on sonar rows
    measured: np.ndarray      # float: the reading [m], NaN = none; glitches kept as they are
    line: np.ndarray          # int64: the reading's line in `path` (1 = a CSV's header)
    decisions: Decisions = None      # the wall detector's decisions, if the log or a decisions file holds them
    t_log: np.ndarray = None         # [s] the server log's time of each record (NaN for a CSV)
    format: str = "csv"              # "csv" or "paparazzi"
    definitions: str = ""            # where a server log's message definitions came from

    def __len__(self):
        return len(self.t)

    def select(self, rows):
        """A new Records with the rows given by an index array or boolean mask (decisions kept whole)."""
        return Records(self.path, self.t[rows], self.vehicle[rows], self.sensor[rows], self.peer[rows],
                       self.measured[rows], self.line[rows], self.decisions,
                       None if self.t_log is None else self.t_log[rows], self.format, self.definitions)


def read_records(path, decisions=None):
    """The copter's records at `path`: a range-log-like CSV, or either file of a Paparazzi server log pair
    (.log/.data). `decisions`: a recorder's decisions CSV to read too (read_decisions), replacing any decisions of
    the server log. Returns Records; raises FlightInputError."""
    path = str(path)
    if ServerLog.is_server_log(path):
        records = _records_of_server_log(ServerLog.open(path))
    else:
        records = _records_of_csv(path)
    if decisions is not None:
        records.decisions = read_decisions(decisions)
    return records


def _records_of_csv(path):
    header = _first_csv_row(path)
    fill = None if header is not None and "true_range" in header else {"true_range": "0"}
    try:
        log = read_range_log(path, fill=fill)
    except RangeLogError as err:
        raise FlightInputError(err.path, err.line, err.reason, err.column) from None
    peer = np.where(np.isnan(log.peer), -1, log.peer).astype(np.int64)
    return Records(path, log.t, log.vehicle.astype(np.int64), log.sensor, peer, log.measured, log.line,
                   t_log=np.full(len(log), np.nan), format="csv")


def _first_csv_row(path):
    """The stripped fields of the first non-blank line of a CSV, or None (the range-log reader says why)."""
    try:
        with open(path, encoding="utf-8-sig", newline="") as f:
            for row in csv.reader(f):
                if any(cell.strip() for cell in row):
                    return [cell.strip() for cell in row]
    except (OSError, UnicodeDecodeError, csv.Error):
        return None
    return None


def _records_of_server_log(log):
    messages = log.messages({RANGE_MESSAGE: "telemetry", DECISION_MESSAGE: "telemetry"})
    ranges, decided = messages[RANGE_MESSAGE], messages[DECISION_MESSAGE]
    if len(ranges) == 0 and len(decided) == 0:
        raise FlightInputError(log.data_path, None, f"no {RANGE_MESSAGE} message: is the recorder module in the "
                                                    "airframe and its messages in the telemetry?")
    t_range, t_decided = _unwrap_stamps(log.data_path, (ranges, decided),
                                        [m.integers("stamp", "stamp") for m in (ranges, decided)])
    # FINKEN_RANGE_READING
    code = ranges.integers("sensor", "sensor")
    bad = code >= len(SENSOR_NAMES)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise FlightInputError(log.data_path, int(ranges.line[i]), f"{RANGE_MESSAGE}: unknown sensor code "
                               f"{code[i]} (0 front, 1 right, 2 back, 3 left, 4 down, 5 ranging)")
    sensor = np.array(SENSOR_NAMES, dtype=object)[code]
    ranging = code == SENSOR_NAMES.index("ranging")
    peer_field = ranges.integers("peer", "peer")
    peer = np.where(ranging, peer_field, -1).astype(np.int64)
    for broken, reason in ((ranging & (peer_field == NO_PEER), lambda i: f"a ranging reading without a peer "
                            f"({NO_PEER})"),
                           (ranging & (peer_field == ranges.ac), lambda i: f"peer {peer_field[i]} is the "
                            "reading's own aircraft: the peer is another copter")):
        if broken.any():
            i = int(np.flatnonzero(broken)[0])
            raise FlightInputError(log.data_path, int(ranges.line[i]), f"{RANGE_MESSAGE}: {reason(i)}")
    measured = ranges.floats("measured", "m")
    _check_time_order(log.data_path, t_range, ranges.ac, code, peer, ranges.line, _RESTART_HINT)
    # FINKEN_WALL_DECISION
    decisions = None
    if len(decided):
        sonar = decided.integers("sonar", "sonar")
        classes = {name: decided.integers(name, name) for name in ("detector_class", "baseline_class")}
        for name, codes, count, what in (("sonar", sonar, 4, "0 front, 1 right, 2 back, 3 left"),
                                         ("detector_class", classes["detector_class"], len(CLASS_NAMES),
                                          "0 unknown, 1 wall, 2 copter, 3 no echo"),
                                         ("baseline_class", classes["baseline_class"], len(CLASS_NAMES),
                                          "0 unknown, 1 wall, 2 copter, 3 no echo")):
            bad = codes >= count
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                raise FlightInputError(log.data_path, int(decided.line[i]),
                                       f"{DECISION_MESSAGE}: unknown {name} code {codes[i]} ({what})")
        _check_time_order(log.data_path, t_decided, decided.ac, sonar, np.full(len(decided), -1), decided.line,
                          _RESTART_HINT)
        names = np.array(CLASS_NAMES, dtype=object)
        decisions = Decisions(log.data_path, t_decided, decided.ac, np.array(SENSOR_NAMES, dtype=object)[sonar],
                              decided.floats("measured", "m"), names[classes["detector_class"]],
                              decided.floats("confidence", None), names[classes["baseline_class"]], decided.line)
    return Records(log.data_path, t_range, ranges.ac, sensor, peer, measured, ranges.line, decisions,
                   t_log=ranges.t_log, format="paparazzi", definitions=log.definitions_note(
                       (RANGE_MESSAGE, DECISION_MESSAGE)))


def _unwrap_stamps(path, messages, stamps):
    """t [s] of each message set: its stamps [us] unwrapped per aircraft over all sets in file order."""
    if sum(len(m) for m in messages) == 0:
        return [np.zeros(0) for _ in messages]
    line = np.concatenate([m.line for m in messages])
    ac = np.concatenate([m.ac for m in messages])
    stamp = np.concatenate(stamps).astype(np.int64)
    order = np.lexsort((line, ac))
    s = stamp[order]
    same = ac[order][1:] == ac[order][:-1]
    step = np.diff(s)
    wraps = np.zeros(len(s), dtype=np.int64)
    wraps[1:] = np.where(same, (step < -STAMP_WRAP // 2).astype(np.int64) - (step > STAMP_WRAP // 2), 0)
    wraps = np.cumsum(wraps)
    starts = np.flatnonzero(np.concatenate(([True], ~same)))
    wraps -= np.repeat(wraps[starts], np.diff(np.append(starts, len(s))))   # per aircraft
    unwrapped = np.empty(len(s), dtype=np.int64)
    unwrapped[order] = s + wraps * STAMP_WRAP
    t = unwrapped / 1e6
    cuts = np.cumsum([len(m) for m in messages])[:-1]
    return np.split(t, cuts)


def _check_time_order(path, t, vehicle, code, peer, line, hint=""):
    """FlightInputError at the first line (in file order) whose time is earlier than its stream's previous one."""
    if len(t) < 2:
        return
    order = np.lexsort((line, peer, code, vehicle))
    same = (vehicle[order][1:] == vehicle[order][:-1]) & (code[order][1:] == code[order][:-1]) & \
        (peer[order][1:] == peer[order][:-1])
    back = same & (np.diff(t[order]) < 0)
    if back.any():
        k = int(np.flatnonzero(back)[np.argmin(line[order][1:][back])])
        row, previous = order[k + 1], order[k]
        raise FlightInputError(path, int(line[row]), f"t = {t[row]:.6f} s goes back in time from "
                               f"t = {t[previous]:.6f} s on line {line[previous]} of the same stream "
                               f"(vehicle {vehicle[row]}, sensor {SENSOR_NAMES[code[row]]}){hint}")


# ------------------------------------------------------------------ the recorder's decisions CSV

def read_decisions(path):
    """The recorder's decisions CSV (DECISION_COLUMNS, any order, other columns ignored) as Decisions; sensor by
    range-log name (the four horizontal sonars), classes by name (CLASS_NAMES) or code (0-3). Raises
    FlightInputError."""
    path = str(path)
    table = read_table(path, DECISION_COLUMNS)
    t = table.numbers("t", finite=True)
    vehicle = table.ids("vehicle")
    sensors = np.array(table.columns["sensor"], dtype=object)
    known = np.isin(sensors, SENSOR_NAMES[:4])
    if not known.all():
        i = int(np.flatnonzero(~known)[0])
        table.fail(i, "sensor", f"unknown sensor '{sensors[i]}' (expected one of: {', '.join(SENSOR_NAMES[:4])})")
    sensors = np.array(SENSOR_NAMES, dtype=object)[[SENSOR_NAMES.index(s) for s in sensors]]
    classes = {}
    for name in ("detector_class", "baseline_class"):
        values = []
        for i, text in enumerate(table.columns[name]):
            if text in CLASS_NAMES:
                values.append(CLASS_NAMES.index(text))
            elif text in ("0", "1", "2", "3"):
                values.append(int(text))
            else:
                table.fail(i, name, f"'{text}': expected one of {', '.join(CLASS_NAMES)} or a code 0-3")
        classes[name] = np.array(CLASS_NAMES, dtype=object)[np.asarray(values, dtype=np.int64)]
    code = np.array([SENSOR_NAMES.index(s) for s in sensors], dtype=np.int64)
    _check_time_order(path, t, vehicle, code, np.full(len(t), -1), table.line)
    return Decisions(path, t, vehicle, sensors, table.numbers("measured", finite=False),
                     classes["detector_class"], table.numbers("confidence", finite=True), classes["baseline_class"],
                     table.line)
