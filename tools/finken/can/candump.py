"""Read can-utils `candump -l` logs: one CAN frame per line, parsed by the C parser the replay uses
(ranging_can_candump_parse(), sw/airborne/modules/ranging/ranging_can_candump.{c,h}; the header documents the
line format), through finken.can._native.

    (1700000000.123456) can0 305#095E065A73000000

Classical, extended, remote, CAN FD and error frames, the `_<dlc>` suffix and the `T`/`R` direction flag are
read; blank lines are skipped; any other line raises CandumpError naming the file, the line and the parser's
reason (what was expected).
"""
from dataclasses import dataclass

from finken.can._native import ffi, lib, text


class CandumpError(ValueError):
    """A candump log that cannot be read: `file:line: reason` (`file: reason` when no line is at fault)."""

    def __init__(self, path, line, reason):
        self.path, self.line, self.reason = str(path), line, reason
        where = self.path if line is None else f"{self.path}:{line}"
        super().__init__(f"{where}: {reason}")


@dataclass(frozen=True)
class CanFrame:
    """One logged frame (struct ranging_can_raw, with its flags as booleans). `can_id` holds the identifier
    without flags."""
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

    @classmethod
    def from_c(cls, line):
        """The frame of a parsed `struct ranging_can_candump_line`."""
        raw = line.frame
        remote = bool(raw.can_id & lib.RANGING_CAN_ID_RTR_FLAG)
        return cls(time_us=line.time_us, ifname=ffi.string(line.ifname).decode("ascii"),
                   can_id=raw.can_id & lib.RANGING_CAN_EFF_MASK,
                   extended=bool(raw.can_id & lib.RANGING_CAN_ID_EFF_FLAG), remote=remote,
                   error=bool(raw.can_id & lib.RANGING_CAN_ID_ERR_FLAG), fd=bool(raw.fd), fd_flags=raw.fd_flags,
                   data=b"" if remote else ffi.buffer(raw.data, raw.len)[:], dlc_len=raw.len)

    def to_c(self):
        """The frame as a `struct ranging_can_raw *` (what the C codec takes)."""
        if len(self.data) > lib.RANGING_CAN_MAX_DLEN:
            raise ValueError(f"CAN frame 0x{self.can_id:X}: {len(self.data)} data bytes, "
                             f"expected at most {lib.RANGING_CAN_MAX_DLEN}")
        raw = ffi.new("struct ranging_can_raw *")
        raw.can_id = (self.can_id | (lib.RANGING_CAN_ID_EFF_FLAG if self.extended else 0)
                      | (lib.RANGING_CAN_ID_RTR_FLAG if self.remote else 0)
                      | (lib.RANGING_CAN_ID_ERR_FLAG if self.error else 0))
        raw.len = self.dlc_len
        raw.fd = self.fd
        raw.fd_flags = self.fd_flags
        ffi.memmove(raw.data, self.data, len(self.data))
        return raw


class _Parser:
    """One C output buffer reused for every line of a log."""

    def __init__(self):
        self.out = ffi.new("struct ranging_can_candump_line *")
        self.why = ffi.new("const char **")

    def __call__(self, line):
        # the C parser reads a NUL-terminated ASCII line: anything it could not see is refused here
        try:
            encoded = line.encode("ascii")
        except UnicodeEncodeError as err:
            raise ValueError(f"non-ASCII character {line[err.start]!r} at column {err.start + 1}") from None
        nul = encoded.find(b"\0")
        if nul >= 0:
            raise ValueError(f"NUL byte at column {nul + 1}: expected a text line")
        rc = lib.ranging_can_candump_parse(encoded, self.out, self.why)
        if rc < 0:
            raise ValueError(text(self.why[0]))
        return CanFrame.from_c(self.out) if rc > 0 else None


def parse_line(line):
    """One log line as a CanFrame, None for a blank line; ValueError(reason) if malformed."""
    return _Parser()(line)


def read_candump(path):
    """All frames of the log at `path`, in file order. Raises CandumpError naming the line."""
    parse = _Parser()
    frames = []
    try:
        with open(path, encoding="ascii", errors="strict") as f:
            for number, line in enumerate(f, start=1):
                try:
                    frame = parse(line)
                except ValueError as err:
                    raise CandumpError(path, number, str(err)) from None
                if frame is not None:
                    frames.append(frame)
    except UnicodeDecodeError as err:
        raise CandumpError(path, None, f"not a text log: {err.reason} at byte {err.start}") from None
    except OSError as err:
        raise CandumpError(path, None, f"cannot read: {err.strerror}") from None
    return frames
