/* sim.h - the lattice runtime tests' world, on the shared fake platform (runtime/testing/
 * dr_fake.h) through its hooks: modules with clocks, operations that take time, NV stores
 * that tear, a broadcast network (optionally lossy, delaying, duplicating, corrupting),
 * resets, and a record of what was physically done, checked at every operation start. */
#ifndef SIM_H
#define SIM_H

#include <setjmp.h>
#include <stdint.h>
#include "dr_fake.h"
#include "dr_lattice.h"

#define SIM_MAX_NODES 8
#define SIM_MAX_EPOCHS 8
#define SIM_MAX_STATEMENTS 64
#define SIM_NV DR_FAKE_NV
#define SIM_INBOX 256
#define SIM_TICK_MS 5u
#define SIM_NONE 0xFFFFu

/* The longest gap between two broadcasts of a module that hears nothing new (jitter aside),
 * and the pace of a failed operation's retries, for the chosen dissemination. */
#if DR_CONF_LATTICE_DISSEMINATION == DR_DISSEMINATION_ADAPTIVE
#define SIM_LONGEST_GAP_MS ((uint32_t)DR_CONF_LATTICE_INTERVAL_MS << DR_CONF_LATTICE_DOUBLINGS)
#define SIM_RETRY_MS ((uint32_t)DR_CONF_LATTICE_INTERVAL_MS)
#else
#define SIM_LONGEST_GAP_MS ((uint32_t)DR_CONF_BROADCAST_MS)
#define SIM_RETRY_MS ((uint32_t)DR_CONF_BROADCAST_MS)
#endif

typedef struct {
    uint32_t at;
    uint8_t from;                 /* the sender's node number: the channel it arrives on */
    uint8_t len;
    uint8_t bytes[DR_CONF_MAX_PACKET];
} sim_packet_t;

/* One operation of a module's batch (the HAL's view: DONE once all have taken effect). */
typedef struct {
    uint8_t active;
    uint8_t failed;
    uint32_t started_ms;
    uint32_t until;
    uint16_t stmt;
    uint16_t epoch;
} sim_op_t;

#define SIM_OPS DR_CONF_LATTICE_BATCH

typedef struct {
    dr_fake_t fake;               /* the shared fake platform (ID, LEDs, NV store, effects) */
    dr_module_t mod;
    uint8_t address;              /* the node's role: operations are checked against it */
    uint8_t answer;               /* what address_of returns (its role predicates) */
    uint32_t clock_offset;
    uint32_t rng;
    /* the operations started since the HAL last reported that all had ended (a batch) */
    sim_op_t ops[SIM_OPS];
    /* network */
    sim_packet_t inbox[SIM_INBOX];
    uint16_t n_inbox;
    uint8_t mute;                 /* drop what it sends (until its next reset) */
    /* fault plans */
    uint8_t reset_now;
    uint8_t reset_at_set;
    uint32_t reset_at;
    int16_t tear_in;              /* tear the NV write this many writes from now; -1: never */
    uint8_t finished_seen;
    /* tickless: the last dr_module_next_wakeup answer, and whether a reset came since it was
     * given (then the next step may act; packets: the answer is asked again) */
    uint8_t wake;
    uint32_t wake_at;
    uint8_t woken;
} sim_node_t;

typedef struct {
    const dr_program_t *program;
    uint8_t n_nodes;
    sim_node_t nodes[SIM_MAX_NODES];
    uint8_t adj[SIM_MAX_NODES][SIM_MAX_NODES];
    uint32_t time;
    uint32_t rng;
    /* network faults */
    uint8_t loss_percent;
    uint8_t dup_percent;
    uint8_t corrupt_percent;
    uint16_t max_delay_ms;
    uint32_t corrupted;           /* packets corrupted on the way */
    /* record */
    uint16_t starts[SIM_MAX_EPOCHS][SIM_MAX_STATEMENTS];
    uint32_t last_start_ms[SIM_MAX_EPOCHS][SIM_MAX_STATEMENTS];
    uint32_t min_restart_gap_ms;  /* shortest gap between two starts of one statement */
    uint8_t reported[SIM_MAX_EPOCHS][SIM_MAX_STATEMENTS]; /* the runtime saw DR_OP_DONE */
    uint32_t reported_ms[SIM_MAX_EPOCHS][SIM_MAX_STATEMENTS];
    uint32_t max_handover_ms;     /* longest wait from the last dependency done to a start */
    uint8_t checks;               /* check S1/S2 at each start (default 1) */
    uint8_t strict;               /* also: never start an op already reported done */
    uint32_t violations;
    uint8_t quiet;                /* count violations without printing them (expected ones) */
    uint32_t total_starts;
    uint16_t largest_batch;       /* most operations of one module running together */
    /* operation faults */
    uint8_t slow_address;         /* operations of this address take 300 ms longer */
    uint16_t fail_stmt;           /* this statement fails fail_times times first */
    uint8_t fail_times;
    uint16_t reset_after_done_stmt; /* its module resets right after it completes, muted ... */
    uint32_t reset_after_done_ms;   /* ... or, if not 0, this many ms later and not muted */
    uint16_t reset_mid_stmt;        /* its module resets half-way through its operation */
    uint16_t tear_after_done_stmt;  /* its completion's NV write number tear_copy is torn */
    int16_t tear_copy;
    uint16_t fault_epoch;           /* the epoch the three plans above apply to */
    uint8_t fault_fired;
    jmp_buf jmp;
} sim_t;

extern sim_t sim;
/* Over every run since the program started: the steps dr_module_next_wakeup said a tickless
 * platform could skip (each is still run, and checked to change nothing), and those that
 * changed something (must stay 0). */
extern unsigned long sim_skippable_steps;
extern unsigned long sim_skippable_acted;

/* The argument table of every test program: row k is (k, 0, ...). */
extern int16_t sim_args[SIM_MAX_STATEMENTS * DR_CONF_MAX_ARGS];
/* A statement of a test program: op 1, index 0, argument row `self` (its first argument is
 * its own index: the fake platform uses it to know which statement an operation belongs
 * to). */
void sim_statement(dr_statement_t *st, uint8_t address, uint16_t self, uint8_t n_deps,
                   uint16_t first_dep);
uint8_t sim_address_of(struct dr_module *m);

/* Channels: node i's channel c is its link to node c; dr_hal_connected(c) = adj[i][c], and a
 * packet from node c is received on channel c. */

/* Sets up n nodes in a line (node i hears i-1 and i+1), node i with id i and address
 * addresses[i], blank NV stores, no faults, and runs dr_module_init on each. */
void sim_setup(const dr_program_t *program, uint8_t n, const uint8_t *addresses, uint32_t seed);
/* Every node hears every other. */
void sim_full_mesh(void);
/* Runs until every node has finished (returns 1) or max_ms of simulated time pass (0). */
uint8_t sim_run(uint32_t max_ms);
/* Whether an operation of node n's batch is still running; the latest end of its batch. */
uint8_t sim_op_running(const sim_node_t *n);
uint32_t sim_op_until(const sim_node_t *n);
/* Resets node i (its NV store survives; its operation and receive buffer do not). */
void sim_reset(uint8_t i);
uint32_t sim_rand(void);

#endif /* SIM_H */
