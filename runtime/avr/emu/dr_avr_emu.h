/* dr_avr_emu.h - one emulated hemisphere board: an ATmega128 (simavr) running a
 * firmware image of runtime/avr, and the board around it (dr_avr_board.h): the controller's
 * registers, the infrared receive arbiter, and a log of what the MCU does to the world.
 *
 * The host (dynarole-sim's firmware runner, or tests/test_emu.c) steps a core in cycles and,
 * between runs, reads the log (bytes sent with the transmitter enables, register writes,
 * status pin changes, arbiter releases), sets the sensor registers and queues received
 * frames. Built as a shared library against simavr (`pkg-config simavr`). */
#ifndef DR_AVR_EMU_H
#define DR_AVR_EMU_H

#include <stdint.h>

struct drav_core;

/* Kinds of log entries. */
enum {
    DRAV_EV_TX = 1,      /* a = byte sent on the USART, b = the transmitter enables (PORTC) */
    DRAV_EV_WRITE = 2,   /* a = controller register written, b = value */
    DRAV_EV_PINS = 3,    /* a = new value of PORTE (the status pins) */
    DRAV_EV_RELEASE = 4, /* the firmware released the receive arbiter */
    DRAV_EV_TEXT = 5,    /* a, b = two characters of the module's state description (images
                          * with DR_AVR_DESCRIBE); the last entry of one holds its NUL */
};

struct drav_event {
    uint64_t cycle; /* the core's cycle count when it happened */
    uint8_t kind;
    uint8_t a;
    uint8_t b;
    uint8_t reserved;
    uint32_t reserved2;
};

/* Longest frame the arbiter passes on (the USART's receive FIFO holds 64 bytes). */
#define DRAV_MAX_FRAME 64u
/* Frames the arbiter holds while the firmware receives another. */
#define DRAV_RX_QUEUE 8u
/* Log entries kept between two drav_take calls. */
#define DRAV_EVENTS 4096u

uint32_t drav_event_size(void);
/* Loads the ELF image at `path` into a new ATmega128 at 16 MHz and resets it; NULL on error,
 * with a message in `err` (at most `cap` bytes with the NUL). */
struct drav_core *drav_open(const char *path, char *err, uint32_t cap);
void drav_close(struct drav_core *core);
/* A reset (also power-on): the MCU restarts from address 0, RAM and I/O registers cleared,
 * EEPROM kept; the arbiter forgets queued frames; the stack area is painted again. The
 * cycle count goes on. */
void drav_reset(struct drav_core *core);
/* Runs until the cycle count reaches `cycle` (an instruction may end a few cycles after it;
 * a sleeping core costs one step per timer event, not per cycle). Returns 0, or 1 when the
 * core has stopped (crashed, or slept with interrupts off). */
int drav_run(struct drav_core *core, uint64_t cycle);
uint64_t drav_cycle(const struct drav_core *core);
/* Cycles spent asleep since drav_open. */
uint64_t drav_sleep_cycles(const struct drav_core *core);
/* Sets controller register `reg` (the sensors: status, ID, latches, neighbours, joints).
 * The status also drives the operation-end line (INT0): high unless RUNNING. */
void drav_set_reg(struct drav_core *core, uint8_t reg, uint8_t value);
/* Moves up to `cap` log entries to `out`, oldest first; returns how many. */
uint32_t drav_take(struct drav_core *core, struct drav_event *out, uint32_t cap);
/* Whether log entries were lost (the log was full) since drav_open. */
int drav_overflowed(const struct drav_core *core);
/* Queues a frame received on `channel` for the firmware; returns 0, or -1 when it is too
 * long or the arbiter's queue is full (the frame is lost). */
int drav_rx(struct drav_core *core, uint8_t channel, const uint8_t *bytes, uint32_t len);
/* Deepest stack use since the last reset, in bytes (painted stack). */
uint32_t drav_stack_high_water(const struct drav_core *core);
/* Reads `len` bytes of the EEPROM at `addr`; returns 0, or -1 outside the EEPROM. */
int drav_eeprom_read(struct drav_core *core, uint16_t addr, uint8_t *out, uint32_t len);
/* Writes `len` bytes into the EEPROM at `addr` (as a programmer would); 0, or -1 outside. */
int drav_eeprom_write(struct drav_core *core, uint16_t addr, const uint8_t *bytes, uint32_t len);

#endif /* DR_AVR_EMU_H */
