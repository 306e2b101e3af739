/* sim.c - the lattice runtime tests' world on the shared fake platform (see sim.h). */
#include <string.h>
#include "sim.h"
#include "check.h"

sim_t sim;
unsigned long sim_skippable_steps;
unsigned long sim_skippable_acted;

static sim_node_t *node_of(struct dr_module *m)
{
    return (sim_node_t *)m->platform;
}

static uint32_t xorshift(uint32_t *state)
{
    uint32_t x = *state;
    x ^= x << 13;
    x ^= x >> 17;
    x ^= x << 5;
    *state = x;
    return x;
}

uint32_t sim_rand(void)
{
    return xorshift(&sim.rng);
}

static void violation(const char *what, uint16_t epoch, uint16_t statement)
{
    sim.violations++;
    if (sim.violations <= 10u && !sim.quiet) {
        fprintf(stderr, "  violation at %lu ms: %s (epoch %u, statement %u)\n",
                (unsigned long)sim.time, what, (unsigned)epoch, (unsigned)statement);
    }
}

/* Operation duration: 20-79 ms, depending on the statement. */
static uint32_t duration(uint16_t statement)
{
    return 20u + ((uint32_t)statement * 37u) % 60u;
}

int16_t sim_args[SIM_MAX_STATEMENTS * DR_CONF_MAX_ARGS];

void sim_statement(dr_statement_t *st, uint8_t address, uint16_t self, uint8_t n_deps,
                   uint16_t first_dep)
{
    memset(st, 0, sizeof *st);
    st->address = address;
    st->op = 1;
    st->index = 0;
    st->n_deps = n_deps;
    st->first_dep = (dr_dep_at_t)first_dep;
    st->args = (dr_args_at_t)self;
    sim_args[self * DR_CONF_MAX_ARGS] = (int16_t)self;
}

uint8_t sim_address_of(struct dr_module *m)
{
    return node_of(m)->answer;
}

/* ---- the world's hooks into the fake platform ---- */

dr_fake_t *dr_fake_of(struct dr_module *m)
{
    return &node_of(m)->fake;
}

static uint32_t sim_now(struct dr_module *m)
{
    return sim.time + node_of(m)->clock_offset;
}

static uint16_t sim_random(struct dr_module *m)
{
    return (uint16_t)(xorshift(&node_of(m)->rng) >> 8);
}

static void sim_broadcast(struct dr_module *m, uint8_t channel, const uint8_t *bytes,
                          uint8_t len)
{
    sim_node_t *from = node_of(m);
    uint8_t i = (uint8_t)(from - sim.nodes);
    uint8_t j;
    uint8_t copies;
    sim_node_t *to;
    sim_packet_t *p;
    if (from->mute) {
        return;
    }
    /* Channel c of node i leads to node c (sim_connected): a send reaches that node only. */
    for (j = 0; j < sim.n_nodes; j++) {
        if (!sim.adj[i][j] || (channel != DR_FAKE_BROADCAST && channel != j)) {
            continue;
        }
        to = &sim.nodes[j];
        if (sim_rand() % 100u < sim.loss_percent) {
            continue;
        }
        copies = (uint8_t)(sim_rand() % 100u < sim.dup_percent ? 2u : 1u);
        while (copies-- > 0u && to->n_inbox < SIM_INBOX) {
            p = &to->inbox[to->n_inbox++];
            p->at = sim.time + 1u + (sim.max_delay_ms ? sim_rand() % sim.max_delay_ms : 0u);
            p->from = i;
            p->len = len;
            memcpy(p->bytes, bytes, len);
            if (sim_rand() % 100u < sim.corrupt_percent) {
                uint32_t b = sim_rand() % (8u * len);
                p->bytes[b / 8u] = (uint8_t)(p->bytes[b / 8u] ^ (1u << (b % 8u)));
                sim.corrupted++;
            }
        }
    }
}

