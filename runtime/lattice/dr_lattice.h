/* dr_lattice.h - the lattice protocol: shared state as a join-semilattice, statements started
 * when their dependencies are complete, resets survived through non-volatile storage (or,
 * with DR_PROGRAM_NO_NV, through the neighbours' copies: a weaker guarantee, see README.md).
 *
 * The generated dr_program.c provides one dr_program_t (the statement table); the platform
 * provides dr_hal.h and calls dr_module_init, dr_module_step and dr_module_receive. */
#ifndef DR_LATTICE_H
#define DR_LATTICE_H

#include <stdint.h>
#include "dr_conf.h"
#include "dr_hal.h"
#include "dr_dissemination.h"
#include "dr_module.h"
#include "dr_packet.h"

/* Bytes of a state payload before its DR_CONF_WINDOW / 8 bytes of done bits: epoch (2) and
 * low (2), big-endian. The compiler reads this line to size the frame (one source). */
#define DR_LATTICE_PAYLOAD_FIXED 4u
/* Bytes a state frame carries after the payload with DR_CONF_SYNC: the synchronous group the
 * sender counts down to (2) and how long ago, in ms, it learnt the group was ready (2), both
 * big-endian (README.md, "Synchronous groups"). The compiler reads this line too. */
#define DR_LATTICE_GO_BYTES 4u

/* dr_module_t.failures of a module whose failure policy gave up: it starts nothing more. */
#define DR_GAVE_UP 0xFFu

/* Returned by a program's address_of when no role, or several, match this module. */
#define DR_NO_ADDRESS 0xFFu
#define DR_MANY_ADDRESSES 0xFEu

/* Bits of dr_program_t.options (0: the default behaviour).
 * DR_PROGRAM_NO_NV: the hardware has no non-volatile storage; the runtime never reads or writes
 * it. After a (re)start a module acts only once it has heard a packet from every neighbour
 * connected at that moment and still connected (it waits as long as one stays silent, and
 * forgets one that unlatched only once it has heard another), and it starts nothing while
 * its own last completion has not been echoed back by a neighbour.
 * Survives one reset at a time, not two close together (README.md, "Without NV").
 * DR_CONF_NV (dr_conf.h, set by the generated header) fixes the mode at compile time; only
 * with DR_CONF_NV_EITHER does the runtime follow this bit. */
#define DR_PROGRAM_NO_NV 0x01u

/* A statement number in the dependency table (generated dr_program_deps): one byte when the
 * program has at most 256 statements (DR_CONF_MAX_STATEMENTS, which the compiler sets), so
 * the table takes half the flash and each read of it one byte. */
#if DR_CONF_MAX_STATEMENTS <= 256
typedef uint8_t dr_dep_t;
#else
typedef uint16_t dr_dep_t;
#endif

/* A statement number (low-water mark, running batch, awaited echo) and an offset in the
 * window: one byte when every statement number, DR_NONE and every offset fit in it (fewer
 * than 255 statements, a window of at most 248), so the runtime's arithmetic on them is one
 * byte wide on an 8-bit core. Sums of a number and an offset are formed in `unsigned` (C's
 * promotion) and compared before they are narrowed. */
#if DR_CONF_MAX_STATEMENTS < 255 && DR_CONF_WINDOW <= 248
typedef uint8_t dr_stmt_t;
#else
typedef uint16_t dr_stmt_t;
#endif
/* No statement (the value of `running` and `unechoed` when there is none). */
#define DR_NONE ((dr_stmt_t)~(dr_stmt_t)0)

/* A position in the dependency table, and a row of the argument table: one byte each when
 * the program's tables are that small (DR_CONF_DEP_ENTRIES and DR_CONF_ARG_ROWS, which the
 * compiler sets), so each statement takes 6 bytes of flash. */
#if DR_CONF_DEP_ENTRIES <= 255
typedef uint8_t dr_dep_at_t;
#else
typedef uint16_t dr_dep_at_t;
#endif
#if DR_CONF_ARG_ROWS <= 256
typedef uint8_t dr_args_at_t;
#else
typedef uint16_t dr_args_at_t;
#endif

/* One statement of the compiled sequence (generated, constant). Statement indices are source
 * order after expansion; `deps` lists the statements that must be complete before this one
 * starts (the previous parallel group: the sequence's meaning; a module's statements that
 * may overlap run together, README.md "Start"). */
