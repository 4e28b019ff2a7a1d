/*
 * libFuzzer harness: the sonar's echo edges as the kernel hands them out, through the driver's seam
 * (sw/airborne/arch/linux/modules/sonar/sonar_gpio.c: a pipe of struct gpioevent_data records read by libgpiod,
 * and a fake trigger line) into the edge rules of sw/airborne/modules/sonar/sonar_echo.c.
 *
 * Input (binary; short inputs read as zeros): configuration (min and max range [mm], timeout, minimum pulse and
 * bounce [us]), then operations: trigger, poll (temperature, or NaN), an edge record (rising or falling, time
 * step [ns]) or raw bytes (a torn record). Properties: a reading's status matches its distance, and a reading
 * is handed out once.
 */
#include "fuzz_common.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <math.h>

#include "modules/sonar/sonar_gpio.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

static int fake_trigger(void *ctx, int level)
{
  (void)ctx;
  (void)level;
  return 0;
}

static void check_reading(const struct sonar_echo_config *cfg, const struct sonar_echo_reading *r,
                          uint32_t trigger_us)
{
  fuzz_require(r->trigger_us == trigger_us);
  switch (r->status) {
    case SONAR_ECHO_VALID:
      fuzz_require(r->distance_m >= cfg->min_range_m && r->distance_m <= cfg->max_range_m &&
                   r->width_us >= cfg->min_pulse_us);
      break;
    case SONAR_ECHO_OUT_OF_RANGE:
      fuzz_require(isinf(r->distance_m) || r->distance_m < cfg->min_range_m || r->distance_m > cfg->max_range_m);
      break;
    case SONAR_ECHO_REJECTED:
      fuzz_require(isnan(r->distance_m));
      break;
    default:
      fuzz_require(!"a reading status");
  }
}

static void write_edge(int fd, bool rising, uint64_t t_ns)
{
  struct gpioevent_data ev;
  memset(&ev, 0, sizeof(ev));
  ev.timestamp = t_ns;
  ev.id = rising ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE;
  (void)!write(fd, &ev, sizeof(ev));   /* a full pipe drops it, as the kernel's event queue would */
}

static void run(struct sonar_gpio *s, const struct sonar_echo_config *cfg, int pipe_in, struct fuzz_bytes *in)
{
  uint32_t now_us = 0, trigger_us = 0;
  uint64_t edge_ns = 5000000000000ULL;
  while (fuzz_more(in)) {
    const uint8_t op = fuzz_u8(in);
    struct sonar_echo_reading r;
    switch (op & 3U) {
      case 0:
        now_us += fuzz_u16(in);
        if (sonar_gpio_trigger(s, now_us) == 0) {
          trigger_us = now_us;
        } else {
          fuzz_require(errno == EIO);   /* a torn record before the trigger: nothing armed */
        }
        break;
      case 1: {
        now_us += (uint32_t)fuzz_u16(in) << (op >> 6);
        const int8_t t = (int8_t)fuzz_u8(in);
        const float temperature_c = op & 4U ? NAN : (float)t;
        if (sonar_gpio_poll(s, now_us, temperature_c, &r) == 1) {
          check_reading(cfg, &r, trigger_us);
          fuzz_require(sonar_gpio_poll(s, now_us, temperature_c, &r) != 1);
        }
        break;
      }
      case 2:
        edge_ns += fuzz_u32(in);
        write_edge(pipe_in, op & 4U, edge_ns);
        break;
      default: {
        uint8_t torn[sizeof(struct gpioevent_data)];
        const size_t n = 1U + (op >> 4) % (sizeof(torn) - 1U);
        for (size_t i = 0; i < n; i++) {
          torn[i] = fuzz_u8(in);
        }
        (void)!write(pipe_in, torn, n);
        break;
      }
    }
  }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  struct fuzz_bytes in = { data, size };
  struct sonar_echo_config cfg = { .min_range_m = fuzz_u16(&in) * 1e-3f, .max_range_m = fuzz_u16(&in) * 1e-3f };
  cfg.timeout_us = fuzz_u32(&in);
  cfg.min_pulse_us = fuzz_u16(&in);
  cfg.bounce_us = fuzz_u16(&in);
  int pipe_fd[2];
  if (pipe2(pipe_fd, O_CLOEXEC | O_NONBLOCK) != 0) {
    abort();
  }
  const struct sonar_gpio_io io = { .echo_fd = pipe_fd[0], .set_trigger = fake_trigger };
  char err[256];
  struct sonar_gpio *s = sonar_gpio_open_io(&cfg, &io, err, sizeof(err));
  if (s != NULL) {
    run(s, &cfg, pipe_fd[1], &in);
    sonar_gpio_close(s);
  } else {
    fuzz_require(errno == EINVAL && err[0] != '\0');
  }
  close(pipe_fd[0]);
  close(pipe_fd[1]);
  return 0;
}
