"""The ranging frame on CAN, decoded in Python (layout documented in
sw/airborne/modules/ranging/ranging_can_frame.h, which the C driver implements; the two are checked against the
same test log, tests/data/can/ranging_session.log).

    CAN id   standard 11-bit, id = id_base + node id, node id in [0, nb_nodes)
    DLC 8, little-endian: peer id (uint8), range [mm] (uint16), quality [%] (uint8), sequence (uint16),
    2 reserved bytes (0)
"""
import struct
from dataclasses import dataclass

ID_BASE = 0x300          # RANGING_CAN_ID_BASE
NB_NODES = 64            # RANGING_CAN_NB_NODES
RANGE_MAX_MM = 60000     # RANGING_CAN_RANGE_MAX_MM
DLC = 8
QUALITY_MAX = 100        # [%]

# Why a frame is not a valid ranging frame (the C verdicts, ranging_can_verdict_str())
NOT_DATA = "not a classical standard-id data frame (error, remote, extended or CAN FD)"
FOREIGN_ID = "CAN id outside the ranging ids"
BAD_DLC = "DLC is not 8"
BAD_PEER = "peer id outside the node ids or equal to the sender's"
BAD_RANGE = "range above the largest valid range"
BAD_QUALITY = "quality above 100 %"
BAD_RESERVED = "reserved bytes 6-7 not zero"


@dataclass(frozen=True)
class Layout:
    """Where the ranging frames sit in the CAN id space."""
    id_base: int = ID_BASE
    nb_nodes: int = NB_NODES
    range_max_mm: int = RANGE_MAX_MM

    def check(self):
        """Raise ValueError naming the field if the layout is unusable (same rules as the C code)."""
        n = self.nb_nodes
        if not 1 <= n <= 256 or n & (n - 1):
            raise ValueError(f"nb_nodes {n}: expected a power of two from 1 to 256")
        if self.id_base % n:
            raise ValueError(f"id_base 0x{self.id_base:X}: expected a multiple of nb_nodes ({n})")
        if self.id_base + n - 1 > 0x7FF:
            raise ValueError(f"id_base 0x{self.id_base:X} + nb_nodes {n}: expected ids up to 0x7FF")
        if not 0 <= self.range_max_mm <= 0xFFFF:
            raise ValueError(f"range_max_mm {self.range_max_mm}: expected 0 to 65535")


@dataclass(frozen=True)
class RangingMsg:
    node: int          # the unit that measured (aircraft id)
    peer: int          # the unit it measured the distance to
    range_mm: int      # [mm]
    quality_pct: int   # [%]
    seq: int           # the node's frame counter


def decode(frame, layout=Layout()):
    """(RangingMsg, None) for a valid ranging frame, else (None, reason) with one of the reasons above."""
    if frame.error or frame.remote or frame.extended or frame.fd:
        return None, NOT_DATA
    if not layout.id_base <= frame.can_id < layout.id_base + layout.nb_nodes:
        return None, FOREIGN_ID
    if len(frame.data) != DLC:
        return None, BAD_DLC
    peer, range_mm, quality, seq, reserved = struct.unpack("<BHBHH", frame.data)
    if reserved:
        return None, BAD_RESERVED
    node = frame.can_id - layout.id_base
    if peer >= layout.nb_nodes or peer == node:
        return None, BAD_PEER
    if range_mm > layout.range_max_mm:
        return None, BAD_RANGE
    if quality > QUALITY_MAX:
        return None, BAD_QUALITY
    return RangingMsg(node, peer, range_mm, quality, seq), None
