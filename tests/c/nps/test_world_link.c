/*
 * nps_world_link over POSIX shared memory: what one aircraft publishes another reads whole, waiting sleeps until the
 * others have caught up, and a world refuses or reclaims as its processes live or not. Processes are forked; a waiter
 * whose sleeps a test counts (nps_world_link_sleeps) is a thread. Nothing checked depends on the wall clock.
 */
#include "test_helpers.h"
#include "nps_world_link.h"
#include "nps_world_shm_layout.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char world_name[64];

static struct nps_world_link_config config(unsigned ac_id, const char *run)
{
  return (struct nps_world_link_config) {
    .name = world_name, .run = run, .ac_id = ac_id, .time_factor = 1.0, .local_time_s = 0.0, .arena_id = 42,
    .plates = 80, .peer_timeout_s = 2.0,
  };
}

static struct nps_world_link *join_as(struct nps_world_link_config cfg)
{
  struct nps_world_link *link;
  char err[512];
  if (nps_world_link_join(&cfg, &link, err, sizeof(err)) < 0) {
    print_error("join %u: %s\n", cfg.ac_id, err);
    fail();
  }
  return link;
}

static struct nps_world_link *join(unsigned ac_id, const char *run)
{
  return join_as(config(ac_id, run));
}

/**
 * Aircraft ac_id that takes a silent peer for gone only after 60 s: in the tests of waiting, no delay of a loaded
 * machine makes a peer time out, so what they check never depends on the wall clock.
 */
static struct nps_world_link *join_patient(unsigned ac_id)
{
  struct nps_world_link_config cfg = config(ac_id, "");
  cfg.peer_timeout_s = 60.0;
  return join_as(cfg);
}

/** The reason a join is refused ("" when it is not). */
static const char *refusal(struct nps_world_link_config cfg)
{
  static char err[512];
  struct nps_world_link *link;
  err[0] = '\0';
  if (nps_world_link_join(&cfg, &link, err, sizeof(err)) == 0) {
    nps_world_link_leave(link);
  }
  return err;
}

static int setup(void **state)
{
  (void)state;
  snprintf(world_name, sizeof(world_name), "test_world_link.%d.%ld", (int)getpid(), random());
  return 0;
}

static struct nps_world_sample sample_at(double t)
{
  return (struct nps_world_sample) { t, { 1.0 + t, 2.0, 0.6 }, 0.5, 0.3 };
}

static void what_one_aircraft_publishes_another_reads(void **state)
{
  (void)state;
  struct nps_world_link *a = join(1, ""), *b = join(2, "");
  assert_true(nps_world_link_created(a));
  assert_false(nps_world_link_created(b));
  struct nps_world_peer peers[4];
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 0);   /* b has published nothing yet */
  for (int k = 0; k < 100; k++) {   /* more than the ring holds: the newest are kept, oldest first */
    const struct nps_world_ping ping = { 0.002 * k + 0.001, (unsigned)k % 5 };
    const struct nps_world_sample s = sample_at(0.002 * k);
    nps_world_link_publish(b, &s, &ping, 1, true);
  }
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 1);
  assert_int_equal(peers[0].ac_id, 2);
  assert_true(peers[0].ranging_equipped);
  assert_int_equal(peers[0].n_samples, NPS_WORLD_SAMPLES);
  assert_close(peers[0].samples[NPS_WORLD_SAMPLES - 1].t_s, 0.198, 1e-12);
  assert_close(peers[0].samples[0].t_s, 0.002 * (100 - NPS_WORLD_SAMPLES), 1e-12);
  assert_close(peers[0].samples[NPS_WORLD_SAMPLES - 1].pos_m[0], 1.198, 1e-12);
  assert_int_equal(peers[0].n_pings, NPS_WORLD_PINGS);
  assert_int_equal(peers[0].pings[NPS_WORLD_PINGS - 1].sonar, 99 % 5);
  const char *news = nps_world_link_news(a);
  assert_non_null(news);
  assert_non_null(strstr(news, "aircraft 2 joined"));
  assert_null(nps_world_link_news(a));
  nps_world_link_leave(b);
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 0);
  assert_non_null(strstr(nps_world_link_news(a), "aircraft 2 left"));
  nps_world_link_leave(a);
  char path[128];
  snprintf(path, sizeof(path), "/dev/shm/finken_world.%s", world_name);
  assert_int_equal(access(path, F_OK), -1);   /* the last one out removed it */
}

