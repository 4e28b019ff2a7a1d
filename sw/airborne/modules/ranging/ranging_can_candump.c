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
 * @file modules/ranging/ranging_can_candump.c
 * Parse can-utils `candump -l` log lines (format in ranging_can_candump.h).
 */

#include "modules/ranging/ranging_can_candump.h"

#include <string.h>

/** Most decimal digits of the seconds of a time stamp (enough for the year 33658) */
#define CANDUMP_SECONDS_DIGITS_MAX 12
/** Most decimals of a time stamp (nanoseconds) */
#define CANDUMP_DECIMALS_MAX 9
/** Classical CAN payload [bytes] */
#define CANDUMP_CLASSIC_MAX_LEN 8

static int hex_value(char c)
{
  if (c >= '0' && c <= '9') {
    return c - '0';
  }
  if (c >= 'a' && c <= 'f') {
    return c - 'a' + 10;
  }
  if (c >= 'A' && c <= 'F') {
    return c - 'A' + 10;
  }
  return -1;
}

static bool is_blank(char c)
{
  return c == ' ' || c == '\t';
}

static bool is_end(char c)
{
  return c == '\0' || c == '\n' || c == '\r';
}

/** "(seconds.decimals)" -> microseconds; returns the position after ')' or NULL. */
static const char *parse_time(const char *p, uint64_t *time_us, const char **why)
{
  if (*p != '(') {
    *why = "expected '(' opening the time stamp, as in (1700000000.123456)";
    return NULL;
  }
  p++;
  uint64_t sec = 0;
  int digits = 0;
  for (; *p >= '0' && *p <= '9'; p++, digits++) {
    if (digits == CANDUMP_SECONDS_DIGITS_MAX) {
      *why = "time stamp: too many digits in the seconds";
      return NULL;
    }
    sec = sec * 10U + (uint64_t)(*p - '0');
  }
  if (digits == 0 || *p != '.') {
    *why = "time stamp: expected seconds, '.', decimals, as in (1700000000.123456)";
    return NULL;
  }
  p++;
  uint64_t frac_us = 0;
  int decimals = 0;
  for (; *p >= '0' && *p <= '9'; p++, decimals++) {
    if (decimals == CANDUMP_DECIMALS_MAX) {
      *why = "time stamp: more than 9 decimals";
      return NULL;
    }
    if (decimals < 6) {
      frac_us = frac_us * 10U + (uint64_t)(*p - '0');
    }
  }
  if (decimals == 0 || *p != ')') {
    *why = "time stamp: expected decimals and ')', as in (1700000000.123456)";
    return NULL;
  }
  for (int d = decimals; d < 6; d++) {
    frac_us *= 10U;
  }
  *time_us = sec * 1000000U + frac_us;
  return p + 1;
}

/** Hex data bytes ('.' allowed between bytes) up to max; returns the position after them or NULL. */
static const char *parse_data(const char *p, uint8_t *data, uint8_t *len, uint8_t max, const char **why)
{
  uint8_t n = 0;
  while (!is_end(*p) && !is_blank(*p) && *p != '_') {
    if (*p == '.') {
      p++;
      continue;
    }
    const int hi = hex_value(p[0]);
    const int lo = hi < 0 ? -1 : hex_value(p[1]);
    if (hi < 0 || lo < 0) {
      *why = "data: expected pairs of hex digits";
      return NULL;
    }
    if (n == max) {
      *why = max == CANDUMP_CLASSIC_MAX_LEN ? "data: more than 8 bytes in a classical frame"
             : "data: more than 64 bytes in a CAN FD frame";
      return NULL;
    }
    data[n++] = (uint8_t)(hi << 4 | lo);
    p += 2;
  }
  *len = n;
  return p;
}

