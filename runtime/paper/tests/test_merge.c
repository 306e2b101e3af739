/* test_merge.c - the Fig. 3 merge in its three variants (e.3) and the pending-set operations (e.4). */
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "machines.h"

#define PRINTED DR_MERGE_PRINTED
#define JAVA DR_MERGE_JAVA
#define CPORT DR_MERGE_C_PORT

typedef struct {
    const char *why;
    uint8_t s0, a0, p0[3];     /* local */
    uint8_t s1, a1, p1[3];     /* incoming */
    uint8_t want_s, want_a;
    uint8_t want[3][3];        /* the pending set per variant: printed, java, c port */
} merge_case_t;

static const merge_case_t CASES[] = {
    /* local newer (s0 > s1) */
    {"local newer, p > s1 unseen by the older copy: 'or' keeps, 'and' drops",
     8, 4, {6, 0, 0}, 5, 3, {0, 0, 0}, 8, 4, {{0}, {6}, {6}}},
    {"local newer, p == s1 unseen: only '>=' keeps (the strict '>' loss)",
     8, 4, {5, 0, 0}, 5, 3, {0, 0, 0}, 8, 4, {{0}, {0}, {5}}},
    {"local newer, p < s1 gone from the older copy: removal taken into account",
     8, 4, {1, 0, 0}, 5, 3, {0, 0, 0}, 8, 4, {{0}, {0}, {0}}},
    {"local newer, p < s1 still in the older copy: 'or' keeps, 'and' needs p > s1",
     8, 4, {1, 0, 0}, 5, 3, {1, 0, 0}, 8, 4, {{0}, {1}, {1}}},
    {"local newer, p > s1 in both: kept by all",
     8, 4, {6, 0, 0}, 5, 3, {6, 0, 0}, 8, 4, {{6}, {6}, {6}}},
    {"local newer, incoming-only pending states are never added",
     8, 4, {0, 0, 0}, 5, 3, {1, 0, 0}, 8, 4, {{0}, {0}, {0}}},
    /* equal states */
    {"equal states: intersection, local address kept",
     5, 3, {1, 2, 0}, 5, 6, {2, 4, 0}, 5, 3, {{2}, {2}, {2}}},
    {"equal states: a just-added pending state the other copy lacks is erased (S1 race)",
     0, 0, {1, 0, 0}, 0, 0, {0, 0, 0}, 0, 0, {{0}, {0}, {0}}},
    /* incoming newer (s0 < s1) */
    {"incoming newer: state and recipient taken, p == s0 unseen: only '>=' keeps",
     4, 0, {0, 0, 0}, 7, 1, {4, 0, 0}, 7, 1, {{0}, {0}, {4}}},
    {"incoming newer, p > s0 unseen here: 'or' keeps",
     4, 0, {0, 0, 0}, 7, 1, {6, 0, 0}, 7, 1, {{0}, {6}, {6}}},
    {"incoming newer, p < s0 already removed here: dropped",
     4, 0, {0, 0, 0}, 7, 1, {1, 0, 0}, 7, 1, {{0}, {0}, {0}}},
    {"incoming newer, p < s0 still here: 'or' keeps",
     4, 0, {1, 0, 0}, 7, 1, {1, 0, 0}, 7, 1, {{0}, {1}, {1}}},
    {"incoming newer, local-only pending states are dropped (no union)",
     4, 0, {1, 0, 0}, 7, 1, {0, 0, 0}, 7, 1, {{0}, {0}, {0}}},
    {"state 0 start: p = 1 > 0, 'or' keeps, 'and' drops",
     0, 0, {0, 0, 0}, 4, 3, {1, 0, 0}, 4, 3, {{0}, {1}, {1}}},
};

static void load(dr_paper_global_t *g, uint8_t s, uint8_t a, const uint8_t *p)
{
    memset(g, 0, sizeof *g);
    g->state = s;
    g->address = a;
    memcpy(g->pending, p, 3);
}

static uint8_t count(const uint8_t *p)
{
    uint8_t n = 0;
    uint8_t i;
    for (i = 0; i < 3; i++) {
        n = (uint8_t)(n + (p[i] != 0u));
    }
    return n;
}

static void test_cases(void)
{
    size_t c;
    uint8_t v;
    dr_paper_global_t local;
    dr_paper_global_t in;
    for (c = 0; c < sizeof CASES / sizeof CASES[0]; c++) {
        for (v = 0; v < 3; v++) {
            load(&local, CASES[c].s0, CASES[c].a0, CASES[c].p0);
            load(&in, CASES[c].s1, CASES[c].a1, CASES[c].p1);
            dr_paper_merge(&local, &in, (enum dr_paper_merge)v);
            if (!CHECK_TRIPLE(&local, CASES[c].want_s, CASES[c].want_a, CASES[c].want[v],
                              count(CASES[c].want[v]))) {
                printf("  case: %s (variant %u)\n", CASES[c].why, (unsigned)v);
            }
        }
    }
}

/* e.3's three-module line, merge only: X sent global state p to Y; Y added p, moved on to
 * s3 and broadcasts (s3, {p}). Round 1: X (p, {}) merges it; round 2: Y merges X's copy.
 * Strict '>' loses p on both; '>=' keeps it. */
static void test_two_round_loss(enum dr_paper_merge v, uint8_t kept)
{
    const uint8_t none[3] = {0, 0, 0};
    const uint8_t p13[3] = {13, 0, 0};
    dr_paper_global_t x;
    dr_paper_global_t y;
    load(&x, 13, 1, none);
    load(&y, 16, 6, p13);
    dr_paper_merge(&x, &y, v);
    CHECK_TRIPLE(&x, 16, 6, p13, kept);
    dr_paper_merge(&y, &x, v);
    CHECK_TRIPLE(&y, 16, 6, p13, kept);
}

