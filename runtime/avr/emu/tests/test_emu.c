/* test_emu.c - the emulated board (dr_avr_emu.c) running a real firmware image (argv[1], the
 * eight2car image of runtime/avr): timer, stepping, sending with the transmitter enables,
 * the controller's bus, receiving through the arbiter, sleep, the painted stack, and a reset
 * that clears RAM and keeps the EEPROM; and (argv[2], the same built with DR_AVR_DESCRIBE)
 * the state descriptions the board reads from the firmware's RAM. */
#include <stdio.h>
#include <string.h>
#include "dr_avr_board.h"
#include "dr_avr_emu.h"

#define CYCLES_PER_MS (DR_AVR_F_CPU / 1000u)

static int failures;

static void check(int ok, const char *what)
{
    if (!ok) {
        printf("FAIL: %s\n", what);
        failures++;
    }
}

struct seen {
    uint32_t step_edges;
    uint64_t first_step;
    uint64_t instant; /* the edge of the first step on an instant */
    uint64_t last_step;
    uint32_t tx_bytes;
    uint8_t tx_mask;
    uint8_t first_frame[DRAV_MAX_FRAME];
    uint32_t releases;
    uint32_t leds_writes;
    uint32_t off_instant; /* step edges not on an instant (first step + k * 5 ms) */
    uint32_t go_writes;
    uint32_t texts;
};

/* How much the time from an instant to its step's edge varies: the wake-up waits for the
 * compare's timer tick (64 cycles) and the instruction under way, then the clock is read
 * and checked before the step. */
#define STEP_LATENCY_CYCLES 300u
#define CYCLES_PER_STEP ((uint64_t)DR_AVR_STEP_MS * CYCLES_PER_MS)

/* Whether a span of cycles between two steps' edges is a whole number of step periods
 * (both on instants), up to the latency either way. */
static int on_instant(uint64_t span)
{
    uint64_t off = span % CYCLES_PER_STEP;
    return off <= STEP_LATENCY_CYCLES || CYCLES_PER_STEP - off <= STEP_LATENCY_CYCLES;
}

/* Runs `ms` milliseconds and tallies the log. */
static void run(struct drav_core *c, uint32_t ms, struct seen *s)
{
    struct drav_event ev[256];
    uint32_t n;
    uint32_t i;
    uint8_t pins = 0;
    check(drav_run(c, drav_cycle(c) + (uint64_t)ms * CYCLES_PER_MS) == 0, "the core runs");
    while ((n = drav_take(c, ev, 256)) > 0u) {
        for (i = 0; i < n; i++) {
            if (ev[i].kind == DRAV_EV_PINS) {
                if ((ev[i].a & (1u << DR_AVR_PIN_STEP)) && !(pins & (1u << DR_AVR_PIN_STEP))) {
                    if (s->step_edges == 0u) {
                        s->first_step = ev[i].cycle; /* at init, off the instants */
                    } else if (s->step_edges == 1u) {
                        s->instant = ev[i].cycle; /* the first on an instant */
                    } else if (!on_instant(ev[i].cycle - s->instant)) {
                        s->off_instant++;
                    }
                    s->last_step = ev[i].cycle;
                    s->step_edges++;
                }
                pins = ev[i].a;
            } else if (ev[i].kind == DRAV_EV_TX) {
                if (s->tx_bytes < DRAV_MAX_FRAME) {
                    s->first_frame[s->tx_bytes] = ev[i].a;
                }
                s->tx_bytes++;
                s->tx_mask = ev[i].b;
            } else if (ev[i].kind == DRAV_EV_RELEASE) {
                s->releases++;
            } else if (ev[i].kind == DRAV_EV_WRITE && ev[i].a == DR_AVR_REG_LEDS) {
                s->leds_writes++;
            } else if (ev[i].kind == DRAV_EV_WRITE && ev[i].a == DR_AVR_REG_GO) {
                s->go_writes++;
            } else if (ev[i].kind == DRAV_EV_TEXT) {
                s->texts++;
            }
        }
    }
}


/* The image built with DR_AVR_DESCRIBE: after init and each step the board logs the
 * runtime's description (the lattice's `e<epoch> low<low> ...`), two characters an entry up
 * to its NUL (the image without it logs none: checked in main). */
static void check_descriptions(const char *path)
{
    char err[256];
    char text[DR_AVR_DESCRIPTION + 2];
    struct drav_event ev[256];
    uint32_t n;
    uint32_t i;
    uint32_t len = 0;
    uint32_t complete = 0;
    struct drav_core *c = drav_open(path, err, sizeof err);
    if (!c) {
        printf("FAIL: %s\n", err);
        failures++;
        return;
    }
    drav_set_reg(c, DR_AVR_REG_ID, 3);
    drav_set_reg(c, DR_AVR_REG_STATUS, 1);
    check(drav_run(c, 50u * CYCLES_PER_MS) == 0, "the describing image runs");
    while ((n = drav_take(c, ev, 256)) > 0u) {
        for (i = 0; i < n; i++) {
            if (ev[i].kind != DRAV_EV_TEXT) {
                continue;
            }
            if (complete == 0u && len + 2u <= sizeof text) {
                text[len++] = (char)ev[i].a;
                text[len++] = (char)ev[i].b;
            }
            if (ev[i].a == 0u || ev[i].b == 0u) {
                complete++;
            }
        }
    }
    check(complete >= 2u, "descriptions after init and the first step");
    check(len >= 2u && text[0] == 'e' && memchr(text, 0, len) != NULL,
          "a description is the runtime's text, NUL-terminated");
    drav_close(c);
}

