/* test_sim.c - modules running programs on the fake platform: dependencies respected, the
 * end reached, resets survived without re-issuing completed operations, epochs. */
#include <string.h>
#include "check.h"
#include "dr_packet.h"
#include "sim.h"

/* ---- fixed programs (statement k's op carries k; addresses are node numbers) ---- */

/* `A & B; C;`  A@0 B@1 C@2 */
static dr_statement_t p1_st[3];
static const dr_dep_t p1_deps[] = { 0, 1 };
/* `A; B & C; D;`  A@0 B@1 C@2 D@0 (D also depends on A, the same module's previous) */
static dr_statement_t p2_st[4];
static const dr_dep_t p2_deps[] = { 0, 0, 1, 2, 0 };
/* `A & B & C; D;`  D on C's module */
static dr_statement_t p3_st[4];
static const dr_dep_t p3_deps[] = { 0, 1, 2 };

static dr_program_t p1 = { 0x11u, 3u, p1_st, p1_deps, sim_args, 1u, sim_address_of, 0u };
static dr_program_t p2 = { 0x22u, 4u, p2_st, p2_deps, sim_args, 1u, sim_address_of, 0u };
static dr_program_t p3 = { 0x33u, 4u, p3_st, p3_deps, sim_args, 1u, sim_address_of, 0u };

static const uint8_t addr3[] = { 0, 1, 2 };

static void build_fixed(void)
{
    sim_statement(&p1_st[0], 0, 0, 0, 0);
    sim_statement(&p1_st[1], 1, 1, 0, 0);
    sim_statement(&p1_st[2], 2, 2, 2, 0);
    sim_statement(&p2_st[0], 0, 0, 0, 0);
    sim_statement(&p2_st[1], 1, 1, 1, 0);
    sim_statement(&p2_st[2], 2, 2, 1, 1);
    sim_statement(&p2_st[3], 0, 3, 3, 2);
    sim_statement(&p3_st[0], 0, 0, 0, 0);
    sim_statement(&p3_st[1], 1, 1, 0, 0);
    sim_statement(&p3_st[2], 2, 2, 0, 0);
    sim_statement(&p3_st[3], 2, 3, 3, 0);
}

/* ---- generated programs: groups of 1-3 statements on random modules; each statement
 * depends on the previous group and on its module's previous statement ---- */

static dr_statement_t g_st[SIM_MAX_STATEMENTS];
static dr_dep_t g_deps[SIM_MAX_STATEMENTS * 5u];
static dr_program_t g_prog;

static void generate(uint16_t n, uint8_t modules, uint16_t epochs)
{
    uint16_t s = 0;
    uint16_t nd = 0;
    uint16_t prev_start = 0;
    uint16_t prev_end = 0;
    uint16_t size;
    uint16_t k;
    uint16_t p;
    uint16_t first;
    uint16_t start;
    uint8_t address;
    int16_t last_of[SIM_MAX_NODES];
    for (k = 0; k < SIM_MAX_NODES; k++) {
        last_of[k] = -1;
    }
    while (s < n) {
        size = (uint16_t)(1u + sim_rand() % 3u);
        if (s + size > n) {
            size = (uint16_t)(n - s);
        }
        start = s;
        for (k = 0; k < size; k++, s++) {
            address = (uint8_t)(sim_rand() % modules);
            first = nd;
            for (p = prev_start; p < prev_end; p++) {
                g_deps[nd++] = (dr_dep_t)p;
            }
            if (last_of[address] >= 0 && (uint16_t)last_of[address] >= start) {
                g_deps[nd++] = (dr_dep_t)last_of[address];
            } else if (last_of[address] >= 0 && (uint16_t)last_of[address] < prev_start) {
                g_deps[nd++] = (dr_dep_t)last_of[address];
            }
            sim_statement(&g_st[s], address, s, (uint8_t)(nd - first), first);
            last_of[address] = (int16_t)s;
        }
        prev_start = start;
        prev_end = s;
    }
    g_prog.fingerprint = 0x40u + n;
    g_prog.n_statements = n;
    g_prog.statements = g_st;
    g_prog.deps = g_deps;
    g_prog.args = sim_args;
    g_prog.n_epochs = epochs;
    g_prog.address_of = sim_address_of;
    g_prog.options = 0;
}

/* ---- helpers ---- */

static void network(uint8_t loss, uint16_t delay, uint8_t dup, uint8_t corrupt)
{
    sim.loss_percent = loss;
    sim.max_delay_ms = delay;
    sim.dup_percent = dup;
    sim.corrupt_percent = corrupt;
}

/* Every statement of epochs [0, epochs) started `times` times, except `special` (started
 * `special_times`). */
static void check_starts(const dr_program_t *p, uint16_t epochs, uint8_t times, uint16_t special,
                         uint8_t special_times)
{
    uint16_t r;
    uint16_t s;
    for (r = 0; r < epochs; r++) {
        for (s = 0; s < p->n_statements; s++) {
            CHECK_EQ(sim.starts[r][s], s == special && r == sim.fault_epoch ? special_times : times);
        }
    }
}

/* Steps for a fixed time, finished or not. */
static void run_for(uint32_t ms)
{
    uint32_t t;
    for (t = 0; t < ms; t += SIM_TICK_MS) {
        (void)sim_run(SIM_TICK_MS);
    }
}

/* ---- tests ---- */

static void test_programs(void)
{
    dr_program_t *programs[3];
    uint8_t k;
    uint8_t net;
    uint8_t mesh;
    uint32_t malformed;
    uint8_t i;
    programs[0] = &p1;
    programs[1] = &p2;
    programs[2] = &p3;
    for (k = 0; k < 3u; k++) {
        for (mesh = 0; mesh < 2u; mesh++) {
            for (net = 0; net < 2u; net++) {
                sim_setup(programs[k], 3, addr3, 100u + k * 10u + mesh * 2u + net);
                if (mesh) {
                    sim_full_mesh();
                }
                if (net) {
                    network(30, 150, 10, 10);
                }
                CHECK(sim_run(60000u));
                CHECK_EQ(sim.violations, 0);
                check_starts(programs[k], 1, 1, SIM_NONE, 0);
                malformed = 0;
                for (i = 0; i < 3u; i++) {
                    malformed += sim.nodes[i].mod.packets_malformed;
                    CHECK_EQ(sim.nodes[i].mod.shared.epoch, 1);
                }
                /* Every corrupted packet delivered is rejected (some are still in flight). */
                CHECK(malformed <= sim.corrupted);
                CHECK(net || malformed == 0u);
                /* Perfect network, everyone in range: a completion is announced at once and
                 * the next statement starts within two steps. */
                CHECK(net || !mesh || sim.max_handover_ms <= 2u * SIM_TICK_MS);
            }
        }
    }
}

