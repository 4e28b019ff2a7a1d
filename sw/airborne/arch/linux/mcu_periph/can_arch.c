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
 * @file arch/linux/mcu_periph/can_arch.c
 * Paparazzi's CAN peripheral over SocketCAN: open, non-blocking receive in can_event(), transmit
 * (see can_arch.h).
 */

#include "mcu_periph/can.h"
#include "mcu_periph/socketcan.h"
#include "mcu_periph/sys_time.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/** Longest error message [chars + 1] */
#define CAN_ARCH_ERR_LEN 256

struct can_arch_periph {
  const char *ifname;   ///< Linux interface name
  int can_ifindex;      ///< Paparazzi's interface number (1 or 2)
  int fd;               ///< socket, -1 if not open
  bool rx_reported;     ///< a receive failure was reported
};

static void (*error_sink)(const char *msg);
static char last_error[CAN_ARCH_ERR_LEN];

#if USE_CAN1
static struct can_arch_periph can1_arch = { .ifname = CAN1_IFNAME, .can_ifindex = 1, .fd = -1 };
#endif
#if USE_CAN2
static struct can_arch_periph can2_arch = { .ifname = CAN2_IFNAME, .can_ifindex = 2, .fd = -1 };
#endif

static void report(void)
{
  if (error_sink != NULL) {
    error_sink(last_error);
  } else {
    fprintf(stderr, "can_arch: %s\n", last_error);
  }
}

const char *can_arch_last_error(void)
{
  return last_error;
}

void can_arch_set_error_sink(void (*sink)(const char *msg))
{
  error_sink = sink;
}

/** The peripheral of Paparazzi's interface number, or NULL. */
static struct can_periph *periph_of(int can_ifindex)
{
#if USE_CAN1
  if (can_ifindex == 1) {
    can1.arch_struct = &can1_arch;
    return &can1;
  }
#endif
#if USE_CAN2
  if (can_ifindex == 2) {
    can2.arch_struct = &can2_arch;
    return &can2;
  }
#endif
  return NULL;
}

static void set_fd(struct can_periph *p, int fd)
{
  struct can_arch_periph *a = p->arch_struct;
  if (a->fd >= 0) {
    close(a->fd);
  }
  a->fd = fd;
  a->rx_reported = false;
  p->fd = fd;
}

static void open_periph(int can_ifindex)
{
  struct can_periph *p = periph_of(can_ifindex);
  struct can_arch_periph *a = p->arch_struct;
  const struct socketcan_config cfg = { .filters = NULL, .err_mask = 0, .fd_frames = SOCKETCAN_MAX_DLEN > CAN_MAX_DLEN };
  const int fd = socketcan_open(a->ifname, &cfg, last_error, sizeof(last_error));
  if (fd < 0) {
    report();
  }
  set_fd(p, fd);
}

void can_hw_init(void)
{
#if USE_CAN1
  open_periph(1);
#endif
#if USE_CAN2
  open_periph(2);
#endif
}

int can_arch_attach_fd(int can_ifindex, int fd)
{
  struct can_periph *p = periph_of(can_ifindex);
  if (p == NULL || fd < 0) {
    errno = EINVAL;
    return -1;
  }
  if (socketcan_adopt(fd, last_error, sizeof(last_error)) < 0) {
    return -1;
  }
  set_fd(p, fd);
  return 0;
}

void can_arch_close(void)
{
#if USE_CAN1
  set_fd(periph_of(1), -1);
#endif
#if USE_CAN2
  set_fd(periph_of(2), -1);
#endif
}

static void receive(struct can_periph *p)
{
  struct can_arch_periph *a = p->arch_struct;
  if (a == NULL || a->fd < 0) {
    return;
  }
  struct pprzaddr_can addr = { .can_ifindex = a->can_ifindex };
  for (int i = 0; i < CAN_ARCH_MAX_FRAMES_PER_EVENT; i++) {
    struct socketcan_rx rx;
    const int rc = socketcan_read(a->fd, &rx);
    if (rc == 0) {
      return;
    }
    if (rc < 0) {
      if (errno == EBADMSG) {
        continue;  /* a malformed message (only a test seam can bring one): skip it */
      }
      if (!a->rx_reported) {
        a->rx_reported = true;
        snprintf(last_error, sizeof(last_error), "CAN interface '%s': receive failed: %s", a->ifname, strerror(errno));
        report();
      }
      return;
    }
    a->rx_reported = false;
    struct pprzcan_frame f = {
      .can_id = rx.frame.can_id,
      .len = rx.frame.len > SOCKETCAN_MAX_DLEN ? SOCKETCAN_MAX_DLEN : rx.frame.len,
      .flags = rx.fd ? (uint8_t)(rx.frame.flags | CANFD_FDF) : 0,
      .timestamp = get_sys_time_usec() - (uint32_t)(rx.age_ns / 1000U),
    };
    memcpy(f.data, rx.frame.data, f.len);
    for (int c = 0; c < CAN_NB_CALLBACKS_MAX; c++) {
      if (p->callbacks[c] != NULL) {
        p->callbacks[c](&f, &addr, p->callback_user_data[c]);
      }
    }
  }
}

void can_event(void)
{
#if USE_CAN1
  receive(&can1);
#endif
#if USE_CAN2
  receive(&can2);
#endif
}

/** Check txframe and build the SocketCAN frame; -1 and EINVAL for a bad id or length. */
static int build(const struct pprzcan_frame *txframe, struct canfd_frame *out, bool *fd)
{
  const bool eff = (txframe->can_id & CAN_FRAME_EFF) != 0;
  const uint32_t id = txframe->can_id & CAN_EID_MASK;
  *fd = (txframe->flags & CANFD_FDF) != 0;
  if ((!eff && id > CAN_SID_MASK) || (txframe->can_id & CAN_FRAME_ERR)
      || txframe->len > (*fd ? SOCKETCAN_MAX_DLEN : CAN_MAX_DLEN)
      || can_dlc_to_len(can_len_to_dlc(txframe->len)) != txframe->len
      || (*fd && (txframe->can_id & CAN_FRAME_RTR))) {
    errno = EINVAL;
    return -1;
  }
  memset(out, 0, sizeof(*out));
  out->can_id = txframe->can_id;
  out->len = txframe->len;
  out->flags = *fd ? (uint8_t)(txframe->flags & (CANFD_BRS | CANFD_ESI)) : 0;
  memcpy(out->data, txframe->data, txframe->len);
  return 0;
}

int can_transmit_frame(struct pprzcan_frame *txframe, struct pprzaddr_can *dst_addr)
{
  struct canfd_frame frame;
  bool fd;
  if (build(txframe, &frame, &fd) < 0) {
    return -1;
  }
  const int ifindex = dst_addr != NULL ? dst_addr->can_ifindex : 0;
  int sent = 0, failed = 0, first_errno = 0;
  for (int i = 1; i <= 2; i++) {
    if (ifindex != 0 && ifindex != i) {
      continue;
    }
    struct can_periph *p = periph_of(i);
    struct can_arch_periph *a = p != NULL ? p->arch_struct : NULL;
    if (a == NULL || a->fd < 0) {
      continue;
    }
    if (socketcan_write(a->fd, &frame, fd) < 0) {
      if (failed++ == 0) {
        first_errno = errno;
      }
    } else {
      sent++;
    }
  }
  if (failed > 0 || sent == 0) {
    errno = failed > 0 ? first_errno : ENODEV;
    return -1;
  }
  return 0;
}
