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
 * @file arch/linux/modules/ranging/ranging_socketcan.c
 * Raw SocketCAN sockets: open, adopt, read with kernel time stamps, write (see ranging_socketcan.h).
 */

#include "modules/ranging/ranging_socketcan.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

/** Control buffer for one time stamp and one drop counter */
#define RANGING_SOCKETCAN_CMSG_LEN (CMSG_SPACE(sizeof(struct timespec)) + CMSG_SPACE(sizeof(uint32_t)))

/** Write "CAN interface 'ifname': what: errno text[hint]" to err; keeps errno. */
static void can_error(char *err, size_t errlen, const char *ifname, const char *what, const char *hint)
{
  const int saved = errno;
  if (err != NULL && errlen > 0) {
    snprintf(err, errlen, "CAN interface '%s': %s: %s%s", ifname, what, strerror(saved), hint);
  }
  errno = saved;
}

/** Reception time stamps and the drop counter on fd; -1 and errno on failure. */
static int enable_stamps(int fd)
{
  const int on = 1;
  if (setsockopt(fd, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) < 0) {
    return -1;
  }
  return setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof(on));
}

int ranging_socketcan_open(const char *ifname, const struct ranging_socketcan_config *cfg, char *err,
                           size_t errlen)
{
  if (strlen(ifname) >= IFNAMSIZ) {
    errno = ENAMETOOLONG;
    can_error(err, errlen, ifname, "bad interface name", "");
    return -1;
  }
  const unsigned ifindex = if_nametoindex(ifname);
  if (ifindex == 0) {
    can_error(err, errlen, ifname, "no such network interface", " (ip link show; is the CAN driver loaded?)");
    return -1;
  }
  const int fd = socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    can_error(err, errlen, ifname, "cannot create a SocketCAN socket",
              errno == EAFNOSUPPORT || errno == EPROTONOSUPPORT
              ? " (this kernel has no CAN_RAW support: CONFIG_CAN and CONFIG_CAN_RAW, or modprobe can-raw)" : "");
    return -1;
  }
  const int on = 1;
  if (cfg->filters != NULL
      && setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FILTER, cfg->filters, cfg->nb_filters * sizeof(*cfg->filters)) < 0) {
    can_error(err, errlen, ifname, "cannot set the receive filters", "");
    goto fail;
  }
  if (setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &cfg->err_mask, sizeof(cfg->err_mask)) < 0) {
    can_error(err, errlen, ifname, "cannot enable error frames", "");
    goto fail;
  }
  if (cfg->fd_frames && setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof(on)) < 0) {
    can_error(err, errlen, ifname, "cannot enable CAN FD frames", "");
    goto fail;
  }
  if (enable_stamps(fd) < 0) {
    can_error(err, errlen, ifname, "cannot enable reception time stamps", "");
    goto fail;
  }
  struct sockaddr_can addr;
  memset(&addr, 0, sizeof(addr));
  addr.can_family = AF_CAN;
  addr.can_ifindex = (int)ifindex;
  if (bind(fd, (struct sockaddr *)&addr, sizeof(addr)) < 0) {
    can_error(err, errlen, ifname, "cannot bind", errno == ENODEV ? " (not a CAN interface?)" : "");
    goto fail;
  }
  return fd;

fail: {
    const int saved = errno;
    close(fd);
    errno = saved;
  }
  return -1;
}

int ranging_socketcan_adopt(int fd, char *err, size_t errlen)
{
  const int fl = fcntl(fd, F_GETFL);
  if (fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0) {
    can_error(err, errlen, "(adopted descriptor)", "cannot make it non-blocking", "");
    return -1;
  }
  const int fdfl = fcntl(fd, F_GETFD);
  if (fdfl < 0 || fcntl(fd, F_SETFD, fdfl | FD_CLOEXEC) < 0) {
    can_error(err, errlen, "(adopted descriptor)", "cannot make it close-on-exec", "");
    return -1;
  }
  if (enable_stamps(fd) < 0) {
    can_error(err, errlen, "(adopted descriptor)", "cannot enable reception time stamps", "");
    return -1;
  }
  return 0;
}

int ranging_socketcan_read(int fd, struct ranging_socketcan_rx *rx)
{
  union {
    char buf[RANGING_SOCKETCAN_CMSG_LEN];
    struct cmsghdr align;
  } control;
  struct iovec iov = { .iov_base = &rx->frame, .iov_len = sizeof(rx->frame) };
  struct msghdr msg = {
    .msg_iov = &iov,
    .msg_iovlen = 1,
    .msg_control = control.buf,
    .msg_controllen = sizeof(control.buf),
  };
  const ssize_t n = recvmsg(fd, &msg, MSG_DONTWAIT);
  if (n < 0) {
    return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? 0 : -1;
  }
  if (n == 0) {
    errno = EPIPE;
    return -1;
  }
  rx->age_ns = 0;
  rx->has_drops = false;
  for (struct cmsghdr *c = CMSG_FIRSTHDR(&msg); c != NULL; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level != SOL_SOCKET) {
      continue;
    }
    if (c->cmsg_type == SCM_TIMESTAMPNS) {
      struct timespec stamp, now;
      memcpy(&stamp, CMSG_DATA(c), sizeof(stamp));
      if (clock_gettime(CLOCK_REALTIME, &now) == 0) {
        const int64_t age = (int64_t)(now.tv_sec - stamp.tv_sec) * 1000000000LL + (now.tv_nsec - stamp.tv_nsec);
        rx->age_ns = age > 0 ? (uint64_t)age : 0U;
      }
    } else if (c->cmsg_type == SO_RXQ_OVFL) {
      memcpy(&rx->drops, CMSG_DATA(c), sizeof(rx->drops));
      rx->has_drops = true;
    }
  }
  if ((msg.msg_flags & MSG_TRUNC) || (n != CAN_MTU && n != CANFD_MTU)
      || (n == CAN_MTU && rx->frame.len > CAN_MAX_DLEN) || rx->frame.len > CANFD_MAX_DLEN) {
    errno = EBADMSG;
    return -1;
  }
  rx->fd = n == CANFD_MTU;
  if (!rx->fd) {
    memset(rx->frame.data + CAN_MAX_DLEN, 0, sizeof(rx->frame.data) - CAN_MAX_DLEN);
  }
  return 1;
}

int ranging_socketcan_write(int fd, const struct canfd_frame *frame, bool fd_frame)
{
  const size_t size = fd_frame ? CANFD_MTU : CAN_MTU;
  const ssize_t n = write(fd, frame, size);
  if (n < 0) {
    return -1;
  }
  if ((size_t)n != size) {
    errno = EIO;
    return -1;
  }
  return 0;
}
