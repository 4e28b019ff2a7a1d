/*
 * Copyright (C) 2026 FINken range-sensor toolkit contributors
 *
 * This file is part of paparazzi.
 *
 * paparazzi is free software; you can redistribute it and/or modify
 * it under the terms of the GNU General Public License as published by
 * the Free Software Foundation; either version 2, or (at your option)
 * any later version.
 *
 * paparazzi is distributed in the hope that it will be useful,
 * but WITHOUT ANY WARRANTY; without even the implied warranty of
 * MERCHANTABILITY or FITNESS FOR A PARTICULAR PURPOSE.  See the
 * GNU General Public License for more details.
 *
 * You should have received a copy of the GNU General Public License
 * along with paparazzi; see the file COPYING.  If not, see
 * <http://www.gnu.org/licenses/>.
 */

/**
 * @file modules/ranging/ranging_can_frame.h
 * The ranging frame on CAN: layout, pack and unpack as pure functions (no socket, no OS).
 *
 * A ranging unit (node) sends one classical CAN data frame per distance it measured to another unit (peer):
 *
 *     CAN id   standard 11-bit, id = id_base + node id, node id in [0, nb_nodes)
 *     DLC      8; all fields little-endian
 *     byte 0     peer id     uint8   [0, nb_nodes), not the node id
 *     bytes 1-2  range       uint16  [mm], 0 .. range_max_mm
 *     byte 3     quality     uint8   [%], 0 .. 100 (the unit's confidence in the distance)
 *     bytes 4-5  sequence    uint16  +1 for every ranging frame the node sends (wraps at 65536)
 *     bytes 6-7  reserved    0 (anything else is a layout this code does not know)
 *
 * Node and peer ids are the copters' aircraft ids. nb_nodes is a power of two and id_base a multiple of it,
 * so one kernel filter (id_base, mask ~(nb_nodes - 1)) passes exactly the ranging ids.
 * Defaults: id_base 0x300, nb_nodes 64 (ids 0x300 .. 0x33F), range_max_mm 60000 (60 m, beyond any indoor
 * arena: a larger value is a corrupt frame, not a far peer).
 *
 * Frame ids use the SocketCAN (and Paparazzi mcu_periph/can.h) convention: bits 0-28 the identifier,
 * bit 29 error frame, bit 30 remote request, bit 31 extended identifier.
 *
 * The Python tools call this code from build/lib/libfinken_can.so through cffi: tools/finken/can/_native.py
 * copies the declarations they use (CDEF), and tests/python/test_candump.py fails when the two drift apart.
 */

#ifndef RANGING_CAN_FRAME_H
#define RANGING_CAN_FRAME_H

#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** First CAN id of the ranging frames (airframe define) */
#ifndef RANGING_CAN_ID_BASE
#define RANGING_CAN_ID_BASE 0x300
#endif
/** Number of node ids (a power of two; airframe define) */
#ifndef RANGING_CAN_NB_NODES
#define RANGING_CAN_NB_NODES 64
#endif
/** Largest range a valid frame carries [mm] */
#ifndef RANGING_CAN_RANGE_MAX_MM
#define RANGING_CAN_RANGE_MAX_MM 60000
#endif

/** Data length of a ranging frame [bytes] */
#define RANGING_CAN_DLC 8
/** Largest node count the 8-bit peer id can address */
#define RANGING_CAN_NB_NODES_MAX 256
/** Largest quality value [%] */
#define RANGING_CAN_QUALITY_MAX 100

/** CAN id flags and masks (values of linux/can.h CAN_EFF_FLAG, CAN_RTR_FLAG, CAN_ERR_FLAG, CAN_SFF_MASK, ...) */
#define RANGING_CAN_ID_EFF_FLAG 0x80000000U
#define RANGING_CAN_ID_RTR_FLAG 0x40000000U
#define RANGING_CAN_ID_ERR_FLAG 0x20000000U
#define RANGING_CAN_SFF_MASK 0x000007FFU
#define RANGING_CAN_EFF_MASK 0x1FFFFFFFU
/** Largest payload of a CAN FD frame [bytes] */
#define RANGING_CAN_MAX_DLEN 64

