"""Paparazzi's server log, read: the pair `<name>.log` (XML: the configuration and the message definitions) and
`<name>.data` (one message a line), as sw/ground_segment/tmtc/server.ml writes them.

A .data line is `"%.3f %s %s %s\\n"`: the time [s] since the server started (or the link's timestamp), the aircraft
id, the message name and the field values separated by single spaces (Server_globals.string_of_values over
PprzLink.string_of_value: integers in decimal, floats as OCaml's string_of_float: `1.`, `0.25`, `1e-05`, `nan`,
`inf`; arrays joined by commas). Either file of the pair may be given; the .log's `data_file` attribute names the
other (beside it), else `<name>.data` (also .gz or .bz2), as sw/logalizer/logplotter.ml looks for it.

Field positions come from the .log's definitions (its <protocol>, pprzlink's messages.xml at logging time); a
message it does not define (or a .data without its .log) is read with the definitions of conf/telemetry/
finken_messages.xml (our recorder's messages) or BUILTIN_MESSAGES (pprzlink's), and ServerLog says so
(definitions_note).

    ServerLog     the pair: which files, their definitions, the lines of the messages asked for
    Messages      the lines of one message: the log's time, the aircraft, the line, each field's values as text
    Field         a field of a message definition, with the factor to SI of its unit (Field.si_scale)
    field_values  a field in SI

Used by finken.flight.records (the recorder's messages) and finken.flight.mocap (the positions Paparazzi received).
Errors: FlightInputError, `file:line: reason` (the .data's line; the .log's for a definition).
"""
import bz2
import gzip
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from lxml import etree

from finken.flight.errors import FlightInputError
from finken.text_numbers import MAX_ID, ColumnError, is_id, parse_column

__all__ = ["BUILTIN_MESSAGES", "OUR_MESSAGES", "Field", "Messages", "ServerLog", "field_values"]

DATA_SUFFIXES = ("", ".gz", ".bz2")

#: Where our recorder's messages are defined (FINKEN_RANGE_READING, FINKEN_WALL_DECISION): read from there when a
#: server log's .log lacks them.
OUR_MESSAGES = Path(__file__).resolve().parents[3] / "conf/telemetry/finken_messages.xml"
#: The definitions of pprzlink's messages a server log is read with when its .log lacks them: ROTORCRAFT_FP,
#: EXTERNAL_POSE and REMOTE_GPS_LOCAL as pprzlink's message_definitions/v1.0/messages.xml has them.
BUILTIN_MESSAGES = """<protocol>
 <msg_class name="telemetry">
  <message name="ROTORCRAFT_FP" id="147">
   <field name="east" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="north" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="up" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="veast" type="int32" alt_unit="m/s" alt_unit_coef="0.0000019"/>
   <field name="vnorth" type="int32" alt_unit="m/s" alt_unit_coef="0.0000019"/>
   <field name="vup" type="int32" alt_unit="m/s" alt_unit_coef="0.0000019"/>
   <field name="phi" type="int32" alt_unit="deg" alt_unit_coef="0.0139882"/>
   <field name="theta" type="int32" alt_unit="deg" alt_unit_coef="0.0139882"/>
   <field name="psi" type="int32" alt_unit="deg" alt_unit_coef="0.0139882"/>
   <field name="carrot_east" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="carrot_north" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="carrot_up" type="int32" alt_unit="m" alt_unit_coef="0.0039063"/>
   <field name="carrot_psi" type="int32" alt_unit="deg" alt_unit_coef="0.0139882"/>
   <field name="thrust" type="int32"/>
   <field name="flight_time" type="uint16" unit="s"/>
  </message>
 </msg_class>
 <msg_class name="datalink">
  <message name="EXTERNAL_POSE" id="54">
   <field name="ac_id" type="uint8"/>
   <field name="timestamp" type="uint32" unit="ms"/>
   <field name="enu_x" type="float" unit="m"/>
   <field name="enu_y" type="float" unit="m"/>
   <field name="enu_z" type="float" unit="m"/>
   <field name="enu_xd" type="float" unit="m/s"/>
   <field name="enu_yd" type="float" unit="m/s"/>
   <field name="enu_zd" type="float" unit="m/s"/>
   <field name="body_qi" type="float"/>
   <field name="body_qx" type="float"/>
   <field name="body_qy" type="float"/>
   <field name="body_qz" type="float"/>
  </message>
  <message name="REMOTE_GPS_LOCAL" id="56">
   <field name="ac_id" type="uint8"/>
   <field name="pad" type="uint8"/>
   <field name="enu_x" type="float" unit="m"/>
   <field name="enu_y" type="float" unit="m"/>
   <field name="enu_z" type="float" unit="m"/>
   <field name="enu_xd" type="float" unit="m/s"/>
   <field name="enu_yd" type="float" unit="m/s"/>
   <field name="enu_zd" type="float" unit="m/s"/>
   <field name="tow" type="uint32"/>
   <field name="course" type="float" unit="deg"/>
  </message>
 </msg_class>
</protocol>
"""

