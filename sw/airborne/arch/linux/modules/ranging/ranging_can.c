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
 * @file arch/linux/modules/ranging/ranging_can.c
 * Ranging frames from a SocketCAN socket into the pure receive logic (see ranging_can.h).
 */

#include "modules/ranging/ranging_can.h"
#include "modules/ranging/ranging_socketcan.h"

#include <errno.h>
#include <linux/can/error.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* the pure logic spells the SocketCAN constants out (it builds without Linux headers): they must agree */
_Static_assert(RANGING_CAN_ID_EFF_FLAG == CAN_EFF_FLAG && RANGING_CAN_ID_RTR_FLAG == CAN_RTR_FLAG
               && RANGING_CAN_ID_ERR_FLAG == CAN_ERR_FLAG && RANGING_CAN_SFF_MASK == CAN_SFF_MASK
               && RANGING_CAN_EFF_MASK == CAN_EFF_MASK && RANGING_CAN_MAX_DLEN == CANFD_MAX_DLEN,
               "CAN id flags differ from linux/can.h");
_Static_assert(RANGING_CAN_ERR_TX_TIMEOUT == CAN_ERR_TX_TIMEOUT && RANGING_CAN_ERR_LOSTARB == CAN_ERR_LOSTARB
               && RANGING_CAN_ERR_CRTL == CAN_ERR_CRTL && RANGING_CAN_ERR_PROT == CAN_ERR_PROT
               && RANGING_CAN_ERR_TRX == CAN_ERR_TRX && RANGING_CAN_ERR_ACK == CAN_ERR_ACK
               && RANGING_CAN_ERR_BUSOFF == CAN_ERR_BUSOFF && RANGING_CAN_ERR_BUSERROR == CAN_ERR_BUSERROR
               && RANGING_CAN_ERR_RESTARTED == CAN_ERR_RESTARTED, "error classes differ from linux/can/error.h");
_Static_assert(RANGING_CAN_ERR_CRTL_RX_OVERFLOW == CAN_ERR_CRTL_RX_OVERFLOW
               && RANGING_CAN_ERR_CRTL_TX_OVERFLOW == CAN_ERR_CRTL_TX_OVERFLOW
               && RANGING_CAN_ERR_CRTL_RX_WARNING == CAN_ERR_CRTL_RX_WARNING
               && RANGING_CAN_ERR_CRTL_TX_WARNING == CAN_ERR_CRTL_TX_WARNING
               && RANGING_CAN_ERR_CRTL_RX_PASSIVE == CAN_ERR_CRTL_RX_PASSIVE
               && RANGING_CAN_ERR_CRTL_TX_PASSIVE == CAN_ERR_CRTL_TX_PASSIVE
               && RANGING_CAN_ERR_CRTL_ACTIVE == CAN_ERR_CRTL_ACTIVE, "controller states differ from linux/can/error.h");

/** Longest error message [chars + 1] */
#define RANGING_CAN_ERR_LEN 256
/** Longest interface name [chars + 1] (IFNAMSIZ) */
#define RANGING_CAN_IFNAME_LEN 16

struct ranging_can {
  struct ranging_can_config cfg;
  char ifname[RANGING_CAN_IFNAME_LEN];  ///< "" for an adopted descriptor (nothing to reopen)
  int fd;
  uint32_t reopen_at_us;                ///< next reopen attempt while fd < 0
  struct ranging_can_rx rx;
  struct ranging_can_stats stats;
  char last_error[RANGING_CAN_ERR_LEN];
};

/** Common checks and set-up; the descriptor is attached by the callers. */
static struct ranging_can *create(const struct ranging_can_config *cfg, char *err, size_t errlen)
{
  const char *why;
  if (ranging_can_rx_config_check(&cfg->rx, &why) != 0) {
    snprintf(err, errlen, "ranging CAN: bad configuration: %s", why);
    errno = EINVAL;
    return NULL;
  }
  if (cfg->max_frames_per_event == 0) {
    snprintf(err, errlen, "ranging CAN: bad configuration: max_frames_per_event must be > 0");
    errno = EINVAL;
    return NULL;
  }
  struct ranging_can *rc = calloc(1, sizeof(*rc));
  if (rc == NULL) {
    snprintf(err, errlen, "ranging CAN: out of memory");
    return NULL;
  }
  rc->cfg = *cfg;
  rc->cfg.ifname = NULL;
  rc->fd = -1;
  ranging_can_rx_init(&rc->rx, &cfg->rx);
  return rc;
}

static int open_socket(const struct ranging_can *rc, char *err, size_t errlen)
{
  struct can_filter filter;
  uint32_t id, mask;
  ranging_can_layout_filter(&rc->cfg.rx.layout, &id, &mask);
  filter.can_id = id;
  filter.can_mask = mask;
  const struct ranging_socketcan_config sc = { .filters = &filter, .nb_filters = 1, .err_mask = CAN_ERR_MASK,
                                               .fd_frames = false };
  return ranging_socketcan_open(rc->ifname, &sc, err, errlen);
}