/* Whether statement s belongs to the batch m runs (its `running` and `batch` fields). */
static uint8_t in_batch(const dr_module_t *m, uint16_t s)
{
    uint16_t k = (uint16_t)(s - m->running);
    if (m->running == DR_NONE || s < m->running || k >= DR_CONF_LATTICE_BATCH) {
        return 0;
    }
    return (uint8_t)(k == 0u || ((m->batch >> (k - 1u)) & 1u));
}

static uint8_t op_ended(const sim_op_t *o)
{
    return (uint8_t)(!o->active || o->failed || sim.time >= o->until);
}

uint8_t sim_op_running(const sim_node_t *n)
{
    uint8_t k;
    for (k = 0; k < SIM_OPS; k++) {
        if (!op_ended(&n->ops[k])) {
            return 1;
        }
    }
    return 0;
}

uint32_t sim_op_until(const sim_node_t *n)
{
    uint8_t k;
    uint32_t until = 0;
    for (k = 0; k < SIM_OPS; k++) {
        if (n->ops[k].active && n->ops[k].until > until) {
            until = n->ops[k].until;
        }
    }
    return until;
}

/* The slot for statement s in n's batch: a new batch once every earlier operation has ended
 * (as the HAL's status reports on everything started since); NULL when the batch is full. */
static sim_op_t *op_slot(sim_node_t *n, uint16_t s)
{
    uint8_t k;
    uint8_t used = 0;
    sim_op_t *free_slot = NULL;
    if (!sim_op_running(n)) {
        memset(n->ops, 0, sizeof n->ops);
    }
    for (k = 0; k < SIM_OPS; k++) {
        if (n->ops[k].active && n->ops[k].stmt == s) {
            return &n->ops[k];
        }
        if (n->ops[k].active) {
            used++;
        } else if (free_slot == NULL) {
            free_slot = &n->ops[k];
        }
    }
    if (used + 1u > sim.largest_batch) {
        sim.largest_batch = (uint16_t)(used + 1u);
    }
    return free_slot;
}

/* The operation the fake noted: checked (S1, S2, the right module, a statement of the batch
 * the runtime says runs, no new batch while an earlier one runs), recorded, timed. */
static void sim_op_start(struct dr_module *m)
{
    sim_node_t *n = node_of(m);
    const dr_program_t *p = sim.program;
    uint16_t s = n->fake.statement;
    uint16_t r = m->running_epoch;
    uint16_t t;
    uint16_t d;
    uint8_t k;
    uint32_t latest;
    sim_op_t *o;
    if (s >= p->n_statements || !in_batch(m, s)) {
        violation("op of an unknown statement", r, s);
        return;
    }
    if ((uint16_t)n->fake.args[0] != s) { /* the test programs carry their number as argument 0 */
        violation("op start names another statement than its arguments", r, s);
    }
    if (p->statements[s].address != n->address) {
        violation("op started on the wrong module", r, s);
    }
    for (k = 0; k < SIM_OPS; k++) {
        if (!op_ended(&n->ops[k]) && n->ops[k].started_ms != sim.time) {
            violation("op started while an earlier batch runs", r, s);
        }
    }
    if (r < SIM_MAX_EPOCHS && sim.checks) {
        /* S1: every dependency done in this epoch, and the whole previous epoch done. */
        latest = 0;
        for (d = 0; d < p->statements[s].n_deps; d++) {
            t = p->deps[p->statements[s].first_dep + d];
            if (!sim.reported[r][t]) {
                violation("S1: started before a dependency was done", r, s);
            } else if (sim.reported_ms[r][t] > latest) {
                latest = sim.reported_ms[r][t];
            }
        }
        if (p->statements[s].n_deps > 0u && !sim.starts[r][s] &&
            sim.time - latest > sim.max_handover_ms) {
            sim.max_handover_ms = sim.time - latest;
        }
        for (t = 0; r > 0u && t < p->n_statements; t++) {
            if (!sim.reported[r - 1u][t]) {
                violation("S1: started before the previous epoch was done", r, s);
            }
        }
        /* S2: no op of a statement that depends on s, nor of a later epoch, was started. */
        for (t = 0; t < p->n_statements; t++) {
            for (d = 0; d < p->statements[t].n_deps; d++) {
                if (p->deps[p->statements[t].first_dep + d] == s && sim.starts[r][t]) {
                    violation("S2: re-issued after a later statement started", r, s);
                }
            }
            if (r + 1u < SIM_MAX_EPOCHS && sim.starts[r + 1u][t]) {
                violation("S2: started after an op of a later epoch", r, s);
            }
        }
        if (sim.strict && sim.reported[r][s]) {
            violation("re-issued an operation already completed", r, s);
        }
    }
    if (r < SIM_MAX_EPOCHS) {
        if (sim.starts[r][s] && sim.time - sim.last_start_ms[r][s] < sim.min_restart_gap_ms) {
            sim.min_restart_gap_ms = sim.time - sim.last_start_ms[r][s];
        }
        sim.starts[r][s]++;
        sim.last_start_ms[r][s] = sim.time;
    }
    sim.total_starts++;
    o = op_slot(n, s);
    if (o == NULL) {
        violation("more operations at once than a batch holds", r, s);
        return;
    }
    o->active = 1;
    o->failed = 0;
    o->stmt = s;
    o->epoch = r;
    o->started_ms = sim.time;
    o->until = sim.time + duration(s) + (n->address == sim.slow_address ? 300u : 0u);
    if (s == sim.reset_mid_stmt && r == sim.fault_epoch && !sim.fault_fired) {
        sim.fault_fired = 1;
        n->reset_at_set = 1;
        n->reset_at = sim.time + duration(s) / 2u;
    }
}

