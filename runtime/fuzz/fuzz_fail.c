/* fuzz_fail.c - how the fuzz drivers report a broken property, in a file of its own below
 * both the platform (fuzz_hal.c) and the framing laws (fuzz_packet.c): the platform calls the
 * laws on every frame a module sends, so the laws calling back into the platform's file would
 * make the two depend on each other. */
#include <stdio.h>
#include <stdlib.h>
#include "fuzz.h"

void (*fuzz_failure_hook)(void);

void fuzz_fail(const char *what)
{
    fprintf(stderr, "fuzz: %s\n", what);
    if (fuzz_failure_hook != NULL) {
        fuzz_failure_hook();
    }
    abort();
}