/* A module with no (or an ambiguous) address relays the state between the others. */
static void test_relay(void)
{
    uint8_t addresses[4] = { 0, DR_NO_ADDRESS, 1, 2 };
    uint8_t k;
    for (k = 0; k < 2u; k++) {
        addresses[1] = k ? DR_MANY_ADDRESSES : DR_NO_ADDRESS;
        sim_setup(&p1, 4, addresses, 5u + k);
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0);
        check_starts(&p1, 1, 1, SIM_NONE, 0);
        CHECK_EQ(sim.nodes[1].fake.leds, addresses[1]);
        CHECK_EQ(sim.nodes[2].fake.leds, 1);
        CHECK(sim.nodes[1].mod.packets_sent > 0u);
    }
}

/* Resets at various moments, the NV store surviving. */
static void test_resets(void)
{
    dr_program_t *programs[3];
    uint8_t k;
    uint16_t s;
    uint8_t i;
    uint8_t lossy;
    uint8_t copy;
    uint32_t starts;
    programs[0] = &p1;
    programs[1] = &p2;
    programs[2] = &p3;
    for (k = 0; k < 3u; k++) {
        const dr_program_t *p = programs[k];
        for (s = 0; s < p->n_statements; s++) {
            uint8_t owner = p->statements[s].address;
            for (lossy = 0; lossy < 2u; lossy++) {
                /* Right after a completion, before it was announced: never re-issued. */
                sim_setup(p, 3, addr3, 200u + s + lossy);
                if (lossy) {
                    network(30, 100, 10, 0);
                }
                sim.reset_after_done_stmt = s;
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                check_starts(p, 1, 1, SIM_NONE, 0);

                /* Half-way through the operation: re-issued once, completes. */
                sim_setup(p, 3, addr3, 300u + s + lossy);
                if (lossy) {
                    network(30, 100, 10, 0);
                }
                sim.reset_mid_stmt = s;
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                check_starts(p, 1, 1, s, 2);
            }
            /* Power lost while persisting the completion: in the first copy, the completion
             * is lost with it (it was not announced yet) and the operation is re-issued; in
             * the second copy, the first one holds it and nothing is re-issued. */
            for (copy = 0; copy < 2u; copy++) {
                sim_setup(p, 3, addr3, 400u + s + copy);
                sim.tear_after_done_stmt = s;
                sim.tear_copy = (int16_t)copy;
                sim.strict = (uint8_t)(copy == 1u);
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                check_starts(p, 1, 1, s, (uint8_t)(copy == 0u ? 2u : 1u));
            }
        }
        /* After the end: each module in turn (the first one first) is reset; nothing is
         * re-issued, and the end is known again (from the NV store of the module that
         * completed the last statement, or else from a neighbour). */
        sim_setup(p, 3, addr3, 500u + k);
        CHECK(sim_run(60000u));
        starts = sim.total_starts;
        for (i = 0; i < 3u; i++) {
            sim_reset(i);
            CHECK(dr_module_finished(&sim.nodes[i].mod) ==
                  (p->statements[p->n_statements - 1u].address == i));
            run_for(1000u);
            CHECK(dr_module_finished(&sim.nodes[i].mod));
        }
        /* All of them at once (a power cycle of the robot): the same. */
        for (i = 0; i < 3u; i++) {
            sim_reset(i);
        }
        CHECK(sim_run(5000u));
        CHECK_EQ(sim.total_starts, starts);
        CHECK_EQ(sim.violations, 0);
        for (i = 0; i < 3u; i++) {
            CHECK_EQ(sim.nodes[i].mod.resets, 2);
        }
    }
}

/* A module reset after the configuration changed keeps the address it had at the start
 * (from its NV store), even if its role predicates now say otherwise. */
static void test_address_kept(void)
{
    sim_setup(&p2, 3, addr3, 88u);
    while (!sim.reported[0][0] && sim.time < 10000u) {
        run_for(SIM_TICK_MS); /* until A (node 0) is done; D (node 0) waits for B and C */
    }
    CHECK_EQ(sim.nodes[0].mod.running, DR_NONE);
    sim.nodes[0].answer = 2; /* its predicates would now make it C's module */
    sim_reset(0);
    CHECK_EQ(sim.nodes[0].mod.address, 0);
    CHECK_EQ(sim.nodes[0].fake.leds, 0);
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    check_starts(&p2, 1, 1, SIM_NONE, 0);
}

/* The limit of the guarantee: a module whose NV store is lost (here: erased before its
 * reset) restarts from the bottom and re-issues its first operation before it hears that the
 * sequence is over. Recorded so that a change of this behaviour is noticed. */
static void test_without_nv(void)
{
    sim_setup(&p1, 3, addr3, 77u);
    CHECK(sim_run(60000u));
    sim.checks = 0;
    memset(sim.nodes[0].fake.nv, 0xFF, SIM_NV);
    sim_reset(0);
    CHECK(!dr_module_finished(&sim.nodes[0].mod));
    run_for(2000u);
    CHECK_EQ(sim.starts[0][0], 2); /* the known weakness without NV */
    CHECK(dr_module_finished(&sim.nodes[0].mod)); /* but the end is learnt again */
    CHECK_EQ(sim.starts[0][1], 1);
}

/* A new launch of the same program (the image flashed again with another execution,
 * dr_packet.h): what the last launch left in NV is ignored, so the sequence runs again from
 * the start, and the last launch's end, recorded and replayed under this robot's identity
 * with the key, is foreign. The old records are written as the other execution's (this
 * binary has one DR_EXECUTION: from the new image's side that is the same thing). */