/* A completed operation: recorded as reported, and the fault plans that follow it armed. */
static void op_reported(sim_node_t *n, const sim_op_t *o)
{
    if (o->epoch < SIM_MAX_EPOCHS) {
        sim.reported[o->epoch][o->stmt] = 1;
        sim.reported_ms[o->epoch][o->stmt] = sim.time;
    }
    if (o->epoch == sim.fault_epoch && !sim.fault_fired) {
        if (o->stmt == sim.reset_after_done_stmt && sim.reset_after_done_ms != 0u) {
            sim.fault_fired = 1;
            n->reset_at_set = 1;
            n->reset_at = sim.time + sim.reset_after_done_ms;
        } else if (o->stmt == sim.reset_after_done_stmt) {
            sim.fault_fired = 1;
            n->reset_now = 1;
            n->mute = 1; /* the completion is not announced before the reset */
        } else if (o->stmt == sim.tear_after_done_stmt) {
            sim.fault_fired = 1;
            n->tear_in = sim.tear_copy;
        }
    }
}

/* RUNNING while one operation of the batch runs; then FAILED when one failed (the planned
 * failures are drawn as each ends), else DONE (all reported done, the batch over). */
static enum dr_op_status sim_op_status(struct dr_module *m)
{
    sim_node_t *n = node_of(m);
    uint8_t k;
    uint8_t any = 0;
    uint8_t failed = 0;
    sim_op_t *o;
    for (k = 0; k < SIM_OPS; k++) {
        any = (uint8_t)(any | n->ops[k].active);
    }
    if (!any) {
        violation("polled with no operation", 0, 0);
        return DR_OP_DONE;
    }
    if (sim_op_running(n)) {
        return DR_OP_RUNNING;
    }
    for (k = 0; k < SIM_OPS; k++) {
        o = &n->ops[k];
        if (o->active && !o->failed && o->stmt == sim.fail_stmt && sim.fail_times > 0u) {
            sim.fail_times--;
            o->failed = 1;
        }
        failed = (uint8_t)(failed | (o->active && o->failed));
    }
    if (failed) {
        return DR_OP_FAILED;
    }
    for (k = 0; k < SIM_OPS; k++) {
        if (n->ops[k].active) {
            op_reported(n, &n->ops[k]);
            n->ops[k].active = 0;
        }
    }
    return DR_OP_DONE;
}

