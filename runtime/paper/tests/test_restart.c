/* test_restart.c - resets: the pending restart of e.6 (re-enter an interrupted parallel statement) and the first-module restart flaw. */
#include "harness.h"
#include "machines.h"

#define M0 0u
#define M1 1u
#define M6 6u
#define ALL 0xFFFFu
#define ALL_BUT_M1 0xFFFDu
#define MAX_ROUNDS 60

static const uint8_t P_13[1] = {13};

/* eight2car's first statements until M1's parallel rotate (state 13) runs and M6 waits for it
 * in state 17. C port with the single-step handover, so that only the reset is at play. */
static void run_until_m6_waits(world_t *w, uint8_t restart_pending)
{
    uint8_t r;
    world_init(w, 7, &eight2car_program, DR_MERGE_C_PORT, 1, restart_pending);
    for (r = 0; r < MAX_ROUNDS && w->mod[M6].local_state != 17u; r++) {
        world_round(w, ALL_BUT_M1);
    }
    world_round(w, ALL_BUT_M1); /* M6's retract completes; it still waits */
    CHECK_EQ(w->mod[M6].local_state, 17);
    CHECK_EQ(w->mod[M1].local_state, 15);
    CHECK_EQ(w->fake[M1].op, OP_ROTATE);
    CHECK_EQ(w->fake[M1].status, DR_OP_RUNNING);
    CHECK_EQ(w->fake[M1].n_starts, 1);
    CHECK_TRIPLE(&w->mod[M6].global, 16, 6, P_13, 1);
}

/* M1 resets in the middle of its rotate (state 15). */
static void test_restart(uint8_t restart_pending)
{
    world_t w;
    uint8_t r;
    run_until_m6_waits(&w, restart_pending);
    world_reset(&w, M1);
    CHECK_EQ(w.mod[M1].resets, 1);
    CHECK_EQ(w.mod[M1].global.state, 0);
    CHECK_EQ(w.mod[M1].local_state, DR_STATE_IDLE);
    for (r = 0; r < MAX_ROUNDS; r++) {
        world_round(&w, ALL); /* from now on every operation completes when asked to */
    }
    /* the copy is restored from the neighbours either way */
    CHECK(w.mod[M1].global.state >= 16u);
    if (restart_pending) {
        /* 13 was pending before and after a merge, M1 is responsible and has not started it
         * since its reset: it re-enters 13, re-issues the rotate, completes and removes 13 */
        CHECK_EQ(w.fake[M1].n_starts, 2);
        CHECK_EQ(w.fake[M1].op, OP_ROTATE);
        CHECK_EQ(w.fake[M1].args[1], 324);
        for (r = 0; r < 7; r++) {
            CHECK(dr_module_finished(&w.mod[r]));
        }
    } else {
        /* nobody removes 13: M6 waits forever (bounded here by MAX_ROUNDS rounds) */
        CHECK_EQ(w.fake[M1].n_starts, 1);
        CHECK_EQ(w.mod[M6].local_state, 17);
        CHECK_EQ(w.mod[M6].global.state, 16);
        CHECK(dr_paper_has_pending(&w.mod[M6]));
        for (r = 0; r < 7; r++) {
            CHECK(!dr_module_finished(&w.mod[r]));
        }
    }
}

/* A module that started the pending state itself is not sent back to it by the check. */
static void test_no_restart_of_own_running_state(void)
{
    world_t w;
    uint8_t r;
    run_until_m6_waits(&w, 1);
    for (r = 0; r < 10; r++) {
        world_round(&w, ALL_BUT_M1);
    }
    CHECK_EQ(w.mod[M1].mailbox, DR_STATE_IDLE);
    CHECK_EQ(w.fake[M1].n_starts, 1);
}

/* Known flaw (protocol notes): resetting the first module restarts the sequence from state
 * 0, even after the end: M0 re-issues its first operation (here the retract of connector 0),
 * a regression (S2) if a later statement had extended that connector again. */
static void test_first_module_reset(void)
{
    world_t w;
    uint8_t r;
    uint16_t starts;
    world_init(&w, 7, &eight2car_program, DR_MERGE_C_PORT, 1, 1);
    for (r = 0; r < MAX_ROUNDS; r++) {
        world_round(&w, ALL);
    }
    CHECK(dr_module_finished(&w.mod[M0]));
    starts = w.fake[M0].n_starts;
    CHECK_EQ(starts, 1);
    world_reset(&w, M0);
    CHECK_EQ(w.mod[M0].mailbox, DR_STATE_INITIAL);
    world_step(&w, M0); /* before any packet arrives */
    CHECK_EQ(w.fake[M0].n_starts, starts + 1u);
    CHECK_EQ(w.fake[M0].op, OP_RETRACT);
    CHECK_EQ(w.fake[M0].index, 0);
    for (r = 0; r < 5; r++) {
        world_round(&w, ALL);
    }
    CHECK(dr_module_finished(&w.mod[M0])); /* and then it learns the end again */
}

int main(void)
{
    test_restart(1);
    test_restart(0);
    test_no_restart_of_own_running_state();
    test_first_module_reset();
    return harness_done("test_restart");
}
