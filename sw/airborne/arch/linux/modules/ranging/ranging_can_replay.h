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
 * @file arch/linux/modules/ranging/ranging_can_replay.h
 * Replay a can-utils `candump -l` log into a descriptor, one struct can_frame / canfd_frame per message, as
 * a CAN socket would deliver them: the other end of a socketpair given to ranging_can_open_fd() then runs the
 * driver on recorded traffic (error frames, foreign ids and CAN FD frames included).
 *
 * Frames are written in log order up to a log time, so a caller can pace the replay (everything at once in a
 * test, in step with the simulated clock in a host). A full descriptor stops the writing without losing the
 * frame; the next call goes on from there.
 */

#ifndef RANGING_CAN_REPLAY_H
#define RANGING_CAN_REPLAY_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct ranging_can_replay;

/**
 * Open the log at path; its frames go to fd_out (not closed by ranging_can_replay_close()).
 * @param ifname replay only the frames logged on this interface (NULL: all)
 * @return the replay, or NULL with errno set and err naming the file
 */
extern struct ranging_can_replay *ranging_can_replay_open(const char *path, const char *ifname, int fd_out,
    char *err, size_t errlen);

/**
 * Write the frames logged up to until_us [us since the epoch, the log's clock] (UINT64_MAX: all).
 * @return 1 frames remain (later ones, or fd_out is full: read it and call again), 0 the log is done,
 *         -1 with err "path:line: what was wrong and what was expected" (malformed line) or errno (write failed)
 */
extern int ranging_can_replay_until(struct ranging_can_replay *r, uint64_t until_us, char *err, size_t errlen);

/** Frames written so far. */
extern uint32_t ranging_can_replay_count(const struct ranging_can_replay *r);

/** Close the log; NULL is a no-op. */
extern void ranging_can_replay_close(struct ranging_can_replay *r);

#ifdef __cplusplus
}
#endif

#endif /* RANGING_CAN_REPLAY_H */
