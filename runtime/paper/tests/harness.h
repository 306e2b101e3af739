/* harness.h - the paper-protocol tests' world of modules on the shared fake platform
 * (runtime/testing/dr_fake.h), and a check of a copy of the global state. */
#ifndef HARNESS_H
#define HARNESS_H

#include <stdint.h>
#include "dr_fake.h"
#include "dr_paper.h"

/* ---- assertions: CHECK and CHECK_EQ come from the shared fake platform (dr_fake.h) ---- */
/* A copy of the global state equals <state, address, {pending...}> (as a set). */
#define CHECK_TRIPLE(g, s, a, pend, n) harness_check_triple((g), (s), (a), (pend), (n), \
                                                            __FILE__, __LINE__)
int harness_check_triple(const dr_paper_global_t *g, uint8_t state, uint8_t address,
                         const uint8_t *pending, uint8_t n_pending, const char *file, int line);
/* Prints the summary; returns the process exit code. */
int harness_done(const char *name);

/* ---- the hardware of one module: the shared fake platform, without hooks (the test
 * delivers packets and completes operations by hand) ---- */
typedef dr_fake_t fake_t;

#define WORLD_MAX 8

/* Modules whose packets the test delivers by hand (the network is the test). */
typedef struct {
    uint8_t n;
    dr_module_t mod[WORLD_MAX];
    fake_t fake[WORLD_MAX];
} world_t;

/* Module i gets ID i; options are set after dr_module_init. */
void world_init(world_t *w, uint8_t n, const dr_paper_program_t *program,
                enum dr_paper_merge merge, uint8_t single_step_handover, uint8_t restart_pending);
/* One step of module i, DR_CONF_BROADCAST_MS after its previous one (so it broadcasts). */
void world_step(world_t *w, uint8_t i);
/* Hands the last packet module `from` broadcast to module `to`. */
void world_deliver(world_t *w, uint8_t from, uint8_t to);
/* The running operation of module i completes. */
void world_complete(world_t *w, uint8_t i);
/* Spurious reset of module i: dr_module_init again; its operation is left unfinished until
 * the test completes it, and nothing it sent before is delivered after. */
void world_reset(world_t *w, uint8_t i);
/* One fair round: every module steps, then every ordered pair (i, j), i != j, is delivered.
 * Running operations of modules in `complete_mask` (bit i) complete before the round. */
void world_round(world_t *w, uint16_t complete_mask);

/* Fig. 4's "state" of a module: the global state, or its own local state when that is ahead
 * (Fig. 4 shows the active module's local progress); address and pending from the copy. */
void fig4_view(const dr_module_t *m, dr_paper_global_t *view);

#endif /* HARNESS_H */
