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
 * @file nps_host_ranging_replay.h
 * Feed a can-utils `candump -l` log of the ranging units to the copters of the host instead of simulated
 * ranging (`--ranging-replay`). Each copter decodes the bus with the same pure logic as the Linux driver
 * (ranging_can_rx.h: frame validation, duplicates, sequence gaps, error frames) and the distances about it reach
 * its virtual_ranging module (virtual_ranging_report) at their logged time, counted from the log's first frame.
 * Copter v listens as CAN node v + 1 (its aircraft id). The bus is the interface of the log's first frame;
 * frames logged on other interfaces are skipped. Every delivered distance is written to
 * ranging_replay.csv (t, vehicle, peer, distance).
 */

#ifndef NPS_HOST_RANGING_REPLAY_H
#define NPS_HOST_RANGING_REPLAY_H

/** Open the log and the output; -1 with a message on stderr (missing file, no virtual_ranging module, ...). */
extern int nps_host_ranging_replay_open(const char *log_path, const char *out_file, unsigned vehicles);
/** Deliver the frames logged up to t_s after the first one; -1 with "file:line: reason" on a malformed line. */
extern int nps_host_ranging_replay_step(double t_s);
/** The output's path when a write to it failed, NULL while every write succeeded. */
extern const char *nps_host_ranging_replay_write_error(void);
/** Close; prints what was replayed; -1 (message on stderr) when the output could not be written. */
extern int nps_host_ranging_replay_close(void);

#endif /* NPS_HOST_RANGING_REPLAY_H */
