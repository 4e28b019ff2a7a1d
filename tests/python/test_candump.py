"""candump -l log reader (tools/finken/can/candump.py) and the ranging frame decoder
(tools/finken/can/ranging_frame.py): thin cffi bindings (tools/finken/can/_native.py) of the C parser and codec the
Linux driver runs.

The lines are the ones the C parser's test uses (tests/c/airborne/test_ranging_can_candump.c): through the
binding they must come out as the same frames, with the C's own reasons. The session log is decoded against its
expected file, which the C driver's replay test (tests/c/linux/test_ranging_can.c) checks too. The cffi
declarations must still match the C headers they copy.
"""
import csv
import os
import re
import subprocess
import sys

import pytest

from finken.can import _native as _can_native
from finken.can.candump import CandumpError, CanFrame, parse_line, read_candump
from finken.can.ranging_frame import (BAD_DLC, BAD_PEER, BAD_QUALITY, BAD_RANGE, BAD_RESERVED, FOREIGN_ID, NOT_DATA,
                                      Layout, decode)


def test_a_classical_frame():
    f = parse_line("(1700000000.123456) can0 123#DEADBEEF\n")
    assert f.time_us == 1700000000123456
    assert f.ifname == "can0"
    assert (f.can_id, f.extended, f.remote, f.error, f.fd) == (0x123, False, False, False, False)
    assert f.data == bytes.fromhex("DEADBEEF")
    assert f.t == pytest.approx(1700000000.123456, abs=1e-6)


def test_extended_empty_dotted_and_flagged_frames():
    f = parse_line("(0.000001) vcan0 1F334455#11.22.33")
    assert (f.can_id, f.extended, f.data, f.time_us) == (0x1F334455, True, bytes([0x11, 0x22, 0x33]), 1)
    f = parse_line("(1.5) can1 7FF#")
    assert (f.data, f.time_us) == (b"", 1500000)
    f = parse_line("(1.123456789) can0 300#0102030405060708_C T\r\n")
    assert (f.time_us, len(f.data)) == (1123456, 8)


def test_remote_fd_and_error_frames():
    f = parse_line("(1.000000) can0 303#R")
    assert f.remote and f.data == b"" and f.dlc_len == 0
    assert parse_line("(1.000000) can0 303#R8").dlc_len == 8
    f = parse_line("(1.000000) can0 303##100112233445566778899AABB")
    assert f.fd and f.fd_flags == 1 and len(f.data) == 12 and f.data[11] == 0xBB
    f = parse_line("(1.000000) can0 20000040#0000000000000000")
    assert f.error and f.can_id == 0x40 and len(f.data) == 8


def test_blank_lines_are_skipped():
    assert parse_line("") is None
    assert parse_line("   \n") is None


@pytest.mark.parametrize("line, reason", [
    ("1700000000.123456 can0 123#00", "expected '(' opening the time stamp"),
    ("(1700000000) can0 123#00", "time stamp: expected seconds, '.', decimals"),
    ("(1700000000.) can0 123#00", "time stamp: expected decimals and ')'"),
    ("(17x.1) can0 123#00", "time stamp: expected seconds"),
    ("(1.1)can0 123#00", "expected a space after the time stamp"),
    ("(1.1) can0", "expected an interface name and a frame after the time stamp"),
    ("(1.1) averyveryverylongname0 123#00", "15 characters"),
    ("(1.1) can0 12#00", "3 (standard) or 8"),
    ("(1.1) can0 1234#00", "3 (standard) or 8"),
    ("(1.1) can0 123456789#00", "3 (standard) or 8"),
    ("(1.1) can0 123:00", "'#'"),
    ("(1.1) can0 123#0", "pairs of hex digits"),
    ("(1.1) can0 123#0G", "pairs of hex digits"),
    ("(1.1) can0 123#001122334455667788", "more than 8 bytes"),
    ("(1.1) can0 123##X00", "flags"),
    ("(1.1) can0 123#001122_9", "needs 8 data bytes"),
    ("(1.1) can0 123#0011223344556677_3", "DLC from 9"),
    ("(1.1) can0 123#00 trailing words", "unexpected text after the frame"),
    ("(1.1) can0 E0000001#00", "error frame id"),
    ("(1.1) can0 7FFFFFFF#00", "error frame id"),
    ("(1.1) can0 20000040##100", "cannot be a CAN FD"),
    ("(1.1) can0 123#_123:456#00", "needs 8 data bytes"),  # a CAN XL line
])
def test_malformed_lines_say_what_was_expected(line, reason):
    with pytest.raises(ValueError) as err:
        parse_line(line)
    assert reason in str(err.value)


@pytest.mark.parametrize("line, reason", [
    ("(1.1) can0 123#00\0", "NUL byte at column 18"),   # the C parser would stop at the NUL and accept the line
    ("(1.1) cän0 123#00", "non-ASCII character 'ä' at column 8"),
])
def test_what_the_c_parser_cannot_see_is_refused(line, reason):
    with pytest.raises(ValueError, match=reason):
        parse_line(line)


GOOD_LINES = ["(1700000000.123456) can0 123#DEADBEEF", "(0.000001) vcan0 1F334455#11.22.33", "(1.5) can1 7FF#",
              "(1.123456789) can0 300#0102030405060708_C T", "(1.000000) can0 303#R", "(1.000000) can0 303#R8",
              "(1.000000) can0 303##100112233445566778899AABB", "(1.000000) can0 20000040#0000000000000000"]