static void test_another_launch(void)
{
    const uint32_t before_word =
        DR_PACKET_PROGRAM_WORD(p1.fingerprint, DR_EXECUTION ^ 0x80000001UL);
    const uint8_t record_len = (uint8_t)(5u + 4u + DR_CONF_WINDOW / 8u + 2u);
    dr_identity_t recorded;
    uint8_t nv[3][SIM_NV];
    uint8_t frames[3][DR_CONF_MAX_PACKET];
    uint8_t lens[3];
    uint8_t payload[4u + DR_CONF_WINDOW / 8u];
    uint8_t i;
    uint8_t copy;
    recorded.robot = DR_ROBOT_ID;
    recorded.fingerprint = before_word;
    sim_setup(&p1, 3, addr3, 61u);
    CHECK(sim_run(60000u));
    for (i = 0; i < 3u; i++) {
        uint8_t *rec;
        CHECK(dr_module_finished(&sim.nodes[i].mod));
        /* The end each module broadcast, as the earlier launch sent it. */
        (void)dr_shared_encode(&sim.nodes[i].mod.shared, payload, sizeof payload);
        lens[i] = dr_packet_frame(frames[i], DR_CONF_MAX_PACKET, &recorded,
                                  DR_PACKET_LATTICE_STATE, payload, sizeof payload);
        CHECK(lens[i] > 0u);
        memcpy(nv[i], sim.nodes[i].fake.nv, SIM_NV);
        for (copy = 0; copy < 2u; copy++) {
            rec = nv[i] + DR_CONF_LATTICE_NV_ADDR + copy * record_len;
            CHECK_EQ(dr_crc16(rec, record_len), 0); /* a valid record of this launch */
            dr_put_be32(rec, before_word);
            dr_crc16_put(rec, (uint8_t)(record_len - 2u));
        }
    }
    /* The new launch: the old records in NV, the old end replayed before anything else. */
    sim_setup(&p1, 3, addr3, 62u);
    for (i = 0; i < 3u; i++) {
        memcpy(sim.nodes[i].fake.nv, nv[i], SIM_NV);
        sim_reset(i);
        CHECK(!dr_module_finished(&sim.nodes[i].mod));
        CHECK_EQ(sim.nodes[i].mod.shared.low, 0);
        dr_module_receive(&sim.nodes[i].mod, 0, frames[i], lens[i]);
        CHECK_EQ(sim.nodes[i].mod.packets_foreign, 1);
        CHECK(!dr_module_finished(&sim.nodes[i].mod));
    }
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    check_starts(&p1, 1, 1, SIM_NONE, 0); /* every operation once, in this launch */
    /* And the records now name this launch: a module reset now restores its record and
     * re-issues nothing (with its record ignored it would redo A: test_without_nv). */
    sim_reset(0);
    run_for(2000u);
    CHECK(dr_module_finished(&sim.nodes[0].mod));
    check_starts(&p1, 1, 1, SIM_NONE, 0);
}

/* Whether the failure policy retries a failed batch at least twice (the tests that fail an
 * operation twice on purpose; test_failure_policy covers every policy). */
#define RETRIES_TWICE (DR_CONF_ON_FAILURE == DR_ON_FAILURE_RETRY && DR_CONF_RETRIES >= 2)

/* A failed operation is re-issued at the pace of the broadcast until it succeeds. */
static void test_failures(void)
{
    if (!RETRIES_TWICE) {
        return;
    }
    sim_setup(&p2, 3, addr3, 9u);
    sim.fail_stmt = 1;
    sim.fail_times = 2;
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    CHECK_EQ(sim.starts[0][1], 3);
    CHECK(sim.min_restart_gap_ms >= SIM_RETRY_MS);
    CHECK_EQ(sim.starts[0][0] + sim.starts[0][2] + sim.starts[0][3], 3);
}

/* A batch that fails more often than the failure policy allows (DR_CONF_ON_FAILURE,
 * DR_CONF_RETRIES): its module issues it once and then as many times again as the policy
 * retries, then stops: it starts nothing more and says so, the other modules go on with what
 * does not depend on it, and what does never starts. */
static void test_failure_policy(void)
{
    uint8_t retries = (uint8_t)(DR_CONF_ON_FAILURE == DR_ON_FAILURE_RETRY ? DR_CONF_RETRIES : 0);
    char text[64];
    sim_setup(&p2, 3, addr3, 19u);
    sim.fail_stmt = 1;
    sim.fail_times = (uint8_t)(retries + 1u);
    CHECK(!sim_run(30000u));
    CHECK_EQ(sim.violations, 0);
    CHECK_EQ(sim.starts[0][1], retries + 1u);
    CHECK_EQ(sim.starts[0][2], 1);
    CHECK_EQ(sim.starts[0][3], 0);
    CHECK_EQ(dr_module_finished(&sim.nodes[1].mod), DR_END_STOPPED);
    CHECK_EQ(dr_module_finished(&sim.nodes[0].mod), DR_END_NONE);
    CHECK_EQ(sim.nodes[1].mod.running, DR_NONE);
    (void)dr_module_describe(&sim.nodes[1].mod, text, (uint8_t)sizeof text);
    CHECK(strstr(text, " stopped") != NULL);
    /* One failure fewer: the last retry succeeds and the sequence ends. */
    sim_setup(&p2, 3, addr3, 20u);
    sim.fail_stmt = 1;
    sim.fail_times = retries;
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    CHECK_EQ(sim.starts[0][1], retries + 1u);
    /* A reset gives the stopped module its retries again (the count is not persisted). */
    sim_setup(&p2, 3, addr3, 21u);
    sim.fail_stmt = 1;
    sim.fail_times = (uint8_t)(retries + 1u);
    CHECK(!sim_run(30000u));
    sim_reset(1);
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    CHECK_EQ(sim.starts[0][1], retries + 2u);
}

static void test_epochs(void)
{
    dr_program_t twice = p2;
    dr_program_t forever = p1;
    uint8_t lossy;
    uint8_t i;
    uint16_t r;
    twice.n_epochs = 2;
    forever.n_epochs = 0;
    for (lossy = 0; lossy < 2u; lossy++) {
        sim_setup(&twice, 3, addr3, 600u + lossy);
        if (lossy) {
            network(30, 100, 10, 2);
        }
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0);
        check_starts(&twice, 2, 1, SIM_NONE, 0);
        for (i = 0; i < 3u; i++) {
            CHECK_EQ(sim.nodes[i].mod.shared.epoch, 2);
        }
        /* A reset mid-operation in the second epoch. */
        sim_setup(&twice, 3, addr3, 610u + lossy);
        sim.reset_mid_stmt = 2;
        sim.fault_epoch = 1;
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0);
        check_starts(&twice, 2, 1, 2, 2);
    }
    /* n_epochs = 0: runs again and again, never finishes. */
    sim_setup(&forever, 3, addr3, 700u);
    CHECK(!sim_run(4000u));
    CHECK_EQ(sim.violations, 0);
    for (i = 0; i < 3u; i++) {
        CHECK(sim.nodes[i].mod.shared.epoch >= 4u);
        CHECK(!dr_module_finished(&sim.nodes[i].mod));
    }
    for (r = 0; r < 3u; r++) {
        CHECK_EQ(sim.starts[r][0] + sim.starts[r][1] + sim.starts[r][2], 3);
    }
}

