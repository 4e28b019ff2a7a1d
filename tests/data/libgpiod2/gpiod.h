/*
 * A stand-in for libgpiod 2.x's gpiod.h, for tests/python/test_libgpiod_version.py: only what tells 2.x from
 * 1.x to sonar_gpiod.c. Like the real 2.x header it declares the line settings and request objects and has
 * no GPIOD_LINE_BULK_MAX_LINES (libgpiod 1.x's bulk API is gone).
 */
#ifndef FAKE_LIBGPIOD2_GPIOD_H
#define FAKE_LIBGPIOD2_GPIOD_H

struct gpiod_chip;
struct gpiod_line_settings;
struct gpiod_line_config;
struct gpiod_line_request;

struct gpiod_chip *gpiod_chip_open(const char *path);
void gpiod_chip_close(struct gpiod_chip *chip);
struct gpiod_line_settings *gpiod_line_settings_new(void);
const char *gpiod_api_version(void);

#endif
