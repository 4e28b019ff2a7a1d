/* Paparazzi's GPIO functions on Linux (arch/linux/mcu_periph/gpio_arch.h): port/pin -> chip/line mapping,
 * set/clear/toggle/get with pin masks, on a fake line backend (the seam); and with libgpiod itself, a missing
 * chip reported in one message naming the chip and the errno text. */
#include "test_helpers.h"
#include "test_error_sink.h"
#include "mcu_periph/gpio.h"

#include <errno.h>
#include <string.h>

/** A fake line: what was requested and its level. */
struct fake_line {
  char chip[32];
  unsigned offset;
  enum gpiod_io_mode mode;
  int level;
  bool released;
};

#define MAX_LINES 64
static struct fake_line lines[MAX_LINES];
static int nb_lines;
static const char *failing_chip;  ///< requests on this chip fail with ENOENT

static void *fake_request(const char *chip, unsigned offset, enum gpiod_io_mode mode, int initial,
                          const char *consumer, char *err, size_t errlen)
{
  assert_string_equal(consumer, GPIO_ARCH_CONSUMER);
  if (failing_chip != NULL && strcmp(chip, failing_chip) == 0) {
    snprintf(err, errlen, "gpiochip '%s' line %u: cannot open the chip: %s", chip, offset, strerror(ENOENT));
    errno = ENOENT;
    return NULL;
  }
  assert_true(nb_lines < MAX_LINES);
  struct fake_line *l = &lines[nb_lines++];
  snprintf(l->chip, sizeof(l->chip), "%s", chip);
  l->offset = offset;
  l->mode = mode;
  l->level = initial;
  return l;
}

static int fake_set(void *line, int value)
{
  ((struct fake_line *)line)->level = value;
  return 0;
}

static int fake_get(void *line)
{
  return ((struct fake_line *)line)->level;
}

static void fake_release(void *line)
{
  ((struct fake_line *)line)->released = true;
}

static const struct gpio_arch_backend fake = { fake_request, fake_set, fake_get, fake_release };


static int setup(void **state)
{
  (void)state;
  memset(lines, 0, sizeof(lines));
  nb_lines = 0;
  nb_messages = 0;
  failing_chip = NULL;
  gpio_arch_set_error_sink(sink);
  gpio_arch_use_backend(&fake);
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  gpio_arch_use_backend(NULL);
  gpio_arch_map_port(1, GPIO_ARCH_PORT1_CHIP, GPIO_ARCH_PORT1_LINE_BASE);
  gpio_arch_set_error_sink(NULL);
  return 0;
}

static void ports_and_pins_map_to_chips_and_lines(void **state)
{
  (void)state;
  gpio_setup_output(0, GPIO3 | GPIO5);
  assert_int_equal(nb_lines, 2);
  assert_string_equal(lines[0].chip, "gpiochip0");
  assert_int_equal(lines[0].offset, 3);
  assert_int_equal(lines[0].mode, GPIOD_IO_OUTPUT);
  assert_int_equal(lines[0].level, 0);  /* outputs start low */
  assert_int_equal(lines[1].offset, 5);
  assert_int_equal(gpio_arch_map_port(1, "gpiochip2", 16), 0);
  gpio_setup_input(1, GPIO0);
  assert_string_equal(lines[2].chip, "gpiochip2");
  assert_int_equal(lines[2].offset, 16);
  assert_int_equal(lines[2].mode, GPIOD_IO_INPUT);
  assert_int_equal(nb_messages, 0);
}

static void set_clear_toggle_and_get(void **state)
{
  (void)state;
  gpio_setup_output(2, GPIO1 | GPIO2);
  gpio_set(2, GPIO1 | GPIO2);
  assert_int_equal(lines[0].level, 1);
  assert_int_equal(lines[1].level, 1);
  gpio_clear(2, GPIO2);
  assert_int_equal(lines[1].level, 0);
  assert_int_equal(gpio_get(2, GPIO1 | GPIO2), GPIO1);
  gpio_toggle(2, GPIO1 | GPIO2);
  assert_int_equal(gpio_get(2, GPIO1 | GPIO2), GPIO2);
  gpio_toggle(2, GPIO2);
  assert_int_equal(gpio_get(2, GPIO1 | GPIO2), 0);
  assert_int_equal(nb_messages, 0);
}

static void setting_up_again_releases_the_old_line(void **state)
{
  (void)state;
  gpio_setup_output(0, GPIO7);
  gpio_setup_input(0, GPIO7);
  assert_true(lines[0].released);
  assert_false(lines[1].released);
  assert_int_equal(lines[1].mode, GPIOD_IO_INPUT);
  gpio_set(0, GPIO7);  /* an input now: reported, not driven */
  assert_int_equal(lines[1].level, 0);
  assert_int_equal(nb_messages, 1);
  assert_non_null(strstr(messages[0], "port 0 pin 7"));
  assert_non_null(strstr(messages[0], "not set up as an output"));
  gpio_arch_release_all();
  assert_true(lines[1].released);
}

static void a_failing_pin_reports_once(void **state)
{
  (void)state;
  failing_chip = "gpiochip3";
  gpio_setup_output(3, GPIO4);
  gpio_set(3, GPIO4);
  gpio_toggle(3, GPIO4);
  assert_int_equal(gpio_get(3, GPIO4), 0);
  gpio_setup_output(3, GPIO4);  /* still failing: not repeated */
  assert_int_equal(nb_messages, 1);
  assert_non_null(strstr(messages[0], "port 3 pin 4"));
  assert_non_null(strstr(messages[0], "gpiochip 'gpiochip3' line 4"));
  assert_non_null(strstr(messages[0], strerror(ENOENT)));
  assert_string_equal(gpio_arch_last_error(), messages[0]);
}

static void unknown_ports_are_refused(void **state)
{
  (void)state;
  errno = 0;
  assert_int_equal(gpio_arch_map_port(GPIO_ARCH_NB_PORTS, "gpiochip0", 0), -1);
  assert_int_equal(errno, EINVAL);
  gpio_setup_output(GPIO_ARCH_NB_PORTS, GPIO0);
  gpio_set(GPIO_ARCH_NB_PORTS, GPIO0);
  assert_int_equal(nb_lines, 0);
  assert_int_equal(nb_messages, 1);
  assert_non_null(strstr(messages[0], "no such port"));
}

static void a_missing_chip_with_libgpiod(void **state)
{
  (void)state;
  gpio_arch_use_backend(NULL);
  assert_int_equal(gpio_arch_map_port(1, "gpiochip-not-here", 0), 0);
  gpio_setup_output(1, GPIO2);
  gpio_set(1, GPIO2);
  assert_int_equal(gpio_get(1, GPIO2), 0);
  assert_int_equal(nb_messages, 1);
  assert_non_null(strstr(messages[0], "gpiochip 'gpiochip-not-here' line 2"));
  assert_non_null(strstr(messages[0], strerror(ENOENT)));
  assert_null(strchr(messages[0], '\n'));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(ports_and_pins_map_to_chips_and_lines, setup, teardown),
    cmocka_unit_test_setup_teardown(set_clear_toggle_and_get, setup, teardown),
    cmocka_unit_test_setup_teardown(setting_up_again_releases_the_old_line, setup, teardown),
    cmocka_unit_test_setup_teardown(a_failing_pin_reports_once, setup, teardown),
    cmocka_unit_test_setup_teardown(unknown_ports_are_refused, setup, teardown),
    cmocka_unit_test_setup_teardown(a_missing_chip_with_libgpiod, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