/* A completion that arrives after the epoch moved on does not count in the new epoch. */
static void test_old_epoch_completion(void)
{
    static dr_statement_t st[2];
    static const dr_dep_t deps[] = { 0 };
    dr_program_t p = { 0x77u, 2u, st, deps, sim_args, 3u, sim_address_of, 0u };
    static const uint8_t one[] = { 0 };
    uint8_t payload[4u + DR_CONF_WINDOW / 8u];
    uint8_t frame[DR_CONF_MAX_PACKET];
    uint8_t len;
    uint32_t until;
    dr_shared_t s;
    dr_module_t *m;
    sim_statement(&st[0], 0, 0, 0, 0);
    sim_statement(&st[1], 0, 1, 1, 0);
    sim_setup(&p, 1, one, 3u);
    sim.checks = 0;
    m = &sim.nodes[0].mod;
    dr_module_step(m);
    CHECK_EQ(m->running, 0);
    CHECK_EQ(m->running_epoch, 0);
    /* Another copy says epoch 1 began (possible only after a lost NV store, say). */
    memset(&s, 0, sizeof s);
    s.epoch = 1;
    len = dr_shared_encode(&s, payload, sizeof payload);
    len = dr_packet_frame(frame, sizeof frame, &m->identity, DR_PACKET_LATTICE_STATE, payload,
                          len);
    dr_module_receive(m, 0, frame, len);
    CHECK_EQ(m->shared.epoch, 1);
    CHECK_EQ(m->running, 0); /* still waiting for the operation it started */
    until = sim_op_until(&sim.nodes[0]);
    while (sim.time < until) {
        sim.time += SIM_TICK_MS;
        dr_module_step(m);
    }
    /* The epoch-0 completion was dropped: statement 0 is not done in epoch 1, and is started
     * (again) in epoch 1. */
    CHECK(!dr_shared_is_done(&m->shared, 0));
    CHECK_EQ(m->shared.epoch, 1);
    CHECK_EQ(m->running, 0);
    CHECK_EQ(m->running_epoch, 1);
    CHECK_EQ(sim.starts[1][0], 1);
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.starts[0][1], 0);
    CHECK_EQ(sim.starts[1][1], 1);
    CHECK_EQ(sim.starts[2][0], 1);
    CHECK_EQ(sim.starts[2][1], 1);
    CHECK_EQ(m->shared.epoch, 3);
}

/* A long program: the window slides over it; with several modules per group. */
static void test_long(void)
{
    uint8_t addresses[5] = { 0, 1, 2, 3, 4 };
    sim_setup(&p1, 1, addresses, 1u); /* seeds sim_rand for generate() */
    generate(SIM_MAX_STATEMENTS, 5, 2);
    sim_setup(&g_prog, 5, addresses, 31u);
    network(20, 80, 5, 1);
    CHECK(sim_run(200000u));
    CHECK_EQ(sim.violations, 0);
    check_starts(&g_prog, 2, 1, SIM_NONE, 0);
}

/* A program that needs a bigger window than it has (the compiler would refuse it): four
 * independent chains of statements, one per module, one of them slow. A statement beyond the window waits until
 * the low-water mark comes close enough: slower, never unsafe, never out of the arrays. */
static void test_window_too_small(void)
{
    static const uint8_t addresses[] = { 0, 1, 2, 3 };
    uint16_t s;
    uint16_t nd = 0;
    uint16_t n = 3u * DR_CONF_WINDOW < SIM_MAX_STATEMENTS ? 3u * DR_CONF_WINDOW : SIM_MAX_STATEMENTS;
    for (s = 0; s < n; s++) {
        if (s >= 4u) {
            g_deps[nd] = (dr_dep_t)(s - 4u);
            sim_statement(&g_st[s], (uint8_t)(s % 4u), s, 1, nd);
            nd++;
        } else {
            sim_statement(&g_st[s], (uint8_t)(s % 4u), s, 0, 0);
        }
    }
    g_prog.fingerprint = 0x99u;
    g_prog.n_statements = n;
    g_prog.statements = g_st;
    g_prog.deps = g_deps;
    g_prog.args = sim_args;
    g_prog.n_epochs = 1;
    g_prog.address_of = sim_address_of;
    g_prog.options = 0;
    sim_setup(&g_prog, 4, addresses, 8u);
    sim_full_mesh();
    sim.slow_address = 3;
    CHECK(sim_run(200000u));
    CHECK_EQ(sim.violations, 0);
    check_starts(&g_prog, 1, 1, SIM_NONE, 0);
    /* The fast chains were held back by the window. */
    CHECK(sim.max_handover_ms > 300u);
}

/* Random programs, networks and resets (the NV store surviving). */
static void test_fuzz(unsigned runs)
{
    unsigned run;
    uint8_t addresses[SIM_MAX_NODES];
    uint8_t n_modules;
    uint8_t n_nodes;
    uint8_t relay;
    uint8_t i;
    uint8_t resets;
    uint8_t k;
    uint16_t r;
    uint16_t s;
    uint32_t starts;
    uint32_t failed_runs = 0;
    for (run = 0; run < runs; run++) {
        sim_setup(&p1, 1, addr3, 1000u + run);
        n_modules = (uint8_t)(2u + sim_rand() % 4u);
        generate((uint16_t)(3u + sim_rand() % 22u), n_modules, (uint16_t)(1u + sim_rand() % 3u));
        relay = (uint8_t)(sim_rand() % 2u);
        n_nodes = (uint8_t)(n_modules + relay);
        for (i = 0; i < n_modules; i++) {
            addresses[i] = i;
        }
        if (relay) {
            addresses[n_modules] = addresses[0];
            addresses[0] = DR_NO_ADDRESS; /* the relay is at one end ... */
            if (n_nodes > 2u) {            /* ... or in the middle */
                addresses[0] = addresses[1];
                addresses[1] = DR_NO_ADDRESS;
            }
        }
        sim_setup(&g_prog, n_nodes, addresses, 5000u + run);
        if (sim_rand() % 2u) {
            sim_full_mesh();
        }
        network((uint8_t)(sim_rand() % 41u), (uint16_t)(sim_rand() % 200u),
                (uint8_t)(sim_rand() % 21u), (uint8_t)(sim_rand() % 6u));
        resets = (uint8_t)(sim_rand() % 6u);
        for (i = 0; i < resets; i++) {
            if (sim_run(sim_rand() % 1500u)) {
                break;
            }
            if (sim_rand() % 4u == 0u) {
                for (k = 0; k < n_nodes; k++) {
                    sim_reset(k); /* all at once: a power cycle */
                }
            } else {
                sim_reset((uint8_t)(sim_rand() % n_nodes));
            }
        }
        CHECK(sim_run(300000u));
        /* After the end, a reset of a random module re-issues nothing. */
        starts = sim.total_starts;
        sim_reset((uint8_t)(sim_rand() % n_nodes));
        run_for(500u);
        CHECK_EQ(sim.total_starts, starts);
        CHECK_EQ(sim.violations, 0);
        for (r = 0; r < g_prog.n_epochs; r++) {
            for (s = 0; s < g_prog.n_statements; s++) {
                CHECK(sim.starts[r][s] >= 1u);
            }
        }
        if (sim.violations != 0u) {
            failed_runs++;
            if (failed_runs <= 3u) {
                fprintf(stderr, "  fuzz run %u failed\n", run);
            }
        }
    }
}

