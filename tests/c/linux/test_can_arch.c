/* Paparazzi's CAN API on Linux (mcu_periph/can.h over SocketCAN, arch/linux/mcu_periph/can_arch.h) on its
 * seam, a socketpair standing in for the CAN socket: callbacks, classical/FD/extended frames both ways,
 * refused frames, DLC <-> length; and can_hw_init() on an interface that cannot be opened. */
#include "test_helpers.h"
#include "test_error_sink.h"
#include "mcu_periph/can.h"
#include "mcu_periph/sys_time.h"

#include <errno.h>
#include <linux/can.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

static int bus[2];  ///< bus[0] is can1's socket, bus[1] the rest of the bus

struct received {
  struct pprzcan_frame frame[4];
  int ifindex[4];
  int n;
};

static void on_frame(struct pprzcan_frame *rxframe, struct pprzaddr_can *src_addr, void *user_data)
{
  struct received *r = user_data;
  if (r->n < 4) {
    r->frame[r->n] = *rxframe;
    r->ifindex[r->n] = src_addr->can_ifindex;
  }
  r->n++;
}


static int setup(void **state)
{
  (void)state;
  memset(can1.callbacks, 0, sizeof(can1.callbacks));
  nb_messages = 0;
  can_arch_set_error_sink(sink);
  assert_int_equal(socketpair(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0, bus), 0);
  assert_int_equal(can_arch_attach_fd(1, bus[0]), 0);
  return 0;
}

static int teardown(void **state)
{
  (void)state;
  can_arch_close();  /* closes bus[0] */
  close(bus[1]);
  can_arch_set_error_sink(NULL);
  return 0;
}

static void frames_reach_the_callbacks(void **state)
{
  (void)state;
  static struct received r;
  memset(&r, 0, sizeof(r));
  struct pprzaddr_can all = { .can_ifindex = 0 };
  assert_int_equal(can_register_callback(on_frame, &all, &r), 0);
  const struct can_frame classic = { .can_id = 0x123, .len = 3, .data = { 1, 2, 3 } };
  assert_int_equal(write(bus[1], &classic, CAN_MTU), CAN_MTU);
  struct canfd_frame fd = { .can_id = 0x1ABCDEF | CAN_EFF_FLAG, .len = 12, .flags = CANFD_BRS };
  fd.data[11] = 0x42;
  assert_int_equal(write(bus[1], &fd, CANFD_MTU), CANFD_MTU);
  sys_time_host_set(10.0);
  can_event();
  assert_int_equal(r.n, 2);
  assert_int_equal(r.ifindex[0], 1);
  assert_int_equal(r.frame[0].can_id, 0x123);
  assert_int_equal(r.frame[0].len, 3);
  assert_int_equal(r.frame[0].flags, 0);
  assert_memory_equal(r.frame[0].data, classic.data, 3);
  assert_true(r.frame[0].timestamp <= 10000000U);  /* the kernel's stamp, on the autopilot's clock */
  assert_int_equal(r.frame[1].can_id, 0x1ABCDEF | CAN_FRAME_EFF);
  assert_int_equal(r.frame[1].len, 12);
  assert_int_equal(r.frame[1].flags, CANFD_BRS | CANFD_FDF);
  assert_int_equal(r.frame[1].data[11], 0x42);
  can_event();  /* nothing more: returns at once */
  assert_int_equal(r.n, 2);
}

static void malformed_messages_are_skipped(void **state)
{
  (void)state;
  static struct received r;
  memset(&r, 0, sizeof(r));
  assert_int_equal(can_register_callback(on_frame, NULL, &r), 0);
  const char junk[5] = { 0 };
  assert_int_equal(write(bus[1], junk, sizeof(junk)), sizeof(junk));
  struct can_frame too_long = { .can_id = 0x10, .len = 9 };
  assert_int_equal(write(bus[1], &too_long, CAN_MTU), CAN_MTU);
  const struct can_frame ok = { .can_id = 0x11, .len = 1 };
  assert_int_equal(write(bus[1], &ok, CAN_MTU), CAN_MTU);
  can_event();
  assert_int_equal(r.n, 1);
  assert_int_equal(r.frame[0].can_id, 0x11);
  assert_int_equal(nb_messages, 0);
}

