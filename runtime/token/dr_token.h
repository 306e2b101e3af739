/* dr_token.h - the token-passing baseline: the controller the paper's shared state replaced
 * (Sec. VI and its footnote 2). One token travels through the robot; the module holding it
 * runs the next statement, strictly in source order, then routes the token to the module of
 * the following statement along an explicit route of latched neighbours computed at compile
 * time by replaying the sequence on the configuration.
 *
 * Two variants, as in the original experiments:
 *  - plain token: each hop sends its message once, unacknowledged; a lost message stalls the
 *    run for good;
 *  - safe token: each hop is a reliable link: a message carries (counter, sender), the
 *    receiver acknowledges it on the channel it came in on and drops duplicates (a cache of
 *    the last DR_CONF_TOKEN_SEEN (sender, counter) pairs); the sender retries every period
 *    (the first try at once) until acknowledged or tried `max_tries` times (0: forever).
 *    A module sends at most one packet per period; acknowledgements only when no message of
 *    its own waits.
 * A reset forgets the token, the queue and the cache; the first module takes the token of
 * statement 0 again and restarts the whole sequence (as the original did). No non-volatile
 * storage is used.
 *
 * The generated dr_program.c provides one dr_token_program_t; the platform provides dr_hal.h
 * (dr_hal_send included) and calls dr_module_init, dr_module_step and dr_module_receive. */
#ifndef DR_TOKEN_H
#define DR_TOKEN_H

#include <stdint.h>
#include "dr_conf.h"
#include "dr_hal.h"
#include "dr_module.h"
#include "dr_packet.h"

/* Returned by a program's address_of when no role, or several, match this module. */
/* Bytes of a safe token's payload, the largest packet (dr_token.c lays it out). The compiler
 * reads this line to size the frame (one source). */
#define DR_TOKEN_SAFE_PAYLOAD 8u

#define DR_NO_ADDRESS 0xFFu
#define DR_MANY_ADDRESSES 0xFEu
#define DR_NONE 0xFFFFu


#if DR_CONF_TOKEN_QUEUE > 255 || DR_CONF_TOKEN_SEEN > 255 || DR_CONF_TOKEN_ACKS > 255
#error "the token runtime counts its queues in one byte"
#endif

/* One step of a route: module `sender` (its ID) sends the token on connector `connector`
 * (not `module`: a keyword of nesC, whose compiler reads this header too). */
typedef struct {
    uint16_t sender;
    uint8_t connector;
} dr_token_hop_t;

/* One statement of the compiled sequence (generated, constant), in source order. */
typedef struct {
    uint8_t address;                   /* the label (role or M<k>) that runs it */
    uint8_t op;                        /* operation code, DR_OP_* of the generated header */
    uint8_t index;                     /* part index (connector, joint); 0 when none */
    uint16_t holder;                   /* ID of the module that runs it on the configuration */
    uint16_t first_hop;                /* the route of the hand-over INTO this statement: */
    uint8_t n_hops;                    /*   hops[first_hop..+n_hops]; 0 when the previous
                                          statement ran on the same module (or s = 0) */
    int16_t args[DR_CONF_MAX_ARGS];
} dr_token_statement_t;

/* A compiled sequence (generated, constant). */
typedef struct {
    uint32_t fingerprint;              /* packets of another program are foreign */
    uint16_t n_statements;
    const dr_token_statement_t *statements;
    const dr_token_hop_t *hops;
    uint8_t (*address_of)(struct dr_module *m); /* evaluates the role predicates */
    uint8_t reliable;                  /* 0: plain token; 1: safe token (acks, retries) */
    uint16_t max_tries;                /* safe token: tries per message; 0: unlimited */
} dr_token_program_t;

/* A message waiting in the safe token's queue (or, plain, for its single send). */
typedef struct {
    uint16_t state;                    /* the statement the token is for */
    uint16_t target;                   /* ID of the module that runs it */
    uint8_t channel;                   /* connector it is sent on */
    uint8_t counter;                   /* this hop's message counter */
    uint16_t tries;
} dr_token_message_t;

/* A (sender, counter) pair already received, or an acknowledgement to send. */
typedef struct {
    uint16_t sender;
    uint8_t counter;
    uint8_t channel;                   /* acknowledgements: where to send it */
} dr_token_seen_t;

/* All per-module state (one per module; the simulator has many, an MCU one). */
typedef struct dr_module {
    void *platform;                    /* the platform's own data; the runtime never reads it */
    const dr_token_program_t *program;
    dr_identity_t identity;            /* DR_ROBOT_ID; program fingerprint ^ execution */
    uint8_t address;
    uint16_t id;
    uint16_t holding;                  /* statement whose token this module holds, or DR_NONE */
    uint8_t running;                   /* 1 once the held statement's operation is started */
    uint8_t finished;                  /* the end is known here (and flooded) */
    uint8_t n_queued;
    uint8_t next_queued;               /* round robin over the queue */
    uint8_t counter;                   /* next message counter */
    uint8_t n_acks;
    uint8_t n_seen;
    uint8_t next_seen;                 /* oldest slot of the cache, overwritten next */
    dr_token_message_t queue[DR_CONF_TOKEN_QUEUE];
    dr_token_seen_t acks[DR_CONF_TOKEN_ACKS];
    dr_token_seen_t seen[DR_CONF_TOKEN_SEEN];
    uint32_t next_send_ms;
    /* counters, for reports */
    uint32_t packets_sent;
    uint32_t packets_received;
    uint32_t packets_malformed;
    uint32_t packets_foreign;
    uint16_t messages_dropped;         /* given up after max_tries, or no room in the queue */
    uint16_t resets;
} dr_module_t;

/* Starts (or restarts after a reset) a module: finds its address and ID, forgets any token;
 * the module of statement 0 takes its token. Cost: O(statements) (role predicates). */
void dr_module_init(dr_module_t *m, const dr_token_program_t *program, void *platform);
/* The entry points of dr_module.h, for this protocol:
 * - dr_module_step: starts or polls the held statement's operation, hands the token on when
 *   it is done, and sends at most one packet when a period is due.
 *   Cost: O(hops of one route + DR_CONF_TOKEN_QUEUE).
 * - dr_module_receive: Cost: O(DR_CONF_TOKEN_SEEN + hops of one route).
 * - dr_module_finished: the last statement is known to be done.
 * - dr_module_describe: `tok<statement>` or `tok-`, `run` when its operation is started,
 *   `q<queued>`, `fin` once finished; e.g. "tok4 run q0".
 * - dr_module_next_wakeup: DR_WAKE_AT the next period's send (every period, even with
 *   nothing queued: its jitter draws a random number), plus DR_WAKE_OP while the held
 *   statement's operation runs, or DR_WAKE_AT now when a held statement has not started.
 *   On an MCU a module without the token sleeps between its periods. Cost: O(1). */

#endif /* DR_TOKEN_H */
