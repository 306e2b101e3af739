/* dr_hal.h - the hardware a module's runtime needs, as functions the platform provides.
 *
 * Every function takes the module context, so the simulator can run many modules of the same
 * code in one process while an MCU has one static instance. The platform implements these;
 * the runtime never touches hardware otherwise. */
#ifndef DR_HAL_H
#define DR_HAL_H

#include <stdint.h>

struct dr_module; /* defined by the protocol's runtime; its entry points: dr_module.h */

/* Status of the operations started with dr_hal_op_start: DR_OP_DONE once every operation
 * started so far has taken effect, DR_OP_FAILED once all have ended and one failed (a new
 * start after either begins a new set). Several run on one module at once: the paper
 * protocol's blocks and the lattice protocol's batches start several and wait for all. */
enum dr_op_status {
    DR_OP_RUNNING = 0,
    DR_OP_DONE = 1,
    DR_OP_FAILED = 2
};

/* Milliseconds since power-on (wraps after 49 days). */
uint32_t dr_hal_now_ms(struct dr_module *m);
/* A pseudo-random 16-bit number (for broadcast jitter). */
uint16_t dr_hal_random(struct dr_module *m);

/* Sends `len` bytes on every channel the module can send on (continuous local broadcast). */
void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len);
/* Sends `len` bytes on one channel (connector) only: the token baseline's routed hand-overs
 * and acknowledgements. Protocols that only broadcast never call it. */
void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len);
/* Incoming packets are handed to dr_module_receive() (dr_module.h) by the platform. */

/* Starts the robot operation of statement `statement` (its number in the generated program,
 * as in dr_meta.c): `op` is the plugin's operation code (generated dr_program.h), `index` the
 * part index (connector or joint; 0 if the part has none), `args` its arguments. The statement
 * number lets a platform log or check exactly which statement runs (the simulator's S1-S3
 * checks rest on it); the operation is fully described by (op, index, args).
 * Operations are idempotent: re-issuing one that already took effect completes at once.
 * A member of a synchronous group (its row's sync_size is not 0: `sync { ... }`, lattice
 * runtime only) is started on every member's module at one agreed instant, and must move at
 * the pace that makes it take as long as the group's longest member (the rows sync_index
 * back from it are its group), so that all of them keep in lock-step (lattice/README.md,
 * "Synchronous groups"). */
void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args);
/* Whether the started operations are still running, all done, or one failed. */
enum dr_op_status dr_hal_op_status(struct dr_module *m);

/* What role predicates may ask (see docs/language.md). */
uint16_t dr_hal_id(struct dr_module *m);
uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector);
/* ID of the module latched to `connector`, -1 when none. */
int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector);
int16_t dr_hal_joint(struct dr_module *m, uint8_t joint);

/* Shows a small number on the module's LEDs (debugging aid; may do nothing). */
void dr_hal_leds(struct dr_module *m, uint8_t value);

/* Non-volatile storage (EEPROM on the ATmega128, a per-module store in the simulator):
 * `len` bytes at byte address `addr`. Reads of never-written storage return 0xFF bytes. */
void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len);
void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len);

/* Constant tables. The generated program's tables (statements, dependencies, routes,
 * arguments) are declared DR_TABLE and the runtime reads them only through
 * dr_hal_table_read(): on the AVR (separate program and data memories) they stay in flash and
 * are read with avr-libc's memcpy_P, where avr-gcc would otherwise copy every `const` table
 * to RAM at start-up; elsewhere they are ordinary constant data and the read is a memcpy. A
 * program's top-level descriptor (dr_program) stays ordinary: it holds pointers to the
 * tables and is read at every step. */
#if defined(__AVR__)
#include <avr/pgmspace.h>
#define DR_TABLE PROGMEM
#define dr_hal_table_read(dst, table, n) memcpy_P((dst), (table), (n))
#else
#include <string.h>
#define DR_TABLE
#define dr_hal_table_read(dst, table, n) memcpy((dst), (table), (n))
#endif

#endif /* DR_HAL_H */