@pytest.mark.parametrize("line", GOOD_LINES)
def test_a_frame_goes_back_to_c_as_the_parser_wrote_it(line):
    """CanFrame.to_c() (what the decoder gets) inverts CanFrame.from_c(), byte for byte."""
    ffi, lib = _can_native.ffi, _can_native.lib
    out, why = ffi.new("struct ranging_can_candump_line *"), ffi.new("const char **")
    assert lib.ranging_can_candump_parse(line.encode(), out, why) == 1
    frame = CanFrame.from_c(out)
    assert frame == parse_line(line)
    assert ffi.buffer(frame.to_c())[:] == ffi.buffer(ffi.addressof(out.frame))[:]


def test_a_bad_line_is_named_by_file_and_line(repo):
    path = repo / "tests/data/can/malformed.log"
    with pytest.raises(CandumpError) as err:
        read_candump(path)
    assert str(err.value) == f"{path}:4: data: expected pairs of hex digits"


def test_a_missing_or_binary_log_is_named(tmp_path):
    with pytest.raises(CandumpError, match="no-such.log.*cannot read"):
        read_candump(tmp_path / "no-such.log")
    binary = tmp_path / "binary.log"
    binary.write_bytes(b"\x00\xff\xfe")
    with pytest.raises(CandumpError, match="binary.log.*not a text log"):
        read_candump(binary)


def frame(data_hex, can_id=0x305):
    return parse_line(f"(1.0) can0 {can_id:03X}#{data_hex}")


def test_the_decoder_follows_the_c_layout():
    msg, reason = decode(frame("07D2045A34120000", 0x303))  # the C test's good frame
    assert reason is None
    assert (msg.node, msg.peer, msg.range_mm, msg.quality_pct, msg.seq) == (3, 7, 1234, 90, 0x1234)
    assert decode(frame("07D2045A3412"))[1] == BAD_DLC
    assert decode(frame("07D2045A34120000", 0x2FF))[1] == FOREIGN_ID
    assert decode(frame("07D2045A34120000", 0x340))[1] == FOREIGN_ID
    assert decode(parse_line("(1.0) can0 00000305#07D2045A34120000"))[1] == NOT_DATA
    assert decode(parse_line("(1.0) can0 305#R"))[1] == NOT_DATA
    assert decode(parse_line("(1.0) can0 305##007D2045A34120000"))[1] == NOT_DATA
    assert decode(frame("40D2045A34120000"))[1] == BAD_PEER
    assert decode(frame("05D2045A34120000"))[1] == BAD_PEER  # node 5 to itself
    assert decode(frame("0761EA5A34120000"))[1] == BAD_RANGE  # 60001 mm
    assert decode(frame("07D2046534120000"))[1] == BAD_QUALITY  # 101 %
    assert decode(frame("07D2045A34120001"))[1] == BAD_RESERVED


def test_bad_layouts_are_named():
    with pytest.raises(ValueError, match="power of two"):
        Layout(nb_nodes=48).check()
    with pytest.raises(ValueError, match="multiple"):
        Layout(id_base=0x310).check()
    with pytest.raises(ValueError, match="0x7FF"):
        Layout(id_base=0x800, nb_nodes=256).check()
    with pytest.raises(ValueError, match="range_max_mm 70000: expected an integer from 0 to 65535"):
        Layout(range_max_mm=70000).check()
    with pytest.raises(ValueError, match="id_base -1: expected an integer from 0 to 65535"):
        Layout(id_base=-1).check()


def test_the_session_log_decodes_as_expected(repo):
    frames = [f for f in read_candump(repo / "tests/data/can/ranging_session.log") if f.ifname == "can0"]
    decoded = [decode(f)[0] for f in frames]
    valid = [(f.time_us, m.node, m.peer, m.range_mm, m.quality_pct, m.seq) for f, m in zip(frames, decoded) if m]
    with open(repo / "tests/data/can/ranging_session.expected.csv") as f:
        expected = [tuple(int(v) for v in row.values()) for row in csv.DictReader(f)]
    # the only valid frame not in the expected file is the duplicate: node 5 repeating sequence 111 later
    extra = [v for v in valid if v not in expected]
    assert len(extra) == 1 and extra[0][1] == 5 and extra[0][5] == 111
    assert [v for v in valid if v != extra[0]] == expected


def _items(text):
    """The declarations of C text, comments and whitespace normalised: #define lines and top-level `...;`."""
    text = re.sub(r"#ifdef __cplusplus.*?#endif", " ", text, flags=re.S)   # the headers' extern "C" guards
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    defines = [" ".join(line.split()) for line in text.splitlines() if line.strip().startswith("#define")]
    body = " ".join(line for line in text.splitlines() if not line.strip().startswith("#"))
    statements = [s for s in re.findall(r"[^;{}]*(?:\{[^}]*\})?[^;{}]*;", body) if s.strip()]
    return defines, [re.sub(r"\s*([(){},;*\[\]=])\s*", r"\1", " ".join(s.split())) for s in statements]


def test_the_cdef_copies_the_c_headers():
    """Every #define, struct, enum and prototype of _can_native.CDEF appears, whitespace aside, in the headers."""
    header_defines, header_items = _items("\n".join(h.read_text() for h in _can_native.HEADERS))
    defines, items = _items(_can_native.CDEF)
    assert len(defines) == 9 and len(items) == 9
    assert [d for d in defines if d not in header_defines] == []
    assert [i for i in items if i not in header_items] == []


def test_a_missing_library_says_how_to_build_it(tmp_path):
    env = {"PYTHONPATH": str(_can_native.REPO / "tools"), "FINKEN_CAN_LIB": str(tmp_path / "libfinken_can.so")}
    done = subprocess.run([sys.executable, "-c", "import finken.can.candump"], capture_output=True, text=True, env=env)
    assert done.returncode != 0
    assert f"the CAN codec library {tmp_path / 'libfinken_can.so'} does not exist: run `make build`" in done.stderr
