/* test_sync.c - synchronous groups (DR_CONF_SYNC): the ready bits are part of the semilattice
 * and of the payload; a group's members start only once every one of them is ready and the
 * countdown is over, all at one instant but for the packets' transit (here one step per hop),
 * whatever the modules' clocks; loss, resets and other epochs change none of that. A build
 * without DR_CONF_SYNC has nothing to test here. */
#include <string.h>
#include "check.h"
#include "sim.h"

#if DR_CONF_SYNC

/* `sync { A & B & C & D; }; E;` on a line of 4 nodes: A@0 B@1 C@2 D@3, E@0. */
static dr_statement_t st[5];
static const dr_dep_t deps[] = { 0, 1, 2, 3 };
static dr_program_t program = { 0x5Cu, 5u, st, deps, sim_args, 2u, sim_address_of, 0u };
static const uint8_t addresses[] = { 0, 1, 2, 3 };

static void build(void)
{
    uint8_t k;
    for (k = 0; k < 4u; k++) {
        sim_statement(&st[k], k, k, 0, 0);
        st[k].sync_size = 4;
        st[k].sync_index = k;
    }
    sim_statement(&st[4], 0, 4, 4, 0);
}

/* The latest minus the earliest first start of A-D in epoch `epoch`. */
static uint32_t spread(uint16_t epoch)
{
    uint32_t low = 0xFFFFFFFFu;
    uint32_t high = 0;
    uint8_t k;
    for (k = 0; k < 4u; k++) {
        uint32_t t = sim.last_start_ms[epoch][k];
        low = t < low ? t : low;
        high = t > high ? t : high;
    }
    return high - low;
}

static void laws(void)
{
    dr_shared_t a;
    dr_shared_t b;
    dr_shared_t c;
    uint8_t payload[DR_LATTICE_PAYLOAD_FIXED + 2u * (DR_CONF_WINDOW / 8u)];
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    a.ready[0] = 0x05u; /* statements 0 and 2 ready */
    b.ready[0] = 0x02u;
    b.done[0] = 0x08u;  /* statement 3 done: ready too */
    dr_shared_join(&a, &b, 6u);
    CHECK_EQ(a.ready[0], 0x07u);
    CHECK(dr_shared_is_ready(&a, 3u));
    CHECK(!dr_shared_is_ready(&a, 4u));
    CHECK_EQ(dr_shared_encode(&a, payload, (uint8_t)sizeof payload), (uint8_t)sizeof payload);
    CHECK(dr_shared_decode(&c, payload, (uint8_t)sizeof payload, 6u));
    CHECK_EQ(c.ready[0], a.ready[0]);
    /* A ready bit of a statement the program does not have is malformed. */
    payload[DR_LATTICE_PAYLOAD_FIXED + DR_CONF_WINDOW / 8u] = 0x80u;
    CHECK(!dr_shared_decode(&c, payload, (uint8_t)sizeof payload, 6u));
}

/* Runs the program from a fresh start with `seed`, clocks offset at random; returns whether
 * every node finished. */
static uint8_t run(uint32_t seed, uint8_t loss)
{
    uint8_t k;
    sim_setup(&program, 4, addresses, seed);
    sim.loss_percent = loss;
    for (k = 0; k < 4u; k++) {
        sim.nodes[k].clock_offset = sim_rand() % 100000u;
    }
    return sim_run(60000u);
}

void test_sync(void)
{
    uint32_t seed;
    uint16_t epoch;
    laws();
    build();
    for (seed = 1; seed <= 20u; seed++) {
        CHECK(run(seed, 0));
        CHECK_EQ(sim.violations, 0u);
        for (epoch = 0; epoch < 2u; epoch++) {
            /* The news takes a step per hop, three hops at most: each member starts when its
             * countdown, late by those steps, ends. */
            CHECK(spread(epoch) <= 3u * SIM_TICK_MS);
            CHECK_EQ(sim.starts[epoch][0], 1u);
        }
        /* Nobody moves before the countdown: A-D start at least the delay of a group of four
         * after time 0. */
        CHECK(sim.last_start_ms[0][0] >=
              DR_CONF_SYNC_DELAY_MS + 3u * DR_CONF_SYNC_DELAY_PER_MEMBER_MS);
    }
    /* Loss: late news can start a member late, never early, and never stops the sequence.
     * The countdown is sent again until the start (DR_CONF_SYNC_REPEAT_MS), so with 30 % of
     * the packets lost every member still hears it within the delay: the spread stays what
     * the transit gives (with the news sent only once, some seeds start a member late). */
    for (seed = 1; seed <= 50u; seed++) {
        CHECK(run(seed, 30));
        CHECK_EQ(sim.violations, 0u);
#if DR_CONF_SYNC_REPEAT_MS > 0
        CHECK(spread(0) <= 3u * SIM_TICK_MS);
#endif
    }
    /* A member reset during the countdown learns it again from its neighbours. */
    for (seed = 1; seed <= 10u; seed++) {
        sim_setup(&program, 4, addresses, seed);
        (void)sim_run(200u);
        sim_reset(2);
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0u);
        CHECK(spread(0) <= 3u * SIM_TICK_MS + 200u);
    }
}

#else

void test_sync(void)
{
}

#endif