/* Merge is idempotent for every variant, and the result never holds duplicates. */
static void test_idempotent_and_duplicates(void)
{
    const uint8_t p[3] = {3, 5, 0};
    const uint8_t dup[3] = {6, 6, 6};
    const uint8_t six[1] = {6};
    dr_paper_global_t a;
    dr_paper_global_t b;
    uint8_t v;
    for (v = 0; v < 3; v++) {
        load(&a, 5, 2, p);
        b = a;
        dr_paper_merge(&a, &b, (enum dr_paper_merge)v);
        CHECK_TRIPLE(&a, 5, 2, p, 2);
        load(&a, 4, 0, p);
        load(&b, 7, 1, dup);
        dr_paper_merge(&a, &b, (enum dr_paper_merge)v);
        CHECK_TRIPLE(&a, 7, 1, six, v == PRINTED ? 0 : 1);
    }
}

/* add / remove / has / sendState (e.4, e.7). */
static void test_pending_ops(void)
{
    world_t w;
    dr_module_t *m;
    const uint8_t five[5] = {1, 2, 3, 4, 5};
    const uint8_t four[4] = {1, 3, 4, 5};
    uint8_t i;
    world_init(&w, 1, &eight2car_program, CPORT, 0, 0);
    m = &w.mod[0];
    CHECK(!dr_paper_has_pending(m));
    for (i = 1; i <= 6; i++) {
        dr_paper_add_pending(m, i); /* the sixth does not fit: silently nothing */
    }
    dr_paper_add_pending(m, 3);     /* present: no-op */
    CHECK_TRIPLE(&m->global, 0, 0, five, 5);
    CHECK(dr_paper_has_pending(m));
    dr_paper_remove_pending(m, 2);
    dr_paper_remove_pending(m, 9);  /* absent: no-op */
    CHECK_TRIPLE(&m->global, 0, 0, four, 4);
    CHECK_EQ(m->global.pending[1], 0); /* the slot is freed in place */
    dr_paper_add_pending(m, 0);     /* 0 marks an empty slot: ignored */
    CHECK_TRIPLE(&m->global, 0, 0, four, 4);

    /* removing deletes the first matching slot only (duplicates can only come from a
     * corrupted state; set by hand here) */
    m->global.pending[1] = 4;
    dr_paper_remove_pending(m, 4);
    CHECK_EQ(m->global.pending[1], 0);
    CHECK_EQ(m->global.pending[3], 4);

    dr_paper_send_state(m, 7, 2);
    CHECK_EQ(m->global.state, 7);
    CHECK_EQ(m->global.address, 2);
    dr_paper_send_state(m, 7, 5);   /* not higher: no change */
    dr_paper_send_state(m, 3, 5);
    CHECK_EQ(m->global.state, 7);
    CHECK_EQ(m->global.address, 2);

    /* handover without the option is sendState alone; with it, it re-adds the pending state */
    world_init(&w, 1, &eight2car_program, CPORT, 0, 0);
    m = &w.mod[0];
    dr_paper_handover(m, 1, 4, 3);
    CHECK_TRIPLE(&m->global, 4, 3, five, 0);
    world_init(&w, 1, &eight2car_program, CPORT, 1, 0);
    m = &w.mod[0];
    dr_paper_handover(m, 1, 4, 3);
    CHECK_TRIPLE(&m->global, 4, 3, five, 1);
}

/* The end (e.11) and init (e.10). */
static void test_init_and_end(void)
{
    world_t w;
    world_init(&w, 7, &eight2car_program, CPORT, 0, 0);
    CHECK_EQ(w.mod[0].mailbox, DR_STATE_INITIAL); /* the first module starts the run */
    CHECK_EQ(w.mod[3].mailbox, DR_STATE_IDLE);
    CHECK_EQ(w.mod[3].address, 3);
    CHECK_EQ(w.fake[3].leds, 3);
    CHECK_EQ(w.mod[3].local_state, DR_STATE_IDLE);
    CHECK(!dr_module_finished(&w.mod[3]));
    dr_paper_send_state(&w.mod[3], DR_STATE_END, DR_ADDRESS_ALL);
    CHECK(dr_module_finished(&w.mod[3]));
    w.fake[5].id = 99;
    w.mod[5].packets_sent = 7;
    dr_module_init(&w.mod[5], &eight2car_program, &w.fake[5]); /* a reset */
    CHECK_EQ(w.mod[5].address, 127);
    CHECK_EQ(w.mod[5].resets, 1);
    CHECK_EQ(w.mod[5].packets_sent, 7); /* a reset keeps the counters ... */
    w.mod[5].merge = DR_MERGE_JAVA;
    w.mod[5].restart_pending = 1;
    world_reset(&w, 5);
    CHECK_EQ(w.mod[5].resets, 2);
    CHECK_EQ(w.mod[5].merge, DR_MERGE_JAVA); /* ... and the options */
    CHECK_EQ(w.mod[5].restart_pending, 1);
    dr_module_init(&w.mod[5], &ab_c_program, &w.fake[5]); /* another program: a first init */
    CHECK_EQ(w.mod[5].resets, 0);
    CHECK_EQ(w.mod[5].merge, CPORT);
    CHECK_EQ(w.mod[5].restart_pending, 0);
}

int main(void)
{
    test_cases();
    test_two_round_loss(PRINTED, 0);
    test_two_round_loss(JAVA, 0);
    test_two_round_loss(CPORT, 1);
    test_idempotent_and_duplicates();
    test_pending_ops();
    test_init_and_end();
    return harness_done("test_merge");
}
