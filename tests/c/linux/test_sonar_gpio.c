/* Sonar GPIO driver (arch/linux/modules/sonar/sonar_gpio.h) on its seam: a pipe carrying the kernel's GPIO
 * event records (read by libgpiod exactly as from a line's event descriptor) and a fake trigger line. Also
 * the errors of a missing chip, the TEMPERATURE ABI input and the ring glue without wiring. */
#define _GNU_SOURCE
#include "test_helpers.h"
#include "modules/sonar/sonar_gpio.h"
#include "modules/sonar/sonar_gpio_temperature.h"
#include "modules/sonar/sonar_array_arch.h"
#include "modules/core/abi.h"
#include "pprz_host_vehicle.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <string.h>
#include <unistd.h>

static const struct sonar_echo_config echo_cfg = {
  .min_range_m = 0.02f, .max_range_m = 4.0f, .timeout_us = 30000, .min_pulse_us = 50, .bounce_us = 20,
};

/** The fake trigger line: the levels driven, and whether it should fail. */
struct fake_trigger {
  int levels[8];
  int n;
  bool fail;
};

static int fake_set_trigger(void *ctx, int level)
{
  struct fake_trigger *t = ctx;
  if (t->fail) {
    errno = EIO;
    return -1;
  }
  if (t->n < 8) {
    t->levels[t->n++] = level;
  }
  return 0;
}

struct fixture {
  int pipe_fd[2];
  struct fake_trigger trigger;
  struct sonar_gpio *sonar;
};

static int setup(void **state)
{
  static struct fixture f;
  memset(&f, 0, sizeof(f));
  assert_int_equal(pipe2(f.pipe_fd, O_CLOEXEC | O_NONBLOCK), 0);
  const struct sonar_gpio_io io = { .echo_fd = f.pipe_fd[0], .set_trigger = fake_set_trigger, .ctx = &f.trigger };
  char err[256];
  f.sonar = sonar_gpio_open_io(&echo_cfg, &io, err, sizeof(err));
  assert_non_null(f.sonar);
  *state = &f;
  return 0;
}

static int teardown(void **state)
{
  struct fixture *f = *state;
  sonar_gpio_close(f->sonar);
  close(f->pipe_fd[0]);
  close(f->pipe_fd[1]);
  return 0;
}

/** The kernel reports an edge at t_ns. */
static void edge(struct fixture *f, bool rising, uint64_t t_ns)
{
  struct gpioevent_data ev;
  memset(&ev, 0, sizeof(ev));   /* the 4 bytes of padding after id are written to the pipe too */
  ev.timestamp = t_ns;
  ev.id = rising ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE;
  assert_int_equal(write(f->pipe_fd[1], &ev, sizeof(ev)), sizeof(ev));
}

/** Kernel time of the echo edges: 5000 s after boot (any value: only differences count) */
#define T0_NS 5000000000000ULL

static void the_trigger_is_a_pulse(void **state)
{
  struct fixture *f = *state;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  assert_int_equal(f->trigger.n, 2);
  assert_int_equal(f->trigger.levels[0], 1);
  assert_int_equal(f->trigger.levels[1], 0);
}

static void the_width_comes_from_the_kernel_stamps(void **state)
{
  struct fixture *f = *state;
  struct sonar_echo_reading r;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  assert_int_equal(sonar_gpio_poll(f->sonar, 1200, 20.0f, &r), 0);  /* nothing yet */
  edge(f, true, T0_NS + 450000);
  edge(f, false, T0_NS + 450000 + 5824000);
  /* read late (25 ms after the trigger): the width is still the kernel's 5824 us */
  assert_int_equal(sonar_gpio_poll(f->sonar, 26000, 20.0f, &r), 1);
  assert_int_equal(r.status, SONAR_ECHO_VALID);
  assert_int_equal(r.width_us, 5824);
  assert_close(r.distance_m, 343.42 * 5824e-6 / 2.0, 1e-6);
  assert_int_equal(r.trigger_us, 1000);
  assert_int_equal(sonar_gpio_poll(f->sonar, 27000, 20.0f, &r), 0);  /* handed out once */
}

static void edges_before_the_trigger_do_not_count(void **state)
{
  struct fixture *f = *state;
  struct sonar_echo_reading r;
  edge(f, true, T0_NS);            /* an echo of the previous cycle, not yet read */
  edge(f, false, T0_NS + 3000000);
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  assert_int_equal(sonar_gpio_poll(f->sonar, 1000 + echo_cfg.timeout_us - 1, 20.0f, &r), 0);
  assert_int_equal(sonar_gpio_poll(f->sonar, 1000 + echo_cfg.timeout_us, 20.0f, &r), 1);
  assert_int_equal(r.status, SONAR_ECHO_OUT_OF_RANGE);
  assert_true(isinf(r.distance_m));
  struct sonar_echo_stats st;
  sonar_gpio_stats(f->sonar, &st);
  assert_int_equal(st.late_edges, 2);
  assert_int_equal(st.timeouts, 1);
}

