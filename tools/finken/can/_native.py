"""Private cffi (ABI mode) binding of libfinken_can: the one C implementation of the ranging CAN frame codec
(sw/airborne/modules/ranging/ranging_can_frame.{c,h}) and of the candump line parser
(sw/airborne/modules/ranging/ranging_can_candump.{c,h}), the code the Linux driver runs.

CDEF copies, comments aside, the declarations of those two headers that the Python tools use;
tests/python/test_candump.py checks that every item still appears in the headers. Change both together.
The library is $FINKEN_CAN_LIB, else <repo>/build/lib/libfinken_can.so (built by `make build`); it is loaded
when this module is imported, so a missing library is an ImportError saying how to build it.
"""
import os
from pathlib import Path

from cffi import FFI

REPO = Path(__file__).resolve().parents[3]
HEADERS = [REPO / "sw" / "airborne" / "modules" / "ranging" / name
           for name in ("ranging_can_frame.h", "ranging_can_candump.h")]

CDEF = """
/* ranging_can_frame.h */
#define RANGING_CAN_ID_BASE 0x300
#define RANGING_CAN_NB_NODES 64
#define RANGING_CAN_RANGE_MAX_MM 60000
#define RANGING_CAN_ID_EFF_FLAG 0x80000000U
#define RANGING_CAN_ID_RTR_FLAG 0x40000000U
#define RANGING_CAN_ID_ERR_FLAG 0x20000000U
#define RANGING_CAN_EFF_MASK 0x1FFFFFFFU
#define RANGING_CAN_MAX_DLEN 64

struct ranging_can_raw {
  uint32_t can_id;
  uint8_t len;
  bool fd;
  uint8_t fd_flags;
  uint8_t data[RANGING_CAN_MAX_DLEN];
};

struct ranging_can_layout {
  uint16_t id_base;
  uint16_t nb_nodes;
  uint16_t range_max_mm;
};

struct ranging_can_msg {
  uint8_t node_id;
  uint8_t peer_id;
  uint16_t range_mm;
  uint8_t quality_pct;
  uint16_t seq;
};

enum ranging_can_verdict {
  RANGING_CAN_FRAME_OK = 0,
  RANGING_CAN_FRAME_NOT_DATA,
  RANGING_CAN_FRAME_FOREIGN_ID,
  RANGING_CAN_FRAME_BAD_DLC,
  RANGING_CAN_FRAME_BAD_PEER,
  RANGING_CAN_FRAME_BAD_RANGE,
  RANGING_CAN_FRAME_BAD_QUALITY,
  RANGING_CAN_FRAME_BAD_RESERVED,
  RANGING_CAN_FRAME_BAD_NODE,
  RANGING_CAN_FRAME_NB_VERDICTS
};

extern int ranging_can_layout_check(const struct ranging_can_layout *layout, const char **why);
extern enum ranging_can_verdict ranging_can_unpack(const struct ranging_can_layout *layout,
    const struct ranging_can_raw *frame, struct ranging_can_msg *msg);
extern const char *ranging_can_verdict_str(enum ranging_can_verdict verdict);

/* ranging_can_candump.h */
#define RANGING_CAN_CANDUMP_IFNAME_LEN 16

struct ranging_can_candump_line {
  uint64_t time_us;
  char ifname[RANGING_CAN_CANDUMP_IFNAME_LEN];
  struct ranging_can_raw frame;
};

extern int ranging_can_candump_parse(const char *line, struct ranging_can_candump_line *out, const char **why);
"""


class CanLibraryError(ImportError):
    """libfinken_can.so cannot be loaded (not built, or built for another machine)."""


def library_path():
    """Where the shared library is expected: $FINKEN_CAN_LIB, else build/lib/libfinken_can.so in the repository."""
    return Path(os.environ.get("FINKEN_CAN_LIB") or REPO / "build" / "lib" / "libfinken_can.so")


def _load():
    path = library_path()
    if not path.is_file():
        raise CanLibraryError(f"the CAN codec library {path} does not exist: run `make build` in {REPO} "
                              "(or point FINKEN_CAN_LIB at libfinken_can.so)")
    ffi = FFI()
    ffi.cdef(CDEF)
    try:
        return ffi, ffi.dlopen(str(path))
    except OSError as err:
        raise CanLibraryError(f"cannot load {path}: {err} (rebuild it with `make build`)") from err


ffi, lib = _load()


def text(cdata):
    """A static C string (a reason or verdict) as str."""
    return ffi.string(cdata).decode("ascii")
