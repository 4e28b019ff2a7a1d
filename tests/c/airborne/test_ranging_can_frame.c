/* Ranging CAN frame codec (modules/ranging/ranging_can_frame.h): the documented byte layout, round trips,
 * and every way a frame can be wrong (DLC, id, flags, values), plus the kernel filter. */
#include "test_helpers.h"
#include "modules/ranging/ranging_can_frame.h"

#include <string.h>

static const struct ranging_can_layout layout = RANGING_CAN_LAYOUT_DEFAULT;

/** A valid frame: node 3 measured 1234 mm to peer 7, quality 90 %, sequence 0x1234. */
static struct ranging_can_raw good_frame(void)
{
  struct ranging_can_raw f = { .can_id = 0x303, .len = 8, .data = { 7, 0xD2, 0x04, 90, 0x34, 0x12, 0, 0 } };
  return f;
}

static void the_layout_is_as_documented(void **state)
{
  (void)state;
  const struct ranging_can_msg m = { .node_id = 3, .peer_id = 7, .range_mm = 1234, .quality_pct = 90, .seq = 0x1234 };
  struct ranging_can_raw f;
  assert_int_equal(ranging_can_pack(&layout, &m, &f), RANGING_CAN_FRAME_OK);
  const struct ranging_can_raw expected = good_frame();
  assert_int_equal(f.can_id, expected.can_id);
  assert_int_equal(f.len, 8);
  assert_false(f.fd);
  assert_memory_equal(f.data, expected.data, 8);
}

static void unpack_reverses_pack(void **state)
{
  (void)state;
  const struct ranging_can_msg cases[] = {
    { .node_id = 0, .peer_id = 63, .range_mm = 0, .quality_pct = 0, .seq = 0 },
    { .node_id = 63, .peer_id = 0, .range_mm = RANGING_CAN_RANGE_MAX_MM, .quality_pct = 100, .seq = 0xFFFF },
    { .node_id = 12, .peer_id = 13, .range_mm = 2500, .quality_pct = 57, .seq = 300 },
  };
  for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
    struct ranging_can_raw f;
    struct ranging_can_msg back;
    assert_int_equal(ranging_can_pack(&layout, &cases[i], &f), RANGING_CAN_FRAME_OK);
    assert_int_equal(ranging_can_unpack(&layout, &f, &back), RANGING_CAN_FRAME_OK);
    assert_int_equal(back.node_id, cases[i].node_id);
    assert_int_equal(back.peer_id, cases[i].peer_id);
    assert_int_equal(back.range_mm, cases[i].range_mm);
    assert_int_equal(back.quality_pct, cases[i].quality_pct);
    assert_int_equal(back.seq, cases[i].seq);
  }
}

static void a_normal_frame_unpacks(void **state)
{
  (void)state;
  const struct ranging_can_raw f = good_frame();
  struct ranging_can_msg m;
  assert_int_equal(ranging_can_unpack(&layout, &f, &m), RANGING_CAN_FRAME_OK);
  assert_int_equal(m.node_id, 3);
  assert_int_equal(m.peer_id, 7);
  assert_int_equal(m.range_mm, 1234);
  assert_int_equal(m.quality_pct, 90);
  assert_int_equal(m.seq, 0x1234);
}

static void expect(const struct ranging_can_raw *f, enum ranging_can_verdict v)
{
  struct ranging_can_msg m;
  memset(&m, 0xA5, sizeof(m));
  struct ranging_can_msg untouched;
  memset(&untouched, 0xA5, sizeof(untouched));
  assert_int_equal(ranging_can_unpack(&layout, f, &m), v);
  assert_memory_equal(&m, &untouched, sizeof(m));  /* a rejected frame leaves the output alone */
  assert_non_null(ranging_can_verdict_str(v));
}

static void short_and_long_frames_are_rejected(void **state)
{
  (void)state;
  for (uint8_t len = 0; len <= RANGING_CAN_MAX_DLEN; len++) {
    if (len == RANGING_CAN_DLC) {
      continue;
    }
    struct ranging_can_raw f = good_frame();
    f.len = len;
    expect(&f, RANGING_CAN_FRAME_BAD_DLC);
  }
}

static void foreign_and_special_frames_are_rejected(void **state)
{
  (void)state;
  struct ranging_can_raw f = good_frame();
  f.can_id = 0x2FF;  /* just below the ranging ids */
  expect(&f, RANGING_CAN_FRAME_FOREIGN_ID);
  f.can_id = 0x340;  /* just above */
  expect(&f, RANGING_CAN_FRAME_FOREIGN_ID);
  f.can_id = 0x303 | RANGING_CAN_ID_EFF_FLAG;  /* the right number as an extended id */
  expect(&f, RANGING_CAN_FRAME_NOT_DATA);
  f.can_id = 0x303 | RANGING_CAN_ID_RTR_FLAG;
  expect(&f, RANGING_CAN_FRAME_NOT_DATA);
  f.can_id = RANGING_CAN_ID_ERR_FLAG | 0x40;
  expect(&f, RANGING_CAN_FRAME_NOT_DATA);
  f = good_frame();
  f.fd = true;
  expect(&f, RANGING_CAN_FRAME_NOT_DATA);
}

