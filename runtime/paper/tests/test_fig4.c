/* test_fig4.c - golden test: the paper's Fig. 4 trace, row by row, on the Fig. 2 machine; and why only ">=" yields it. */
#include "harness.h"
#include "machines.h"

#define M0 0u
#define M3 3u

static const uint8_t P_NONE[1] = {0};
static const uint8_t P_1[1] = {1};

static void view(const world_t *w, uint8_t i, dr_paper_global_t *v)
{
    fig4_view(&w->mod[i], v);
}

/* Fig. 4's premise: both copies at <1,0,{}> (as if global state 1 had already been shared),
 * M0 about to run state 1 (its mailbox holds the entry state 0, which falls through to 1). */
static void fig4_setup(world_t *w, enum dr_paper_merge merge)
{
    world_init(w, 7, &eight2car_program, merge, 0, 0);
    w->mod[M0].global.state = 1;
    w->mod[M3].global.state = 1;
}

/* Fig. 4, C port (">=" or). Each row: what the figure prints for M0 and M3. The acting
 * module is read right after the state the row is numbered with (Fig. 2's fall-throughs run
 * the next state in the same step: "5: M3 continue" is the moment state 5 has set state 6).
 *
 * One deviation, asserted as it really is: from the second "State propagate" on, Fig. 4
 * prints M0 at state 5. Fig. 2's code never shares state 5: M3's step 4 -> 5 is local, and
 * the global state changes only by sendState (state 2 sends 4; the next send is in state 7).
 * So M0's copy stays at 4 (the figure draws M3's local progress as if it were shared). Every
 * address and every pending set matches the figure exactly. */
static void test_fig4_c_port(void)
{
    world_t w;
    dr_paper_global_t v0;
    dr_paper_global_t v3;
    fig4_setup(&w, DR_MERGE_C_PORT);

    /* Initial state: <1,0,{}> <1,0,{}> */
    view(&w, M0, &v0);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v0, 1, 0, P_NONE, 0);
    CHECK_TRIPLE(&v3, 1, 0, P_NONE, 0);

    /* 1: M0 retract => <2,0,{1}> <1,0,{}> */
    world_step(&w, M0);
    CHECK_EQ(w.fake[M0].op, OP_RETRACT);
    CHECK_TRIPLE(&eight2car_after[M0][1], 2, 0, P_1, 1);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v3, 1, 0, P_NONE, 0);

    /* 2: M0 transition => <4,3,{1}> <1,0,{}> */
    world_step(&w, M0);
    CHECK_TRIPLE(&eight2car_after[M0][2], 4, 3, P_1, 1);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v3, 1, 0, P_NONE, 0);

    /* State propagate => <4,3,{1}> <4,3,{1}>  (1 >= 1: kept) */
    world_deliver(&w, M0, M3);
    view(&w, M0, &v0);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v0, 4, 3, P_1, 1);
    CHECK_TRIPLE(&v3, 4, 3, P_1, 1);
    CHECK_EQ(w.mod[M3].mailbox, 4);

    /* 4: M3 retract => <4,3,{1}> <5,3,{1}> */
    world_step(&w, M3);
    CHECK_EQ(w.fake[M3].op, OP_RETRACT);
    CHECK_EQ(w.fake[M3].index, 4);
    view(&w, M0, &v0);
    CHECK_TRIPLE(&v0, 4, 3, P_1, 1);
    CHECK_TRIPLE(&eight2car_after[M3][4], 5, 3, P_1, 1);

    /* State propagate => figure <5,3,{1}> <5,3,{1}>; M0 really <4,3,{1}> (see above) */
    world_deliver(&w, M3, M0);
    view(&w, M0, &v0);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v0, 4 /* Fig. 4: 5 */, 3, P_1, 1);
    CHECK_TRIPLE(&v3, 5, 3, P_1, 1);

    /* M3's retract finishes first; it must still wait for M0 (pending 1). */
    world_complete(&w, M3);
    world_step(&w, M3);
    CHECK_EQ(w.mod[M3].local_state, 5);
    CHECK_EQ(w.fake[M3].n_starts, 1);

    /* 3: M0 complete => figure <5,3,{}> <5,3,{1}> */
    world_complete(&w, M0);
    world_step(&w, M0);
    CHECK_EQ(w.mod[M0].local_state, DR_STATE_IDLE);
    CHECK_TRIPLE(&eight2car_after[M0][3], 4 /* Fig. 4: 5 */, 3, P_NONE, 0);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v3, 5, 3, P_1, 1);

    /* Pending propagate => figure <5,3,{}> <5,3,{}> (equal states: intersection) */
    world_deliver(&w, M0, M3);
    view(&w, M0, &v0);
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v0, 4 /* Fig. 4: 5 */, 3, P_NONE, 0);
    CHECK_TRIPLE(&v3, 5, 3, P_NONE, 0);

    /* 5: M3 continue => figure <5,3,{}> <6,3,{}> */
    world_step(&w, M3);
    CHECK_TRIPLE(&eight2car_after[M3][5], 6, 3, P_NONE, 0);
    view(&w, M0, &v0);
    CHECK_TRIPLE(&v0, 4 /* Fig. 4: 5 */, 3, P_NONE, 0);
    /* ... and state 6 ran in the same step: M3 rotates, after M0's retract finished. */
    CHECK_EQ(w.fake[M3].op, OP_ROTATE);
    CHECK_EQ(w.mod[M3].local_state, 7);
}

