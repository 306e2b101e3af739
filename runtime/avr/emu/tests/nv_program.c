/* nv_program.c - a stand-in for a compiled program, linked with dr_avr.c in place of the
 * runtime, that tests the board's EEPROM (dr_hal_nv_write, dr_hal_nv_read) on the emulated
 * board (test_nv.c) under each build's compiler options: what a record written before a
 * reset reads after it. The EEPROM's timed sequence (EEWE within four cycles of EEMWE) is
 * what the options could break, and simavr, like the chip, writes nothing when it is late.
 *
 * At each start (power-on or reset) it reads its records and says on the LEDs what it found
 * and did:
 *   nothing of its own (a blank EEPROM)  writes record A        LEDs NV_WROTE_A
 *   record A                             writes record B over A  LEDs NV_WROTE_B
 *   record B                             writes nothing          LEDs NV_FOUND_B
 * (B differs from A in some bytes only: the write changes only those). Each written record is read back before the LEDs are set; a record that does not read
 * back sets NV_LOST. The records sit at the EEPROM's first and last bytes, and a write that
 * would run past its end must change nothing (NV_BOUNDS otherwise).
 *
 * Built with a compiled program's headers (for dr_module_t and its sizes), without its C:
 * make -C runtime/avr test builds it as dr_avr.c is built in every image (Makefile). With
 * DR_AVR_NESC it stands in for the nesC component instead (its boot, clock and receive
 * path), as runtime/avr's nesc-image links dr_avr.c. */
#include <stdint.h>
#include "dr_hal.h"
#include "dr_program.h"
#include "nv_program.h"
#ifdef DR_AVR_NESC
#include "dr_nesc_platform.h"
#endif

#define LAST (NV_EEPROM_SIZE - NV_RECORD) /* the record at the EEPROM's end */

static const uint8_t record_a[NV_RECORD] = NV_RECORD_A;
static const uint8_t record_b[NV_RECORD] = NV_RECORD_B;

static uint8_t same(const uint8_t *a, const uint8_t *b)
{
    uint8_t i;
    for (i = 0; i < NV_RECORD; i++) {
        if (a[i] != b[i]) {
            return 0;
        }
    }
    return 1;
}

/* Whether both copies (first and last bytes of the EEPROM) hold `r`. */
static uint8_t holds(struct dr_module *m, const uint8_t *r)
{
    uint8_t buf[NV_RECORD];
    dr_hal_nv_read(m, 0, buf, NV_RECORD);
    if (!same(buf, r)) {
        return 0;
    }
    dr_hal_nv_read(m, LAST, buf, NV_RECORD);
    return same(buf, r);
}

static uint8_t write_both(struct dr_module *m, const uint8_t *r)
{
    dr_hal_nv_write(m, 0, r, NV_RECORD);
    dr_hal_nv_write(m, LAST, r, NV_RECORD);
    return holds(m, r);
}

static uint8_t check(struct dr_module *m)
{
    uint8_t before;
    uint8_t after;
    /* A write one byte past the end is refused whole: the last byte stays as it was. */
    dr_hal_nv_read(m, NV_EEPROM_SIZE - 1u, &before, 1);
    dr_hal_nv_write(m, NV_EEPROM_SIZE - 1u, record_a, 2);
    dr_hal_nv_read(m, NV_EEPROM_SIZE - 1u, &after, 1);
    if (after != before) {
        return NV_BOUNDS;
    }
    if (holds(m, record_b)) {
        return NV_FOUND_B;
    }
    if (holds(m, record_a)) {
        return write_both(m, record_b) ? NV_WROTE_B : NV_LOST;
    }
    return write_both(m, record_a) ? NV_WROTE_A : NV_LOST;
}

/* The entry points dr_avr.c calls: the test runs at the start, then nothing is to do. */

#ifdef DR_AVR_NESC

dr_module_t DynaRoleP__self;

void dr_nesc_boot(void)
{
    dr_hal_leds(&DynaRoleP__self, check(&DynaRoleP__self));
}

void dr_nesc_advance_ms(uint32_t ms)
{
    (void)ms;
}

uint32_t dr_nesc_until_due_ms(void)
{
    return DR_NESC_NEVER;
}

void dr_platform_receive(uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    (void)channel;
    (void)bytes;
    (void)len;
}

#else

void dr_program_init(dr_module_t *m, void *platform)
{
    (void)platform;
    m->address = 0;
    dr_hal_leds(m, check(m));
}

void dr_module_step(struct dr_module *m)
{
    (void)m;
}

void dr_module_receive(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    (void)m;
    (void)channel;
    (void)bytes;
    (void)len;
}

uint8_t dr_module_next_wakeup(struct dr_module *m, uint32_t *at_ms)
{
    (void)m;
    (void)at_ms;
    return 0; /* only a frame would make a step useful */
}

#endif

uint8_t dr_module_finished(const struct dr_module *m)
{
    (void)m;
    return 0;
}