static void bounced_edges_are_merged(void **state)
{
  struct fixture *f = *state;
  struct sonar_echo_reading r;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  edge(f, true, T0_NS);
  edge(f, false, T0_NS + 4000);    /* 4 us glitch */
  edge(f, true, T0_NS + 9000);     /* 5 us later: bounce */
  edge(f, false, T0_NS + 2000000);
  edge(f, true, T0_NS + 2003000);  /* bounce at the fall: late */
  edge(f, false, T0_NS + 2005000);
  assert_int_equal(sonar_gpio_poll(f->sonar, 5000, 20.0f, &r), 1);
  assert_int_equal(r.width_us, 2000);
  struct sonar_echo_stats st;
  sonar_gpio_stats(f->sonar, &st);
  assert_int_equal(st.glitches, 1);
}

static void a_new_trigger_drops_an_unread_echo(void **state)
{
  struct fixture *f = *state;
  struct sonar_echo_reading r;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  edge(f, true, T0_NS);
  edge(f, false, T0_NS + 1000000);
  assert_int_equal(sonar_gpio_trigger(f->sonar, 51000), 0);  /* the echo above was never polled */
  assert_int_equal(sonar_gpio_poll(f->sonar, 52000, 20.0f, &r), 0);
  struct sonar_echo_stats st;
  sonar_gpio_stats(f->sonar, &st);
  assert_int_equal(st.overruns, 1);
}

static void a_truncated_event_record_is_an_error(void **state)
{
  struct fixture *f = *state;
  struct sonar_echo_reading r;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), 0);
  const char half[5] = { 0 };
  assert_int_equal(write(f->pipe_fd[1], half, sizeof(half)), sizeof(half));
  errno = 0;
  assert_int_equal(sonar_gpio_poll(f->sonar, 2000, 20.0f, &r), -1);
  assert_int_equal(errno, EIO);
}

static void a_failing_trigger_line_is_an_error(void **state)
{
  struct fixture *f = *state;
  f->trigger.fail = true;
  errno = 0;
  assert_int_equal(sonar_gpio_trigger(f->sonar, 1000), -1);
  assert_int_equal(errno, EIO);
  struct sonar_echo_stats st;
  sonar_gpio_stats(f->sonar, &st);
  assert_int_equal(st.triggers, 0);  /* nothing armed */
}

static void a_missing_chip_gives_one_clear_message(void **state)
{
  (void)state;
  const struct sonar_gpio_config cfg = {
    .trigger_chip = "gpiochip-not-here", .trigger_line = 3, .echo_chip = "gpiochip-not-here", .echo_line = 4,
    .consumer = "test", .echo = echo_cfg,
  };
  char err[256] = "";
  errno = 0;
  assert_null(sonar_gpio_open(&cfg, err, sizeof(err)));
  assert_int_equal(errno, ENOENT);
  assert_non_null(strstr(err, "gpiochip 'gpiochip-not-here' line 3"));
  assert_non_null(strstr(err, strerror(ENOENT)));
  assert_null(strchr(err, '\n'));
}

static void a_bad_configuration_is_named(void **state)
{
  (void)state;
  struct sonar_gpio_config cfg = {
    .trigger_chip = "gpiochip0", .echo_chip = "gpiochip0", .consumer = "test", .echo = echo_cfg,
  };
  cfg.echo.timeout_us = 1000;
  char err[256] = "";
  errno = 0;
  assert_null(sonar_gpio_open(&cfg, err, sizeof(err)));
  assert_int_equal(errno, EINVAL);
  assert_non_null(strstr(err, "timeout_us"));
}

static void the_temperature_comes_from_the_abi(void **state)
{
  (void)state;
  pprz_vehicles_setup(1, NULL);
  assert_true(sonar_gpio_temperature_init());
  assert_close(sonar_gpio_temperature_c(), SONAR_GPIO_TEMPERATURE, 0.0);
  AbiSendMsgTEMPERATURE(1, 31.5f);
  assert_close(sonar_gpio_temperature_c(), 31.5, 0.0);
  AbiSendMsgTEMPERATURE(1, 300.0f);  /* a broken sensor */
  AbiSendMsgTEMPERATURE(1, NAN);
  assert_close(sonar_gpio_temperature_c(), 31.5, 0.0);
  assert_int_equal(sonar_gpio_temperature_rejected(), 2);
  pprz_vehicles_teardown();
}

static void the_ring_needs_wiring(void **state)
{
  (void)state;
  pprz_vehicles_setup(1, NULL);
  assert_false(sonar_array_arch_init());  /* no SONAR_GPIO_<NAME>_TRIGGER/_ECHO defined in this build */
  assert_true(isnan(sonar_array_arch_read(0, 0, 1000)));
  sonar_array_arch_trigger(0, 1000);    /* harmless */
  pprz_vehicles_teardown();
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(the_trigger_is_a_pulse, setup, teardown),
    cmocka_unit_test_setup_teardown(the_width_comes_from_the_kernel_stamps, setup, teardown),
    cmocka_unit_test_setup_teardown(edges_before_the_trigger_do_not_count, setup, teardown),
    cmocka_unit_test_setup_teardown(bounced_edges_are_merged, setup, teardown),
    cmocka_unit_test_setup_teardown(a_new_trigger_drops_an_unread_echo, setup, teardown),
    cmocka_unit_test_setup_teardown(a_truncated_event_record_is_an_error, setup, teardown),
    cmocka_unit_test_setup_teardown(a_failing_trigger_line_is_an_error, setup, teardown),
    cmocka_unit_test(a_missing_chip_gives_one_clear_message),
    cmocka_unit_test(a_bad_configuration_is_named),
    cmocka_unit_test(the_temperature_comes_from_the_abi),
    cmocka_unit_test(the_ring_needs_wiring),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