/* ---- without non-volatile storage (DR_PROGRAM_NO_NV) ---- */

static dr_program_t without_nv(const dr_program_t *p)
{
    dr_program_t q = *p;
    q.options = DR_PROGRAM_NO_NV;
    return q;
}

/* The runtime never touched any node's NV store. */
static void check_no_nv_access(void)
{
    uint8_t i;
    uint16_t b;
    for (i = 0; i < sim.n_nodes; i++) {
        CHECK_EQ(sim.nodes[i].fake.nv_reads, 0);
        CHECK_EQ(sim.nodes[i].fake.nv_writes, 0);
        for (b = 0; b < SIM_NV && sim.nodes[i].fake.nv[b] == 0xFFu; b++) {
        }
        CHECK_EQ(b, SIM_NV);
    }
}

/* Without resets: every program finishes, each operation started once, S1 checked at each
 * start, under a perfect or a lossy/delaying/duplicating/corrupting network, line or mesh,
 * one or two epochs, and a long program with five modules. */
static void test_no_nv_programs(void)
{
    dr_program_t programs[4];
    uint8_t addresses[5] = { 0, 1, 2, 3, 4 };
    uint8_t k;
    uint8_t net;
    uint8_t mesh;
    programs[0] = without_nv(&p1);
    programs[1] = without_nv(&p2);
    programs[2] = without_nv(&p3);
    programs[3] = without_nv(&p2);
    programs[3].n_epochs = 2;
    for (k = 0; k < 4u; k++) {
        for (mesh = 0; mesh < 2u; mesh++) {
            for (net = 0; net < 2u; net++) {
                sim_setup(&programs[k], 3, addr3, 800u + k * 10u + mesh * 2u + net);
                if (mesh) {
                    sim_full_mesh();
                }
                if (net) {
                    network(30, 150, 10, 10);
                }
                CHECK(sim_run(60000u));
                CHECK_EQ(sim.violations, 0);
                check_starts(&programs[k], programs[k].n_epochs, 1, SIM_NONE, 0);
                check_no_nv_access();
                /* Perfect network: everyone broadcasts at start-up, so rule 1 costs one tick. */
                CHECK(net || sim.last_start_ms[0][0] <= 2u * SIM_TICK_MS);
            }
        }
    }
    sim_setup(&p1, 1, addresses, 1u); /* seeds sim_rand for generate() */
    generate(SIM_MAX_STATEMENTS, 5, 2);
    g_prog.options = DR_PROGRAM_NO_NV;
    sim_setup(&g_prog, 5, addresses, 32u);
    network(20, 80, 5, 1);
    CHECK(sim_run(200000u));
    CHECK_EQ(sim.violations, 0);
    check_starts(&g_prog, 2, 1, SIM_NONE, 0);
    check_no_nv_access();
}

/* The two rules, one at a time, on `A; B;` (both on node 0) with a relay as node 0's only
 * neighbour; and a module with no neighbour at all. */
static void test_no_nv_rules(void)
{
    static dr_statement_t st[2];
    static const dr_dep_t deps[] = { 0 };
    static const uint8_t nodes[] = { 0, DR_NO_ADDRESS };
    dr_program_t q = { 0x55u, 2u, st, deps, sim_args, 1u, sim_address_of, DR_PROGRAM_NO_NV };
    uint32_t t;
    sim_statement(&st[0], 0, 0, 0, 0);
    sim_statement(&st[1], 0, 1, 1, 0);

    /* Rule 1: while the relay is silent, node 0 starts nothing, however long; once it has
     * heard the relay (its next broadcast: with adaptive dissemination, after up to the
     * longest interval, since the relay heard nothing new meanwhile), it starts at once. */
    sim_setup(&q, 2, nodes, 51u);
    sim.nodes[1].mute = 1;
    CHECK_EQ(sim.nodes[0].mod.unheard, 2); /* channel 1: the relay */
    run_for(10000u);
    CHECK_EQ(sim.starts[0][0], 0);
    CHECK_EQ(sim.nodes[0].mod.unheard, 2);
    t = sim.time;
    sim.nodes[1].mute = 0;
    while (sim.starts[0][0] == 0 &&
           sim.time - t <= SIM_LONGEST_GAP_MS + DR_CONF_BROADCAST_JITTER_MS + 2u * SIM_TICK_MS) {
        run_for(SIM_TICK_MS);
    }
    CHECK_EQ(sim.nodes[0].mod.unheard, 0);
    CHECK_EQ(sim.starts[0][0], 1);
    CHECK(sim.last_start_ms[0][0] > t);
    /* Rule 2: the relay falls silent again; A is done (and broadcast), but no neighbour has
     * sent it back: B waits. */
    sim.nodes[1].mute = 1;
    run_for(2000u);
    CHECK(sim.reported[0][0]);
    CHECK(dr_shared_is_done(&sim.nodes[0].mod.shared, 0));
    CHECK_EQ(sim.nodes[0].mod.unechoed, 0);
    CHECK_EQ(sim.starts[0][1], 0);
    /* Rule 1 when the neighbour talks: a start-up costs about one tick. */
    sim_setup(&q, 2, nodes, 52u);
    CHECK(sim_run(5000u));
    CHECK(sim.last_start_ms[0][0] <= 2u * SIM_TICK_MS);
    CHECK_EQ(sim.violations, 0);

    /* No connected neighbour: nothing to wait for and no one to echo; it runs alone (and a
     * reset of it starts the program again: nobody else holds a copy). */
    sim_setup(&q, 1, nodes, 53u);
    CHECK_EQ(sim.nodes[0].mod.unheard, 0);
    CHECK(sim_run(5000u));
    CHECK(sim.last_start_ms[0][0] <= SIM_TICK_MS);
    CHECK_EQ(sim.violations, 0);
    check_starts(&q, 1, 1, SIM_NONE, 0);
    check_no_nv_access();
}

