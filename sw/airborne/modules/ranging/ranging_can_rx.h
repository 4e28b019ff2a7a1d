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
 * @file modules/ranging/ranging_can_rx.h
 * What a copter makes of the ranging frames it receives, as pure logic (no socket, no clock): the newest
 * distance to each other copter with its time stamp, sequence gaps per sending node, stale peers, and the bus
 * state from SocketCAN error frames. The Linux driver (arch/linux/modules/ranging/ranging_can.h) feeds it from
 * a CAN socket, a replay feeds it from a candump log; both call ranging_can_rx_frame().
 *
 * Which frames are about this copter (self_id): those it sent (node == self: the distance to `peer`) and those
 * sent about it (peer == self: the distance to `node`). The table is keyed by the other copter's id, so it
 * holds nb_nodes entries at most whatever the bus brings (bounded memory).
 *
 * Sequence counters (one per sending node, all valid ranging frames): +1 is in order; 0 is a duplicate
 * (dropped); +2 .. +32767 is a gap (the frames in between were lost: counted); a step back is a node that
 * restarted (counted, accepted). A node silent for longer than stale_us starts afresh (its gap is not counted).
 *
 * Bus state from error frames (linux/can/error.h classes): bus-off (counted once per bus-off), the
 * controller's warning and passive states, back to active on a "restarted" error frame or a "back to error
 * active" controller report; a valid ranging frame while bus-off also counts as a restart (the frames flow
 * again, the restart report was missed). Error frames never touch the peer table: its freshness is by age only.
 */

#ifndef RANGING_CAN_RX_H
#define RANGING_CAN_RX_H

#include "modules/ranging/ranging_can_frame.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Error classes in the id of an error frame (linux/can/error.h CAN_ERR_*) */
#define RANGING_CAN_ERR_TX_TIMEOUT 0x001U
#define RANGING_CAN_ERR_LOSTARB 0x002U
#define RANGING_CAN_ERR_CRTL 0x004U
#define RANGING_CAN_ERR_PROT 0x008U
#define RANGING_CAN_ERR_TRX 0x010U
#define RANGING_CAN_ERR_ACK 0x020U
#define RANGING_CAN_ERR_BUSOFF 0x040U
#define RANGING_CAN_ERR_BUSERROR 0x080U
#define RANGING_CAN_ERR_RESTARTED 0x100U
/** Controller status in data[1] of a CAN_ERR_CRTL error frame (linux/can/error.h CAN_ERR_CRTL_*) */
#define RANGING_CAN_ERR_CRTL_RX_OVERFLOW 0x01U
#define RANGING_CAN_ERR_CRTL_TX_OVERFLOW 0x02U
#define RANGING_CAN_ERR_CRTL_RX_WARNING 0x04U
#define RANGING_CAN_ERR_CRTL_TX_WARNING 0x08U
#define RANGING_CAN_ERR_CRTL_RX_PASSIVE 0x10U
#define RANGING_CAN_ERR_CRTL_TX_PASSIVE 0x20U
#define RANGING_CAN_ERR_CRTL_ACTIVE 0x40U

enum ranging_can_bus_state {
  RANGING_CAN_BUS_ACTIVE = 0,  ///< error active: normal operation
  RANGING_CAN_BUS_WARNING,     ///< an error counter passed 96
  RANGING_CAN_BUS_PASSIVE,     ///< an error counter passed 127
  RANGING_CAN_BUS_OFF,         ///< the controller left the bus (transmit error counter passed 255)
};

struct ranging_can_rx_config {
  struct ranging_can_layout layout;
  uint8_t self_id;    ///< this copter's node id (its aircraft id)
  uint32_t stale_us;  ///< a distance older than this is stale [us]
};

/** One distance between this copter and another. */
struct ranging_can_reading {
  uint8_t other_id;     ///< the other copter
  uint8_t node_id;      ///< who measured (self_id or other_id)
  float range_m;        ///< distance [m]
  uint8_t quality_pct;  ///< confidence [%]
  uint16_t seq;         ///< sequence counter of the frame
  uint32_t stamp_us;    ///< reception time (the caller's clock) [us]
};

