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
 * @file arch/linux/mcu_periph/gpio_arch.c
 * Paparazzi's GPIO functions on the GPIO character device (port/pin mapping in gpio_arch.h).
 */

#include "mcu_periph/gpio.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

/** Longest chip name kept [chars + 1] */
#define GPIO_ARCH_CHIP_LEN 64
/** Longest error message [chars + 1] */
#define GPIO_ARCH_ERR_LEN 256

struct gpio_arch_pin {
  void *line;              ///< requested line, NULL if none
  enum gpiod_io_mode mode;
  int level;               ///< last level driven (outputs)
  bool reported;           ///< a failure on this pin was reported
};

struct gpio_arch_port {
  char chip[GPIO_ARCH_CHIP_LEN];
  unsigned line_base;
  struct gpio_arch_pin pin[GPIO_ARCH_PINS_PER_PORT];
};

static void *gpiod_backend_request(const char *chip, unsigned offset, enum gpiod_io_mode mode, int initial,
                                   const char *consumer, char *err, size_t errlen)
{
  return gpiod_io_request(chip, offset, mode, initial, consumer, err, errlen);
}
static int gpiod_backend_set(void *line, int value)
{
  return gpiod_io_set(line, value);
}
static int gpiod_backend_get(void *line)
{
  return gpiod_io_get(line);
}
static void gpiod_backend_release(void *line)
{
  gpiod_io_release(line);
}
static const struct gpio_arch_backend gpiod_backend = {
  gpiod_backend_request, gpiod_backend_set, gpiod_backend_get, gpiod_backend_release
};

static const struct gpio_arch_backend *backend = &gpiod_backend;
static void (*error_sink)(const char *msg);
static char last_error[GPIO_ARCH_ERR_LEN];

#define GPIO_ARCH_PORT_INIT(_chip, _base) { .chip = _chip, .line_base = _base }
static struct gpio_arch_port ports[GPIO_ARCH_NB_PORTS] = {
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT0_CHIP, GPIO_ARCH_PORT0_LINE_BASE),
#if GPIO_ARCH_NB_PORTS > 1
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT1_CHIP, GPIO_ARCH_PORT1_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 2
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT2_CHIP, GPIO_ARCH_PORT2_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 3
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT3_CHIP, GPIO_ARCH_PORT3_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 4
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT4_CHIP, GPIO_ARCH_PORT4_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 5
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT5_CHIP, GPIO_ARCH_PORT5_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 6
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT6_CHIP, GPIO_ARCH_PORT6_LINE_BASE),
#endif
#if GPIO_ARCH_NB_PORTS > 7
  GPIO_ARCH_PORT_INIT(GPIO_ARCH_PORT7_CHIP, GPIO_ARCH_PORT7_LINE_BASE),
#endif
};

static void report(const char *fmt_port_pin, gpio_port_t port, unsigned bit, const char *detail)
{
  snprintf(last_error, sizeof(last_error), fmt_port_pin, (unsigned)port, bit, detail);
  if (error_sink != NULL) {
    error_sink(last_error);
  } else {
    fprintf(stderr, "gpio_arch: %s\n", last_error);
  }
}

const char *gpio_arch_last_error(void)
{
  return last_error;
}

void gpio_arch_set_error_sink(void (*sink)(const char *msg))
{
  error_sink = sink;
}

static void release_pin(struct gpio_arch_pin *p)
{
  if (p->line != NULL) {
    backend->release(p->line);
  }
  *p = (struct gpio_arch_pin) { .line = NULL };
}

void gpio_arch_release_all(void)
{
  for (unsigned port = 0; port < GPIO_ARCH_NB_PORTS; port++) {
    for (unsigned bit = 0; bit < GPIO_ARCH_PINS_PER_PORT; bit++) {
      release_pin(&ports[port].pin[bit]);
    }
  }
}

void gpio_arch_use_backend(const struct gpio_arch_backend *b)
{
  gpio_arch_release_all();
  backend = b != NULL ? b : &gpiod_backend;
}

int gpio_arch_map_port(gpio_port_t port, const char *chip, unsigned line_base)
{
  if (port >= GPIO_ARCH_NB_PORTS || chip == NULL || strlen(chip) >= GPIO_ARCH_CHIP_LEN) {
    errno = EINVAL;
    return -1;
  }
  for (unsigned bit = 0; bit < GPIO_ARCH_PINS_PER_PORT; bit++) {
    release_pin(&ports[port].pin[bit]);
  }
  strcpy(ports[port].chip, chip);
  ports[port].line_base = line_base;
  return 0;
}

