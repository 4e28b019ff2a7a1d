"""Read can-utils `candump -l` logs: one CAN frame per line.

Line format (can-utils lib.c / candump.c; the same rules as the C parser
sw/airborne/modules/ranging/ranging_can_candump.h):

    (1700000000.123456) can0 123#DEADBEEF        classical frame; 3 hex digits: standard id
    (1700000000.123456) can0 1F334455#11.22      8 hex digits: extended id ('.' between bytes allowed)
    (1700000000.123456) can0 123#R  or  123#R4   remote request (optional length digit)
    (1700000000.123456) can0 123##1112233        CAN FD: one hex digit of flags (BRS 1, ESI 2), then data
    (1700000000.123456) can0 20000040#00...      error frame (8 digits with bit 29 set)

Optional: a `_<hex digit>` DLC suffix after 8 data bytes, a trailing direction flag `T` or `R` (candump -x).
Time stamps may carry 1 to 9 decimals (kept to the microsecond). Blank lines are skipped; any other line that
does not fit (a CAN XL frame, an odd number of hex digits, too much data, ...) raises CandumpError naming the
file, the line and what was expected.
"""
import re
from dataclasses import dataclass

CAN_EFF_FLAG = 0x80000000  # linux/can.h
CAN_RTR_FLAG = 0x40000000
CAN_ERR_FLAG = 0x20000000
CAN_EFF_MASK = 0x1FFFFFFF
CLASSIC_MAX_LEN = 8   # bytes
FD_MAX_LEN = 64       # bytes
IFNAME_MAX = 15       # characters (Linux IFNAMSIZ - 1)

_LINE = re.compile(r"^\((\d{1,12})\.(\d{1,9})\)[ \t]+(\S+)[ \t]+(\S+)(?:[ \t]+([TR]))?[ \t]*$")
_ID = re.compile(r"^([0-9A-Fa-f]{3}|[0-9A-Fa-f]{8})#(.*)$")
_HEX_PAIRS = re.compile(r"^\.*(?:[0-9A-Fa-f]{2}\.*)*$")


class CandumpError(ValueError):
    """A candump log line that cannot be read: `file:line: reason`."""

    def __init__(self, path, line, reason):
        self.path, self.line, self.reason = str(path), line, reason
        super().__init__(f"{self.path}:{line}: {reason}")


@dataclass(frozen=True)
class CanFrame:
    """One logged frame. `can_id` holds the identifier without flags."""
    time_us: int       # log time stamp [us since the epoch]
    ifname: str        # interface it was logged on
    can_id: int        # 11-bit or 29-bit identifier, or the error classes of an error frame
    extended: bool     # 29-bit identifier
    remote: bool       # remote request (no data)
    error: bool        # error frame
    fd: bool           # CAN FD frame
    fd_flags: int      # CAN FD flags (BRS 1, ESI 2)
    data: bytes        # payload (remote frames: empty)
    dlc_len: int       # the length field (a remote frame's requested length, else len(data))

    @property
    def t(self):
        """Time stamp [s since the epoch]."""
        return self.time_us / 1e6


def _data(text, max_len):
    """Hex bytes with optional '.' separators."""
    if not _HEX_PAIRS.match(text):
        raise ValueError("data: expected pairs of hex digits")
    data = bytes.fromhex(text.replace(".", ""))
    if len(data) > max_len:
        kind = "a classical frame" if max_len == CLASSIC_MAX_LEN else "a CAN FD frame"
        raise ValueError(f"data: more than {max_len} bytes in {kind}")
    return data


def parse_line(line):
    """One log line as a CanFrame, None for a blank line; ValueError(reason) if malformed."""
    text = line.strip(" \t\r\n")
    if not text:
        return None
    m = _LINE.match(text)
    if not m:
        raise ValueError("expected '(seconds.decimals) interface frame', as in (1700000000.123456) can0 123#DEADBEEF")
    sec, decimals, ifname, frame, _direction = m.groups()
    if len(ifname) > IFNAME_MAX:
        raise ValueError(f"interface name longer than {IFNAME_MAX} characters")
    time_us = int(sec) * 1000000 + int((decimals + "000000")[:6])
    fm = _ID.match(frame)
    if not fm:
        raise ValueError("frame: expected a CAN id of 3 (standard) or 8 (extended/error) hex digits and '#'")
    id_text, rest = fm.groups()
    raw_id = int(id_text, 16)
    extended = error = False
    if len(id_text) == 8:
        if raw_id & CAN_ERR_FLAG:
            if raw_id & (CAN_EFF_FLAG | CAN_RTR_FLAG):
                raise ValueError("frame: an error frame id with the extended or remote flag")
            error = True
            raw_id &= CAN_EFF_MASK
        elif raw_id > CAN_EFF_MASK:
            raise ValueError("frame: an extended id above 0x1FFFFFFF")
        else:
            extended = True
    if rest.startswith("#"):
        if error:
            raise ValueError("frame: an error frame cannot be a CAN FD frame")
        if len(rest) < 2 or rest[1] not in "0123456789abcdefABCDEF":
            raise ValueError("CAN FD frame: expected one hex digit of flags after '##'")
        if "_" in rest:
            raise ValueError("CAN FD frame: a DLC suffix belongs to classical frames only")
        data = _data(rest[2:], FD_MAX_LEN)
        return CanFrame(time_us, ifname, raw_id, extended, False, False, True, int(rest[1], 16), data, len(data))
    body, _, dlc_suffix = rest.partition("_")
    remote = body[:1] in ("R", "r")
    if remote:
        if body[1:] and not re.fullmatch(r"[0-8]", body[1:]):
            raise ValueError("remote frame: expected 'R' and an optional length digit 0-8")
        data, dlc_len = b"", int(body[1:] or 0)
    else:
        data = _data(body, CLASSIC_MAX_LEN)
        dlc_len = len(data)
    if dlc_suffix or rest.endswith("_"):
        if dlc_len != CLASSIC_MAX_LEN or not re.fullmatch(r"[9A-Fa-f]", dlc_suffix):
            raise ValueError("frame: a '_' DLC suffix needs 8 data bytes and a DLC from 9 to F")
    return CanFrame(time_us, ifname, raw_id, extended, remote, error, False, 0, data, dlc_len)


def read_candump(path):
    """All frames of the log at `path`, in file order. Raises CandumpError naming the line."""
    frames = []
    try:
        with open(path, encoding="ascii", errors="strict") as f:
            for number, line in enumerate(f, start=1):
                try:
                    frame = parse_line(line)
                except ValueError as err:
                    raise CandumpError(path, number, str(err)) from None
                if frame is not None:
                    frames.append(frame)
    except UnicodeDecodeError as err:
        raise CandumpError(path, None, f"not a text log: {err.reason} at byte {err.start}") from None
    except OSError as err:
        raise CandumpError(path, None, f"cannot read: {err.strerror}") from None
    return frames