/** One CAN frame as it came off the bus or out of a log (classical or FD). */
struct ranging_can_raw {
  uint32_t can_id;                      ///< identifier and flags (see file comment)
  uint8_t len;                          ///< payload length [bytes], <= 8 classical, <= 64 FD
  bool fd;                              ///< a CAN FD frame
  uint8_t fd_flags;                     ///< CAN FD flags (BRS 0x01, ESI 0x02)
  uint8_t data[RANGING_CAN_MAX_DLEN];
};

/** Where the ranging frames sit in the CAN id space. */
struct ranging_can_layout {
  uint16_t id_base;       ///< CAN id of node 0
  uint16_t nb_nodes;      ///< node ids 0 .. nb_nodes - 1 (power of two, <= 256)
  uint16_t range_max_mm;  ///< largest valid range [mm]
};

/** The layout from the airframe defines. */
#define RANGING_CAN_LAYOUT_DEFAULT { RANGING_CAN_ID_BASE, RANGING_CAN_NB_NODES, RANGING_CAN_RANGE_MAX_MM }

/** One ranging measurement. */
struct ranging_can_msg {
  uint8_t node_id;      ///< the unit that measured (sender of the frame)
  uint8_t peer_id;      ///< the unit it measured the distance to
  uint16_t range_mm;    ///< distance [mm]
  uint8_t quality_pct;  ///< confidence [%]
  uint16_t seq;         ///< the node's frame counter
};

/** What unpacking (or packing) found. */
enum ranging_can_verdict {
  RANGING_CAN_FRAME_OK = 0,
  RANGING_CAN_FRAME_NOT_DATA,     ///< an error, remote-request, extended-id or CAN FD frame
  RANGING_CAN_FRAME_FOREIGN_ID,   ///< an id outside [id_base, id_base + nb_nodes)
  RANGING_CAN_FRAME_BAD_DLC,      ///< a length other than 8
  RANGING_CAN_FRAME_BAD_PEER,     ///< peer id >= nb_nodes, or the node's own id
  RANGING_CAN_FRAME_BAD_RANGE,    ///< range above range_max_mm
  RANGING_CAN_FRAME_BAD_QUALITY,  ///< quality above 100 %
  RANGING_CAN_FRAME_BAD_RESERVED, ///< reserved bytes not zero
  RANGING_CAN_FRAME_BAD_NODE,     ///< (pack only) node id >= nb_nodes
  RANGING_CAN_FRAME_NB_VERDICTS
};

/** Check a layout: 0 if usable, else -1 with *why naming the field and what was expected. */
extern int ranging_can_layout_check(const struct ranging_can_layout *layout, const char **why);

/** The kernel filter passing exactly the ranging ids: (received id & mask) == (id & mask). */
extern void ranging_can_layout_filter(const struct ranging_can_layout *layout, uint32_t *id, uint32_t *mask);

/** Encode msg into frame; anything but RANGING_CAN_FRAME_OK leaves frame untouched. */
extern enum ranging_can_verdict ranging_can_pack(const struct ranging_can_layout *layout,
    const struct ranging_can_msg *msg, struct ranging_can_raw *frame);

/** Decode and validate frame into msg; anything but RANGING_CAN_FRAME_OK leaves msg untouched. */
extern enum ranging_can_verdict ranging_can_unpack(const struct ranging_can_layout *layout,
    const struct ranging_can_raw *frame, struct ranging_can_msg *msg);

/** A short English description of a verdict ("DLC is not 8", ...). */
extern const char *ranging_can_verdict_str(enum ranging_can_verdict verdict);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_CAN_FRAME_H */