typedef struct {
    uint8_t address;                   /* the module (role or M<k>) that runs it */
    uint8_t op;                        /* operation code, DR_OP_* of the generated header */
    uint8_t index;                     /* part index (connector, joint); 0 when none */
    uint8_t n_deps;
    dr_dep_at_t first_dep;             /* position of its first dependency in deps[] */
    dr_args_at_t args;                 /* its arguments: row `args` of the program's args[] */
#if DR_CONF_SYNC
    uint8_t sync_size;                 /* members of its synchronous group; 0: none */
    uint8_t sync_index;                /* its place in the group (the first is statement
                                          number minus this) */
#endif
} dr_statement_t;

/* A compiled sequence (generated, constant). */
typedef struct {
    uint32_t fingerprint;              /* packets of another program are foreign */
    uint16_t n_statements;
    const dr_statement_t *statements;
    const dr_dep_t *deps;
    const int16_t *args;               /* argument lists, DR_CONF_MAX_ARGS per row (each
                                          distinct list once) */
    uint16_t n_epochs;                 /* runs of the whole sequence before the end; 0: forever */
    uint8_t (*address_of)(struct dr_module *m); /* evaluates the role predicates */
    uint8_t options;                   /* DR_PROGRAM_* bits; 0: the default behaviour */
} dr_program_t;

/* A set of channels (connectors), bit c = channel c. */
#if DR_CONF_CHANNELS <= 8
typedef uint8_t dr_channels_t;
#elif DR_CONF_CHANNELS <= 16
typedef uint16_t dr_channels_t;
#else
typedef uint32_t dr_channels_t;
#endif

/* The shared state: epoch, low-water mark (every statement below it is complete in this
 * epoch) and, for the window of statements above it, the completed bits. Which statements
 * have started is not shared: nothing decides on it (a module's own running batch is
 * `running` and `batch`). */
typedef struct {
    uint16_t epoch;
    dr_stmt_t low;
    uint8_t done[DR_CONF_WINDOW / 8];
#if DR_CONF_SYNC
    /* The statements of synchronous groups whose modules are ready to start them (a done
     * statement is ready too): a group starts once all its members are. Same window. */
    uint8_t ready[DR_CONF_WINDOW / 8];
#endif
} dr_shared_t;

/* A report counter (DR_CONF_COUNTER_BITS). */
#if DR_CONF_COUNTER_BITS == 16
typedef uint16_t dr_counter_t;
#else
typedef uint32_t dr_counter_t;
#endif

/* All per-module state (one per module; the simulator has many, an MCU one). */
typedef struct dr_module {
    void *platform;                    /* the platform's own data; the runtime never reads it */
    const dr_program_t *program;
    dr_identity_t identity;            /* DR_ROBOT_ID; program fingerprint ^ execution */
    uint8_t address;
    dr_shared_t shared;
    dr_stmt_t running;                 /* first statement of the batch being executed
                                          here, or DR_NONE */
    uint16_t running_epoch;            /* the epoch it started in */
    uint8_t batch;                     /* the batch's others: bit k = statement running+1+k */
    uint8_t failures;                  /* times the running batch failed and was issued again,
                                          or DR_GAVE_UP once the failure policy stopped the
                                          module (dr_conf.h, DR_CONF_ON_FAILURE) */
    /* DR_PROGRAM_NO_NV only (otherwise unheard = 0 and unechoed = DR_NONE, always): */
    dr_stmt_t unechoed;                /* own completion (its epoch: running_epoch) that no
                                          neighbour has sent back yet, or DR_NONE */
    dr_channels_t unheard;             /* channels connected at the (re)start, not heard yet */
    uint8_t heard;                     /* a state packet arrived since the (re)start */
#if DR_CONF_SYNC
    uint8_t relay;                     /* news of a synchronous group: send at the next step */
    uint8_t go_open;                   /* the countdown of go_group is over */
    dr_stmt_t go_group;                /* first statement of the synchronous group this module
                                          counts down to, or DR_NONE */
    uint16_t go_epoch;                 /* the epoch of go_group */
    uint32_t go_at_ms;                 /* when go_group starts, on this module's clock */
    uint32_t go_repeat_ms;             /* the countdown's next repeat (DR_CONF_SYNC_REPEAT_MS) */
#endif
    uint32_t next_broadcast_ms;        /* the next broadcast, and (adaptive) the next retry
                                          of a failed operation: the one timer of the runtime */
    /* The dissemination policy's own fields (dr_dissemination.h; none for the fixed period). */
    DR_DISSEMINATION_STATE
    /* counters, for reports */
    dr_counter_t packets_sent;
    dr_counter_t packets_received;
    dr_counter_t packets_malformed;
    dr_counter_t packets_foreign;
    uint16_t resets;
} dr_module_t;


