/*
 * The error sink the Linux driver tests hand to the drivers: it keeps the first messages for the assertions.
 */
#ifndef TEST_ERROR_SINK_H
#define TEST_ERROR_SINK_H

#include <stdio.h>

static char messages[4][256];
static int nb_messages;

static void sink(const char *msg)
{
  if (nb_messages < 4) {
    snprintf(messages[nb_messages], sizeof(messages[0]), "%s", msg);
  }
  nb_messages++;
}

#endif /* TEST_ERROR_SINK_H */
