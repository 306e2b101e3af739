/* test_dissemination.c - how often the lattice runtime speaks, for the dissemination it was
 * built with (DR_CONF_LATTICE_DISSEMINATION): a quiet robot stops talking (adaptive) or talks
 * at the fixed period (fixed); news and hand-overs travel at once; a module that is behind, or
 * cut off and connected again, hears what it missed. */
#include <string.h>
#include "check.h"
#include "sim.h"

#define ADAPTIVE (DR_CONF_LATTICE_DISSEMINATION == DR_DISSEMINATION_ADAPTIVE)

static dr_statement_t two_st[2];
static const dr_dep_t two_deps[] = { 0 };
/* `A; B;`: A on address 0, B (after A) on address 1. */
static dr_program_t two = { 0x61u, 2u, two_st, two_deps, sim_args, 1u, sim_address_of, 0u };
static dr_program_t two_no_nv = { 0x62u, 2u, two_st, two_deps, sim_args, 1u, sim_address_of,
                                  DR_PROGRAM_NO_NV };

static void build(void)
{
    sim_statement(&two_st[0], 0, 0, 0, 0);
    sim_statement(&two_st[1], 1, 1, 1, 0);
}

static uint32_t packets_sent(void)
{
    uint32_t total = 0;
    uint8_t i;
    for (i = 0; i < sim.n_nodes; i++) {
        total += sim.nodes[i].mod.packets_sent;
    }
    return total;
}

static void run_ticks(uint32_t ms)
{
    uint32_t t;
    for (t = 0; t < ms; t += SIM_TICK_MS) {
        (void)sim_run(SIM_TICK_MS);
    }
}

/* Runs `program` on `n` modules from `seed` to its end, then 30 s with nothing new: where the
 * tests of a restart and of a quiet neighbour begin. */
static void run_to_a_quiet_end(const dr_program_t *program, uint8_t n, const uint8_t *addr,
                               uint32_t seed)
{
    sim_setup(program, n, addr, seed);
    CHECK(sim_run(10000u));
    run_ticks(30000u);
}

/* After the end, a minute of nothing new: fixed sends every period; adaptive backs off to the
 * longest interval after a few broadcasts. */
static void test_quiet_robot(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, DR_NO_ADDRESS, 1 };
    uint32_t before;
    uint32_t idle;
    sim_setup(&two, 4, addr, 71u);
    CHECK(sim_run(10000u));
    before = packets_sent();
    run_ticks(60000u);
    idle = packets_sent() - before;
#if ADAPTIVE
    /* Per module: at most the resends and doublings, then one per longest interval. */
    CHECK(idle <= 4u * (60000u / SIM_LONGEST_GAP_MS + DR_CONF_LATTICE_DOUBLINGS +
                        DR_CONF_LATTICE_RESENDS + 2u));
#else
    CHECK(idle >= 4u * (60000u / (DR_CONF_BROADCAST_MS + DR_CONF_BROADCAST_JITTER_MS) - 1u));
#endif
    CHECK_EQ(sim.violations, 0);
}

/* A's completion crosses three relays to B's module: with adaptive dissemination each relay
 * passes the news on at its next step (plus the relay jitter), even after a long
 * quiet start (every module at its longest interval); fixed relays at its next period. */
static void test_handover_across_relays(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, DR_NO_ADDRESS, DR_NO_ADDRESS, 1 };
    sim_setup(&two, 5, addr, 72u);
    sim.slow_address = 0; /* A takes 300 ms more: the relays are quiet by then */
    CHECK(sim_run(20000u));
    CHECK_EQ(sim.starts[0][1], 1);
#if ADAPTIVE
    CHECK(sim.max_handover_ms <= 4u * (2u * SIM_TICK_MS + DR_CONF_LATTICE_RELAY_JITTER_MS));
#else
    CHECK(sim.max_handover_ms <= 4u * (DR_CONF_BROADCAST_MS + DR_CONF_BROADCAST_JITTER_MS +
                                       SIM_TICK_MS));
#endif
    CHECK_EQ(sim.violations, 0);
}

/* A module that restarts without NV after a long quiet end is behind every neighbour: they
 * answer at once, and it learns the end without re-issuing anything. */
static void test_behind_is_answered(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, 1 };
    uint32_t t;
    run_to_a_quiet_end(&two_no_nv, 3, addr, 73u);
    sim_reset(1);
    CHECK(!dr_module_finished(&sim.nodes[1].mod));
    t = sim.time;
    while (!dr_module_finished(&sim.nodes[1].mod) && sim.time - t < 10000u) {
        run_ticks(SIM_TICK_MS);
    }
    CHECK(dr_module_finished(&sim.nodes[1].mod));
#if ADAPTIVE
    CHECK(sim.time - t <= 4u * SIM_TICK_MS + DR_CONF_LATTICE_RELAY_JITTER_MS);
