/* dr_dissemination.h - the lattice protocol's dissemination policy: when a module broadcasts
 * its copy of the shared state, and what it keeps to decide it. The protocol (dr_lattice.c)
 * owns the state, its join and its persistence; a policy is a small set of hooks it calls at
 * the moments below. Two policies, chosen by DR_CONF_LATTICE_DISSEMINATION (dr_conf.h), each
 * in its own file: dr_dissemination_fixed.h (a broadcast every DR_CONF_BROADCAST_MS) and
 * dr_dissemination_adaptive.h (Trickle-like, README.md "Adaptive dissemination").
 *
 * Why headers of static functions, and not a .c file per policy or a table of function
 * pointers (Contiki's drivers): an image's flash is measured to the byte (docs/benchmarks.md)
 * and every build gives exactly the code it gave when the two policies were #if blocks inside
 * dr_lattice.c. A policy compiled on its own, without -flto, could not be inlined into the
 * protocol's functions (a call, its arguments and a return for each hook), and a pointer
 * table costs an indirect call and its RAM or flash; a fixed policy's empty hooks would still
 * be calls. As static functions of dr_lattice.c's translation unit, the hooks inline where
 * the #if blocks were and the empty ones vanish. They are declared `static`, not `static
 * inline`: the functions moved here (send_state, disseminate, same_facts, ...) keep the
 * inlining GCC chose for them before (`inline` raises its limits, so a function called twice
 * could be copied into both callers); the small hooks are inlined anyway (called once, or a
 * few instructions). Checked when the policies moved here: the disassembled .text of
 * dr_lattice.o (-O2 and -Os, both policies, the test builds' windows) and of the ATmega128
 * images (C and nesC) was unchanged; only the sanitizer builds (-O1, instrumented) differ.
 *
 * Each policy file has two parts, included at two places:
 * - The state, through dr_lattice.h (this file's first inclusion): DR_DISSEMINATION_STATE,
 *   the policy's fields of dr_module_t, declarations with their semicolons (or nothing), so
 *   that the struct's layout is what the inline fields gave.
 * - The hooks, through a second inclusion of this file by dr_lattice.c, with
 *   DR_DISSEMINATION_HOOKS defined, after the protocol's helpers and before their callers.
 *   A hook may use what dr_lattice.c defines before that point: PROGRAM(m), W, NBYTES,
 *   PAYLOAD, FRAME, connected(m) (the latched channels), no_nv(m) (the build runs without NV),
 *   the dr_shared_* functions, dr_packet_frame and the HAL. No other file defines
 *   DR_DISSEMINATION_HOOKS.
 *
 * The hooks (every policy defines all of them; `now` is the step's dr_hal_now_ms):
 * - DR_DISSEMINATION_ASKS, 1 or 0: whether the policy sends asking frames
 *   (DR_PACKET_LATTICE_ASK, a retry that a receiver holding our copy answers at once). With
 *   1, dr_module_receive unframes a packet whose header says ASK as that kind. A constant,
 *   not a function: the receive path's test is then the very code the #if gave (GCC
 *   allocated the registers of an inlined function's answer otherwise).
 * - dissemination_init(m): dr_module_init, after next_broadcast_ms = now (a broadcast at the
 *   first step): the policy's state at a (re)start.
 * - dissemination_issued(m): the running batch's operations were (re)issued.
 * - dissemination_completed(m): the own batch completed, a new fact in m->shared (it is
 *   then sent: dissemination_send with `changed`).
 * - dissemination_retry_now(m, now): the running batch failed and the broadcast is due;
 *   returns whether to re-issue it now (operations are idempotent).
 * - dissemination_start_is_news(started): start_next's answer (a batch started) becomes
 *   whether that start is to be sent at once: the value or'ed into `changed`.
 * - dissemination_send(m, now, changed, retrying): the broadcast is due, or the own copy
 *   changed (`changed`: a completion, or a start that is news); `retrying`: a failed batch
 *   awaits its retry. Sends (or suppresses) and sets next_broadcast_ms, the protocol's one
 *   timer, which dr_module_step and dr_module_next_wakeup read.
 * - dissemination_heard(m, channel, before, in, asked): a well-formed copy `in` (decoded, not
 *   normalised; the hook may normalise it) arrived on `channel` and was joined into m->shared;
 *   `before` is m->shared before the join; `asked`: its frame kind was
 *   DR_PACKET_LATTICE_ASK. */
#ifndef DR_DISSEMINATION_H
#define DR_DISSEMINATION_H
#include "dr_conf.h"
#endif /* DR_DISSEMINATION_H */

/* Outside the guard: the second inclusion, for the hooks, reaches the policy file again. */
#if DR_CONF_LATTICE_DISSEMINATION == DR_DISSEMINATION_ADAPTIVE
#include "dr_dissemination_adaptive.h"
#else
#include "dr_dissemination_fixed.h"
#endif
