/* dr_fake.h - the one fake platform of the runtime's C tests (lattice, paper, token): every
 * function of dr_hal.h, on one dr_fake_t per module, and the tests' assertion helpers.
 *
 * The fake holds the plain hardware of a module: its ID, clock, random numbers, LEDs, NV
 * store, connectors, the last operation started (and its status) and the last packet sent,
 * and counts the HAL calls with an effect (the tickless checks: a step that
 * dr_module_next_wakeup said could be skipped must have none). A test's world (a network that
 * loses and delays, operations that take time, S1/S2 checks, faults) adds its behaviour
 * through hooks; a hook left 0 keeps the fake's own behaviour, written next to it below.
 *
 * The world owns the modules and their fakes; the one thing the fake needs from it is
 * dr_fake_of (one line: m->platform is the world's record, whose fake it returns), because
 * only the suite knows its protocol's dr_module_t. */
#ifndef DR_FAKE_H
#define DR_FAKE_H

#include <stdint.h>
#include "dr_conf.h"
#include "dr_hal.h"

#define DR_FAKE_NV 256u
/* The channel dr_hal_broadcast sends on, for the send hook. */
#define DR_FAKE_BROADCAST 0xFFu

struct dr_fake;

typedef struct {
    /* The clock (0: the fake's now_ms). */
    uint32_t (*now_ms)(struct dr_module *m);
    /* A random number (0: a per-module linear congruential generator seeded by dr_fake_init). */
    uint16_t (*random)(struct dr_module *m);
    /* A packet on one channel, or on every one (DR_FAKE_BROADCAST), after the fake kept it
     * as the last packet (0: nothing else happens; the test delivers by hand). */
    void (*send)(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len);
    /* An operation started, after the fake noted it (0: it runs until the test sets status). */
    void (*op_start)(struct dr_module *m);
    /* The operation's status (0: the fake's status). */
    enum dr_op_status (*op_status)(struct dr_module *m);
    /* Whether a connector is connected (0: bit c of the fake's connected). */
    uint8_t (*connected)(struct dr_module *m, uint8_t connector);
    /* An NV write about to happen (0: none); the hook may tear it (power failure). */
    void (*nv_write)(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len);
    /* A call the hardware would not accept (NV out of range, a packet of a bad length), with
     * the offending value (0: counted in dr_fake_misuses and printed). */
    void (*misuse)(struct dr_module *m, const char *what, uint32_t value);
} dr_fake_hooks_t;

typedef struct dr_fake {
    const dr_fake_hooks_t *hooks;  /* never 0 after dr_fake_init */
    uint16_t id;
    uint32_t now_ms;
    uint16_t random;               /* the generator's state */
    uint32_t connected;            /* bit c: connector c is connected */
    uint8_t leds;
    /* the last operation started */
    enum dr_op_status status;
    uint16_t statement;
    uint8_t op;
    uint8_t index;
    int16_t args[DR_CONF_MAX_ARGS];
    uint16_t n_starts;             /* operations started since dr_fake_init */
    /* the last packet sent */
    uint8_t packet[DR_CONF_MAX_PACKET];
    uint8_t packet_len;
    uint8_t packet_channel;
    /* the NV store (erased: 0xFF) */
    uint8_t nv[DR_FAKE_NV];
    uint32_t nv_reads;
    uint32_t nv_writes;
    uint32_t effects;              /* HAL calls with an effect: sends, random, ops, LEDs, NV */
} dr_fake_t;

/* A module's fake, defined by the test's world (see the file's header). */
dr_fake_t *dr_fake_of(struct dr_module *m);

/* Module `id`'s fake: clock 0, nothing connected, nothing running (DR_OP_DONE), NV erased,
 * the generator seeded with id + 1. `hooks` may be 0 (no hooks). */
void dr_fake_init(dr_fake_t *f, uint16_t id, const dr_fake_hooks_t *hooks);

/* Misuses no hook took (over the whole test program). */
extern unsigned long dr_fake_misuses;

/* ---- Assertions: count and report, never abort, so one run shows every failure ---- */
extern unsigned long dr_fake_checks;
extern unsigned long dr_fake_failures;
#define CHECK(cond) dr_fake_check((cond) != 0, #cond, __FILE__, __LINE__)
#define CHECK_EQ(a, b) dr_fake_check_eq((long)(a), (long)(b), #a, #b, __FILE__, __LINE__)
int dr_fake_check(int ok, const char *what, const char *file, int line);
int dr_fake_check_eq(long a, long b, const char *sa, const char *sb, const char *file, int line);
/* Counts a failure found otherwise (printed by the caller). */
void dr_fake_fail(void);
/* Prints `name: N checks, M failed` (misuses are failures); returns the exit code. */
int dr_fake_done(const char *name);

#endif /* DR_FAKE_H */