#else
    CHECK(sim.time - t <= DR_CONF_BROADCAST_MS + DR_CONF_BROADCAST_JITTER_MS + 2u * SIM_TICK_MS);
#endif
    CHECK_EQ(sim.starts[0][0] + sim.starts[0][1], 2);
    CHECK_EQ(sim.violations, 0);
}

/* B's module is cut off (both links of the last hop gone) while A runs and completes; ten
 * seconds later the link is back: within one longest interval someone speaks, and B starts. */
static void test_cut_off_and_back(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, 1 };
    uint32_t t;
    sim_setup(&two, 3, addr, 74u);
    sim.adj[1][2] = 0;
    sim.adj[2][1] = 0;
    run_ticks(10000u);
    CHECK(sim.reported[0][0]);
    CHECK_EQ(sim.starts[0][1], 0);
    sim.adj[1][2] = 1;
    sim.adj[2][1] = 1;
    t = sim.time;
    while (sim.starts[0][1] == 0 && sim.time - t < 20000u) {
        run_ticks(SIM_TICK_MS);
    }
    CHECK_EQ(sim.starts[0][1], 1);
    CHECK(sim.time - t <= SIM_LONGEST_GAP_MS + DR_CONF_BROADCAST_JITTER_MS + 3u * SIM_TICK_MS);
    CHECK(sim_run(10000u));
    CHECK_EQ(sim.violations, 0);
}

#if ADAPTIVE
/* The interval: the smallest after news, the longest once every neighbour has our copy; next_broadcast_ms is the one timer (the platform may sleep until it). */
static void test_interval(void)
{
    static const uint8_t addr[] = { 0, 1 };
    dr_module_t *m = &sim.nodes[0].mod;
    uint32_t gap;
    sim_setup(&two, 2, addr, 75u);
    CHECK_EQ(m->doublings, 0);
    CHECK(sim_run(10000u));
    run_ticks(30000u);
    CHECK_EQ(m->doublings, DR_CONF_LATTICE_DOUBLINGS);
    gap = m->next_broadcast_ms - dr_hal_now_ms(m);
    CHECK(gap <= SIM_LONGEST_GAP_MS + DR_CONF_BROADCAST_JITTER_MS);
    /* A neighbour reset with a blank store is behind: node 0 answers at its next step. */
    memset(sim.nodes[1].fake.nv, 0xFF, SIM_NV);
    sim.checks = 0; /* the known weakness of a lost NV store (test_lost_nv) */
    sim_reset(1);
    run_ticks(4u * SIM_TICK_MS + DR_CONF_LATTICE_RELAY_JITTER_MS);
    CHECK(m->doublings <= 1u);
    CHECK(dr_module_finished(&sim.nodes[1].mod));
}

/* A module restarted with its NV record after a quiet end holds the copy its neighbour holds
 * (B, the last statement, is its own: its record has the end), so the neighbour has nothing
 * new to say (and suppresses its periodic broadcasts); the restarted module's first packet
 * asks (it has acknowledged no one), and the neighbour answers it at its next step. Then
 * both are quiet (without that answer: a packet every capped interval for good). */
static void test_resend_is_answered(void)
{
    static const uint8_t addr[] = { 0, 1 };
    dr_module_t *m = &sim.nodes[1].mod;
    uint32_t before;
    run_to_a_quiet_end(&two, 2, addr, 76u);
    sim_reset(1);
    run_ticks(4u * SIM_TICK_MS + DR_CONF_LATTICE_RELAY_JITTER_MS);
    CHECK_EQ(m->acked, 1u); /* channel 0: node 0 */
    before = m->packets_sent;
    run_ticks(5000u);
    CHECK(m->packets_sent - before <= 5000u / SIM_LONGEST_GAP_MS + 1u);
    CHECK_EQ(sim.violations, 0);
}

/* A relay of news goes on every channel, the one it came from too: it is the sender's
 * acknowledgement (sent only to the others, the sender resent for want of it). A's module
 * (node 0) completes; the middle node relays at once, and node 0 has it acknowledged before
 * its first resend would be due. */
static void test_relay_acknowledges(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, 1 };
    dr_module_t *m = &sim.nodes[0].mod;
    uint32_t before;
    sim_setup(&two, 3, addr, 78u);
    while (!sim.reported[0][0] && sim.time < 10000u) {
        run_ticks(SIM_TICK_MS);
    }
    CHECK(sim.reported[0][0]);
    before = m->packets_sent; /* its news went out in the step that saw the completion */
    run_ticks(2u * SIM_TICK_MS + DR_CONF_LATTICE_RELAY_JITTER_MS + SIM_TICK_MS);
    CHECK_EQ(m->acked, 2u); /* channel 1: the middle node */
    CHECK_EQ(m->packets_sent, before);
    CHECK(sim_run(10000u));
    CHECK_EQ(sim.violations, 0);
}

