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
 * @file modules/ranging/ranging_can_frame.c
 * Pack and unpack the ranging CAN frame (layout in ranging_can_frame.h).
 */

#include "modules/ranging/ranging_can_frame.h"

#include <string.h>

int ranging_can_layout_check(const struct ranging_can_layout *layout, const char **why)
{
  const uint32_t n = layout->nb_nodes;
  if (n == 0 || n > RANGING_CAN_NB_NODES_MAX || (n & (n - 1)) != 0) {
    *why = "nb_nodes must be a power of two from 1 to 256";
    return -1;
  }
  if (layout->id_base % n != 0) {
    *why = "id_base must be a multiple of nb_nodes (one kernel filter covers the ids)";
    return -1;
  }
  if (layout->id_base + n - 1 > RANGING_CAN_SFF_MASK) {
    *why = "id_base + nb_nodes - 1 must be a standard 11-bit id (<= 0x7FF)";
    return -1;
  }
  return 0;
}

void ranging_can_layout_filter(const struct ranging_can_layout *layout, uint32_t *id, uint32_t *mask)
{
  *id = layout->id_base;
  /* the flags are in the mask so that extended, remote and error frames never match */
  *mask = RANGING_CAN_ID_EFF_FLAG | RANGING_CAN_ID_RTR_FLAG | RANGING_CAN_ID_ERR_FLAG
          | (RANGING_CAN_SFF_MASK & ~((uint32_t)layout->nb_nodes - 1U));
}

/** Checks shared by pack and unpack. */
static enum ranging_can_verdict check_fields(const struct ranging_can_layout *layout,
    const struct ranging_can_msg *msg)
{
  if (msg->peer_id >= layout->nb_nodes || msg->peer_id == msg->node_id) {
    return RANGING_CAN_FRAME_BAD_PEER;
  }
  if (msg->range_mm > layout->range_max_mm) {
    return RANGING_CAN_FRAME_BAD_RANGE;
  }
  if (msg->quality_pct > RANGING_CAN_QUALITY_MAX) {
    return RANGING_CAN_FRAME_BAD_QUALITY;
  }
  return RANGING_CAN_FRAME_OK;
}

enum ranging_can_verdict ranging_can_pack(const struct ranging_can_layout *layout,
    const struct ranging_can_msg *msg, struct ranging_can_raw *frame)
{
  if (msg->node_id >= layout->nb_nodes) {
    return RANGING_CAN_FRAME_BAD_NODE;
  }
  const enum ranging_can_verdict v = check_fields(layout, msg);
  if (v != RANGING_CAN_FRAME_OK) {
    return v;
  }
  memset(frame, 0, sizeof(*frame));
  frame->can_id = (uint32_t)layout->id_base + msg->node_id;
  frame->len = RANGING_CAN_DLC;
  frame->data[0] = msg->peer_id;
  frame->data[1] = (uint8_t)(msg->range_mm & 0xFFU);
  frame->data[2] = (uint8_t)(msg->range_mm >> 8);
  frame->data[3] = msg->quality_pct;
  frame->data[4] = (uint8_t)(msg->seq & 0xFFU);
  frame->data[5] = (uint8_t)(msg->seq >> 8);
  return RANGING_CAN_FRAME_OK;
}

enum ranging_can_verdict ranging_can_unpack(const struct ranging_can_layout *layout,
    const struct ranging_can_raw *frame, struct ranging_can_msg *msg)
{
  if (frame->fd || (frame->can_id & (RANGING_CAN_ID_EFF_FLAG | RANGING_CAN_ID_RTR_FLAG | RANGING_CAN_ID_ERR_FLAG))) {
    return RANGING_CAN_FRAME_NOT_DATA;
  }
  const uint32_t id = frame->can_id & RANGING_CAN_SFF_MASK;
  if (frame->can_id > RANGING_CAN_SFF_MASK || id < layout->id_base || id >= (uint32_t)layout->id_base + layout->nb_nodes) {
    return RANGING_CAN_FRAME_FOREIGN_ID;
  }
  if (frame->len != RANGING_CAN_DLC) {
    return RANGING_CAN_FRAME_BAD_DLC;
  }
  if (frame->data[6] != 0 || frame->data[7] != 0) {
    return RANGING_CAN_FRAME_BAD_RESERVED;
  }
  const struct ranging_can_msg m = {
    .node_id = (uint8_t)(id - layout->id_base),
    .peer_id = frame->data[0],
    .range_mm = (uint16_t)(frame->data[1] | (frame->data[2] << 8)),
    .quality_pct = frame->data[3],
    .seq = (uint16_t)(frame->data[4] | (frame->data[5] << 8)),
  };
  const enum ranging_can_verdict v = check_fields(layout, &m);
  if (v == RANGING_CAN_FRAME_OK) {
    *msg = m;
  }
  return v;
}

const char *ranging_can_verdict_str(enum ranging_can_verdict verdict)
{
  switch (verdict) {
    case RANGING_CAN_FRAME_OK: return "ok";
    case RANGING_CAN_FRAME_NOT_DATA: return "not a classical standard-id data frame (error, remote, extended or CAN FD)";
    case RANGING_CAN_FRAME_FOREIGN_ID: return "CAN id outside the ranging ids";
    case RANGING_CAN_FRAME_BAD_DLC: return "DLC is not 8";
    case RANGING_CAN_FRAME_BAD_PEER: return "peer id outside the node ids or equal to the sender's";
    case RANGING_CAN_FRAME_BAD_RANGE: return "range above the largest valid range";
    case RANGING_CAN_FRAME_BAD_QUALITY: return "quality above 100 %";
    case RANGING_CAN_FRAME_BAD_RESERVED: return "reserved bytes 6-7 not zero";
    case RANGING_CAN_FRAME_BAD_NODE: return "node id outside the node ids";
    case RANGING_CAN_FRAME_NB_VERDICTS:
    default: return "unknown verdict";
  }
}
