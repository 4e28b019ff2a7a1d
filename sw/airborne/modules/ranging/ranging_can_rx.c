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
 * @file modules/ranging/ranging_can_rx.c
 * Peer table, sequence gaps, stale peers and bus state from ranging CAN frames (see ranging_can_rx.h).
 */

#include "modules/ranging/ranging_can_rx.h"

#include <string.h>

/** Sequence steps from 1 to this are gaps; larger steps went back (half the 16-bit counter range) */
#define RANGING_CAN_SEQ_FORWARD_MAX 0x7FFFU

int ranging_can_rx_config_check(const struct ranging_can_rx_config *cfg, const char **why)
{
  if (ranging_can_layout_check(&cfg->layout, why) != 0) {
    return -1;
  }
  if (cfg->self_id >= cfg->layout.nb_nodes) {
    *why = "self_id must be a node id (below nb_nodes)";
    return -1;
  }
  if (cfg->stale_us == 0 || cfg->stale_us > INT32_MAX) {
    *why = "stale_us must be from 1 us to 2^31 - 1 us";
    return -1;
  }
  return 0;
}

void ranging_can_rx_init(struct ranging_can_rx *rx, const struct ranging_can_rx_config *cfg)
{
  memset(rx, 0, sizeof(*rx));
  rx->cfg = *cfg;
  rx->bus_state = RANGING_CAN_BUS_ACTIVE;
}

/** Age of a stamp at now_us [us]; a stamp ahead of now (clock skew) is age 0. */
static uint32_t age_us(uint32_t stamp_us, uint32_t now_us)
{
  const int32_t age = (int32_t)(now_us - stamp_us);
  return age < 0 ? 0U : (uint32_t)age;
}

static void error_frame(struct ranging_can_rx *rx, const struct ranging_can_raw *frame)
{
  const uint32_t classes = frame->can_id & RANGING_CAN_EFF_MASK;
  const uint8_t crtl = frame->len >= 2 ? frame->data[1] : 0;
  rx->stats.error_frames++;
  if (classes & (RANGING_CAN_ERR_TX_TIMEOUT | RANGING_CAN_ERR_LOSTARB | RANGING_CAN_ERR_PROT
                 | RANGING_CAN_ERR_TRX | RANGING_CAN_ERR_ACK | RANGING_CAN_ERR_BUSERROR)) {
    rx->stats.bus_errors++;
  }
  if ((classes & RANGING_CAN_ERR_CRTL) && (crtl & (RANGING_CAN_ERR_CRTL_RX_OVERFLOW | RANGING_CAN_ERR_CRTL_TX_OVERFLOW))) {
    rx->stats.controller_overflows++;
  }
  if (classes & RANGING_CAN_ERR_BUSOFF) {
    if (rx->bus_state != RANGING_CAN_BUS_OFF) {
      rx->stats.bus_off++;
    }
    rx->bus_state = RANGING_CAN_BUS_OFF;
    return;
  }
  if (classes & RANGING_CAN_ERR_RESTARTED) {
    if (rx->bus_state == RANGING_CAN_BUS_OFF) {
      rx->stats.restarts++;
    }
    rx->bus_state = RANGING_CAN_BUS_ACTIVE;
    return;
  }
  if (!(classes & RANGING_CAN_ERR_CRTL) || rx->bus_state == RANGING_CAN_BUS_OFF) {
    return;  /* controller states do not end a bus-off: only a restart does */
  }
  if (crtl & (RANGING_CAN_ERR_CRTL_RX_PASSIVE | RANGING_CAN_ERR_CRTL_TX_PASSIVE)) {
    rx->bus_state = RANGING_CAN_BUS_PASSIVE;
  } else if (crtl & (RANGING_CAN_ERR_CRTL_RX_WARNING | RANGING_CAN_ERR_CRTL_TX_WARNING)) {
    rx->bus_state = RANGING_CAN_BUS_WARNING;
  } else if (crtl & RANGING_CAN_ERR_CRTL_ACTIVE) {
    rx->bus_state = RANGING_CAN_BUS_ACTIVE;
  }
}