/* Our copy heard in a plain state frame is not answered (a quiet broadcast, a relay); heard
 * in an asking frame (a retry: its sender has not heard us with it) it is, at the next step,
 * on that channel only, and as a plain frame (an asking answer would be answered again). */
static void test_ask_is_answered(void)
{
    static const uint8_t addr[] = { 0, DR_NO_ADDRESS, 1 };
    dr_module_t *m = &sim.nodes[1].mod;
    uint8_t payload[DR_CONF_MAX_PACKET];
    uint8_t frame[DR_CONF_MAX_PACKET];
    uint8_t len;
    uint8_t flen;
    uint16_t inbox0;
    uint16_t inbox2;
    uint32_t due;
    run_to_a_quiet_end(&two, 3, addr, 79u);
    len = dr_shared_encode(&m->shared, payload, sizeof payload);
    flen = dr_packet_frame(frame, sizeof frame, &m->identity, DR_PACKET_LATTICE_STATE, payload,
                           len);
    due = m->next_broadcast_ms;
    dr_module_receive(m, 0, frame, flen);
    CHECK_EQ(m->answer, 0);
    CHECK_EQ(m->asking, 0u);
    CHECK_EQ(m->next_broadcast_ms, due);
    flen = dr_packet_frame(frame, sizeof frame, &m->identity, DR_PACKET_LATTICE_ASK, payload,
                           len);
    dr_module_receive(m, 0, frame, flen);
    CHECK(m->answer != 0u);
    CHECK_EQ(m->asking, 1u); /* channel 0: node 0 */
    due = m->next_broadcast_ms - dr_hal_now_ms(m);
    CHECK(due <= DR_CONF_LATTICE_RELAY_JITTER_MS);
    CHECK_EQ(m->packets_malformed + m->packets_foreign, 0);
    inbox0 = sim.nodes[0].n_inbox;
    inbox2 = sim.nodes[2].n_inbox;
    sim.time += due;
    dr_module_step(m);
    CHECK_EQ(sim.nodes[0].n_inbox, inbox0 + 1u);
    CHECK_EQ(sim.nodes[2].n_inbox, inbox2);
    CHECK_EQ(sim.nodes[0].inbox[inbox0].bytes[DR_PACKET_HEADER - 1u], DR_PACKET_LATTICE_STATE);
    CHECK_EQ(m->asking, 0u);
    CHECK_EQ(m->answer, 0);
    /* A restarted module has acknowledged no one: its first packet asks. */
    inbox2 = sim.nodes[1].n_inbox;
    sim_reset(0);
    dr_module_step(&sim.nodes[0].mod);
    CHECK_EQ(sim.nodes[1].n_inbox, inbox2 + 1u);
    CHECK_EQ(sim.nodes[1].inbox[inbox2].bytes[DR_PACKET_HEADER - 1u], DR_PACKET_LATTICE_ASK);
    CHECK(sim_run(10000u));
    CHECK_EQ(sim.violations, 0);
}

/* Toward a neighbour heard behind and not heard with our copy since (a link that loses most
 * packets), the smallest interval, as long as it lasts; once it is heard with our copy, the
 * longest. */
static void test_lagging_neighbour(void)
{
    static const uint8_t addr[] = { 0, 1 };
    dr_module_t *m = &sim.nodes[0].mod;
    uint32_t before;
    run_to_a_quiet_end(&two_no_nv, 2, addr, 77u);
    sim.nodes[0].mute = 1; /* node 1 is heard, node 0's answers are lost */
    sim_reset(1);          /* without NV: behind, and it stays so */
    run_ticks(100u);
    CHECK_EQ(m->lagging, 2u);
    sim.loss_percent = 100; /* now nothing passes either way */
    sim.nodes[0].mute = 0;
    before = m->packets_sent;
    run_ticks(2000u);
    CHECK(m->packets_sent - before >=
          2000u / (DR_CONF_LATTICE_INTERVAL_MS + DR_CONF_BROADCAST_JITTER_MS + SIM_TICK_MS));
    sim.loss_percent = 0;
    run_ticks(1000u);
    CHECK(dr_module_finished(&sim.nodes[1].mod));
    CHECK_EQ(m->lagging, 0u);
    CHECK_EQ(m->doublings, DR_CONF_LATTICE_DOUBLINGS);
    CHECK_EQ(sim.starts[0][0] + sim.starts[0][1], 2);
    CHECK_EQ(sim.violations, 0);
}
#endif

void test_dissemination(void)
{
    build();
    test_quiet_robot();
    test_handover_across_relays();
    test_behind_is_answered();
    test_cut_off_and_back();
#if ADAPTIVE
    test_interval();
    test_resend_is_answered();
    test_relay_acknowledges();
    test_ask_is_answered();
    test_lagging_neighbour();
#endif
}
