/*
 * libFuzzer harness: can-utils `candump -l` logs, line by line, sw/airborne/modules/ranging/ranging_can_candump.c,
 * and the ranging frame codec behind it (ranging_can_frame.c). Properties:
 *   - a parsed frame is within its kind's length, with zeros beyond it;
 *   - written back as candump writes it, a parsed line parses to the same time, interface and frame;
 *   - a frame that unpacks as a ranging frame packs back to the same id and bytes.
 */
#include "fuzz_common.h"

#include <inttypes.h>

#include "modules/ranging/ranging_can_candump.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
  (void)argc;
  (void)argv;
  fuzz_quiet_stdio();
  return 0;
}

/** The line candump -l would write for l (classical data as hex pairs, remote as R<len>, FD as ##<flags>). */
static void format_line(const struct ranging_can_candump_line *l, char *out, size_t len)
{
  const struct ranging_can_raw *f = &l->frame;
  int n = snprintf(out, len, "(%" PRIu64 ".%06" PRIu64 ") %s ", l->time_us / 1000000U, l->time_us % 1000000U,
                   l->ifname);
  if (f->can_id & RANGING_CAN_ID_ERR_FLAG) {
    n += snprintf(out + n, len - (size_t)n, "%08" PRIX32 "#", f->can_id);
  } else if (f->can_id & RANGING_CAN_ID_EFF_FLAG) {
    n += snprintf(out + n, len - (size_t)n, "%08" PRIX32 "#", f->can_id & RANGING_CAN_EFF_MASK);
  } else {
    n += snprintf(out + n, len - (size_t)n, "%03" PRIX32 "#", f->can_id & ~RANGING_CAN_ID_RTR_FLAG);
  }
  if (f->fd) {
    n += snprintf(out + n, len - (size_t)n, "#%X", f->fd_flags);
  } else if (f->can_id & RANGING_CAN_ID_RTR_FLAG) {
    snprintf(out + n, len - (size_t)n, "R%u", f->len);
    return;
  }
  for (unsigned i = 0; i < f->len; i++) {
    n += snprintf(out + n, len - (size_t)n, "%02X", f->data[i]);
  }
}

static bool same_line(const struct ranging_can_candump_line *a, const struct ranging_can_candump_line *b)
{
  return a->time_us == b->time_us && strcmp(a->ifname, b->ifname) == 0 && a->frame.can_id == b->frame.can_id &&
         a->frame.len == b->frame.len && a->frame.fd == b->frame.fd && a->frame.fd_flags == b->frame.fd_flags &&
         memcmp(a->frame.data, b->frame.data, sizeof(a->frame.data)) == 0;
}

static void check_codec(const struct ranging_can_raw *frame)
{
  static const struct ranging_can_layout layout = RANGING_CAN_LAYOUT_DEFAULT;
  struct ranging_can_msg msg;
  const enum ranging_can_verdict verdict = ranging_can_unpack(&layout, frame, &msg);
  fuzz_require(verdict < RANGING_CAN_FRAME_NB_VERDICTS && ranging_can_verdict_str(verdict) != NULL);
  if (verdict == RANGING_CAN_FRAME_OK) {
    struct ranging_can_raw packed;
    memset(&packed, 0, sizeof(packed));
    fuzz_require(ranging_can_pack(&layout, &msg, &packed) == RANGING_CAN_FRAME_OK);
    fuzz_require(packed.can_id == frame->can_id && packed.len == RANGING_CAN_DLC &&
                 memcmp(packed.data, frame->data, RANGING_CAN_DLC) == 0);
  }
}

static void check_line(const char *text)
{
  struct ranging_can_candump_line l, again;
  const char *why = NULL;
  const int rc = ranging_can_candump_parse(text, &l, &why);
  fuzz_require(rc >= -1 && rc <= 1);
  if (rc < 0) {
    fuzz_require(why != NULL && why[0] != '\0');
  }
  if (rc != 1) {
    return;
  }
  fuzz_require(l.ifname[0] != '\0' && l.frame.len <= (l.frame.fd ? RANGING_CAN_MAX_DLEN : 8));
  for (unsigned i = l.frame.len; i < RANGING_CAN_MAX_DLEN; i++) {
    fuzz_require(l.frame.data[i] == 0);
  }
  char written[256];
  format_line(&l, written, sizeof(written));
  if (ranging_can_candump_parse(written, &again, &why) != 1 || !same_line(&l, &again)) {
    fprintf(fuzz_report, "line:         %s\nwritten back: %s\n", text, written);
  }
  fuzz_require(ranging_can_candump_parse(written, &again, &why) == 1 && same_line(&l, &again));
  check_codec(&l.frame);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  char *text = fuzz_string(data, size);
  for (char *line = text, *next; line != NULL && line < text + size; line = next) {
    next = strchr(line, '\n');
    if (next != NULL) {
      *next++ = '\0';
    }
    check_line(line);
  }
  free(text);
  return 0;
}