static uint8_t sim_connected(struct dr_module *m, uint8_t connector)
{
    uint8_t i = (uint8_t)(node_of(m) - sim.nodes);
    return (uint8_t)(connector < sim.n_nodes && sim.adj[i][connector]);
}

/* An NV write about to happen: torn when planned (power fails half-way through it). */
static void sim_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    sim_node_t *n = node_of(m);
    if (n->tear_in == 0) {
        n->tear_in = -1;
        memcpy(n->fake.nv + addr, buf, len / 2u);
        n->fake.nv[addr + len / 2u] = (uint8_t)~buf[len / 2u];
        longjmp(sim.jmp, 1);
    }
    if (n->tear_in > 0) {
        n->tear_in--;
    }
}

static void sim_misuse(struct dr_module *m, const char *what, uint32_t value)
{
    (void)m;
    violation(what, 0, (uint16_t)value);
}

static const dr_fake_hooks_t hooks = {
    sim_now, sim_random, sim_broadcast, sim_op_start, sim_op_status, sim_connected,
    sim_nv_write, sim_misuse
};

/* ---- the simulation ---- */

void sim_setup(const dr_program_t *program, uint8_t n, const uint8_t *addresses, uint32_t seed)
{
    uint8_t i;
    memset(&sim, 0, sizeof sim);
    sim.program = program;
    sim.n_nodes = n;
    sim.rng = seed ? seed : 1u;
    sim.checks = 1;
    sim.strict = 1;
    sim.min_restart_gap_ms = 0xFFFFFFFFu;
    sim.fail_stmt = SIM_NONE;
    sim.slow_address = 0xFEu;
    sim.reset_after_done_stmt = SIM_NONE;
    sim.reset_mid_stmt = SIM_NONE;
    sim.tear_after_done_stmt = SIM_NONE;
    for (i = 0; i < n; i++) {
        sim_node_t *nd = &sim.nodes[i];
        dr_fake_init(&nd->fake, i, &hooks);
        nd->address = addresses[i];
        nd->answer = addresses[i];
        nd->rng = 0x9E3779B9u * (i + 1u) ^ sim.rng;
        /* Clocks close to the 32-bit wrap, each a little different. */
        nd->clock_offset = 0xFFFFFFFFu - 700u + 13u * i;
        nd->tear_in = -1;
        nd->woken = 1;
        if (i > 0u) {
            sim.adj[i][i - 1u] = 1;
            sim.adj[i - 1u][i] = 1;
        }
    }
    for (i = 0; i < n; i++) {
        dr_module_init(&sim.nodes[i].mod, program, &sim.nodes[i]);
    }
}

void sim_full_mesh(void)
{
    uint8_t i;
    uint8_t j;
    for (i = 0; i < sim.n_nodes; i++) {
        for (j = 0; j < sim.n_nodes; j++) {
            sim.adj[i][j] = (uint8_t)(i != j);
        }
    }
}

void sim_reset(uint8_t i)
{
    sim_node_t *n = &sim.nodes[i];
    memset(n->ops, 0, sizeof n->ops);
    n->mute = 0;
    n->reset_now = 0;
    n->reset_at_set = 0;
    n->n_inbox = 0;
    n->tear_in = -1;
    n->woken = 1;
    /* RAM is lost: scribble over the protocol state (the counters are kept for reports). */
    memset(&n->mod.shared, 0xA5, sizeof n->mod.shared);
    n->mod.address = 0xA5u;
    n->mod.running = (dr_stmt_t)0xA5A5u;
    n->mod.running_epoch = 0xA5A5u;
    n->mod.batch = 0xA5u;
    n->mod.next_broadcast_ms = 0xA5A5A5A5u;
    n->mod.unechoed = (dr_stmt_t)0xA5A5u;
    n->mod.unheard = (dr_channels_t)0xA5A5A5A5u;
    n->mod.heard = 0xA5u;
    dr_module_init(&n->mod, sim.program, n);
}