static void values_out_of_range_are_rejected(void **state)
{
  (void)state;
  struct ranging_can_raw f = good_frame();
  f.data[0] = 64;  /* peer beyond the node ids */
  expect(&f, RANGING_CAN_FRAME_BAD_PEER);
  f.data[0] = 3;   /* the sender itself */
  expect(&f, RANGING_CAN_FRAME_BAD_PEER);
  f = good_frame();
  f.data[1] = (RANGING_CAN_RANGE_MAX_MM + 1) & 0xFF;
  f.data[2] = (RANGING_CAN_RANGE_MAX_MM + 1) >> 8;
  expect(&f, RANGING_CAN_FRAME_BAD_RANGE);
  f = good_frame();
  f.data[3] = 101;
  expect(&f, RANGING_CAN_FRAME_BAD_QUALITY);
  f = good_frame();
  f.data[7] = 1;
  expect(&f, RANGING_CAN_FRAME_BAD_RESERVED);
}

static void pack_refuses_what_unpack_would_reject(void **state)
{
  (void)state;
  struct ranging_can_raw f;
  memset(&f, 0x5A, sizeof(f));
  const struct ranging_can_raw untouched = f;
  const struct ranging_can_msg bad_node = { .node_id = 64, .peer_id = 1 };
  assert_int_equal(ranging_can_pack(&layout, &bad_node, &f), RANGING_CAN_FRAME_BAD_NODE);
  const struct ranging_can_msg self = { .node_id = 5, .peer_id = 5 };
  assert_int_equal(ranging_can_pack(&layout, &self, &f), RANGING_CAN_FRAME_BAD_PEER);
  const struct ranging_can_msg far = { .node_id = 5, .peer_id = 6, .range_mm = 60001 };
  assert_int_equal(ranging_can_pack(&layout, &far, &f), RANGING_CAN_FRAME_BAD_RANGE);
  const struct ranging_can_msg sure = { .node_id = 5, .peer_id = 6, .quality_pct = 200 };
  assert_int_equal(ranging_can_pack(&layout, &sure, &f), RANGING_CAN_FRAME_BAD_QUALITY);
  assert_memory_equal(&f, &untouched, sizeof(f));
}

static void the_kernel_filter_passes_exactly_the_ranging_ids(void **state)
{
  (void)state;
  uint32_t id, mask;
  ranging_can_layout_filter(&layout, &id, &mask);
  for (uint32_t can_id = 0; can_id <= RANGING_CAN_SFF_MASK; can_id++) {
    const bool in_window = can_id >= layout.id_base && can_id < (uint32_t)layout.id_base + layout.nb_nodes;
    assert_int_equal((can_id & mask) == (id & mask), in_window);
    /* extended, remote and error frames with a ranging number never pass */
    assert_false(((can_id | RANGING_CAN_ID_EFF_FLAG) & mask) == (id & mask));
    assert_false(((can_id | RANGING_CAN_ID_RTR_FLAG) & mask) == (id & mask));
    assert_false(((can_id | RANGING_CAN_ID_ERR_FLAG) & mask) == (id & mask));
  }
}

static void bad_layouts_are_named(void **state)
{
  (void)state;
  const char *why = NULL;
  assert_int_equal(ranging_can_layout_check(&layout, &why), 0);
  struct ranging_can_layout l = layout;
  l.nb_nodes = 48;
  assert_int_equal(ranging_can_layout_check(&l, &why), -1);
  assert_non_null(strstr(why, "power of two"));
  l = layout;
  l.id_base = 0x310;
  assert_int_equal(ranging_can_layout_check(&l, &why), -1);
  assert_non_null(strstr(why, "multiple"));
  l = layout;
  l.id_base = 0x800;
  l.nb_nodes = 256;
  assert_int_equal(ranging_can_layout_check(&l, &why), -1);
  assert_non_null(strstr(why, "0x7FF"));
}

int main(void)
{
  const struct CMUnitTest tests[] = {
    cmocka_unit_test(the_layout_is_as_documented),
    cmocka_unit_test(unpack_reverses_pack),
    cmocka_unit_test(a_normal_frame_unpacks),
    cmocka_unit_test(short_and_long_frames_are_rejected),
    cmocka_unit_test(foreign_and_special_frames_are_rejected),
    cmocka_unit_test(values_out_of_range_are_rejected),
    cmocka_unit_test(pack_refuses_what_unpack_would_reject),
    cmocka_unit_test(the_kernel_filter_passes_exactly_the_ranging_ids),
    cmocka_unit_test(bad_layouts_are_named),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