/* A single reset at various moments, on a perfect or a lossy network (loss, duplication,
 * corruption; no delay, so no packet sent before a reset arrives after it): S1 and S2 hold
 * at every start and the program finishes. */
static void test_no_nv_resets(void)
{
    dr_program_t programs[3];
    uint8_t k;
    uint16_t s;
    uint8_t i;
    uint16_t t;
    uint8_t lossy;
    uint32_t starts;
    programs[0] = without_nv(&p1);
    programs[1] = without_nv(&p2);
    programs[2] = without_nv(&p3);
    for (k = 0; k < 3u; k++) {
        const dr_program_t *p = &programs[k];
        for (s = 0; s < p->n_statements; s++) {
            uint8_t owner = p->statements[s].address;
            for (lossy = 0; lossy < 2u; lossy++) {
                /* Right after a completion, before it was broadcast: the completion is lost
                 * with the reset and the operation re-issued once; harmless, nothing after it
                 * could start (no neighbour had echoed it). */
                sim_setup(p, 3, addr3, 900u + s + lossy);
                if (lossy) {
                    network(30, 0, 10, 5);
                }
                sim.reset_after_done_stmt = s;
                sim.strict = 0;
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                check_starts(p, 1, 1, s, 2);
                check_no_nv_access();

                /* 10 ms after a completion was broadcast (before or after its echo): a
                 * neighbour holds it, so it is not re-issued (on the lossy network it is
                 * when every copy of the broadcast was lost: harmless as above). */
                sim_setup(p, 3, addr3, 1000u + s + lossy);
                if (lossy) {
                    network(30, 0, 10, 5);
                }
                sim.reset_after_done_stmt = s;
                sim.reset_after_done_ms = 10;
                sim.strict = (uint8_t)!lossy;
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                for (t = 0; t < p->n_statements; t++) {
                    CHECK(sim.starts[0][t] == 1u ||
                          (lossy && t == s && sim.starts[0][t] == 2u));
                }
                check_no_nv_access();

                /* Half-way through the operation: re-issued once, completes. */
                sim_setup(p, 3, addr3, 1100u + s + lossy);
                if (lossy) {
                    network(30, 0, 10, 5);
                }
                sim.reset_mid_stmt = s;
                CHECK(sim_run(60000u));
                CHECK(sim.fault_fired);
                CHECK_EQ(sim.nodes[owner].mod.resets, 1);
                CHECK_EQ(sim.violations, 0);
                check_starts(p, 1, 1, s, 2);
                check_no_nv_access();
            }
        }
        /* After the end, each module in turn: it starts from the bottom, hears a neighbour
         * that knows the end, re-issues nothing. */
        sim_setup(p, 3, addr3, 1200u + k);
        CHECK(sim_run(60000u));
        starts = sim.total_starts;
        for (i = 0; i < 3u; i++) {
            sim_reset(i);
            CHECK(!dr_module_finished(&sim.nodes[i].mod));
            run_for(1500u);
            CHECK(dr_module_finished(&sim.nodes[i].mod));
        }
        CHECK_EQ(sim.total_starts, starts);
        CHECK_EQ(sim.violations, 0);
        check_no_nv_access();
    }
}

/* A reset while every neighbour is silent (its links blocked, or the neighbours powered off):
 * `A; B & C; D;` on three nodes, in a line (node 0's only neighbour is node 1) or all hearing
 * each other. B and C run when node 0 resets with its neighbours mute for 5 s. Node 0 starts
 * from the bottom and has heard no one, so it must not act: it waits, however long (it used
 * to give up after ten broadcast periods and re-issue A after B and C had started). When
 * they speak, it learns that A is done and goes on. */
static void test_no_nv_silent_neighbours(void)
{
    dr_program_t q2 = without_nv(&p2);
    uint8_t mesh;
    uint8_t i;
    dr_channels_t all;
    for (mesh = 0; mesh < 2u; mesh++) {
        sim_setup(&q2, 3, addr3, 1400u + mesh);
        if (mesh) {
            sim_full_mesh();
        }
        all = (dr_channels_t)(mesh ? 6u : 2u); /* channel c: the link to node c */
        while ((sim.starts[0][1] == 0u || sim.starts[0][2] == 0u) && sim.time < 10000u) {
            run_for(SIM_TICK_MS);
        }
        CHECK_EQ(sim.starts[0][0], 1);
        sim.nodes[1].mute = 1;
        sim.nodes[2].mute = 1;
        sim_reset(0);
        CHECK_EQ(sim.nodes[0].mod.unheard, all);
        run_for(5000u);
        CHECK_EQ(sim.starts[0][0], 1);
        CHECK_EQ(sim.nodes[0].mod.running, DR_NONE);
        CHECK_EQ(sim.nodes[0].mod.unheard, all);
        /* One neighbour speaks: with a second one still silent, node 0 still waits. */
        sim.nodes[2].mute = 0;
        run_for(300u);
        CHECK_EQ(sim.nodes[0].mod.unheard, (dr_channels_t)(all & 2u));
        CHECK_EQ(sim.starts[0][0], 1);
        for (i = 1; i < 3u; i++) {
            sim.nodes[i].mute = 0;
        }
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0);
        check_starts(&q2, 1, 1, SIM_NONE, 0);
        check_no_nv_access();
    }
}

/* A neighbour that unlatches while a restarted module waits for it (in the simulator: the
 * module's own retract, under way at the reset, completes and leaves the neighbour unable to
 * reach it). `A; B & C; D;` with all three nodes hearing each other; node 0 resets while B
 * and C run, node 2 is mute and then unlatches from node 0: once node 0 has heard node 1, it
 * forgets node 2 and goes on. On the line, node 0's only neighbour falls silent and unlatches
 * before node 0 heard anyone: node 0 knows nothing, so it still waits, until the link is back
 * and the neighbour speaks. */
