/* dr_paper.h - the paper's protocol, faithfully (Sec. III, Fig. 2-4): a global state
 * (active state, active address, pending set) shared by continuous broadcast and merged on
 * receipt by the Fig. 3 function, in one of its three historical variants.
 *
 * The generated dr_program.c provides a dr_paper_program_t whose `step` is the state machine
 * in the shape of Fig. 2; it calls the functions below. */
#ifndef DR_PAPER_H
#define DR_PAPER_H

#include <stdint.h>
#include "dr_conf.h"
#include "dr_hal.h"
#include "dr_module.h"
#include "dr_packet.h"

/* Bytes of a state payload before its DR_CONF_MAX_PENDING pending slots: alternate flag,
 * global state, recipient. The compiler reads this line to size the frame (one source). */
#define DR_PAPER_PAYLOAD_FIXED 3u

#define DR_NO_ADDRESS 0xFFu
#define DR_MANY_ADDRESSES 0xFEu
#define DR_STATE_INITIAL 0u
#define DR_STATE_END 254u
#define DR_STATE_IDLE 255u      /* "nothing": the local state of a module with nothing to do */
#define DR_ADDRESS_ALL 255u     /* recipient of the end state */

/* The merge of Fig. 3 (see the protocol domain notes, e.3). */
enum dr_paper_merge {
    DR_MERGE_PRINTED = 0,       /* paper Fig. 3 as printed: p > s_other AND p in P_other */
    DR_MERGE_JAVA = 1,          /* the simulator code of the experiments: p > s_other OR ... */
    DR_MERGE_C_PORT = 2         /* the later C port (and the text, Fig. 4): p >= s_other OR ... */
};

typedef struct {
    uint32_t fingerprint;           /* packets of another program are foreign */
    uint8_t first_address;       /* the module of the first statement, which starts the run */
    uint8_t (*address_of)(struct dr_module *m);
    void (*step)(struct dr_module *m);               /* one step of the generated switch */
    uint8_t (*responsible)(uint8_t address, uint8_t state); /* checkPendingStateResponsibility */
} dr_paper_program_t;

typedef struct {
    uint8_t state;                          /* global active state */
    uint8_t address;                        /* address of the active module */
    uint8_t pending[DR_CONF_MAX_PENDING];   /* 0 = empty slot */
} dr_paper_global_t;

typedef struct dr_module {
    void *platform;
    const dr_paper_program_t *program;
    dr_identity_t identity;         /* DR_ROBOT_ID; program fingerprint ^ execution */
    uint8_t address;
    enum dr_paper_merge merge;
    uint8_t single_step_handover;   /* option: add pending and transfer as one step */
    uint8_t restart_pending;        /* option: Sec. III-C restart of an interrupted pending op */
    dr_paper_global_t global;       /* this module's copy of the global state */
    uint8_t local_state;            /* the generated switch's `state` (Fig. 2) */
    uint8_t mailbox;                /* a state handed to this module, DR_STATE_IDLE if none */
    uint8_t started[DR_CONF_MAX_PENDING]; /* pending states this module started since reset */
    uint32_t next_broadcast_ms;
    uint32_t packets_sent;
    uint32_t packets_received;
    uint32_t packets_malformed;
    uint32_t packets_foreign;
    uint16_t resets;
} dr_module_t;

void dr_module_init(dr_module_t *m, const dr_paper_program_t *program, void *platform);
/* The entry points of dr_module.h, for this protocol: dr_module_finished is the end state
 * (254) held; dr_module_describe writes `s<state> a<address> p{<pending>} l<local_state>`, in
 * decimal, the non-empty pending slots in slot order separated by commas; e.g.
 * "s4 a3 p{1,4} l255". Cost: O(pending).
 * dr_module_next_wakeup: DR_WAKE_AT the broadcast deadline while the module is idle (local
 * state and mailbox DR_STATE_IDLE), else DR_WAKE_AT now: a running state polls at every
 * step (the generated switch decides what it waits for). On an MCU an idle module sleeps
 * between its broadcasts. Cost: O(1). */

/* Called by the generated state machine. */
/* dr_hal_op_start with the arguments read from the program's table (DR_TABLE, dr_hal.h);
 * `part` is its index (not `index`, which would shadow string.h's index() in nesC's check). */
void dr_paper_op_start(dr_module_t *m, uint16_t statement, uint8_t op, uint8_t part,
                       const int16_t *table_args);
void dr_paper_add_pending(dr_module_t *m, uint8_t state);
void dr_paper_remove_pending(dr_module_t *m, uint8_t state);
uint8_t dr_paper_has_pending(const dr_module_t *m);
/* sendState(s, r) of Fig. 2: changes the local copy only if s is higher than the global state. */
void dr_paper_send_state(dr_module_t *m, uint8_t state, uint8_t address);
/* State S+1 of a parallel statement S: sendState(next_state, next_address); with
 * single_step_handover it first re-adds `pending` (S), so the transfer always carries it. */
void dr_paper_handover(dr_module_t *m, uint8_t pending, uint8_t next_state, uint8_t next_address);

/* The merge itself (exported for tests and the model checker). */
void dr_paper_merge(dr_paper_global_t *local, const dr_paper_global_t *incoming,
                    enum dr_paper_merge variant);

#endif /* DR_PAPER_H */