struct ranging_can *ranging_can_open(const struct ranging_can_config *cfg, char *err, size_t errlen)
{
  if (cfg->ifname == NULL || strlen(cfg->ifname) >= RANGING_CAN_IFNAME_LEN) {
    snprintf(err, errlen, "ranging CAN: bad configuration: ifname must name a network interface (< 16 chars)");
    errno = EINVAL;
    return NULL;
  }
  struct ranging_can *rc = create(cfg, err, errlen);
  if (rc == NULL) {
    return NULL;
  }
  strcpy(rc->ifname, cfg->ifname);
  rc->fd = open_socket(rc, err, errlen);
  if (rc->fd < 0) {
    const int saved = errno;
    free(rc);
    errno = saved;
    return NULL;
  }
  return rc;
}

struct ranging_can *ranging_can_open_fd(int fd, const struct ranging_can_config *cfg, char *err, size_t errlen)
{
  struct ranging_can *rc = create(cfg, err, errlen);
  if (rc == NULL) {
    return NULL;
  }
  if (ranging_socketcan_adopt(fd, err, errlen) < 0) {
    const int saved = errno;
    free(rc);
    errno = saved;
    return NULL;
  }
  rc->fd = fd;
  return rc;
}

/** A failed read: keep the socket over ENETDOWN, else close it (reopened later if it has an interface). */
static void read_failed(struct ranging_can *rc, uint32_t now_us)
{
  const int saved = errno;
  rc->stats.read_errors++;
  snprintf(rc->last_error, sizeof(rc->last_error), "CAN interface '%s': receive failed: %s",
           rc->ifname[0] ? rc->ifname : "(adopted descriptor)", strerror(saved));
  if (saved != ENETDOWN) {
    close(rc->fd);
    rc->fd = -1;
    rc->reopen_at_us = now_us + RANGING_CAN_REOPEN_MS * 1000U;
  }
  errno = saved;
}

/** Reopen a failed socket when its time has come; 0 if open, -1 with errno if not (yet). */
static int reopen(struct ranging_can *rc, uint32_t now_us)
{
  if (rc->ifname[0] == '\0') {
    errno = ENOTCONN;
    return -1;
  }
  if ((int32_t)(now_us - rc->reopen_at_us) < 0) {
    errno = ENOTCONN;
    return -1;
  }
  rc->fd = open_socket(rc, rc->last_error, sizeof(rc->last_error));
  if (rc->fd < 0) {
    rc->reopen_at_us = now_us + RANGING_CAN_REOPEN_MS * 1000U;
    return -1;
  }
  rc->stats.reopens++;
  return 0;
}

int ranging_can_event(struct ranging_can *rc, uint32_t now_us, ranging_can_reading_cb cb, void *user)
{
  if (rc->fd < 0 && reopen(rc, now_us) < 0) {
    return -1;
  }
  int readings = 0;
  int status = 0;
  for (unsigned i = 0; i < rc->cfg.max_frames_per_event; i++) {
    struct ranging_socketcan_rx in;
    const int r = ranging_socketcan_read(rc->fd, &in);
    if (r == 0) {
      break;
    }
    if (r < 0) {
      if (errno == EBADMSG) {
        rc->stats.malformed++;
        continue;
      }
      read_failed(rc, now_us);
      status = -1;
      break;
    }
    if (in.has_drops) {
      rc->stats.kernel_drops = in.drops;
    }
    struct ranging_can_raw raw = { .can_id = in.frame.can_id, .len = in.frame.len, .fd = in.fd,
                                   .fd_flags = in.fd ? in.frame.flags : 0 };
    memcpy(raw.data, in.frame.data, in.frame.len);
    const uint64_t age_us = in.age_ns / 1000U;
    const uint32_t stamp_us = now_us - (uint32_t)(age_us > INT32_MAX ? INT32_MAX : age_us);
    struct ranging_can_reading reading;
    if (ranging_can_rx_frame(&rc->rx, &raw, stamp_us, &reading) == RANGING_CAN_RX_READING) {
      readings++;
      if (cb != NULL) {
        cb(user, &reading);
      }
    }
  }
  rc->stats.stale_peers = ranging_can_rx_check_stale(&rc->rx, now_us);
  if (status < 0) {
    return -1;
  }
  return readings;
}

int ranging_can_peer(const struct ranging_can *rc, uint8_t other_id, uint32_t now_us,
                     struct ranging_can_reading *out)
{
  return ranging_can_rx_peer(&rc->rx, other_id, now_us, out);
}

void ranging_can_stats(const struct ranging_can *rc, struct ranging_can_stats *out)
{
  *out = rc->stats;
  out->rx = rc->rx.stats;
  out->bus_state = rc->rx.bus_state;
}

const char *ranging_can_last_error(const struct ranging_can *rc)
{
  return rc->last_error;
}

int ranging_can_fd(const struct ranging_can *rc)
{
  return rc->fd;
}

void ranging_can_close(struct ranging_can *rc)
{
  if (rc == NULL) {
    return;
  }
  if (rc->fd >= 0) {
    close(rc->fd);
  }
  free(rc);
}
