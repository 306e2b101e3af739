/* test_nv.c - a record written to the EEPROM survives a reset: each image named on the command
 * line is nv_program.c linked with dr_avr.c under one build's compiler options (Makefile,
 * `make test`), run on the emulated board from a blank EEPROM through two resets. Each start
 * says on the LEDs what it found (nv_program.h); the EEPROM is also read from outside. */
#include <stdio.h>
#include <string.h>
#include "dr_avr_board.h"
#include "dr_avr_emu.h"
#include "nv_program.h"

#define CYCLES_PER_MS (DR_AVR_F_CPU / 1000u)
/* Long enough for a start's 24 byte writes (a few ms each) and reads. */
#define START_MS 500u

static int failures;

static void check(int ok, const char *image, const char *what)
{
    if (!ok) {
        printf("FAIL: %s: %s\n", image, what);
        failures++;
    }
}

/* Runs one start; returns the LEDs' last value (-1 if never set), and how many times they
 * were set in `writes`. */
static int run_start(struct drav_core *c, uint32_t *writes)
{
    struct drav_event ev[256];
    uint32_t n;
    uint32_t i;
    int leds = -1;
    *writes = 0;
    if (drav_run(c, drav_cycle(c) + (uint64_t)START_MS * CYCLES_PER_MS) != 0) {
        return -2;
    }
    while ((n = drav_take(c, ev, 256)) > 0u) {
        for (i = 0; i < n; i++) {
            if (ev[i].kind == DRAV_EV_WRITE && ev[i].a == DR_AVR_REG_LEDS) {
                leds = ev[i].b;
                (*writes)++;
            }
        }
    }
    return leds;
}

/* Whether the EEPROM's first and last NV_RECORD bytes hold `r`, read from outside. */
static int holds(struct drav_core *c, const uint8_t *r)
{
    uint8_t buf[NV_RECORD];
    return drav_eeprom_read(c, 0, buf, NV_RECORD) == 0 && memcmp(buf, r, NV_RECORD) == 0 &&
           drav_eeprom_read(c, NV_EEPROM_SIZE - NV_RECORD, buf, NV_RECORD) == 0 &&
           memcmp(buf, r, NV_RECORD) == 0;
}

static void test_image(const char *path)
{
    static const uint8_t a[NV_RECORD] = NV_RECORD_A;
    static const uint8_t b[NV_RECORD] = NV_RECORD_B;
    static const uint8_t blank[NV_RECORD] = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                             0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
    char err[256];
    uint32_t writes;
    uint8_t middle[NV_RECORD];
    struct drav_core *c = drav_open(path, err, sizeof err);
    if (!c) {
        printf("FAIL: %s\n", err);
        failures++;
        return;
    }
    check(holds(c, blank), path, "the EEPROM starts blank");
    check(run_start(c, &writes) == NV_WROTE_A && writes == 1u, path,
          "power-on: record A written and read back");
    check(holds(c, a), path, "the EEPROM holds record A");
    drav_reset(c);
    check(run_start(c, &writes) == NV_WROTE_B && writes == 1u, path,
          "after a reset: record A found, record B written over it");
    check(holds(c, b), path, "the EEPROM holds record B");
    drav_reset(c);
    check(run_start(c, &writes) == NV_FOUND_B && writes == 1u, path,
          "after a second reset: record B found");
    check(drav_eeprom_read(c, 2048, middle, NV_RECORD) == 0 &&
              memcmp(middle, blank, NV_RECORD) == 0,
          path, "the bytes between the records were not written");
    check(!drav_overflowed(c), path, "no log entry lost");
    drav_close(c);
}

/* Whether the EEPROM holds anything but erased bytes; a copy of it in `out`. */
static int written(struct drav_core *c, uint8_t *out)
{
    uint32_t i;
    if (drav_eeprom_read(c, 0, out, NV_EEPROM_SIZE) != 0) {
        return 0;
    }
    for (i = 0; i < NV_EEPROM_SIZE; i++) {
        if (out[i] != 0xFFu) {
            return 1;
        }
    }
    return 0;
}

/* A runtime's image (the lattice protocol's, with its NV record): module 3 writes its record
 * at its first start (its address and state), and finds it unchanged after a reset (it
 * writes only what differs, and nothing differs before its operation ends). */
static void test_runtime_image(const char *path)
{
    static uint8_t first[NV_EEPROM_SIZE];
    static uint8_t again[NV_EEPROM_SIZE];
    char err[256];
    uint32_t writes;
    struct drav_core *c = drav_open(path, err, sizeof err);
    if (!c) {
        printf("FAIL: %s\n", err);
        failures++;
        return;
    }
    drav_set_reg(c, DR_AVR_REG_ID, 3);
    check(!written(c, first), path, "the EEPROM starts blank");
    check(run_start(c, &writes) != -2, path, "the core runs");
    check(written(c, first), path, "the runtime wrote its record at its first start");
    drav_reset(c);
    check(run_start(c, &writes) != -2, path, "the core runs after a reset");
    check(written(c, again) && memcmp(first, again, NV_EEPROM_SIZE) == 0, path,
          "the record is kept across the reset");
    drav_close(c);
}

int main(int argc, char **argv)
{
    int i;
    int images = 0;
    if (argc < 2) {
        printf("usage: test_nv NV-IMAGE.elf... [--runtime IMAGE.elf...]\n");
        return 2;
    }
    for (i = 1; i < argc && strcmp(argv[i], "--runtime") != 0; i++) {
        test_image(argv[i]);
        images++;
    }
    for (i++; i < argc; i++) {
        test_runtime_image(argv[i]);
        images++;
    }
    if (failures == 0) {
        printf("test_nv: a record written survives a reset, in all %d images\n", images);
    }
    return failures == 0 ? 0 : 1;
}
