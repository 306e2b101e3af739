/* dr_module.h - the entry points every protocol's runtime gives the platform (lattice, paper,
 * token: each defines `struct dr_module`, its program type and dr_module_init, and says in its
 * own header what these do for it and what they cost).
 *
 * A platform calls dr_program_init (generated, dr_program.h) at power-on and after a reset,
 * then dr_module_step every few milliseconds and dr_module_receive for each packet. A
 * platform may instead step a module only when it needs it (tickless, or asleep on an MCU):
 * dr_module_next_wakeup below says when. */
#ifndef DR_MODULE_H
#define DR_MODULE_H

#include <stdint.h>

struct dr_module;

/* One step of the module: starts or polls its operation, sends when a packet is due. */
void dr_module_step(struct dr_module *m);
/* A packet arrived on `channel` (the connector it came in on). Malformed and foreign packets
 * (dr_packet.h) are counted and dropped. A module must not be handed its own packets. */
void dr_module_receive(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len);
/* Answers of dr_module_finished. */
#define DR_END_NONE 0u    /* the module knows of no end */
#define DR_END_GOAL 1u    /* the sequence has ended: every statement of its last run is done */
#define DR_END_STOPPED 2u /* an operation of this module failed and its failure policy gave up
                           * (dr_conf.h, DR_CONF_ON_FAILURE): it starts nothing more */
/* Whether, and how, this module knows that the sequence has ended (DR_END_*: 0 while it
 * runs, so a platform that tests it as a truth value sees either end as the end). */
uint8_t dr_module_finished(const struct dr_module *m);
/* A short description of the module's protocol state, for traces and debugging (the format
 * is the protocol's). Writes at most `cap` bytes including the terminating NUL (a shorter
 * prefix when it does not fit; nothing when cap is 0) and returns the length without the
 * NUL. No printf, no allocation. */
uint8_t dr_module_describe(const struct dr_module *m, char *out, uint8_t cap);

/* Bits of dr_module_next_wakeup's answer. */
#define DR_WAKE_AT 0x01u /* at the first step instant whose dr_hal_now_ms() >= *at_ms */
#define DR_WAKE_OP 0x02u /* at the first step instant at which dr_hal_op_status() is not
                          * DR_OP_RUNNING (an operation completed or failed) */

/* When the module next needs a dr_module_step, for a platform that steps it only then
 * (the simulator's tickless stepping; an MCU that sleeps between steps and wakes on its
 * timer, its infrared receiver or its actuator's end).
 *
 * The contract: let the answer be A (and *at_ms when A has DR_WAKE_AT). Until the module's
 * next dr_module_receive, dr_module_init or dr_module_step, a dr_module_step at any instant
 * that the bits of A do not name changes nothing in *m and calls no HAL function other than
 * the queries (dr_hal_now_ms, dr_hal_op_status, dr_hal_connected, dr_hal_id,
 * dr_hal_neighbour_id, dr_hal_joint): skipping it gives exactly the run that stepping every
 * period gives. A == 0: only a packet can make a step useful. DR_WAKE_AT with *at_ms at or
 * before now: at the next step instant. The answer is valid until the next call of one of
 * those three entry points; ask again after each (a received packet may make a step useful
 * at once, e.g. a dependency now complete). Packets are still handed over on arrival, as
 * dr_module_receive has always required.
 * Precondition: dr_module_init has run. No side effect: reads *m and dr_hal_now_ms only.
 * Every protocol documents its own answer and cost in its header. */
uint8_t dr_module_next_wakeup(struct dr_module *m, uint32_t *at_ms);

#endif /* DR_MODULE_H */
