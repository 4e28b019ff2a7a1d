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
 * @file nps_world_link_shm.c
 * nps_world_link.h over POSIX shared memory: the world "NAME" is the segment /finken_world.NAME (/dev/shm).
 *
 * Layout: a header (who made it: version, run, arena, time base) and one slot per aircraft id. Each slot and the
 * walls' state have one writer and are guarded by a sequence lock: the writer makes the counter odd, writes, makes
 * it even; a reader copies and keeps the copy only if the counter was even and unchanged around it. Readers never
 * block the writer, and a copy is never torn. A process waiting for the others to reach a world time sleeps on a
 * futex of its own slot, and the one whose sample completes the wait wakes it: one wake-up per wait, not one per
 * peer that publishes (with N processes on fewer cores, waking every waiter at every sample made the wake-ups
 * grow as N^2).
 * Joining and leaving hold an flock on the segment, so that two processes never both create or claim.
 */

#include "nps_world_link.h"
#include "nps_world_peer.h"
#include "nps_world_shm_layout.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <linux/futex.h>
#include <math.h>
#include <sched.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

/** Copy attempts of a slot being written before the reader gives up for this step. */
#define READ_ATTEMPTS 64
/** Longest sleep of a waiting reader before it looks at the peers' processes again [ns]. */
#define WAIT_SLICE_NS 5000000L
/** A peer silent this long (wall clock) has its process checked [ns]. */
#define CHECK_PROCESS_AFTER_NS 50000000L

struct nps_world_link {
  struct nps_world_shm *world;
  int fd;
  char shm_name[NAME_MAX];
  char world_name[NAME_MAX];
  unsigned ac_id;
  double offset_s;
  double peer_timeout_s;
  bool created;
  bool present[NPS_WORLD_MAX_AIRCRAFT + 1];   ///< peers as this process last saw them (for the news)
  char news[4096];
  uint64_t sleeps;   ///< futex waits of nps_world_link_wait that slept (atomic: a test reads it from another thread)
};

/* ---------------------------------------------------------------- clocks, processes, futexes */