int main(int argc, char **argv)
{
    char err[256];
    struct drav_core *c;
    struct seen s;
    uint8_t nv[4] = {1, 2, 3, 4};
    uint8_t back[4];
    uint32_t stack;
    uint64_t asleep;
    uint64_t ended;
    uint32_t steps;
    uint32_t len;
    if (argc != 3) {
        printf("usage: test_emu FIRMWARE.elf DESCRIBING-FIRMWARE.elf\n");
        return 2;
    }
    check(drav_open("no/such/image.elf", err, sizeof err) == NULL, "a missing image is refused");
    check(strstr(err, "no/such/image.elf") != NULL, "the error names the file");
    c = drav_open(argv[1], err, sizeof err);
    if (!c) {
        printf("FAIL: %s\n", err);
        return 1;
    }
    check(drav_event_size() == (uint32_t)sizeof(struct drav_event), "event layout");
    drav_set_reg(c, DR_AVR_REG_ID, 3);
    memset(&s, 0, sizeof s);
    /* Steps only when the module asks (dr_module_next_wakeup): a lone lattice module has no
     * neighbour to wait for, so it speaks at the longest adaptive interval (3.2 s), each step
     * on one of the 5 ms instants from the first (a fixed stepping would make 1,600 in 8 s).
     * Module 3 starts its first operation at once. */
    run(c, 8000, &s);
    check(s.step_edges >= 3u && s.step_edges < 100u, "steps only when the module needs them");
    check(s.go_writes == 1u, "module 3 starts an operation");
    check(s.texts == 0u, "no description without DR_AVR_DESCRIBE");
    /* The operation's end (the controller raises INT0) wakes the MCU for a step at the next
     * instant. */
    ended = drav_cycle(c);
    steps = s.step_edges;
    drav_set_reg(c, DR_AVR_REG_STATUS, 1);
    run(c, 10, &s);
    check(s.step_edges > steps && s.last_step - ended <= CYCLES_PER_STEP + STEP_LATENCY_CYCLES,
          "the operation's end makes a step at the next instant");
    check(s.off_instant == 0u, "every step on an instant (k * 5 ms after the first)");
    check(s.leds_writes >= 1u, "init shows the address on the LEDs through the bus");
    /* Broadcasts: whole frames, on every transmitter, byte 1 the length. */
    check(s.tx_bytes > 0u, "the module broadcasts");
    check(s.tx_mask == 0xFFu, "a broadcast enables every transmitter");
    len = s.first_frame[1];
    check(len >= 8u && s.tx_bytes % len == 0u, "frames are whole");
    check(drav_sleep_cycles(c) > 990u * CYCLES_PER_MS, "the MCU sleeps most of the time");
    stack = drav_stack_high_water(c);
    check(stack > 16u && stack < 1024u, "the painted stack shows a plausible depth");
    /* Its own frame comes back on channel 2: the firmware takes it and releases the arbiter,
     * twice (the second waits for the first). */
    check(drav_rx(c, 2, s.first_frame, len) == 0, "a frame is queued");
    check(drav_rx(c, 2, s.first_frame, len) == 0, "a second frame is queued");
    memset(&s, 0, sizeof s);
    run(c, 100, &s);
    check(s.releases == 2u, "both frames were received and released");
    /* Frames whose length byte no frame can have (below 2, above DR_CONF_MAX_PACKET) are
     * dropped at that byte: the arbiter is released and passes the next frame. */
    {
        static const uint8_t too_short[2] = {0x5A, 1};
        static const uint8_t too_long[2] = {0x5A, 200};
        check(drav_rx(c, 1, too_short, 2) == 0 && drav_rx(c, 1, too_long, 2) == 0 &&
                  drav_rx(c, 2, s.first_frame, len) == 0,
              "frames with impossible lengths are queued");
        memset(&s, 0, sizeof s);
        run(c, 100, &s);
        check(s.releases == 3u, "impossible lengths released at once, then the frame after them");
    }
    check(drav_rx(c, 0, back, DRAV_MAX_FRAME + 1u) == -1, "an over-long frame is refused");
    /* EEPROM survives a reset; the steps start again from scratch. */
    check(drav_eeprom_write(c, 4000, nv, 4) == 0, "EEPROM write");
    check(drav_eeprom_write(c, 4094, nv, 4) == -1, "EEPROM bounds");
    drav_reset(c);
    check(drav_eeprom_read(c, 4000, back, 4) == 0 && memcmp(nv, back, 4) == 0,
          "EEPROM kept across a reset");
    check(drav_stack_high_water(c) == 0u, "the stack is painted again at reset");
    memset(&s, 0, sizeof s);
    run(c, 20, &s);
    check(s.leds_writes == 1u, "the firmware starts again after a reset");
    asleep = drav_sleep_cycles(c);
    run(c, 100, &s);
    check(drav_sleep_cycles(c) - asleep > 50u * CYCLES_PER_MS, "the MCU sleeps again after a reset");
    check(!drav_overflowed(c), "no log entry lost");
    drav_close(c);
    check_descriptions(argv[2]);
    if (failures == 0) {
        printf("test_emu: all checks passed\n");
    }
    return failures == 0 ? 0 : 1;
}
