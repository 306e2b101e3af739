/* check.h - the lattice runtime's test groups, and their assertions. */
#ifndef CHECK_H
#define CHECK_H

#include <stdio.h>

/* CHECK and CHECK_EQ: the shared fake platform's (runtime/testing/dr_fake.h), which counts
 * them in dr_fake_checks and dr_fake_failures and prints the first failures. */
#include "dr_fake.h"

/* The test groups (one file each). */
void test_laws(void);
void test_packets(void);
void test_sim(void);
void test_describe(void);
void test_dissemination(void);
void test_sync(void);

#endif /* CHECK_H */
