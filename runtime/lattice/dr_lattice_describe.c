/* dr_lattice_describe.c - a one-line description of a lattice module's state, for traces
 * (host and simulator builds; not needed on the modules). */
#include "dr_lattice.h"
#include "dr_text.h"

#define W ((uint16_t)DR_CONF_WINDOW)

static const char hex[] = "0123456789abcdef";

/* Appends v in hexadecimal, without leading zeros. Cost: O(8). */
static void text_hex(char *out, uint8_t cap, uint8_t *n, uint32_t v)
{
    uint8_t digits = 1;
    while (digits < 8u && (v >> (4u * digits)) != 0u) {
        digits++;
    }
    while (digits > 0u) {
        digits--;
        dr_text_char(out, cap, n, hex[(v >> (4u * digits)) & 0x0Fu]);
    }
}

/* Appends the window's set `set` (bit i: statement low + i) as one hexadecimal number, without
 * leading zeros ("0" when empty). Cost: O(W/4). */
static void text_set(char *out, uint8_t cap, uint8_t *n, const uint8_t *set)
{
    uint8_t leading = 1;
    uint8_t nibble;
    uint16_t j;
    for (j = (uint16_t)(W / 4u); j > 0u; j--) {
        nibble = (uint8_t)(((unsigned)set[(j - 1u) >> 1] >> (((j - 1u) & 1u) * 4u)) & 0x0Fu);
        if (nibble != 0u || j == 1u || !leading) {
            leading = 0;
            dr_text_char(out, cap, n, hex[nibble]);
        }
    }
}

/* Cost: O(W/4). */
uint8_t dr_module_describe(const dr_module_t *m, char *out, uint8_t cap)
{
    uint8_t n = 0;
#if DR_CONF_SYNC
    uint16_t j;
    uint8_t any = 0;
#endif
    if (cap == 0u) {
        return 0;
    }
    dr_text_char(out, cap, &n, 'e');
    dr_text_decimal(out, cap, &n, m->shared.epoch);
    dr_text_str(out, cap, &n, " low");
    dr_text_decimal(out, cap, &n, m->shared.low);
    dr_text_str(out, cap, &n, " done");
    text_set(out, cap, &n, m->shared.done);
    dr_text_str(out, cap, &n, " run");
    if (m->running == DR_NONE) {
        dr_text_char(out, cap, &n, '-');
    } else {
        dr_text_decimal(out, cap, &n, m->running);
        if (m->batch != 0u) {
            dr_text_char(out, cap, &n, '+'); /* the batch's others */
            text_hex(out, cap, &n, m->batch);
        }
        if (m->failures != 0u) {
            dr_text_str(out, cap, &n, " retry"); /* issued again after failing */
            dr_text_decimal(out, cap, &n, m->failures);
        }
    }
#if DR_CONF_SYNC
    /* Synchronous groups: the ready set (as `done`; absent when empty) and the group counted
     * down to. */
    for (j = 0; j < (uint16_t)(W / 8u); j++) {
        any = (uint8_t)(any | m->shared.ready[j]);
    }
    if (any != 0u) {
        dr_text_str(out, cap, &n, " ready");
        text_set(out, cap, &n, m->shared.ready);
    }
    if (m->go_group != DR_NONE) {
        dr_text_str(out, cap, &n, m->go_open ? " went" : " go");
        dr_text_decimal(out, cap, &n, m->go_group);
    }
#endif
    /* DR_PROGRAM_NO_NV: what the module waits for before it may start anything. */
    if (m->unheard != 0u) {
        dr_text_str(out, cap, &n, " hear");
        text_hex(out, cap, &n, (uint32_t)m->unheard);
    }
    if (m->unechoed != DR_NONE) {
        dr_text_str(out, cap, &n, " echo");
        dr_text_decimal(out, cap, &n, m->unechoed);
    }
    if (m->failures == DR_GAVE_UP) {
        dr_text_str(out, cap, &n, " stopped");
    }
    out[n] = '\0';
    return n;
}