static void the_lowest_id_present_owns_the_walls(void **state)
{
  (void)state;
  struct nps_world_link *a = join(3, ""), *b = join(5, "");
  const struct nps_world_sample s = sample_at(1.0);
  nps_world_link_publish(a, &s, NULL, 0, false);
  nps_world_link_publish(b, &s, NULL, 0, false);
  struct nps_world_peer peers[4];
  nps_world_link_peers(a, peers, 4, -INFINITY);
  nps_world_link_peers(b, peers, 4, -INFINITY);
  assert_true(nps_world_link_owns_walls(a));
  assert_false(nps_world_link_owns_walls(b));
  static struct nps_world_walls walls, read;
  assert_int_equal(nps_world_link_read_walls(b, &read), -1);   /* nothing published yet */
  walls.t_s = 1.0;
  walls.n = 80;
  walls.angle_rad[7] = 0.3;
  walls.rate_rad_s[7] = -0.1;
  walls.integral_deg_s[7] = 2.0;
  nps_world_link_publish_walls(a, &walls);
  assert_int_equal(nps_world_link_read_walls(b, &read), 0);
  assert_int_equal(read.owner_id, 3);
  assert_close(read.angle_rad[7], 0.3, 0.0);
  assert_close(read.integral_deg_s[7], 2.0, 0.0);
  walls.angle_rad[8] = 4.0;   /* beyond the hinge's quarter turn: not a state */
  nps_world_link_publish_walls(a, &walls);
  assert_int_equal(nps_world_link_read_walls(b, &read), -1);
  nps_world_link_leave(a);
  nps_world_link_peers(b, peers, 4, -INFINITY);
  assert_true(nps_world_link_owns_walls(b));   /* handed over */
  nps_world_link_leave(b);
}

/** A thread in nps_world_link_wait(link, t_s), which the test watches sleep. */
struct waiter {
  struct nps_world_link *link;
  double t_s;
  pthread_t thread;
  bool returned;   ///< set (atomically) when the wait has returned
};

static void *wait_in_thread(void *arg)
{
  struct waiter *w = arg;
  nps_world_link_wait(w->link, w->t_s);
  __atomic_store_n(&w->returned, true, __ATOMIC_RELEASE);
  return NULL;
}

/**
 * Whether the waiter, still in its wait, has slept in the kernel at least n times in all: looked at every ms, for up
 * to 10 s (only a failing test takes that long). A waiter that spins never gets there.
 */
static bool still_waiting_after_sleeps(struct waiter *w, uint64_t n)
{
  for (int ms = 0; ms < 10000 && !__atomic_load_n(&w->returned, __ATOMIC_ACQUIRE); ms++) {
    if (nps_world_link_sleeps(w->link) >= n) {
      return !__atomic_load_n(&w->returned, __ATOMIC_ACQUIRE);
    }
    usleep(1000);
  }
  return false;
}

static void waiting_sleeps_until_the_other_has_caught_up(void **state)
{
  (void)state;
  struct nps_world_link *a = join_patient(1), *b = join(2, "");
  const struct nps_world_sample behind = sample_at(0.0), short_of_it = sample_at(0.079), there = sample_at(0.08);
  nps_world_link_publish(b, &behind, NULL, 0, false);
  struct waiter w = { .link = a, .t_s = 0.08 };
  assert_int_equal(pthread_create(&w.thread, NULL, wait_in_thread, &w), 0);
  /* b is behind: a waits, asleep on the futex (a and b map the segment apart: the wake-up crosses mappings as it
   * crosses processes) */
  const bool slept = still_waiting_after_sleeps(&w, 1);
  /* a sample short of 0.08 wakes it and it sleeps on: the second sleep counted from here began after the sample */
  nps_world_link_publish(b, &short_of_it, NULL, 0, false);
  const bool slept_on = slept && still_waiting_after_sleeps(&w, nps_world_link_sleeps(a) + 2);
  nps_world_link_publish(b, &there, NULL, 0, false);   /* b has caught up: the wait returns */
  assert_int_equal(pthread_join(w.thread, NULL), 0);   /* first, so that no failed check leaves the thread behind */
  assert_true(slept);
  assert_true(slept_on);
  struct nps_world_peer peers[4];
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 1);
  assert_close(peers[0].samples[peers[0].n_samples - 1].t_s, 0.08, 0.0);
  const uint64_t sleeps = nps_world_link_sleeps(a);
  nps_world_link_leave(b);
  nps_world_link_wait(a, 10.0);   /* b left: no wait for it, not one sleep */
  assert_int_equal(nps_world_link_sleeps(a), sleeps);
  nps_world_link_leave(a);
}