/* The same premise with strict ">" (the Java of the experiments) or the printed "> and": at
 * the first propagation M3 (global 1) keeps pending 1 only if 1 > 1, so it drops it; M3's
 * copy then erases it from M0's too (equal states: intersection), and M3 rotates while M0's
 * retract is still running. So Fig. 4 is NOT yielded by ">" (e.3: "Fig. 4 starts from state
 * 1 ... only works with >="). */
static void test_fig4_strict(enum dr_paper_merge merge)
{
    world_t w;
    dr_paper_global_t v0;
    dr_paper_global_t v3;
    fig4_setup(&w, merge);
    world_step(&w, M0);
    world_step(&w, M0);
    CHECK_TRIPLE(&eight2car_after[M0][2], 4, 3, P_1, 1);

    world_deliver(&w, M0, M3); /* Fig. 4: <4,3,{1}>; here the pending state is lost */
    view(&w, M3, &v3);
    CHECK_TRIPLE(&v3, 4, 3, P_NONE, 0);

    world_step(&w, M3);        /* 4: M3 retract */
    world_deliver(&w, M3, M0); /* M0 (4,{1}) meets (4,{}): intersection erases M0's own 1 */
    view(&w, M0, &v0);
    CHECK_TRIPLE(&v0, 4, 3, P_NONE, 0);

    world_complete(&w, M3);
    world_step(&w, M3);        /* 5: nothing pending -> 6: rotate */
    CHECK_EQ(w.fake[M3].op, OP_ROTATE);
    CHECK_EQ(w.fake[M0].status, DR_OP_RUNNING); /* S1 violated: M0's retract still runs */

    world_complete(&w, M0);
    world_step(&w, M0);        /* 3: the removal finds nothing */
    CHECK_EQ(w.mod[M0].local_state, DR_STATE_IDLE);
}

/* From the real start (global state 0, e.10) ">" keeps the first pending state: 1 > 0.
 * "Initial state 0 hides the problem for the first statement" (e.3). The printed "and" still
 * loses it (1 is not in M3's empty set). */
static void test_state0_hides(enum dr_paper_merge merge, uint8_t kept)
{
    world_t w;
    world_init(&w, 7, &eight2car_program, merge, 0, 0);
    world_step(&w, M0); /* 0 -> 1: add pending 1 at global state 0, retract */
    world_step(&w, M0); /* 2: sendState(4,3) */
    world_deliver(&w, M0, M3);
    CHECK_TRIPLE(&w.mod[M3].global, 4, 3, P_1, kept);
    world_step(&w, M3);
    world_complete(&w, M3);
    world_step(&w, M3);
    CHECK_EQ(w.mod[M3].local_state, kept ? 5 : 7); /* waits for M0, or does not */
}

int main(void)
{
    test_fig4_c_port();
    test_fig4_strict(DR_MERGE_JAVA);
    test_fig4_strict(DR_MERGE_PRINTED);
    test_state0_hides(DR_MERGE_JAVA, 1);
    test_state0_hides(DR_MERGE_C_PORT, 1);
    test_state0_hides(DR_MERGE_PRINTED, 0);
    return harness_done("test_fig4");
}