static void test_no_nv_unlatched_neighbour(void)
{
    dr_program_t q2 = without_nv(&p2);
    uint8_t mesh;
    for (mesh = 0; mesh < 2u; mesh++) {
        uint8_t gone = (uint8_t)(mesh ? 2u : 1u);
        sim_setup(&q2, 3, addr3, 1500u + mesh);
        if (mesh) {
            sim_full_mesh();
        }
        while ((sim.starts[0][1] == 0u || sim.starts[0][2] == 0u) && sim.time < 10000u) {
            run_for(SIM_TICK_MS);
        }
        sim.nodes[gone].mute = 1;
        sim_reset(0);
        sim.adj[0][gone] = 0;
        sim.adj[gone][0] = 0;
        run_for(3000u);
        CHECK_EQ(sim.starts[0][0], 1);
        if (mesh) {
            CHECK_EQ(sim.nodes[0].mod.unheard, 0); /* heard node 1, forgot node 2 */
            CHECK(sim.nodes[0].mod.heard);
        } else {
            CHECK_EQ(sim.nodes[0].mod.unheard, 2); /* heard no one: still waits for node 1 */
            CHECK(!sim.nodes[0].mod.heard);
            CHECK_EQ(sim.nodes[0].mod.running, DR_NONE);
            sim.adj[0][gone] = 1;
            sim.adj[gone][0] = 1;
        }
        sim.nodes[gone].mute = 0;
        CHECK(sim_run(60000u));
        CHECK_EQ(sim.violations, 0);
        check_starts(&q2, 1, 1, SIM_NONE, 0);
        check_no_nv_access();
    }
}

/* The limits, recorded as expected outcomes: resets close together, and a packet sent before
 * a reset and delivered after it. */
static void test_no_nv_limits(void)
{
    static dr_statement_t st[2];
    static const dr_dep_t deps[] = { 0 };
    static const uint8_t two[] = { 0, 1 };
    dr_program_t q2 = without_nv(&p2);
    static const uint8_t with_relay[] = { 0, DR_NO_ADDRESS };
    dr_program_t ab = { 0x56u, 2u, st, deps, sim_args, 1u, sim_address_of, DR_PROGRAM_NO_NV };
    uint8_t payload[4u + DR_CONF_WINDOW / 8u];
    sim_packet_t *stale;
    dr_shared_t old;
    uint32_t c_started;
    uint32_t starts;
    uint8_t i;
    /* `A; B & C; D;` on the line 0-1-2. A (node 0) is done, B (node 1) and C (node 2) run;
     * nodes 0 and 1 reset at the same moment. Node 2 still holds A, but node 0's only
     * neighbour is node 1, whose first packet after its reset is the bottom: node 0 has heard
     * every neighbour and re-issues A after B and C started. S2 is broken (the checker sees
     * it); the sequence still finishes. */
    sim_setup(&q2, 3, addr3, 1300u);
    while ((sim.starts[0][1] == 0u || sim.starts[0][2] == 0u) && sim.time < 10000u) {
        run_for(SIM_TICK_MS);
    }
    c_started = sim.last_start_ms[0][2];
    CHECK_EQ(sim.starts[0][0], 1);
    sim.quiet = 1;
    sim_reset(0);
    sim_reset(1);
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.starts[0][0], 2);
    CHECK(sim.last_start_ms[0][0] > c_started);
    CHECK(sim.violations >= 1u); /* S2: re-issued after a later statement started */
    CHECK_EQ(sim.starts[0][2], 1);
    CHECK_EQ(sim.starts[0][3], 1);

    /* Two modules, both reset after the end (two resets, or one power cycle): every copy of
     * the state is gone, and the whole sequence runs again. */
    sim_statement(&st[0], 0, 0, 0, 0);
    sim_statement(&st[1], 1, 1, 1, 0);
    sim_setup(&ab, 2, two, 1301u);
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.violations, 0);
    starts = sim.total_starts;
    sim.quiet = 1;
    for (i = 0; i < 2u; i++) {
        sim_reset(i);
    }
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.total_starts, 2u * starts);
    CHECK_EQ(sim.starts[0][0], 2);
    CHECK_EQ(sim.starts[0][1], 2);
    CHECK(sim.violations >= 1u);
    check_no_nv_access();

    /* One reset, and a packet the relay sent before it (A started, not done) delivered to
     * node 0 after it: `A; B;` both on node 0. B runs (A was echoed); node 0 resets; the stale
     * packet counts as fresh, node 0 has heard its only neighbour and re-issues A after B
     * started (S2 broken). The platform must drop what was received before a reset. */
    sim_statement(&st[1], 0, 1, 1, 0);
    sim_setup(&ab, 2, with_relay, 1302u);
    while (sim.starts[0][1] == 0u && sim.time < 10000u) {
        run_for(SIM_TICK_MS);
    }
    CHECK_EQ(sim.starts[0][0], 1);
    c_started = sim.last_start_ms[0][1];
    sim.quiet = 1;
    sim_reset(0);
    memset(&old, 0, sizeof old); /* the relay's state while A ran: nothing done */
    stale = &sim.nodes[0].inbox[sim.nodes[0].n_inbox++];
    stale->at = sim.time;
    stale->from = 1;
    stale->len = dr_packet_frame(stale->bytes, sizeof stale->bytes, &sim.nodes[0].mod.identity,
                                 DR_PACKET_LATTICE_STATE, payload,
                                 dr_shared_encode(&old, payload, sizeof payload));
    CHECK(sim_run(60000u));
    CHECK_EQ(sim.starts[0][0], 2);
    CHECK(sim.last_start_ms[0][0] > c_started);
    CHECK(sim.violations >= 1u);
    check_no_nv_access();
}

/* Random programs and networks (no delay: see test_no_nv_resets), with up to five single
 * resets at random moments, each one 1500-3000 ms after the previous one (enough for the
 * previous one's rule-1 wait to end on these networks): S1 and S2 hold at every start, every program finishes, and a reset after
 * the end re-issues nothing. */