static uint64_t monotonic_ns(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static bool process_alive(int32_t pid)
{
  return pid > 0 && (kill(pid, 0) == 0 || errno == EPERM);
}

/** Sleep while *word == expected, at most timeout_ns; whether it slept (false: *word had already changed). */
static bool futex_wait(uint32_t *word, uint32_t expected, long timeout_ns)
{
  const struct timespec timeout = { 0, timeout_ns };
  return syscall(SYS_futex, word, FUTEX_WAIT, expected, &timeout, NULL, 0) == 0 || errno == ETIMEDOUT ||
         errno == EINTR;   /* woken, timed out or interrupted: it was asleep in the kernel */
}

static void futex_wake_one(uint32_t *word)
{
  syscall(SYS_futex, word, FUTEX_WAKE, 1, NULL, NULL, 0);
}

/**
 * A double shared outside the sequence lock (a slot's newest time, the time its process waits for), read and written
 * sequentially consistent: a waiter announces its time and then reads the others' times, a publisher writes its time
 * and then reads the announcements; in a single total order one of the two sees the other's write (no lost wake-up).
 */
static double load_shared(const double *p)
{
  double v;
  __atomic_load(p, &v, __ATOMIC_SEQ_CST);
  return v;
}

static void store_shared(double *p, double v)
{
  __atomic_store(p, &v, __ATOMIC_SEQ_CST);
}

/**
 * Wake every process whose wait is complete: all the others present have published up to the time it waits for.
 * The others' earliest time is the earliest of all but when the waiter itself is the earliest (then the second
 * earliest): one pass over the slots for the two earliest, one for the waiters.
 */
static void wake_completed_waits(struct nps_world_shm *w)
{
  double first = INFINITY, second = INFINITY;
  unsigned first_id = 0;
  for (unsigned id = 1; id <= NPS_WORLD_MAX_AIRCRAFT; id++) {
    const struct nps_world_shm_slot *s = &w->slot[id];
    if (__atomic_load_n(&s->pid, __ATOMIC_ACQUIRE) == 0) {
      continue;
    }
    const double t = load_shared(&s->time_s);
    if (t < first) {
      second = first, first = t, first_id = id;
    } else if (t < second) {
      second = t;
    }
  }
  for (unsigned id = 1; id <= NPS_WORLD_MAX_AIRCRAFT; id++) {
    struct nps_world_shm_slot *s = &w->slot[id];
    double waits_for = load_shared(&s->waiting_for_s);
    double done = INFINITY;
    /* woken once: only the process that takes the announcement back wakes it (a newer one stays) */
    if (waits_for <= (id == first_id ? second : first) &&
        __atomic_compare_exchange(&s->waiting_for_s, &waits_for, &done, false, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) {
      __atomic_add_fetch(&s->wake, 1, __ATOMIC_SEQ_CST);
      futex_wake_one(&s->wake);
    }
  }
}

/* ---------------------------------------------------------------- sequence lock */

static uint32_t write_begin(struct nps_world_seqlock *l)
{
  const uint32_t seq = __atomic_load_n(&l->seq, __ATOMIC_RELAXED) + 1;
  __atomic_store_n(&l->seq, seq, __ATOMIC_RELAXED);
  __atomic_thread_fence(__ATOMIC_RELEASE);
  return seq;
}

static void write_end(struct nps_world_seqlock *l, uint32_t seq)
{
  __atomic_store_n(&l->seq, seq + 1, __ATOMIC_RELEASE);
}

/**
 * Run copy(ctx), which copies data guarded by l, until a run saw no write under way (the counter even before and
 * unchanged after it); false when none did in READ_ATTEMPTS.
 */
static bool read_consistently(const struct nps_world_seqlock *l, void (*copy)(void *ctx), void *ctx)
{
  for (int attempt = 0; attempt < READ_ATTEMPTS; attempt++) {
    const uint32_t before = __atomic_load_n(&l->seq, __ATOMIC_ACQUIRE);
    if ((before & 1u) == 0) {
      copy(ctx);
      __atomic_thread_fence(__ATOMIC_ACQUIRE);
      if (__atomic_load_n(&l->seq, __ATOMIC_RELAXED) == before) {
        return true;
      }
    }
    sched_yield();   /* the writer is in the middle of it: let it finish */
  }
  return false;
}
/* ---------------------------------------------------------------- joining */

static int refuse(char *err, size_t err_len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int refuse(char *err, size_t err_len, const char *fmt, ...)
{
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(err, err_len, fmt, ap);
  va_end(ap);
  return -1;
}

/** The live aircraft of a world, "1 (process 123), 2 (process 124)", in buf; how many. */
static int live_aircraft(const struct nps_world_shm *w, char *buf, size_t len)
{
  int n = 0;
  size_t used = 0;
  buf[0] = '\0';
  for (unsigned id = 1; id <= NPS_WORLD_MAX_AIRCRAFT; id++) {
    if (process_alive(w->slot[id].pid)) {
      if (used < len) {
        used += (size_t)snprintf(buf + used, len - used, "%s%u (process %d)", n > 0 ? ", " : "", id,
                                 (int)w->slot[id].pid);
      }
      n++;
    }
  }
  return n;
}

/** Whether the segment holds a world of this layout. */
static bool layout_matches(const struct nps_world_shm *w)
{
  return w->magic == NPS_WORLD_SHM_MAGIC && w->version == NPS_WORLD_SHM_VERSION && w->size == sizeof(struct nps_world_shm);
}

static void world_create(struct nps_world_shm *w, const struct nps_world_link_config *cfg)
{
  memset(w, 0, sizeof(*w));
  w->version = NPS_WORLD_SHM_VERSION;
  w->size = sizeof(*w);
  w->creator_pid = (int32_t)getpid();
  snprintf(w->run, sizeof(w->run), "%s", cfg->run != NULL ? cfg->run : "");
  w->epoch_ns = monotonic_ns();
  w->time_factor = cfg->time_factor;
  w->arena_id = cfg->arena_id;
  w->plates = cfg->plates;
  __atomic_store_n(&w->magic, NPS_WORLD_SHM_MAGIC, __ATOMIC_RELEASE);
}

/** Check a live world against this process; 0 when it may join. */
static int check_compatible(const struct nps_world_shm *w, const struct nps_world_link_config *cfg, const char *live,
                            char *err, size_t err_len)
{
  const char *run = cfg->run != NULL ? cfg->run : "";
  if (strcmp(w->run, run) != 0) {
    return refuse(err, err_len, "world \"%s\" is in use by another run (\"%s\"; aircraft %s): stop it, or give this "
                  "run another world name (FINKEN_WORLD)", cfg->name, w->run, live);
  }
  if (w->arena_id != cfg->arena_id || w->plates != cfg->plates) {
    return refuse(err, err_len, "world \"%s\" (aircraft %s) has another arena (%u plates, id %llx; this one %u "
                  "plates, id %llx): every aircraft of a world needs the same FINKEN_WORLD_ARENA", cfg->name, live,
                  w->plates, (unsigned long long)w->arena_id, cfg->plates, (unsigned long long)cfg->arena_id);
  }
  if (w->time_factor != cfg->time_factor) {
    return refuse(err, err_len, "world \"%s\" (aircraft %s) runs at time factor %g, this process at %g: start "
                  "every aircraft with the same --time_factor", cfg->name, live, w->time_factor, cfg->time_factor);
  }
  if (process_alive(w->slot[cfg->ac_id].pid)) {
    return refuse(err, err_len, "aircraft %u already flies in world \"%s\" (process %d)", cfg->ac_id, cfg->name,
                  (int)w->slot[cfg->ac_id].pid);
  }
  return 0;
}

static void claim_slot(struct nps_world_link *link)
{
  struct nps_world_shm_slot *s = &link->world->slot[link->ac_id];
  const uint32_t seq = write_begin(&s->lock);
  s->pid = (int32_t)getpid();
  s->ranging_equipped = 0;
  s->sample_count = s->ping_count = 0;
  write_end(&s->lock, seq);
  store_shared(&s->time_s, -INFINITY);
  store_shared(&s->waiting_for_s, INFINITY);
  __atomic_store_n(&s->heartbeat_ns, monotonic_ns(), __ATOMIC_RELEASE);
}

/** Open, check, create or reclaim the segment, claim the slot; under the segment's flock. */
static int join_locked(struct nps_world_link *link, const struct nps_world_link_config *cfg, char *err, size_t err_len)
{
  struct stat st;
  if (fstat(link->fd, &st) < 0) {
    return refuse(err, err_len, "world \"%s\": /dev/shm%s: %s", cfg->name, link->shm_name, strerror(errno));
  }
  const bool sized = (size_t)st.st_size == sizeof(struct nps_world_shm);
  if (!sized && st.st_size != 0) {
    /* another layout: only its creator's pid is where ours is */
    int32_t creator = 0;
    if ((size_t)st.st_size >= offsetof(struct nps_world_shm, run) &&
        pread(link->fd, &creator, sizeof(creator), offsetof(struct nps_world_shm, creator_pid)) == sizeof(creator) &&
        process_alive(creator)) {
      return refuse(err, err_len, "world \"%s\" was made by another version of finken_world (process %d still "
                    "runs): stop it, or choose another world name (FINKEN_WORLD)", cfg->name, (int)creator);
    }
  }
  if (!sized && ftruncate(link->fd, sizeof(struct nps_world_shm)) < 0) {
    return refuse(err, err_len, "world \"%s\": cannot size /dev/shm%s: %s", cfg->name, link->shm_name,
                  strerror(errno));
  }
  void *map = mmap(NULL, sizeof(struct nps_world_shm), PROT_READ | PROT_WRITE, MAP_SHARED, link->fd, 0);
  if (map == MAP_FAILED) {
    return refuse(err, err_len, "world \"%s\": cannot map /dev/shm%s: %s", cfg->name, link->shm_name,
                  strerror(errno));
  }
  link->world = map;
  char live[1024];
  if (sized && layout_matches(link->world) && live_aircraft(link->world, live, sizeof(live)) > 0) {
    if (check_compatible(link->world, cfg, live, err, err_len) < 0) {
      return -1;
    }
  } else {   /* new, or stale: its processes are gone */
    link->created = true;
    if (sized && layout_matches(link->world)) {
      snprintf(link->news, sizeof(link->news), "reclaimed world \"%s\" of a run that ended (\"%s\")\n", cfg->name,
               link->world->run);
    }
    world_create(link->world, cfg);
  }
  claim_slot(link);
  const double world_now_s = (monotonic_ns() - link->world->epoch_ns) * 1e-9 * link->world->time_factor;
  link->offset_s = world_now_s - cfg->local_time_s;
  return 0;
}

int nps_world_link_join(const struct nps_world_link_config *cfg, struct nps_world_link **out, char *err,
                        size_t err_len)
{
  *out = NULL;
  if (cfg->ac_id < 1 || cfg->ac_id > NPS_WORLD_MAX_AIRCRAFT) {
    return refuse(err, err_len, "aircraft id %u is outside 1..%d, the ids a world holds", cfg->ac_id,
                  NPS_WORLD_MAX_AIRCRAFT);
  }
  if (cfg->plates > NPS_WORLD_MAX_PLATES) {
    return refuse(err, err_len, "the arena has %u plates, a shared world holds at most %d", cfg->plates,
                  NPS_WORLD_MAX_PLATES);
  }
  if (!(cfg->time_factor > 0.0) || !isfinite(cfg->time_factor)) {
    return refuse(err, err_len, "time factor %g is not a positive number", cfg->time_factor);
  }
  if (cfg->name[0] == '\0' || strchr(cfg->name, '/') != NULL || strlen(cfg->name) > 200) {
    return refuse(err, err_len, "world name \"%s\" must be 1 to 200 characters without '/'", cfg->name);
  }
  struct nps_world_link *link = calloc(1, sizeof(*link));
  if (link == NULL) {
    return refuse(err, err_len, "out of memory");
  }
  snprintf(link->shm_name, sizeof(link->shm_name), "/finken_world.%s", cfg->name);
  snprintf(link->world_name, sizeof(link->world_name), "%s", cfg->name);
  link->ac_id = cfg->ac_id;
  link->peer_timeout_s = cfg->peer_timeout_s;
  link->fd = shm_open(link->shm_name, O_RDWR | O_CREAT | O_CLOEXEC, 0600);
  if (link->fd < 0) {
    refuse(err, err_len, "world \"%s\": cannot open /dev/shm%s: %s", cfg->name, link->shm_name, strerror(errno));
    free(link);
    return -1;
  }
  flock(link->fd, LOCK_EX);
  const int rc = join_locked(link, cfg, err, err_len);
  flock(link->fd, LOCK_UN);
  if (rc < 0) {
    if (link->world != NULL) {
      munmap(link->world, sizeof(*link->world));
    }
    close(link->fd);
    free(link);
    return -1;
  }
  *out = link;
  return 0;
}

void nps_world_link_leave(struct nps_world_link *link)
{
  if (link == NULL) {
    return;
  }
  flock(link->fd, LOCK_EX);
  struct nps_world_shm_slot *s = &link->world->slot[link->ac_id];
  const uint32_t seq = write_begin(&s->lock);
  s->pid = 0;
  write_end(&s->lock, seq);
  store_shared(&s->time_s, INFINITY);   /* nobody waits for a copter that left */
  wake_completed_waits(link->world);
  char live[16];
  if (live_aircraft(link->world, live, sizeof(live)) == 0) {
    shm_unlink(link->shm_name);   /* the last one out */
  }
  flock(link->fd, LOCK_UN);
  munmap(link->world, sizeof(*link->world));
  close(link->fd);
  free(link);
}

double nps_world_link_offset_s(const struct nps_world_link *link)
{
  return link->offset_s;
}

bool nps_world_link_created(const struct nps_world_link *link)
{
  return link->created;
}

/* ---------------------------------------------------------------- exchange */

void nps_world_link_publish(struct nps_world_link *link, const struct nps_world_sample *sample,
                            const struct nps_world_ping *pings, unsigned n_pings, bool ranging_equipped)
{
  struct nps_world_shm_slot *s = &link->world->slot[link->ac_id];
  const uint32_t seq = write_begin(&s->lock);
  s->samples[s->sample_count % NPS_WORLD_SAMPLES] = *sample;
  s->sample_count++;
  for (unsigned i = 0; i < n_pings; i++) {
    s->pings[s->ping_count % NPS_WORLD_PINGS] = pings[i];
    s->ping_count++;
  }
  s->ranging_equipped = ranging_equipped;
  store_shared(&s->time_s, sample->t_s);
  __atomic_store_n(&s->heartbeat_ns, monotonic_ns(), __ATOMIC_RELAXED);
  write_end(&s->lock, seq);
  wake_completed_waits(link->world);
}

/** Why aircraft id is not (or no longer) in the world, NULL when it is: from its slot, without the lock. */
static const char *absence(const struct nps_world_link *link, unsigned id, uint64_t now_ns)
{
  const struct nps_world_shm_slot *s = &link->world->slot[id];
  const int32_t pid = __atomic_load_n(&s->pid, __ATOMIC_ACQUIRE);
  if (pid == 0) {
    return "left";
  }
  const uint64_t heartbeat_ns = __atomic_load_n(&s->heartbeat_ns, __ATOMIC_ACQUIRE);
  const uint64_t silent_ns = now_ns > heartbeat_ns ? now_ns - heartbeat_ns : 0;
  if (silent_ns > link->peer_timeout_s * 1e9) {
    return "no news within the timeout";
  }
  if (silent_ns > CHECK_PROCESS_AFTER_NS && !process_alive(pid)) {
    return "its process ended";
  }
  return NULL;
}

/** Whether every other aircraft present has published up to world time t_s (or is gone). */
static bool others_reached(const struct nps_world_link *link, double t_s)
{
  const uint64_t now_ns = monotonic_ns();
  for (unsigned id = 1; id <= NPS_WORLD_MAX_AIRCRAFT; id++) {
    const struct nps_world_shm_slot *s = &link->world->slot[id];
    if (id != link->ac_id && __atomic_load_n(&s->pid, __ATOMIC_ACQUIRE) != 0 && load_shared(&s->time_s) < t_s &&
        absence(link, id, now_ns) == NULL) {
      return false;
    }
  }
  return true;
}

void nps_world_link_wait(struct nps_world_link *link, double t_s)
{
  struct nps_world_shm_slot *own = &link->world->slot[link->ac_id];
  for (;;) {
    /* the wake word first, the wait announced, then the condition: a sample published after the check finds the
     * announcement and bumps the word, so the sleep below returns at once (no lost wake-up) */
    const uint32_t wake = __atomic_load_n(&own->wake, __ATOMIC_SEQ_CST);
    store_shared(&own->waiting_for_s, t_s);
    if (others_reached(link, t_s)) {
      break;
    }
    __atomic_store_n(&own->heartbeat_ns, monotonic_ns(), __ATOMIC_RELEASE);   /* alive while it waits */
    if (futex_wait(&own->wake, wake, WAIT_SLICE_NS)) {   /* the slice: a peer that died is seen on waking */
      __atomic_add_fetch(&link->sleeps, 1, __ATOMIC_RELAXED);
    }
  }
  store_shared(&own->waiting_for_s, INFINITY);
}

uint64_t nps_world_link_sleeps(const struct nps_world_link *link)
{
  return __atomic_load_n(&link->sleeps, __ATOMIC_RELAXED);
}

/**
 * What a reading at t_s needs of a peer's slot (nps_world_link_peers): its header, its samples from the newest back to
 * the newest at or before t_s (at least two), its pulses. A whole slot is some 3 kB: copied for every peer at every
 * step it made the exchange's cost grow with the swarm; a step needs two or three samples.
 */
struct peer_copy {
  const struct nps_world_shm_slot *slot;
  double t_s;
  struct nps_world_peer *peer;   ///< its samples newest first at the end of the array (oldest first once moved)
  int32_t pid;
};

static void copy_peer(void *ctx)
{
  struct peer_copy *c = ctx;
  const struct nps_world_shm_slot *s = c->slot;
  struct nps_world_peer *peer = c->peer;
  c->pid = s->pid;
  const uint32_t samples = s->sample_count, pings = s->ping_count;
  peer->ranging_equipped = s->ranging_equipped != 0;
  const unsigned kept = samples < NPS_WORLD_SAMPLES ? samples : NPS_WORLD_SAMPLES;
  unsigned n = 0;
  while (n < kept) {
    const struct nps_world_sample *sample = &s->samples[(samples - 1 - n) % NPS_WORLD_SAMPLES];
    peer->samples[NPS_WORLD_SAMPLES - 1 - n] = *sample;
    n++;
    if (n >= 2 && sample->t_s <= c->t_s) {
      break;
    }
  }
  peer->n_samples = n;
  peer->n_pings = pings < NPS_WORLD_PINGS ? pings : NPS_WORLD_PINGS;
  for (unsigned i = 0; i < peer->n_pings; i++) {
    peer->pings[i] = s->pings[(pings - peer->n_pings + i) % NPS_WORLD_PINGS];
  }
}

/** A consistent, sanitised copy of what a reading at t_s needs of aircraft id's slot; false when there is none. */
static bool read_peer(struct nps_world_link *link, unsigned id, struct nps_world_peer *peer, double t_s)
{
  struct peer_copy c = { .slot = &link->world->slot[id], .t_s = t_s, .peer = peer };
  if (!read_consistently(&c.slot->lock, copy_peer, &c) || c.pid == 0) {
    return false;
  }
  const unsigned n = peer->n_samples;
  memmove(peer->samples, peer->samples + NPS_WORLD_SAMPLES - n, n * sizeof(peer->samples[0]));
  peer->ac_id = id;
  nps_world_peer_sanitize(peer);
  return peer->n_samples > 0;
}

/** Add a line to the news. */
static void news(struct nps_world_link *link, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void news(struct nps_world_link *link, const char *fmt, ...)
{
  const size_t used = strlen(link->news);
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(link->news + used, sizeof(link->news) - used, fmt, ap);
  va_end(ap);
}

unsigned nps_world_link_peers(struct nps_world_link *link, struct nps_world_peer *peers, unsigned max, double t_s)
{
  const uint64_t now_ns = monotonic_ns();
  unsigned n = 0;
  for (unsigned id = 1; id <= NPS_WORLD_MAX_AIRCRAFT; id++) {
    if (id == link->ac_id) {
      continue;
    }
    const char *why_absent = absence(link, id, now_ns);
    const bool present = why_absent == NULL && n < max && read_peer(link, id, &peers[n], t_s);
    if (present != link->present[id]) {
      if (present) {
        news(link, "aircraft %u joined world \"%s\"\n", id, link->world_name);
      } else {
        news(link, "aircraft %u left world \"%s\" (%s)\n", id, link->world_name,
             why_absent != NULL ? why_absent : "its shared data could not be read");
      }
      link->present[id] = present;
    }
    n += present;
  }
  return n;
}

bool nps_world_link_owns_walls(struct nps_world_link *link)
{
  for (unsigned id = 1; id < link->ac_id; id++) {
    if (link->present[id]) {
      return false;
    }
  }
  return true;
}

void nps_world_link_publish_walls(struct nps_world_link *link, const struct nps_world_walls *walls)
{
  struct nps_world_shm *w = link->world;
  const uint32_t seq = write_begin(&w->walls_lock);
  w->walls.t_s = walls->t_s;
  w->walls.owner_id = link->ac_id;
  w->walls.n = walls->n;
  memcpy(w->walls.angle_rad, walls->angle_rad, walls->n * sizeof(double));
  memcpy(w->walls.rate_rad_s, walls->rate_rad_s, walls->n * sizeof(double));
  memcpy(w->walls.integral_deg_s, walls->integral_deg_s, walls->n * sizeof(double));
  w->walls_published = 1;
  write_end(&w->walls_lock, seq);
}

struct walls_copy {
  struct nps_world_walls *dst;
  const struct nps_world_walls *src;
};

static void copy_walls(void *ctx)
{
  const struct walls_copy *c = ctx;
  *c->dst = *c->src;
}

int nps_world_link_read_walls(struct nps_world_link *link, struct nps_world_walls *walls)
{
  const struct nps_world_shm *w = link->world;
  if (!__atomic_load_n(&w->walls_published, __ATOMIC_ACQUIRE) ||
      !read_consistently(&w->walls_lock, copy_walls, &(struct walls_copy) { walls, &w->walls }) ||
      walls->n != w->plates) {
    return -1;
  }
  for (unsigned i = 0; i < walls->n; i++) {   /* a hinge angle is within [0, pi/2] */
    if (!(walls->angle_rad[i] >= 0.0 && walls->angle_rad[i] <= M_PI / 2) || !isfinite(walls->rate_rad_s[i]) ||
        !isfinite(walls->integral_deg_s[i])) {
      return -1;
    }
  }
  return isfinite(walls->t_s) ? 0 : -1;
}

const char *nps_world_link_news(struct nps_world_link *link)
{
  static char delivered[sizeof(link->news)];
  if (link->news[0] == '\0') {
    return NULL;
  }
  memcpy(delivered, link->news, sizeof(delivered));
  link->news[0] = '\0';
  return delivered;
}
