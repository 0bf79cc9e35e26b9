/* checks.h: the check helpers hang.c and engine.c share (C99). Each program
 * that includes it counts its failed checks in `failures`. */
#ifndef COIF_EXAMPLE_CHECKS_H
#define COIF_EXAMPLE_CHECKS_H

#include "coif.h"

#include <stdio.h>

static int failures = 0;

/* Counts a failure, naming it, unless `ok`. */
static void check(int ok, const char *what) {
    if (!ok) {
        fprintf(stderr, "FAIL: %s\n", what);
        failures++;
    }
}

/* Counts a failure, with both statuses' messages, unless `got == want`. */
static void expect(CoifStatus got, CoifStatus want, const char *what) {
    if (got != want) {
        fprintf(stderr, "FAIL: %s: got %d (%s), want %d (%s)\n", what, (int)got,
                coif_status_message_code((int)got), (int)want, coif_status_message(want));
        failures++;
    }
}

#endif
