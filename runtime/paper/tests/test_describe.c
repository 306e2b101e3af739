/* test_describe.c - dr_module_describe: the format, the pending set, and bounds (every cap
 * from 0 up: a NUL-terminated prefix, nothing written at or beyond cap). */
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "machines.h"

#define BUF 64u

static void check_text(const dr_module_t *m, const char *want)
{
    char buf[BUF];
    uint8_t len = dr_module_describe(m, buf, (uint8_t)sizeof buf);
    CHECK_EQ(len, strlen(want));
    if (!CHECK(strcmp(buf, want) == 0)) {
        fprintf(stderr, "  described \"%s\", want \"%s\"\n", buf, want);
    }
}

static void check_bounded(const dr_module_t *m, const char *want)
{
    char buf[BUF];
    uint8_t full = (uint8_t)strlen(want);
    uint8_t cap;
    uint8_t len;
    uint8_t i;
    uint8_t untouched;
    for (cap = 0; cap <= (uint8_t)(full + 3u); cap++) {
        memset(buf, 'X', sizeof buf);
        len = dr_module_describe(m, buf, cap);
        untouched = 1;
        for (i = cap; i < BUF; i++) {
            untouched = (uint8_t)(untouched & (buf[i] == 'X'));
        }
        CHECK(untouched);
        if (cap == 0u) {
            CHECK_EQ(len, 0);
            continue;
        }
        CHECK_EQ(len, cap > full ? full : (uint8_t)(cap - 1u));
        CHECK_EQ(buf[len], '\0');
        CHECK(strncmp(buf, want, len) == 0);
    }
}

static void test_format(void)
{
    dr_module_t m;
    memset(&m, 0, sizeof m);
    check_text(&m, "s0 a0 p{} l0");
    check_bounded(&m, "s0 a0 p{} l0");

    m.global.state = 4;
    m.global.address = 3;
    m.global.pending[1] = 1;   /* empty slots are skipped, the others kept in slot order */
    m.global.pending[3] = 4;
    m.local_state = DR_STATE_IDLE;
    check_text(&m, "s4 a3 p{1,4} l255");
    check_bounded(&m, "s4 a3 p{1,4} l255");

    m.global.pending[0] = 200;
    m.global.pending[4] = 9;
    m.global.state = DR_STATE_END;
    m.global.address = DR_ADDRESS_ALL;
    m.local_state = 17;
    check_text(&m, "s254 a255 p{200,1,4,9} l17");
}

/* The description follows the module: after init, module 0 (the first address) is in state 0. */
static void test_running_module(void)
{
    world_t w;
    char buf[BUF];
    uint8_t len;
    world_init(&w, 2, &eight2car_program, DR_MERGE_C_PORT, 0, 0);
    len = dr_module_describe(&w.mod[0], buf, (uint8_t)sizeof buf);
    CHECK_EQ(len, strlen(buf));
    CHECK(strncmp(buf, "s0 a", 4) == 0);
}

int main(void)
{
    test_format();
    test_running_module();
    return harness_done("test_describe");
}