# SI value of one unit, for the units our readers meet in message definitions
_SI = {"m": 1.0, "cm": 0.01, "mm": 0.001, "m/s": 1.0, "cm/s": 0.01, "mm/s": 0.001, "rad": 1.0,
       "deg": math.pi / 180, "decideg": math.pi / 1800, "centideg": math.pi / 18000, "s": 1.0, "ms": 1e-3,
       "us": 1e-6}
_INTEGER_TYPES = {"uint8": (0, 2**8 - 1), "uint16": (0, 2**16 - 1), "uint32": (0, 2**32 - 1),
                  "int8": (-2**7, 2**7 - 1), "int16": (-2**15, 2**15 - 1), "int32": (-2**31, 2**31 - 1)}


@dataclass
class Field:
    """A field of a message definition (pprzlink messages.xml): name, type, unit, alt_unit, alt_unit_coef, and
    where it was defined (file, line)."""
    name: str
    type: str
    unit: str = None
    alt_unit: str = None
    alt_unit_coef: str = None
    path: str = "BUILTIN_MESSAGES"
    line: int = None

    def si_scale(self, message):
        """The factor turning the field's value into SI (m, m/s, rad, s): alt_unit_coef times alt_unit when the
        definition gives a coefficient, else its unit (pprzlink computes a missing alt_unit_coef from the unit)."""
        if self.alt_unit_coef is not None and self.alt_unit in _SI:
            try:
                return float(self.alt_unit_coef) * _SI[self.alt_unit]
            except ValueError:
                raise FlightInputError(self.path, self.line, f"{message}.{self.name}: alt_unit_coef "
                                       f"'{self.alt_unit_coef}' is not a number") from None
        if self.unit in _SI:
            return _SI[self.unit]
        raise FlightInputError(self.path, self.line, f"{message}.{self.name}: no unit to read it in (unit "
                               f"'{self.unit}', alt_unit '{self.alt_unit}', alt_unit_coef '{self.alt_unit_coef}')")


@dataclass
class Messages:
    """The lines of one message in a server log's .data: the log's time t_log [s], the aircraft id `ac`, the
    line, and each field's values as text (`values` {field name: list of str})."""
    name: str
    path: str                 # the .data
    fields: list              # [Field] in the definition's order
    t_log: np.ndarray
    ac: np.ndarray
    line: np.ndarray
    values: dict

    def __len__(self):
        return len(self.line)

    def field(self, name):
        for f in self.fields:
            if f.name == name:
                return f
        where = self.fields[0] if self.fields else Field(name, "")
        raise FlightInputError(where.path, where.line, f"{self.name} has no field '{name}' (its fields: "
                               + ", ".join(f.name for f in self.fields) + ")")

    def numbers(self, name):
        """Field `name` as float64, unscaled (nan and inf as written)."""
        self.field(name)
        try:
            return parse_column(self.values[name])
        except ColumnError as err:
            raise FlightInputError(self.path, int(self.line[err.index]), f"{self.name}: field '{name}': "
                                   f"{err.reason}") from None

    def integers(self, name, what):
        """Field `name` as int64, each a whole number in the range of the field's integer type."""
        values = self.numbers(name)
        low, high = _INTEGER_TYPES.get(self.field(name).type, (0, 2**32 - 1))
        with np.errstate(invalid="ignore"):
            bad = ~((values >= low) & (values <= high) & (values == np.floor(values)))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise FlightInputError(self.path, int(self.line[i]), f"{self.name}: {what} '{self.values[name][i]}' "
                                   f"is not an integer from {low} to {high}")
        return values.astype(np.int64)

    def floats(self, name, unit):
        """Field `name` as float64 [unit]; refused if its definition states another unit."""
        f = self.field(name)
        if unit is not None and f.unit not in (None, unit):
            raise FlightInputError(f.path, f.line, f"{self.name}.{name}: unit '{f.unit}', expected '{unit}'")
        return self.numbers(name)


