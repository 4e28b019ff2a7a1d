/*
 * nps_world_link over POSIX shared memory: what one aircraft publishes another reads whole, waiting sleeps until the
 * others have caught up, and a world refuses or reclaims as its processes live or not. Processes are forked.
 */
#include "test_helpers.h"
#include "nps_world_link.h"
#include "nps_world_shm_layout.h"

#include <fcntl.h>
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

static struct nps_world_link *join(unsigned ac_id, const char *run)
{
  struct nps_world_link *link;
  char err[512];
  const struct nps_world_link_config cfg = config(ac_id, run);
  if (nps_world_link_join(&cfg, &link, err, sizeof(err)) < 0) {
    print_error("join %u: %s\n", ac_id, err);
    fail();
  }
  return link;
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
  assert_int_equal(nps_world_link_peers(a, peers, 4), 0);   /* b has published nothing yet */
  for (int k = 0; k < 100; k++) {   /* more than the ring holds: the newest are kept, oldest first */
    const struct nps_world_ping ping = { 0.002 * k + 0.001, (unsigned)k % 5 };
    const struct nps_world_sample s = sample_at(0.002 * k);
    nps_world_link_publish(b, &s, &ping, 1, true);
  }
  assert_int_equal(nps_world_link_peers(a, peers, 4), 1);
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
  assert_int_equal(nps_world_link_peers(a, peers, 4), 0);
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
  nps_world_link_peers(a, peers, 4);
  nps_world_link_peers(b, peers, 4);
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
  nps_world_link_peers(b, peers, 4);
  assert_true(nps_world_link_owns_walls(b));   /* handed over */
  nps_world_link_leave(b);
}

static double monotonic_s(void)
{
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void waiting_sleeps_until_the_other_has_caught_up(void **state)
{
  (void)state;
  struct nps_world_link *a = join(1, "");
  const pid_t child = fork();
  if (child == 0) {   /* aircraft 2: 1 ms of simulated time every 2 ms of wall clock, up to 0.1 s */
    struct nps_world_link *b = join(2, "");
    for (int k = 0; k <= 100; k++) {
      const struct nps_world_sample s = sample_at(0.001 * k);
      nps_world_link_publish(b, &s, NULL, 0, false);
      usleep(2000);
    }
    _exit(0);
  }
  struct nps_world_peer peers[4];
  const double start_s = monotonic_s();
  while (nps_world_link_peers(a, peers, 4) == 0 && monotonic_s() - start_s < 5.0) {
    usleep(1000);
  }
  const clock_t cpu_start = clock();
  nps_world_link_wait(a, 0.08);
  const double waited_s = monotonic_s() - start_s;
  const double cpu_s = (double)(clock() - cpu_start) / CLOCKS_PER_SEC;
  assert_int_equal(nps_world_link_peers(a, peers, 4), 1);
  assert_true(peers[0].samples[peers[0].n_samples - 1].t_s >= 0.08);
  assert_true(waited_s >= 0.1);        /* 80 samples at 2 ms */
  assert_true(cpu_s < 0.5 * waited_s); /* asleep, not spinning */
  int status;
  waitpid(child, &status, 0);
  assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  nps_world_link_wait(a, 10.0);        /* it left (exit without leave): no wait for it */
  nps_world_link_leave(a);
}

static void a_killed_process_leaves_the_world(void **state)
{
  (void)state;
  struct nps_world_link *a = join(1, "");
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
  assert_int_equal(nps_world_link_peers(a, peers, 4), 1);
  kill(child, SIGKILL);
  waitpid(child, NULL, 0);
  const double start_s = monotonic_s();
  nps_world_link_wait(a, 1.0);   /* does not wait for a dead process: found within ~50 ms, not the 2 s timeout */
  assert_true(monotonic_s() - start_s < 1.0);
  assert_int_equal(nps_world_link_peers(a, peers, 4), 0);
  assert_non_null(strstr(nps_world_link_news(a), "aircraft 2 left"));
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
  assert_int_equal(nps_world_link_peers(a, peers, 4), 1);
  struct nps_world_shm *w = map_segment();
  w->slot[2].lock.seq |= 1u;   /* a writer that died in the middle of a write */
  assert_int_equal(nps_world_link_peers(a, peers, 4), 0);
  assert_non_null(strstr(nps_world_link_news(a), "could not be read"));
  w->slot[2].lock.seq += 1u;   /* consistent again, but the only sample flies off */
  w->slot[2].samples[0].pos_m[1] = 1e300;
  assert_int_equal(nps_world_link_peers(a, peers, 4), 0);
  const struct nps_world_sample good = sample_at(0.6);
  nps_world_link_publish(b, &good, NULL, 0, false);
  assert_int_equal(nps_world_link_peers(a, peers, 4), 1);
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
