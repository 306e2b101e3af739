/* dr_module.h - the entry points every protocol's runtime gives the platform (lattice, paper,
 * token: each defines `struct dr_module`, its program type and dr_module_init, and says in its
 * own header what these do for it and what they cost).
 *
 * A platform calls dr_program_init (generated, dr_program.h) at power-on and after a reset,
 * then dr_module_step every few milliseconds and dr_module_receive for each packet. */
#ifndef DR_MODULE_H
#define DR_MODULE_H

#include <stdint.h>

struct dr_module;

/* One step of the module: starts or polls its operation, sends when a packet is due. */
void dr_module_step(struct dr_module *m);
/* A packet arrived on `channel` (the connector it came in on). Malformed and foreign packets
 * (dr_packet.h) are counted and dropped. A module must not be handed its own packets. */
void dr_module_receive(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len);
/* Whether this module knows that the sequence has ended. */
uint8_t dr_module_finished(const struct dr_module *m);
/* A short description of the module's protocol state, for traces and debugging (the format
 * is the protocol's). Writes at most `cap` bytes including the terminating NUL (a shorter
 * prefix when it does not fit; nothing when cap is 0) and returns the length without the
 * NUL. No printf, no allocation. */
uint8_t dr_module_describe(const struct dr_module *m, char *out, uint8_t cap);

#endif /* DR_MODULE_H */