static void frames_are_transmitted(void **state)
{
  (void)state;
  struct pprzcan_frame tx = { .can_id = 0x7FF, .len = 8, .data = { 9, 8, 7, 6, 5, 4, 3, 2 } };
  struct pprzaddr_can can1_addr = { .can_ifindex = 1 };
  assert_int_equal(can_transmit_frame(&tx, &can1_addr), 0);
  struct canfd_frame got;
  assert_int_equal(read(bus[1], &got, sizeof(got)), CAN_MTU);
  assert_int_equal(got.can_id, 0x7FF);
  assert_int_equal(got.len, 8);
  assert_memory_equal(got.data, tx.data, 8);
  struct pprzcan_frame fd = { .can_id = 0x100 | CAN_FRAME_EFF, .len = 64, .flags = CANFD_FDF | CANFD_BRS };
  assert_int_equal(can_transmit_frame(&fd, NULL), 0);
  assert_int_equal(read(bus[1], &got, sizeof(got)), CANFD_MTU);
  assert_int_equal(got.can_id, 0x100 | CAN_EFF_FLAG);
  assert_int_equal(got.len, 64);
  assert_int_equal(got.flags, CANFD_BRS);
}

static void bad_frames_are_refused(void **state)
{
  (void)state;
  struct pprzcan_frame bad[] = {
    { .can_id = 0x800, .len = 1 },                              /* 12 bits without the extended flag */
    { .can_id = 0x100, .len = 9 },                              /* classical frames carry 8 bytes */
    { .can_id = 0x100, .len = 13, .flags = CANFD_FDF },         /* not a CAN FD length */
    { .can_id = 0x100 | CAN_FRAME_ERR, .len = 8 },              /* error frames are the controller's */
    { .can_id = 0x100 | CAN_FRAME_RTR, .len = 8, .flags = CANFD_FDF },  /* CAN FD has no remote frames */
  };
  for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
    errno = 0;
    assert_int_equal(can_transmit_frame(&bad[i], NULL), -1);
    assert_int_equal(errno, EINVAL);
  }
  struct pprzcan_frame ok = { .can_id = 0x100, .len = 1 };
  struct pprzaddr_can can2_addr = { .can_ifindex = 2 };  /* not enabled */
  errno = 0;
  assert_int_equal(can_transmit_frame(&ok, &can2_addr), -1);
  assert_int_equal(errno, ENODEV);
}

static void dlc_and_length(void **state)
{
  (void)state;
  static const uint8_t len_of_dlc[16] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64 };
  for (uint8_t dlc = 0; dlc < 16; dlc++) {
    assert_int_equal(can_dlc_to_len(dlc), len_of_dlc[dlc]);
    assert_int_equal(can_len_to_dlc(len_of_dlc[dlc]), dlc);
  }
  assert_int_equal(can_len_to_dlc(13), 10);  /* the next length that holds 13 bytes is 16 */
  assert_int_equal(can_len_to_dlc(65), 15);
  assert_int_equal(can_dlc_to_len(16), 0);
}

static void the_callback_table_is_bounded(void **state)
{
  (void)state;
  static struct received r;
  for (int i = 0; i < CAN_NB_CALLBACKS_MAX; i++) {
    assert_int_equal(can_register_callback(on_frame, NULL, &r), 0);
  }
  errno = 0;
  assert_int_equal(can_register_callback(on_frame, NULL, &r), -1);
  assert_int_equal(errno, ENOSPC);
  struct pprzaddr_can nowhere = { .can_ifindex = 7 };
  memset(can1.callbacks, 0, sizeof(can1.callbacks));
  assert_int_equal(can_register_callback(on_frame, &nowhere, &r), -1);
  assert_int_equal(errno, ENODEV);
}

static void an_interface_that_cannot_be_opened_gives_one_message(void **state)
{
  (void)state;
  can_hw_init();  /* CAN1_IFNAME: on this machine no such interface, or no PF_CAN */
  if (can1.fd >= 0) {
    skip();  /* a machine with a working can0 */
  }
  assert_int_equal(nb_messages, 1);
  assert_non_null(strstr(messages[0], "CAN interface '" CAN1_IFNAME "'"));
  assert_true(strstr(messages[0], strerror(ENODEV)) != NULL || strstr(messages[0], strerror(EAFNOSUPPORT)) != NULL);
  can_event();  /* nothing open: no read, no more messages */
  struct pprzcan_frame tx = { .can_id = 1, .len = 0 };
  errno = 0;
  assert_int_equal(can_transmit_frame(&tx, NULL), -1);
  assert_int_equal(errno, ENODEV);
  assert_int_equal(nb_messages, 1);
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test_setup_teardown(frames_reach_the_callbacks, setup, teardown),
    cmocka_unit_test_setup_teardown(malformed_messages_are_skipped, setup, teardown),
    cmocka_unit_test_setup_teardown(frames_are_transmitted, setup, teardown),
    cmocka_unit_test_setup_teardown(bad_frames_are_refused, setup, teardown),
    cmocka_unit_test(dlc_and_length),
    cmocka_unit_test_setup_teardown(the_callback_table_is_bounded, setup, teardown),
    cmocka_unit_test_setup_teardown(an_interface_that_cannot_be_opened_gives_one_message, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
