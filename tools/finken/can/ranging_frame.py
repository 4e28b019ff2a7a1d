"""The ranging frame on CAN: decoding and validation by the C codec the Linux driver runs
(sw/airborne/modules/ranging/ranging_can_frame.{c,h}, which documents the layout), through finken.can._native.

    CAN id   standard 11-bit, id = id_base + node id, node id in [0, nb_nodes)
    DLC 8, little-endian: peer id (uint8), range [mm] (uint16), quality [%] (uint8), sequence (uint16),
    2 reserved bytes (0)

The reasons a frame is rejected are the C verdict strings (ranging_can_verdict_str()): NOT_DATA, FOREIGN_ID,
BAD_DLC, BAD_PEER, BAD_RANGE, BAD_QUALITY, BAD_RESERVED.
"""
from dataclasses import dataclass, fields

from finken.can._native import ffi, lib, text

ID_BASE = lib.RANGING_CAN_ID_BASE            # CAN id of node 0
NB_NODES = lib.RANGING_CAN_NB_NODES          # node ids
RANGE_MAX_MM = lib.RANGING_CAN_RANGE_MAX_MM  # largest valid range [mm]


def _reason(verdict):
    return text(lib.ranging_can_verdict_str(verdict))


NOT_DATA = _reason(lib.RANGING_CAN_FRAME_NOT_DATA)
FOREIGN_ID = _reason(lib.RANGING_CAN_FRAME_FOREIGN_ID)
BAD_DLC = _reason(lib.RANGING_CAN_FRAME_BAD_DLC)
BAD_PEER = _reason(lib.RANGING_CAN_FRAME_BAD_PEER)
BAD_RANGE = _reason(lib.RANGING_CAN_FRAME_BAD_RANGE)
BAD_QUALITY = _reason(lib.RANGING_CAN_FRAME_BAD_QUALITY)
BAD_RESERVED = _reason(lib.RANGING_CAN_FRAME_BAD_RESERVED)


@dataclass(frozen=True)
class Layout:
    """Where the ranging frames sit in the CAN id space (struct ranging_can_layout)."""
    id_base: int = ID_BASE            # CAN id of node 0
    nb_nodes: int = NB_NODES          # node ids 0 .. nb_nodes - 1
    range_max_mm: int = RANGE_MAX_MM  # largest valid range [mm]

    def _describe(self):
        return f"layout id_base 0x{self.id_base:X}, nb_nodes {self.nb_nodes}, range_max_mm {self.range_max_mm}"

    def to_c(self):
        """The layout as a `struct ranging_can_layout *`; ValueError naming the field if one does not fit."""
        layout = ffi.new("struct ranging_can_layout *")
        for name in (f.name for f in fields(self)):
            value = getattr(self, name)
            try:
                setattr(layout, name, value)
            except (OverflowError, TypeError):
                raise ValueError(f"{self._describe()}: {name} {value!r}: expected an integer from 0 to 65535") \
                    from None
        return layout

    def check(self):
        """Raise ValueError naming the layout and what the C code expects if it is unusable
        (ranging_can_layout_check())."""
        why = ffi.new("const char **")
        if lib.ranging_can_layout_check(self.to_c(), why) != 0:
            raise ValueError(f"{self._describe()}: {text(why[0])}")


@dataclass(frozen=True)
class RangingMsg:
    """One ranging measurement (struct ranging_can_msg)."""
    node: int          # the unit that measured (aircraft id)
    peer: int          # the unit it measured the distance to
    range_mm: int      # [mm]
    quality_pct: int   # [%]
    seq: int           # the node's frame counter


def decode(frame, layout=Layout()):
    """(RangingMsg, None) for a valid ranging frame (a finken.can.candump.CanFrame), else (None, reason) with one of
    the reasons above (ranging_can_unpack())."""
    msg = ffi.new("struct ranging_can_msg *")
    verdict = lib.ranging_can_unpack(layout.to_c(), frame.to_c(), msg)
    if verdict != lib.RANGING_CAN_FRAME_OK:
        return None, _reason(verdict)
    return RangingMsg(msg.node_id, msg.peer_id, msg.range_mm, msg.quality_pct, msg.seq), None
