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
 * @file arch/linux/mcu_periph/gpio_arch.h
 * Paparazzi's GPIO functions (mcu_periph/gpio.h) for Linux, on the GPIO character device through libgpiod.
 *
 * Paparazzi names a pin by a port and a bit mask (GPIO0 .. GPIO15); Linux by a gpiochip and a line offset.
 * Port p maps to chip GPIO_ARCH_PORTp_CHIP, and bit b of the mask to line GPIO_ARCH_PORTp_LINE_BASE + b:
 *
 *     <define name="GPIO_ARCH_PORT1_CHIP" value="\"gpiochip2\""/>   port 1 is /dev/gpiochip2 ...
 *     <define name="GPIO_ARCH_PORT1_LINE_BASE" value="16"/>          ... lines 16 to 31
 *     gpio_setup_output(1, GPIO3);  gpio_set(1, GPIO3);              drives gpiochip2 line 19
 *
 * Defaults: port p is "gpiochip<p>" from line 0, for p < GPIO_ARCH_NB_PORTS (8); gpio_arch_map_port() changes
 * a mapping at run time. The chip may be given as libgpiod's lookup accepts it (name, number, path, label).
 *
 * Lines are requested on setup (outputs start low) and kept until set up again or gpio_arch_release_all().
 * Errors cannot be returned through Paparazzi's void functions: each failure gives one message (naming port,
 * pin, chip, line and the errno text) to the error sink (stderr by default) and gpio_arch_last_error();
 * the pin then stays inert (writes ignored, reads 0) without repeating the message. Not thread-safe: call
 * from the main loop, as Paparazzi does.
 */

#ifndef GPIO_ARCH_H
#define GPIO_ARCH_H

#include "std.h"
#include "mcu_periph/gpiod_io.h"

typedef uint32_t gpio_port_t;

/** Pin masks (the libopencm3 names Paparazzi's boards use) */
#ifndef GPIO0
#define GPIO0 (1U << 0)
#define GPIO1 (1U << 1)
#define GPIO2 (1U << 2)
#define GPIO3 (1U << 3)
#define GPIO4 (1U << 4)
#define GPIO5 (1U << 5)
#define GPIO6 (1U << 6)
#define GPIO7 (1U << 7)
#define GPIO8 (1U << 8)
#define GPIO9 (1U << 9)
#define GPIO10 (1U << 10)
#define GPIO11 (1U << 11)
#define GPIO12 (1U << 12)
#define GPIO13 (1U << 13)
#define GPIO14 (1U << 14)
#define GPIO15 (1U << 15)
#endif

/** Pins per port (bits of the mask) */
#define GPIO_ARCH_PINS_PER_PORT 16

/** Number of ports */
#ifndef GPIO_ARCH_NB_PORTS
#define GPIO_ARCH_NB_PORTS 8
#endif
/** Consumer label of the requested lines (what gpioinfo shows) */
#ifndef GPIO_ARCH_CONSUMER
#define GPIO_ARCH_CONSUMER "paparazzi"
#endif

/** Chip and first line of each port (airframe defines, see file comment) */
#ifndef GPIO_ARCH_PORT0_CHIP
#define GPIO_ARCH_PORT0_CHIP "gpiochip0"
#endif
#ifndef GPIO_ARCH_PORT1_CHIP
#define GPIO_ARCH_PORT1_CHIP "gpiochip1"
#endif
#ifndef GPIO_ARCH_PORT2_CHIP
#define GPIO_ARCH_PORT2_CHIP "gpiochip2"
#endif
#ifndef GPIO_ARCH_PORT3_CHIP
#define GPIO_ARCH_PORT3_CHIP "gpiochip3"
#endif
#ifndef GPIO_ARCH_PORT4_CHIP
#define GPIO_ARCH_PORT4_CHIP "gpiochip4"
#endif
#ifndef GPIO_ARCH_PORT5_CHIP
#define GPIO_ARCH_PORT5_CHIP "gpiochip5"
#endif
#ifndef GPIO_ARCH_PORT6_CHIP
#define GPIO_ARCH_PORT6_CHIP "gpiochip6"
#endif
#ifndef GPIO_ARCH_PORT7_CHIP
#define GPIO_ARCH_PORT7_CHIP "gpiochip7"
#endif
#ifndef GPIO_ARCH_PORT0_LINE_BASE
#define GPIO_ARCH_PORT0_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT1_LINE_BASE
#define GPIO_ARCH_PORT1_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT2_LINE_BASE
#define GPIO_ARCH_PORT2_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT3_LINE_BASE
#define GPIO_ARCH_PORT3_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT4_LINE_BASE
#define GPIO_ARCH_PORT4_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT5_LINE_BASE
#define GPIO_ARCH_PORT5_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT6_LINE_BASE
#define GPIO_ARCH_PORT6_LINE_BASE 0
#endif
#ifndef GPIO_ARCH_PORT7_LINE_BASE
#define GPIO_ARCH_PORT7_LINE_BASE 0
#endif

/**
 * Setup one or more pins of the given GPIO port as outputs (driven low).
 * @param[in] port
 * @param[in] gpios If multiple pins are to be changed, use logical OR '|' to separate them.
 */
extern void gpio_setup_output(gpio_port_t port, uint16_t gpios);

/**
 * Setup one or more pins of the given GPIO port as inputs.
 * @param[in] port
 * @param[in] gpios If multiple pins are to be changed, use logical OR '|' to separate them.
 */
extern void gpio_setup_input(gpio_port_t port, uint16_t gpios);

/** Set gpio outputs to high level. */
extern void gpio_set(gpio_port_t port, uint16_t gpios);

/** Clear gpio outputs to low level. */
extern void gpio_clear(gpio_port_t port, uint16_t gpios);

/** Toggle gpio outputs. */
extern void gpio_toggle(gpio_port_t port, uint16_t gpios);

/** Read gpio levels: the bits of gpios whose line is high. */
extern uint16_t gpio_get(gpio_port_t port, uint16_t gpios);

/* Linux only */

/** Map port to chip from line line_base (releases the port's lines); -1 and errno EINVAL for a bad port/chip. */
extern int gpio_arch_map_port(gpio_port_t port, const char *chip, unsigned line_base);

/** Release every requested line (at shutdown, or between tests). */
extern void gpio_arch_release_all(void);

/** The last error message ("" if none). */
extern const char *gpio_arch_last_error(void);

/** Where error messages go (NULL: stderr). */
extern void gpio_arch_set_error_sink(void (*sink)(const char *msg));

/** The line operations (the test seam; gpio_arch_use_backend(NULL) restores libgpiod). */
struct gpio_arch_backend {
  void *(*request)(const char *chip, unsigned offset, enum gpiod_io_mode mode, int initial, const char *consumer,
                   char *err, size_t errlen);
  int (*set)(void *line, int value);
  int (*get)(void *line);
  void (*release)(void *line);
};
/** Use backend for the lines requested from now on (release the old ones first). */
extern void gpio_arch_use_backend(const struct gpio_arch_backend *backend);

#endif /* GPIO_ARCH_H */