/* Starts (or restarts after a reset) a module: finds its address, restores the shared state
 * from non-volatile storage when it is valid (with DR_PROGRAM_NO_NV: evaluates the role
 * predicates, starts from the bottom and notes the connected channels to hear from first).
 * With DR_CONF_ONE_PROGRAM (an MCU's image), `program` is the generated dr_program: the
 * runtime reads that one's fields as constants. Cost: O(statements + DR_CONF_CHANNELS). */
void dr_module_init(dr_module_t *m, const dr_program_t *program, void *platform);
/* The entry points of dr_module.h, for this protocol:
 * - dr_module_step: merging is done on receipt; a step starts or polls the module's own
 *   operations (a batch, README.md "Start") and broadcasts when due. Cost: O(statements).
 * - dr_module_receive: with DR_PROGRAM_NO_NV a valid packet counts as hearing that
 *   neighbour. Cost: O(len + W).
 * - dr_module_next_wakeup: always DR_WAKE_AT the broadcast deadline (next_broadcast_ms,
 *   however it is set), plus DR_WAKE_OP while an operation of its own runs (its completion;
 *   a failed one is retried at the deadline), or DR_WAKE_AT now when the next step would act
 *   at once: a statement can start (a received packet completed its dependencies), or, with
 *   DR_PROGRAM_NO_NV, a neighbour is still awaited after another was heard (the step re-reads
 *   the links). Between the broadcasts of an idle module nothing runs: on an MCU the
 *   module sleeps until its timer, its receiver or its actuator wakes it. Cost: O(W * deps).
 * - dr_module_finished: DR_END_GOAL once the last epoch is complete, DR_END_STOPPED once an
 *   operation of the module's failed and its policy gave up (DR_CONF_ON_FAILURE). Cost: O(1).
 * - dr_module_describe: `e<epoch> low<low> done<window> run<statement>`, decimal except `done`, the completed set
 * of the window as a hexadecimal number (bit i: statement low + i; no leading zeros), and
 * `run-` when nothing runs here; a batch's other statements follow the first as `+<hex>`
 * (bit k: statement run + 1 + k); e.g. "e0 low3 done5 run4", "e0 low22 done0 run22+1". With DR_PROGRAM_NO_NV, what the
 * module waits for follows: ` hear<channels>` (hexadecimal, bit c = channel c) while a
 * neighbour connected at the restart has not been heard, ` echo<statement>` while its own
 * completion has not been sent back; e.g. "e0 low0 done0 run- hear11". With DR_CONF_SYNC,
 * after `run`: ` ready<window>` (hexadecimal as `done`; absent when empty) and ` go<statement>`
 * while the module counts down to the synchronous group whose first statement that is
 * (` went<statement>` once the countdown is over and until the group is done); e.g.
 * "e0 low0 done0 run- ready3 go0". A module whose failure policy gave up ends with ` stopped`;
 * one that issues a failed batch again shows how many times after `run`: ` retry<n>`.
 * Cost: O(W/4). */

/* The semilattice (exported for tests and for the model checker's reference):
 * join: commutative, associative, idempotent; normalise: advance the low-water mark over the
 * completed prefix and roll over to the next epoch when everything is complete. */
void dr_shared_join(dr_shared_t *into, const dr_shared_t *other, uint16_t n_statements);
void dr_shared_normalise(dr_shared_t *s, uint16_t n_statements);
uint8_t dr_shared_is_done(const dr_shared_t *s, dr_stmt_t statement);
#if DR_CONF_SYNC
/* Whether `statement` is ready (its module is set to start it with its synchronous group)
 * or done, in s's epoch. */
uint8_t dr_shared_is_ready(const dr_shared_t *s, dr_stmt_t statement);
#endif
/* Encode/decode the payload of a DR_PACKET_LATTICE_STATE packet; decode returns 0 when the
 * payload has the wrong size or inconsistent fields. */
uint8_t dr_shared_encode(const dr_shared_t *s, uint8_t *out, uint8_t cap);
uint8_t dr_shared_decode(dr_shared_t *s, const uint8_t *in, uint8_t len, uint16_t n_statements);

#endif /* DR_LATTICE_H */
