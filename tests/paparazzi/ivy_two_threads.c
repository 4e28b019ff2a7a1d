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
 * @file tests/paparazzi/ivy_two_threads.c
 * Reproducer of the crash of several Paparazzi NPS processes on one Ivy bus (docs/paparazzi.md, "One Ivy bus per
 * aircraft"). Paparazzi's nps_ivy.c runs IvyMainLoop in a thread of its own and calls IvySendMsg, IvyBindMsg and
 * IvyUnbindMsg from the display thread, under a mutex that only the display thread takes; ivy-c is not
 * thread-safe. Each NPS process unbinds and binds again its WORLD_ENV reply at every request: the other processes'
 * Ivy threads then free that regexp (IvyBindingFree) while their display threads may be running it (IvySendMsg ->
 * IvyBindingExec -> pcre_exec): a use after free.
 *
 * This program does what nps_ivy.c does, faster: `ivy_two_threads BUS SECONDS threads` sends from a second thread
 * under its own mutex, as NPS; `... loop` does the same from a timer of the Ivy loop, one thread only (the control:
 * it never crashes). Run several on one bus (tools/finken/paparazzi/ivy_race.py, `make paparazzi-ivy-race`).
 */

#include <Ivy/ivy.h>
#include <Ivy/ivyloop.h>
#include <Ivy/timer.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/** Requests a second: NPS requests WORLD_ENV every NPS_WORLD_ENV_UPDATE; here every millisecond, to crash sooner. */
#define REQUEST_PERIOD_MS 1

static MsgRcvPtr reply;
static long requests;
static long requests_left;

static void on_world_env(IvyClientPtr app, void *user_data, int argc, char **argv)
{
  (void)app; (void)user_data; (void)argc; (void)argv;
}

/** What nps_ivy_send_WORLD_ENV_REQ does, then one display message, as nps_ivy_display. */
static void request(void)
{
  const int pid = (int)getpid();
  if (reply != NULL) {
    IvyUnbindMsg(reply);
  }
  reply = IvyBindMsg(on_world_env, NULL, "^%d_%ld (\\S*) WORLD_ENV (\\S*) (\\S*) (\\S*)", pid, requests);
  IvySendMsg("nps %d_%ld WORLD_ENV_REQ 43.5 1.3 150 0 0 0", pid, requests);
  IvySendMsg("%d NPS_POS_LLH 43.5 1.3 150 0 0 0 0 0 0", pid);
  requests++;
}

static void *ivy_thread(void *arg)
{
  (void)arg;
  IvyMainLoop();
  return NULL;
}

static void on_timer(TimerId id, void *user_data, unsigned long delta)
{
  (void)id; (void)user_data; (void)delta;
  request();
  if (--requests_left <= 0) {
    IvyStop();
  }
}

int main(int argc, char **argv)
{
  if (argc != 4 || (strcmp(argv[3], "threads") != 0 && strcmp(argv[3], "loop") != 0)) {
    fprintf(stderr, "usage: %s BUS SECONDS threads|loop\n", argv[0]);
    return 2;
  }
  requests_left = (long)(atof(argv[2]) * 1000 / REQUEST_PERIOD_MS);
  char name[64];
  snprintf(name, sizeof(name), "ivy_two_threads_%d", (int)getpid());
  IvyInit(name, NULL, NULL, NULL, NULL, NULL);
  IvyBindMsg(on_world_env, NULL, "^(\\S*) WORLD_ENV (\\S*) (\\S*) (\\S*)");
  IvyStart(argv[1]);
  if (strcmp(argv[3], "loop") == 0) {
    TimerRepeatAfter(TIMER_LOOP, REQUEST_PERIOD_MS, on_timer, NULL);
    IvyMainLoop();
    return 0;
  }
  pthread_t thread;
  pthread_mutex_t send_mutex = PTHREAD_MUTEX_INITIALIZER;   /* nps_ivy.c's ivy_mutex: the sending side only */
  pthread_create(&thread, NULL, ivy_thread, NULL);
  for (; requests_left > 0; requests_left--) {
    pthread_mutex_lock(&send_mutex);
    request();
    pthread_mutex_unlock(&send_mutex);
    usleep(REQUEST_PERIOD_MS * 1000);
  }
  return 0;
}