static void a_killed_process_leaves_the_world(void **state)
{
  (void)state;
  struct nps_world_link *a = join_patient(1);
  int ready[2];
  assert_int_equal(pipe(ready), 0);
  const pid_t child = fork();
  if (child == 0) {
    struct nps_world_link *b = join(2, "");
    const struct nps_world_sample s = sample_at(0.0);
    nps_world_link_publish(b, &s, NULL, 0, false);
    assert_int_equal(write(ready[1], "x", 1), 1);
    pause();
  }
  char c;
  assert_int_equal(read(ready[0], &c, 1), 1);
  struct nps_world_peer peers[4];
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 1);
  kill(child, SIGKILL);
  waitpid(child, NULL, 0);
  nps_world_link_wait(a, 1.0);   /* does not wait for a dead process: its process is looked at, not the timeout */
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 0);
  const char *news = nps_world_link_news(a);
  assert_non_null(strstr(news, "aircraft 2 left"));
  assert_non_null(strstr(news, "(its process ended)"));   /* found out, not timed out (a waits 60 s for news) */
  close(ready[0]);
  close(ready[1]);
  nps_world_link_leave(a);
}

static void a_live_world_refuses_another_run_the_same_id_or_another_arena(void **state)
{
  (void)state;
  struct nps_world_link *a = join(1, "run-A");
  assert_non_null(strstr(refusal(config(2, "run-B")), "in use by another run"));
  assert_non_null(strstr(refusal(config(1, "run-A")), "aircraft 1 already flies"));
  struct nps_world_link_config other = config(2, "run-A");
  other.arena_id = 43;
  assert_non_null(strstr(refusal(other), "another arena"));
  other = config(2, "run-A");
  other.time_factor = 10.0;
  assert_non_null(strstr(refusal(other), "time factor"));
  assert_string_equal(refusal(config(2, "run-A")), "");
  other = config(0, "run-A");
  assert_non_null(strstr(refusal(other), "outside 1..64"));
  nps_world_link_leave(a);
}

static void a_stale_world_is_reclaimed(void **state)
{
  (void)state;
  const pid_t child = fork();
  if (child == 0) {   /* joins and crashes without leaving */
    join(1, "crashed-run");
    _exit(3);
  }
  waitpid(child, NULL, 0);
  struct nps_world_link *a = join(2, "new-run");   /* another run, but nobody lives there */
  assert_true(nps_world_link_created(a));
  assert_non_null(strstr(nps_world_link_news(a), "reclaimed"));
  nps_world_link_leave(a);
}

/** The segment of world_name mapped (for damaging it). */
static struct nps_world_shm *map_segment(void)
{
  char name[128];
  snprintf(name, sizeof(name), "/finken_world.%s", world_name);
  const int fd = shm_open(name, O_RDWR, 0600);
  assert_true(fd >= 0);
  struct nps_world_shm *w = mmap(NULL, sizeof(*w), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  close(fd);
  assert_true(w != MAP_FAILED);
  return w;
}

static void torn_or_implausible_data_is_never_used(void **state)
{
  (void)state;
  struct nps_world_link *a = join(1, ""), *b = join(2, "");
  const struct nps_world_sample s = sample_at(0.5);
  nps_world_link_publish(b, &s, NULL, 0, false);
  struct nps_world_peer peers[4];
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 1);
  struct nps_world_shm *w = map_segment();
  w->slot[2].lock.seq |= 1u;   /* a writer that died in the middle of a write */
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 0);
  assert_non_null(strstr(nps_world_link_news(a), "could not be read"));
  w->slot[2].lock.seq += 1u;   /* consistent again, but the only sample flies off */
  w->slot[2].samples[0].pos_m[1] = 1e300;
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 0);
  const struct nps_world_sample good = sample_at(0.6);
  nps_world_link_publish(b, &good, NULL, 0, false);
  assert_int_equal(nps_world_link_peers(a, peers, 4, -INFINITY), 1);
  assert_int_equal(peers[0].n_samples, 1);   /* the bad one dropped */
  munmap(w, sizeof(*w));
  nps_world_link_leave(b);
  nps_world_link_leave(a);
}

int main(void)
{
  srandom((unsigned)time(NULL));
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup(what_one_aircraft_publishes_another_reads, setup),
    cmocka_unit_test_setup(the_lowest_id_present_owns_the_walls, setup),
    cmocka_unit_test_setup(waiting_sleeps_until_the_other_has_caught_up, setup),
    cmocka_unit_test_setup(a_killed_process_leaves_the_world, setup),
    cmocka_unit_test_setup(a_live_world_refuses_another_run_the_same_id_or_another_arena, setup),
    cmocka_unit_test_setup(a_stale_world_is_reclaimed, setup),
    cmocka_unit_test_setup(torn_or_implausible_data_is_never_used, setup),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
