/* test_describe.c - dr_module_describe: the format, the window in hexadecimal, and bounds
 * (every cap from 0 up: a NUL-terminated prefix, nothing written at or beyond cap). */
#include <string.h>
#include "check.h"
#include "dr_lattice.h"

#define BUF 96u

/* Describes `m` with every cap from 0 to past the full length; each result is a prefix of
 * the full description and no byte at or beyond cap is touched. */
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

static void check_text(const dr_module_t *m, const char *want)
{
    char buf[BUF];
    uint8_t len = dr_module_describe(m, buf, (uint8_t)sizeof buf);
    CHECK_EQ(len, strlen(want));
    CHECK(strcmp(buf, want) == 0);
    if (strcmp(buf, want) != 0) {
        fprintf(stderr, "  described \"%s\", want \"%s\"\n", buf, want);
    }
}

void test_describe(void)
{
    dr_module_t m;
    char want[BUF];
    uint16_t k;

    memset(&m, 0, sizeof m);
    m.running = DR_NONE;
    m.unechoed = DR_NONE;
#if DR_CONF_SYNC
    m.go_group = DR_NONE;
#endif
    check_text(&m, "e0 low0 done0 run-");
    check_bounded(&m, "e0 low0 done0 run-");

    /* statements low + 0 and low + 2 done, statement 4 running */
    m.shared.epoch = 12u;
    m.shared.low = 3u;
    m.shared.done[0] = 0x05u;
    m.running = 4u;
    check_text(&m, "e12 low3 done5 run4");
    check_bounded(&m, "e12 low3 done5 run4");

    /* a batch: statements 4, 5 and 8 */
    m.batch = 0x09u;
    check_text(&m, "e12 low3 done5 run4+9");
    check_bounded(&m, "e12 low3 done5 run4+9");
    m.batch = 0;

    /* the largest values: every field at its maximum width (a statement number is one or
     * two bytes, dr_stmt_t; its largest is the one below DR_NONE) */
    m.shared.epoch = 65535u;
    m.shared.low = (dr_stmt_t)(DR_NONE - 1u);
    m.running = (dr_stmt_t)(DR_NONE - 1u);
    m.shared.done[0] = 0xA5u;
    check_text(&m, sizeof(dr_stmt_t) == 1u ? "e65535 low254 donea5 run254"
                                           : "e65535 low65534 donea5 run65534");

    /* the top of the window: W/4 hexadecimal digits, the first '8' */
    memset(m.shared.done, 0, sizeof m.shared.done);
    m.shared.done[DR_CONF_WINDOW / 8 - 1] = 0x80u;
    m.shared.epoch = 1u;
    m.shared.low = 0u;
    m.running = DR_NONE;
    strcpy(want, "e1 low0 done8");
    for (k = 1; k < DR_CONF_WINDOW / 4; k++) {
        strcat(want, "0");
    }
    strcat(want, " run-");
    check_text(&m, want);
    check_bounded(&m, want);

    /* a zero in the middle of the window is kept (only leading zeros are dropped) */
    if (DR_CONF_WINDOW >= 16) {
        memset(m.shared.done, 0, sizeof m.shared.done);
        m.shared.done[1] = 0x01u;
        m.shared.done[0] = 0x0Fu;
        check_text(&m, "e1 low0 done10f run-");
    }

    memset(m.shared.done, 0, sizeof m.shared.done);
    check_text(&m, "e1 low0 done0 run-");

    /* DR_PROGRAM_NO_NV: the channels not heard since the restart (hexadecimal), and the own
     * completion not echoed yet */
    m.unheard = (dr_channels_t)0x11u;
    check_text(&m, "e1 low0 done0 run- hear11");
    check_bounded(&m, "e1 low0 done0 run- hear11");
    m.unheard = (dr_channels_t)1u;
    m.unechoed = 7u;
    check_text(&m, "e1 low0 done0 run- hear1 echo7");
    m.unheard = 0;
    check_text(&m, "e1 low0 done0 run- echo7");
    check_bounded(&m, "e1 low0 done0 run- echo7");
    /* every channel of the widest set */
    m.unheard = (dr_channels_t)~(dr_channels_t)0;
    m.unechoed = DR_NONE;
    strcpy(want, "e1 low0 done0 run- hear");
    for (k = 0; k < sizeof(dr_channels_t) * 2u; k++) {
        strcat(want, "f");
    }
    check_text(&m, want);
    m.unheard = 0;

#if DR_CONF_SYNC
    /* Synchronous groups: the ready set after `run` (absent when empty), then the group
     * counted down to, `went` once its countdown is over. */
    m.shared.ready[0] = 0x03u;
    check_text(&m, "e1 low0 done0 run- ready3");
    m.go_group = 0u;
    check_text(&m, "e1 low0 done0 run- ready3 go0");
    check_bounded(&m, "e1 low0 done0 run- ready3 go0");
    m.go_open = 1u;
    m.running = 1u;
    check_text(&m, "e1 low0 done0 run1 ready3 went0");
    if (DR_CONF_WINDOW >= 16) {
        m.shared.ready[1] = 0x01u;
        m.shared.ready[0] = 0x00u;
        m.unechoed = 7u;
        check_text(&m, "e1 low0 done0 run1 ready100 went0 echo7");
    }
#endif
}