static void deliver(sim_node_t *n)
{
    uint16_t k;
    uint16_t kept = 0;
    for (k = 0; k < n->n_inbox; k++) {
        if ((int32_t)(sim.time - n->inbox[k].at) >= 0) {
            dr_module_receive(&n->mod, n->inbox[k].from, n->inbox[k].bytes, n->inbox[k].len);
            /* a tickless platform asks again after each packet (it need not step) */
            n->wake = dr_module_next_wakeup(&n->mod, &n->wake_at);
        } else {
            n->inbox[kept++] = n->inbox[k];
        }
    }
    n->n_inbox = kept;
}

/* Whether a step now is one that n's last dr_module_next_wakeup answer lets a tickless
 * platform skip: no packet or reset since, its deadline not reached, and (DR_WAKE_OP) its
 * operation still running. */
static uint8_t skippable(const sim_node_t *n)
{
    uint32_t now = sim.time + n->clock_offset;
    uint8_t op_running = sim_op_running(n);
    if (n->woken || ((n->wake & DR_WAKE_AT) && (int32_t)(now - n->wake_at) >= 0)) {
        return 0;
    }
    return (uint8_t)(!(n->wake & DR_WAKE_OP) || op_running);
}

/* Returns 1 when the step was cut short by a torn NV write (power failure). */
static int guarded_step(sim_node_t *n)
{
    if (setjmp(sim.jmp) != 0) {
        return 1;
    }
    dr_module_step(&n->mod);
    return 0;
}

/* guarded_step, and a step that dr_module_next_wakeup said could be skipped is checked to
 * change nothing (the module's whole state and every HAL effect): what a tickless
 * platform's exactness rests on. Then the next answer is asked for. */
static int checked_step(sim_node_t *n)
{
    uint8_t skip = skippable(n);
    dr_module_t before = n->mod;
    uint32_t effects = n->fake.effects;
    if (guarded_step(n)) {
        return 1;
    }
    if (skip) {
        sim_skippable_steps++;
        if (memcmp(&before, &n->mod, sizeof before) != 0 || effects != n->fake.effects) {
            sim_skippable_acted++;
            violation("tickless: a step next_wakeup let skip changed something",
                      n->mod.shared.epoch, n->mod.running);
        }
    }
    n->wake = dr_module_next_wakeup(&n->mod, &n->wake_at);
    n->woken = 0;
    return 0;
}

uint8_t sim_run(uint32_t max_ms)
{
    uint32_t end = sim.time + max_ms;
    uint8_t i;
    uint8_t k;
    uint8_t all;
    uint16_t r;
    uint16_t s;
    sim_node_t *n;
    while ((int32_t)(sim.time - end) < 0) {
        uint8_t first = (uint8_t)(sim_rand() % sim.n_nodes);
        all = 1;
        for (k = 0; k < sim.n_nodes; k++) {
            i = (uint8_t)((first + k) % sim.n_nodes);
            n = &sim.nodes[i];
            deliver(n);
            if (checked_step(n) || n->reset_now || (n->reset_at_set && sim.time >= n->reset_at)) {
                sim_reset(i);
            }
            if (n->mod.running != DR_NONE && n->mod.running_epoch == n->mod.shared.epoch &&
                n->mod.running >= n->mod.shared.low &&
                n->mod.running - n->mod.shared.low >= DR_CONF_WINDOW) {
                violation("running a statement outside the window", n->mod.shared.epoch,
                          n->mod.running);
            }
            if (dr_module_finished(&n->mod) == DR_END_GOAL) {
                if (!n->finished_seen && sim.checks) {
                    /* S3: when the end is known, every operation of every epoch is done. */
                    n->finished_seen = 1;
                    for (r = 0; r < sim.program->n_epochs && r < SIM_MAX_EPOCHS; r++) {
                        for (s = 0; s < sim.program->n_statements; s++) {
                            if (!sim.reported[r][s]) {
                                violation("S3: end known before every operation was done", r, s);
                            }
                        }
                    }
                }
            } else {
                all = 0;
            }
        }
        sim.time += SIM_TICK_MS;
        if (all) {
            return 1;
        }
    }
    return 0;
}