/** The pin of (port, bit), or NULL (reported once per port) for a port beyond GPIO_ARCH_NB_PORTS. */
static struct gpio_arch_pin *pin_of(gpio_port_t port, unsigned bit)
{
  static bool bad_port_reported;
  if (port < GPIO_ARCH_NB_PORTS) {
    return &ports[port].pin[bit];
  }
  if (!bad_port_reported) {
    bad_port_reported = true;
    report("port %u pin %u: %s", port, bit, "no such port (raise GPIO_ARCH_NB_PORTS and map it)");
  }
  return NULL;
}

static void setup(gpio_port_t port, uint16_t gpios, enum gpiod_io_mode mode)
{
  for (unsigned bit = 0; bit < GPIO_ARCH_PINS_PER_PORT; bit++) {
    if (!(gpios & (1U << bit))) {
      continue;
    }
    struct gpio_arch_pin *p = pin_of(port, bit);
    if (p == NULL) {
      return;
    }
    const bool was_reported = p->reported;
    release_pin(p);
    char err[GPIO_ARCH_ERR_LEN - 32];
    p->line = backend->request(ports[port].chip, ports[port].line_base + bit, mode, 0, GPIO_ARCH_CONSUMER, err,
                               sizeof(err));
    p->mode = mode;
    if (p->line == NULL) {
      p->reported = true;
      if (!was_reported) {
        report("port %u pin %u: %s", port, bit, err);
      }
    }
  }
}

void gpio_setup_output(gpio_port_t port, uint16_t gpios)
{
  setup(port, gpios, GPIOD_IO_OUTPUT);
}

void gpio_setup_input(gpio_port_t port, uint16_t gpios)
{
  setup(port, gpios, GPIOD_IO_INPUT);
}

/** Drive the output pins of gpios: 0, 1, or the opposite of their level (toggle). */
static void drive(gpio_port_t port, uint16_t gpios, int value, bool toggle)
{
  for (unsigned bit = 0; bit < GPIO_ARCH_PINS_PER_PORT; bit++) {
    if (!(gpios & (1U << bit))) {
      continue;
    }
    struct gpio_arch_pin *p = pin_of(port, bit);
    if (p == NULL) {
      return;
    }
    if (p->line == NULL || p->mode != GPIOD_IO_OUTPUT) {
      if (!p->reported) {
        p->reported = true;
        report("port %u pin %u: %s", port, bit, "written but not set up as an output (gpio_setup_output)");
      }
      continue;
    }
    const int level = toggle ? !p->level : value;
    if (backend->set(p->line, level) < 0) {
      if (!p->reported) {
        p->reported = true;
        report("port %u pin %u: cannot set the line: %s", port, bit, strerror(errno));
      }
      continue;
    }
    p->level = level;
  }
}

void gpio_set(gpio_port_t port, uint16_t gpios)
{
  drive(port, gpios, 1, false);
}

void gpio_clear(gpio_port_t port, uint16_t gpios)
{
  drive(port, gpios, 0, false);
}

void gpio_toggle(gpio_port_t port, uint16_t gpios)
{
  drive(port, gpios, 0, true);
}

uint16_t gpio_get(gpio_port_t port, uint16_t gpios)
{
  uint16_t levels = 0;
  for (unsigned bit = 0; bit < GPIO_ARCH_PINS_PER_PORT; bit++) {
    if (!(gpios & (1U << bit))) {
      continue;
    }
    struct gpio_arch_pin *p = pin_of(port, bit);
    if (p == NULL) {
      return levels;
    }
    if (p->line == NULL) {
      if (!p->reported) {
        p->reported = true;
        report("port %u pin %u: %s", port, bit, "read but not set up (gpio_setup_input or gpio_setup_output)");
      }
      continue;
    }
    const int v = backend->get(p->line);
    if (v < 0) {
      if (!p->reported) {
        p->reported = true;
        report("port %u pin %u: cannot read the line: %s", port, bit, strerror(errno));
      }
      continue;
    }
    if (v) {
      levels |= (uint16_t)(1U << bit);
    }
  }
  return levels;
}