class ServerLog:
    """A Paparazzi server log pair: `log_path` (the XML .log, or None), `data_path` (the .data), `definitions`
    {(class, message name): [Field]} of the .log."""

    def __init__(self, log_path, data_path, definitions):
        self.log_path, self.data_path, self.definitions = log_path, data_path, definitions
        self.builtin_used = set()

    @staticmethod
    def is_server_log(path):
        """True for a .log/.data (.data.gz, .data.bz2) name, or a file starting as a .log's XML or a .data line."""
        name = str(path)
        if name.endswith((".log", ".data", ".data.gz", ".data.bz2")):
            return True
        first = _first_line(name)
        return first is not None and (first.startswith("<") or _is_data_line(first))

    @classmethod
    def open(cls, path):
        """The pair of `path` (either file): its .log's definitions and the .data beside it."""
        path = str(path)
        if not os.path.exists(path):
            raise FlightInputError(path, None, "cannot read: no such file")
        first = _first_line(path)
        if first is not None and first.startswith("<"):
            return cls(path, _data_of_log(path), _read_definitions(path))
        log_path = None
        stem = path
        for suffix in (".gz", ".bz2"):
            stem = stem.removesuffix(suffix)
        if stem.endswith(".data") and os.path.exists(stem[:-len(".data")] + ".log"):
            candidate = stem[:-len(".data")] + ".log"
            if (_first_line(candidate) or "").startswith("<"):
                log_path = candidate
        # a .log holding data lines: Paparazzi's server started with -log_name writes its data over the .log
        return cls(log_path, path, _read_definitions(log_path) if log_path else {})

    def definition(self, name, msg_class):
        """[Field] of message `name` in `msg_class`: the .log's, else the built-in ones (_builtin_definitions; noted)."""
        found = self.definitions.get((msg_class, name))
        if found is None:
            found = _builtin_definitions().get((msg_class, name))
            if found is None:
                raise FlightInputError(self.log_path or self.data_path, None, f"no definition of {name}")
            self.builtin_used.add(name)
        return found

    def definitions_note(self, names):
        """Where the definitions of `names` came from, in words."""
        builtin = [n for n in names if n in self.builtin_used]
        if not builtin:
            return f"message definitions from {self.log_path}"
        source = f"{self.log_path} lacks" if self.log_path else "no .log: built-in definitions of"
        return f"{source} {', '.join(builtin)}" + (": built-in definitions used" if self.log_path else "")

    def messages(self, wanted):
        """{name: Messages} of the .data's lines of each message in `wanted` ({name: message class}), in file
        order. Other lines are skipped unread (any aircraft name, any content)."""
        fields = {name: self.definition(name, cls) for name, cls in wanted.items()}
        keys = {name.encode(): name for name in wanted}
        rows = {name: ([], [], [], []) for name in wanted}   # t, ac, line, values text
        try:
            with _open_data(self.data_path) as f:
                for number, raw in enumerate(f, 1):
                    parts = raw.split(None, 3)
                    if len(parts) < 3 or parts[2] not in keys:
                        continue
                    name = keys[parts[2]]
                    t, ac, line, text = rows[name]
                    t.append(parts[0].decode("ascii", "replace"))
                    ac.append(parts[1].decode("ascii", "replace"))
                    line.append(number)
                    text.append(parts[3].decode("utf-8", "replace") if len(parts) > 3 else "")
        except (OSError, EOFError) as err:
            raise FlightInputError(self.data_path, None, f"cannot read: {err}") from None
        return {name: self._messages(name, fields[name], *rows[name]) for name in wanted}

    def _messages(self, name, fields, t_text, ac_text, lines, texts):
        lines = np.asarray(lines, dtype=np.int64)
        values = {f.name: [] for f in fields}
        columns = [values[f.name] for f in fields]
        for number, text in zip(lines, texts):
            tokens = text.split()
            if len(tokens) != len(fields):
                raise FlightInputError(self.data_path, int(number), f"{name}: expected {len(fields)} values ("
                                       + " ".join(f.name for f in fields) + f"), found {len(tokens)}")
            for column, token in zip(columns, tokens):
                column.append(token)
        try:
            t_log = parse_column(t_text)
        except ColumnError as err:
            raise FlightInputError(self.data_path, int(lines[err.index]), f"time {err.reason}") from None
        bad = ~np.isfinite(t_log)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise FlightInputError(self.data_path, int(lines[i]), f"time '{t_text[i]}' is not a finite number")
        try:
            ac = parse_column(ac_text)
        except ColumnError:
            ac = np.full(len(ac_text), np.nan)
        bad = ~is_id(ac)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise FlightInputError(self.data_path, int(lines[i]), f"{name} from aircraft '{ac_text[i]}': "
                                   f"expected an aircraft id (an integer from 0 to {MAX_ID})")
        return Messages(name, self.data_path, fields, t_log, ac.astype(np.int64), lines, values)