static void test_no_nv_fuzz(unsigned runs)
{
    unsigned run;
    uint8_t addresses[SIM_MAX_NODES];
    uint8_t n_modules;
    uint8_t n_nodes;
    uint8_t relay;
    uint8_t i;
    uint8_t resets;
    uint16_t r;
    uint16_t s;
    uint32_t starts;
    uint32_t failed_runs = 0;
    for (run = 0; run < runs; run++) {
        sim_setup(&p1, 1, addr3, 7000u + run);
        n_modules = (uint8_t)(2u + sim_rand() % 4u);
        generate((uint16_t)(3u + sim_rand() % 22u), n_modules, (uint16_t)(1u + sim_rand() % 3u));
        g_prog.options = DR_PROGRAM_NO_NV;
        relay = (uint8_t)(sim_rand() % 2u);
        n_nodes = (uint8_t)(n_modules + relay);
        for (i = 0; i < n_modules; i++) {
            addresses[i] = i;
        }
        if (relay) {
            addresses[n_modules] = addresses[0];
            addresses[0] = DR_NO_ADDRESS;
            if (n_nodes > 2u) {
                addresses[0] = addresses[1];
                addresses[1] = DR_NO_ADDRESS;
            }
        }
        sim_setup(&g_prog, n_nodes, addresses, 8000u + run);
        sim.strict = 0; /* an unannounced completion lost with a reset is re-issued */
        if (sim_rand() % 2u) {
            sim_full_mesh();
        }
        network((uint8_t)(sim_rand() % 41u), 0, (uint8_t)(sim_rand() % 21u),
                (uint8_t)(sim_rand() % 6u));
        resets = (uint8_t)(sim_rand() % 6u);
        if (sim_run(sim_rand() % 1500u)) {
            resets = 0;
        }
        for (i = 0; i < resets; i++) {
            sim_reset((uint8_t)(sim_rand() % n_nodes));
            if (sim_run(1500u + sim_rand() % 1500u)) {
                break;
            }
        }
        CHECK(sim_run(300000u));
        starts = sim.total_starts;
        sim_reset((uint8_t)(sim_rand() % n_nodes));
        run_for(1500u);
        CHECK_EQ(sim.total_starts, starts);
        CHECK_EQ(sim.violations, 0);
        for (r = 0; r < g_prog.n_epochs; r++) {
            for (s = 0; s < g_prog.n_statements; s++) {
                CHECK(sim.starts[r][s] >= 1u);
            }
        }
        check_no_nv_access();
        if (sim.violations != 0u) {
            failed_runs++;
            if (failed_runs <= 3u) {
                fprintf(stderr, "  no-NV fuzz run %u failed\n", run);
            }
        }
    }
}

/* Batches: node 0 runs statements 0 and 2 (no dependencies) together, then 3 (after 0);
 * node 1 runs 1, then 4 (after 2 and 3). */
static dr_statement_t batch_st[5];
static const dr_dep_t batch_deps[] = { 0, 2, 3 };
static dr_program_t pb = { 0x6Bu, 5u, batch_st, batch_deps, sim_args, 1u, sim_address_of, 0u };
static const uint8_t addr2[] = { 0, 1 };

static void build_batch(void)
{
    sim_statement(&batch_st[0], 0, 0, 0, 0);
    sim_statement(&batch_st[1], 1, 1, 0, 0);
    sim_statement(&batch_st[2], 0, 2, 0, 0);
    sim_statement(&batch_st[3], 0, 3, 1, 0);
    sim_statement(&batch_st[4], 1, 4, 2, 1);
}

/* Node 0's batch {0, 2} ran at once (the same start time), and 3 only after it was done. */
static void check_batch_ran(uint8_t times)
{
    CHECK_EQ(sim.violations, 0);
    CHECK_EQ(sim.starts[0][0], times);
    CHECK_EQ(sim.starts[0][2], times);
    CHECK_EQ(sim.last_start_ms[0][0], sim.last_start_ms[0][2]);
    CHECK(sim.last_start_ms[0][3] >= sim.reported_ms[0][2]);
    CHECK(sim.starts[0][3] >= 1); /* twice when a reset interrupts it */
    CHECK_EQ(sim.starts[0][1], 1);
    CHECK_EQ(sim.largest_batch, 2);
}

static void test_batches(void)
{
    dr_program_t q = without_nv(&pb);
    uint8_t k;
    build_batch();
    /* Two operations of one module run together; their completion is one update. */
    sim_setup(&pb, 2, addr2, 61u);
    run_for(SIM_TICK_MS);
    CHECK_EQ(sim.nodes[0].mod.running, 0);
    CHECK_EQ(sim.nodes[0].mod.batch, 0x02u); /* statement 0 + 2 */
    CHECK_EQ(sim.starts[0][3], 0);
    CHECK(sim_run(60000u));
    check_batch_ran(1);
    CHECK_EQ(sim.starts[0][3], 1);
    CHECK_EQ(sim.starts[0][4], 1);
    /* One of them fails twice: the whole batch is re-issued, nothing after it starts. */
    if (RETRIES_TWICE) {
        sim_setup(&pb, 2, addr2, 62u);
        sim.fail_stmt = 2;
        sim.fail_times = 2;
        CHECK(sim_run(60000u));
        check_batch_ran(3);
        CHECK(sim.min_restart_gap_ms >= SIM_RETRY_MS);
    }
    /* A reset half-way through the batch, with and without NV: both re-entered together. */
    for (k = 0; k < 2u; k++) {
        sim_setup(k ? &q : &pb, 2, addr2, 63u + k);
        sim.reset_mid_stmt = 0;
        CHECK(sim_run(60000u));
        CHECK(sim.fault_fired);
        CHECK_EQ(sim.nodes[0].mod.resets, 1);
        check_batch_ran(2);
    }
    check_no_nv_access();
    /* Without NV, a reset 10 ms after the batch's completion was broadcast: the neighbour's
     * copy holds both (one echo stands for the batch), so neither is re-issued. */
    sim_setup(&q, 2, addr2, 65u);
    sim.reset_after_done_stmt = 2;
    sim.reset_after_done_ms = 10;
    CHECK(sim_run(60000u));
    CHECK(sim.fault_fired);
    check_batch_ran(1);
    /* ... and right after it, before it was broadcast: both re-issued, together. */
    sim_setup(&q, 2, addr2, 66u);
    sim.reset_after_done_stmt = 2;
    sim.strict = 0;
    CHECK(sim_run(60000u));
    CHECK(sim.fault_fired);
    check_batch_ran(2);
    check_no_nv_access();
}

void test_sim(void)
{
    build_fixed();
    test_programs();
    test_relay();
    test_resets();
    test_address_kept();
    test_without_nv();
    test_another_launch();
    test_failures();
    test_failure_policy();
    test_epochs();
    test_old_epoch_completion();
    test_long();
    test_window_too_small();
    test_fuzz(300u);
    test_no_nv_programs();
    test_no_nv_rules();
    test_no_nv_resets();
    test_no_nv_silent_neighbours();
    test_no_nv_unlatched_neighbour();
    test_no_nv_limits();
    test_no_nv_fuzz(300u);
    test_batches();
    /* Every step above was also a check of dr_module_next_wakeup (sim.c, guarded_step): the
     * ones it let skip changed nothing. Most steps of these runs are skippable (a module
     * broadcasts every 100 ms and is stepped every 5), so the check has bite. */
    CHECK(sim_skippable_steps > 10000ul);
    CHECK_EQ(sim_skippable_acted, 0);
    printf("  tickless: %lu skippable steps checked\n", sim_skippable_steps);
}