struct ranging_can_rx_stats {
  uint32_t frames;                                      ///< frames given to ranging_can_rx_frame()
  uint32_t readings;                                    ///< distances about this copter accepted
  uint32_t not_ours;                                    ///< valid frames between two other copters
  uint32_t invalid[RANGING_CAN_FRAME_NB_VERDICTS];      ///< rejected data frames, by verdict
  uint32_t duplicates;                                  ///< repeated sequence numbers (dropped)
  uint32_t seq_gaps;                                    ///< sequence gaps
  uint32_t frames_lost;                                 ///< frames missing in those gaps
  uint32_t node_restarts;                               ///< sequence counters that went back
  uint32_t error_frames;                                ///< error frames
  uint32_t bus_errors;                                  ///< error frames of the protocol/ack/arbitration/... classes
  uint32_t controller_overflows;                        ///< controller RX/TX buffer overflows
  uint32_t bus_off;                                     ///< times the bus went off
  uint32_t restarts;                                    ///< times it came back after bus-off
  uint32_t stale_events;                                ///< peers that went from fresh to stale
};

struct ranging_can_peer_entry {
  bool heard;                   ///< a reading arrived since init
  bool stale_counted;           ///< its going stale was counted
  struct ranging_can_reading reading;  ///< the newest one
};

struct ranging_can_node_seq {
  bool heard;
  uint16_t last_seq;
  uint32_t last_us;
};

struct ranging_can_rx {
  struct ranging_can_rx_config cfg;
  enum ranging_can_bus_state bus_state;
  struct ranging_can_peer_entry peer[RANGING_CAN_NB_NODES_MAX];
  struct ranging_can_node_seq node[RANGING_CAN_NB_NODES_MAX];
  struct ranging_can_rx_stats stats;
};

/** What one frame was. */
enum ranging_can_rx_kind {
  RANGING_CAN_RX_READING = 0,  ///< a distance about this copter: *out filled, table updated
  RANGING_CAN_RX_NOT_OURS,     ///< a valid ranging frame between two other copters
  RANGING_CAN_RX_DUPLICATE,    ///< a repeated sequence number
  RANGING_CAN_RX_INVALID,      ///< a data frame that is not a valid ranging frame
  RANGING_CAN_RX_ERROR_FRAME,  ///< an error frame (bus state and counters updated)
};

/** Check a configuration: 0 if usable, else -1 with *why naming the field and what was expected. */
extern int ranging_can_rx_config_check(const struct ranging_can_rx_config *cfg, const char **why);

/** Start with cfg (checked by the caller with ranging_can_rx_config_check()). */
extern void ranging_can_rx_init(struct ranging_can_rx *rx, const struct ranging_can_rx_config *cfg);

/**
 * Take one frame received at stamp_us (the caller's clock).
 * @param out filled for RANGING_CAN_RX_READING (may be NULL)
 */
extern enum ranging_can_rx_kind ranging_can_rx_frame(struct ranging_can_rx *rx, const struct ranging_can_raw *frame,
    uint32_t stamp_us, struct ranging_can_reading *out);

/**
 * The newest distance to other_id at now_us.
 * @return 1 fresh (at most stale_us old), 0 stale (*out still filled), -1 never heard or not a node id
 */
extern int ranging_can_rx_peer(const struct ranging_can_rx *rx, uint8_t other_id, uint32_t now_us,
                               struct ranging_can_reading *out);

/** Count peers that went stale since the last call (stats.stale_events); returns how many are stale now. */
extern unsigned ranging_can_rx_check_stale(struct ranging_can_rx *rx, uint32_t now_us);

/** "active", "warning", "passive" or "bus-off". */
extern const char *ranging_can_bus_state_str(enum ranging_can_bus_state state);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_CAN_RX_H */