/** The frame "<id>#<data>", "<id>#R<len>", "<id>##<flags><data>"; returns the position after it or NULL. */
static const char *parse_frame(const char *p, struct ranging_can_raw *f, const char **why)
{
  uint32_t id = 0;
  int digits = 0;
  for (; hex_value(*p) >= 0; p++, digits++) {
    if (digits == 8) {
      break;
    }
    id = id << 4 | (uint32_t)hex_value(*p);
  }
  if (*p != '#' || (digits != 3 && digits != 8)) {
    *why = "frame: expected a CAN id of 3 (standard) or 8 (extended/error) hex digits and '#'";
    return NULL;
  }
  p++;
  if (digits == 3) {
    f->can_id = id;
  } else if (id & RANGING_CAN_ID_ERR_FLAG) {
    if (id & (RANGING_CAN_ID_EFF_FLAG | RANGING_CAN_ID_RTR_FLAG)) {
      *why = "frame: an error frame id with the extended or remote flag";
      return NULL;
    }
    f->can_id = id;
  } else if (id > RANGING_CAN_EFF_MASK) {
    *why = "frame: an extended id above 0x1FFFFFFF";
    return NULL;
  } else {
    f->can_id = id | RANGING_CAN_ID_EFF_FLAG;
  }
  if (*p == '#') {  /* CAN FD */
    if (f->can_id & RANGING_CAN_ID_ERR_FLAG) {
      *why = "frame: an error frame cannot be a CAN FD frame";
      return NULL;
    }
    const int flags = hex_value(p[1]);
    if (flags < 0) {
      *why = "CAN FD frame: expected one hex digit of flags after '##'";
      return NULL;
    }
    f->fd = true;
    f->fd_flags = (uint8_t)flags;
    p = parse_data(p + 2, f->data, &f->len, RANGING_CAN_MAX_DLEN, why);
    if (p != NULL && *p == '_') {
      *why = "CAN FD frame: a DLC suffix belongs to classical frames only";
      return NULL;
    }
    return p;
  }
  if (*p == 'R' || *p == 'r') {  /* remote request, optional length digit */
    if (f->can_id & RANGING_CAN_ID_ERR_FLAG) {
      *why = "frame: an error frame cannot be a remote request";
      return NULL;
    }
    f->can_id |= RANGING_CAN_ID_RTR_FLAG;
    p++;
    if (*p >= '0' && *p <= '8') {
      f->len = (uint8_t)(*p - '0');
      p++;
    }
  } else {
    p = parse_data(p, f->data, &f->len, CANDUMP_CLASSIC_MAX_LEN, why);
    if (p == NULL) {
      return NULL;
    }
  }
  if (*p == '_') {  /* DLC 9..15 of an 8-byte classical frame */
    const int dlc = hex_value(p[1]);
    if (f->len != CANDUMP_CLASSIC_MAX_LEN || dlc < 9) {
      *why = "frame: a '_' DLC suffix needs 8 data bytes and a DLC from 9 to F";
      return NULL;
    }
    p += 2;
  }
  return p;
}

int ranging_can_candump_parse(const char *line, struct ranging_can_candump_line *out, const char **why)
{
  const char *p = line;
  while (is_blank(*p)) {
    p++;
  }
  if (is_end(*p)) {
    return 0;
  }
  struct ranging_can_candump_line l;
  memset(&l, 0, sizeof(l));
  p = parse_time(p, &l.time_us, why);
  if (p == NULL) {
    return -1;
  }
  if (!is_blank(*p)) {
    *why = "expected a space after the time stamp";
    return -1;
  }
  while (is_blank(*p)) {
    p++;
  }
  size_t n = 0;
  for (; !is_end(p[n]) && !is_blank(p[n]); n++) {
    if (n == RANGING_CAN_CANDUMP_IFNAME_LEN - 1) {
      *why = "interface name longer than 15 characters";
      return -1;
    }
    l.ifname[n] = p[n];
  }
  if (n == 0 || !is_blank(p[n])) {
    *why = "expected an interface name and a frame after the time stamp";
    return -1;
  }
  p += n;
  while (is_blank(*p)) {
    p++;
  }
  p = parse_frame(p, &l.frame, why);
  if (p == NULL) {
    return -1;
  }
  while (is_blank(*p)) {
    p++;
  }
  if ((*p == 'T' || *p == 'R') && (is_end(p[1]) || is_blank(p[1]))) {
    p++;
    while (is_blank(*p)) {
      p++;
    }
  }
  if (!is_end(*p)) {
    *why = "unexpected text after the frame (expected the end of the line or a direction flag T/R)";
    return -1;
  }
  *out = l;
  return 1;
}