def _first_line(path):
    """The first non-blank line of a file (decompressed .gz/.bz2), stripped; None if unreadable or empty."""
    try:
        with _open_data(path) as f:
            for raw in f:
                text = raw.decode("utf-8", "replace").lstrip("\ufeff").strip()
                if text:
                    return text
    except (OSError, EOFError):
        return None
    return None


def _is_data_line(text):
    parts = text.split(None, 3)
    if len(parts) < 3 or not parts[2].replace("_", "").isalnum() or not parts[2].isupper():
        return False
    try:
        float(parts[0])
    except ValueError:
        return False
    return True


def _open_data(path):
    if path.endswith(".gz"):
        return gzip.open(path, "rb")
    if path.endswith(".bz2"):
        return bz2.open(path, "rb")
    return open(path, "rb")


def _parse_log_xml(path):
    parser = etree.XMLParser(remove_comments=True, huge_tree=True)
    try:
        return etree.parse(path, parser).getroot()
    except OSError as err:
        raise FlightInputError(path, None, f"cannot read: {err}") from None
    except etree.XMLSyntaxError as err:
        raise FlightInputError(path, err.lineno, f"malformed XML: {err.msg}") from None


def _data_of_log(log_path):
    """The .data of a .log: its data_file attribute (beside the .log), else <name>.data; .gz/.bz2 too."""
    root = _parse_log_xml(log_path)
    folder = os.path.dirname(log_path)
    names = []
    if root.get("data_file"):
        names.append(os.path.basename(root.get("data_file")))
    stem = os.path.basename(log_path)
    names.append((stem[:-len(".log")] if stem.endswith(".log") else stem) + ".data")
    tried = []
    for name in names:
        for suffix in DATA_SUFFIXES:
            candidate = os.path.join(folder, name + suffix)
            if os.path.exists(candidate) and candidate != log_path:
                return candidate
            tried.append(candidate)
    raise FlightInputError(log_path, None, "no data file beside it: looked for " + ", ".join(tried))


def _attr(element, name, default=None):
    """An attribute by its name in lower or upper case: the server writes the .log's protocol in upper case
    (`<message NAME="ROTORCRAFT_FP" ID="147">`, OCaml's Xml-light), pprzlink's messages.xml in lower case."""
    return element.get(name, element.get(name.upper(), default))


def _definitions_of(root, path):
    definitions = {}
    for msg_class in root.iter("msg_class"):
        class_name = _attr(msg_class, "name", "")
        for message in msg_class.iter("message"):
            fields = [Field(_attr(f, "name", "").strip().lower(), _attr(f, "type", "").strip(), _attr(f, "unit"),
                            _attr(f, "alt_unit"), _attr(f, "alt_unit_coef"), path, f.sourceline)
                      for f in message.iter("field")]
            definitions[(class_name, _attr(message, "name", ""))] = fields
    return definitions


def _read_definitions(log_path):
    return _definitions_of(_parse_log_xml(log_path), log_path)


_BUILTIN = {}


def _builtin_definitions():
    """BUILTIN_MESSAGES' definitions and our recorder's (OUR_MESSAGES)."""
    if not _BUILTIN:
        _BUILTIN.update(_definitions_of(etree.fromstring(BUILTIN_MESSAGES), "BUILTIN_MESSAGES"))
        _BUILTIN.update(_read_definitions(str(OUR_MESSAGES)))
    return _BUILTIN


def field_values(messages, name, scale_message=None):
    """Field `name` of `messages` in SI (Field.si_scale of its definition)."""
    f = messages.field(name)
    return messages.numbers(name) * f.si_scale(scale_message or messages.name)