/** Track the node's sequence counter; false for a duplicate. */
static bool sequence(struct ranging_can_rx *rx, const struct ranging_can_msg *msg, uint32_t stamp_us)
{
  struct ranging_can_node_seq *n = &rx->node[msg->node_id];
  const bool fresh_run = n->heard && age_us(n->last_us, stamp_us) <= rx->cfg.stale_us;
  if (fresh_run) {
    const uint16_t step = (uint16_t)(msg->seq - n->last_seq);
    if (step == 0) {
      rx->stats.duplicates++;
      return false;
    }
    if (step > RANGING_CAN_SEQ_FORWARD_MAX) {
      rx->stats.node_restarts++;
    } else if (step > 1) {
      rx->stats.seq_gaps++;
      rx->stats.frames_lost += step - 1U;
    }
  }
  n->heard = true;
  n->last_seq = msg->seq;
  n->last_us = stamp_us;
  return true;
}

enum ranging_can_rx_kind ranging_can_rx_frame(struct ranging_can_rx *rx, const struct ranging_can_raw *frame,
    uint32_t stamp_us, struct ranging_can_reading *out)
{
  rx->stats.frames++;
  if (!frame->fd && (frame->can_id & RANGING_CAN_ID_ERR_FLAG)) {
    error_frame(rx, frame);
    return RANGING_CAN_RX_ERROR_FRAME;
  }
  struct ranging_can_msg msg;
  const enum ranging_can_verdict v = ranging_can_unpack(&rx->cfg.layout, frame, &msg);
  if (v != RANGING_CAN_FRAME_OK) {
    rx->stats.invalid[v]++;
    return RANGING_CAN_RX_INVALID;
  }
  if (rx->bus_state == RANGING_CAN_BUS_OFF) {
    rx->stats.restarts++;
    rx->bus_state = RANGING_CAN_BUS_ACTIVE;
  }
  if (!sequence(rx, &msg, stamp_us)) {
    return RANGING_CAN_RX_DUPLICATE;
  }
  const uint8_t self = rx->cfg.self_id;
  if (msg.node_id != self && msg.peer_id != self) {
    rx->stats.not_ours++;
    return RANGING_CAN_RX_NOT_OURS;
  }
  const uint8_t other = msg.node_id == self ? msg.peer_id : msg.node_id;
  struct ranging_can_peer_entry *e = &rx->peer[other];
  e->heard = true;
  e->stale_counted = false;
  e->reading = (struct ranging_can_reading) {
    .other_id = other,
    .node_id = msg.node_id,
    .range_m = (float)msg.range_mm * 1e-3f,
    .quality_pct = msg.quality_pct,
    .seq = msg.seq,
    .stamp_us = stamp_us,
  };
  rx->stats.readings++;
  if (out != NULL) {
    *out = e->reading;
  }
  return RANGING_CAN_RX_READING;
}

int ranging_can_rx_peer(const struct ranging_can_rx *rx, uint8_t other_id, uint32_t now_us,
                        struct ranging_can_reading *out)
{
  if (other_id >= rx->cfg.layout.nb_nodes || !rx->peer[other_id].heard) {
    return -1;
  }
  *out = rx->peer[other_id].reading;
  return age_us(out->stamp_us, now_us) <= rx->cfg.stale_us ? 1 : 0;
}

unsigned ranging_can_rx_check_stale(struct ranging_can_rx *rx, uint32_t now_us)
{
  unsigned stale = 0;
  for (unsigned i = 0; i < rx->cfg.layout.nb_nodes; i++) {
    struct ranging_can_peer_entry *e = &rx->peer[i];
    if (!e->heard || age_us(e->reading.stamp_us, now_us) <= rx->cfg.stale_us) {
      continue;
    }
    stale++;
    if (!e->stale_counted) {
      e->stale_counted = true;
      rx->stats.stale_events++;
    }
  }
  return stale;
}

const char *ranging_can_bus_state_str(enum ranging_can_bus_state state)
{
  switch (state) {
    case RANGING_CAN_BUS_ACTIVE: return "active";
    case RANGING_CAN_BUS_WARNING: return "warning";
    case RANGING_CAN_BUS_PASSIVE: return "passive";
    case RANGING_CAN_BUS_OFF: return "bus-off";
    default: return "unknown";
  }
}
