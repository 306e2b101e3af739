/* dr_paper.c - the paper's protocol, faithfully: a global state shared by broadcast and merged by Fig. 3 in one of its three historical variants, flaws included. */
#include "dr_paper.h"
#include "dr_packet.h"

#define N_PENDING ((uint8_t)DR_CONF_MAX_PENDING)
/* Payload: alternate flag, global state, recipient, pending_0 .. pending_{N-1} (e.1 without
 * the leading 107, whose job the dr_packet frame does). */
#define PAYLOAD_LEN ((uint8_t)(DR_PAPER_PAYLOAD_FIXED + DR_CONF_MAX_PENDING))
#define FRAME_LEN ((uint8_t)(DR_PACKET_OVERHEAD + DR_PAPER_PAYLOAD_FIXED + DR_CONF_MAX_PENDING))

/* Compile-time check: a frame fits the receive buffers and a uint8_t length. */
typedef char dr_paper_frame_fits[(DR_PACKET_OVERHEAD + DR_PAPER_PAYLOAD_FIXED + DR_CONF_MAX_PENDING
                                  <= DR_CONF_MAX_PACKET && DR_CONF_MAX_PACKET <= 255u) ? 1 : -1];

/* Whether state `s` is in the N-slot set. Cost: O(N). */
static uint8_t set_has(const uint8_t *set, uint8_t s)
{
    uint8_t i;
    for (i = 0; i < N_PENDING; i++) {
        if (set[i] == s) {
            return 1;
        }
    }
    return 0;
}

/* Fig. 3 (e.3). One loop, as in the original: "keep from the first set whatever passes the
 * bound or is also in the second set"; equal states intersect. Cost: O(N^2). */
void dr_paper_merge(dr_paper_global_t *local, const dr_paper_global_t *incoming,
                    enum dr_paper_merge variant)
{
    uint8_t out[DR_CONF_MAX_PENDING];
    const uint8_t *first;
    const uint8_t *second;
    uint8_t bound;
    uint8_t equal = 0;
    uint8_t n = 0;
    uint8_t i;
    uint8_t p;
    uint8_t above;
    uint8_t known;
    uint8_t keep;

    if (local->state == incoming->state) {
        equal = 1;
        first = local->pending;
        second = incoming->pending;
        bound = local->state;
    } else if (local->state > incoming->state) {
        first = local->pending;
        second = incoming->pending;
        bound = incoming->state;
    } else {
        first = incoming->pending;
        second = local->pending;
        bound = local->state;
    }
    for (i = 0; i < N_PENDING; i++) {
        out[i] = 0;
    }
    for (i = 0; i < N_PENDING; i++) {
        p = first[i];
        if (p == 0u || set_has(out, p)) {
            continue; /* empty slot, or a duplicate from a packet */
        }
        known = set_has(second, p);
        if (equal) {
            keep = known;
        } else {
            above = (uint8_t)(variant == DR_MERGE_C_PORT ? p >= bound : p > bound);
            keep = (uint8_t)(variant == DR_MERGE_PRINTED ? (above && known) : (above || known));
        }
        if (keep) {
            out[n] = p;
            n++;
        }
    }
    if (local->state < incoming->state) {
        local->state = incoming->state;
        local->address = incoming->address;
    }
    for (i = 0; i < N_PENDING; i++) {
        local->pending[i] = out[i];
    }
}

/* Records that this module started pending state `s` (e.2); when all slots are used the
 * lowest (oldest: states only grow during a run) mark gives way. Cost: O(N). */
static void mark_started(dr_module_t *m, uint8_t s)
{
    uint8_t i;
    uint8_t low = 0;
    if (set_has(m->started, s)) {
        return;
    }
    for (i = 0; i < N_PENDING; i++) {
        if (m->started[i] == 0u) {
            m->started[i] = s;
            return;
        }
        if (m->started[i] < m->started[low]) {
            low = i;
        }
    }
    m->started[low] = s;
}

void dr_paper_op_start(dr_module_t *m, uint16_t statement, uint8_t op, uint8_t part,
                       const int16_t *table_args)
{
    int16_t args[DR_CONF_MAX_ARGS];
    dr_hal_table_read(args, table_args, sizeof args);
    dr_hal_op_start(m, statement, op, part, args);
}

void dr_paper_add_pending(dr_module_t *m, uint8_t state)
{
    uint8_t i;
    if (state == 0u) {
        return; /* 0 marks an empty slot and cannot be pending */
    }
    mark_started(m, state);
    if (set_has(m->global.pending, state)) {
        return;
    }
    for (i = 0; i < N_PENDING; i++) {
        if (m->global.pending[i] == 0u) {
            m->global.pending[i] = state;
            return;
        }
    }
    /* Full set: silently nothing (e.4, e.7; faithful). */
}

void dr_paper_remove_pending(dr_module_t *m, uint8_t state)
{
    uint8_t i;
    if (state == 0u) {
        return;
    }
    for (i = 0; i < N_PENDING; i++) {
        if (m->global.pending[i] == state) {
            m->global.pending[i] = 0;
            return; /* the first matching slot only */
        }
    }
}

uint8_t dr_paper_has_pending(const dr_module_t *m)
{
    uint8_t i;
    for (i = 0; i < N_PENDING; i++) {
        if (m->global.pending[i] != 0u) {
            return 1;
        }
    }
    return 0;
}

void dr_paper_send_state(dr_module_t *m, uint8_t state, uint8_t address)
{
    if (state > m->global.state) {
        m->global.state = state;
        m->global.address = address;
    }
}

void dr_paper_handover(dr_module_t *m, uint8_t pending, uint8_t next_state, uint8_t next_address)
{
    if (m->single_step_handover) {
        /* Re-add in the step that transfers, so no packet merged between S and S+1 (equal
         * states: intersection) can have removed it from what the transfer carries. */
        dr_paper_add_pending(m, pending);
    }
    dr_paper_send_state(m, next_state, next_address);
}

/* e.6: pending states present before and after a merge that did not raise the global state,
 * that this module is responsible for and has not started since its reset: re-enter the
 * first one. Cost: O(N^2) plus N calls of responsible(). */
static void restart_check(dr_module_t *m, const uint8_t *before)
{
    uint8_t i;
    uint8_t p;
    if (m->program->responsible == 0) {
        return;
    }
    for (i = 0; i < N_PENDING; i++) {
        p = before[i];
        if (p == 0u || !set_has(m->global.pending, p) || set_has(m->started, p)) {
            continue;
        }
        if (m->program->responsible(m->address, p)) {
            m->mailbox = p;
            return;
        }
    }
}

void dr_module_receive(dr_module_t *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    const uint8_t *payload = 0;
    uint8_t payload_len = 0;
    uint8_t before[DR_CONF_MAX_PENDING];
    uint8_t before_state;
    dr_paper_global_t in;
    enum dr_packet_result r;
    uint8_t i;

    (void)channel;
    m->packets_received++;
    r = dr_packet_unframe(bytes, len, &m->identity, DR_PACKET_PAPER_STATE, &payload,
                          &payload_len);
    if (r == DR_PACKET_MALFORMED || (r == DR_PACKET_OK && payload_len != PAYLOAD_LEN)) {
        m->packets_malformed++;
        return;
    }
    /* The alternate-sequence flag is always 0 (dead in the Java version, e.5): every module
     * counts as "starting" and ignores packets carrying the other value. */
    if (r != DR_PACKET_OK || payload[0] != 0u) {
        m->packets_foreign++;
        return;
    }
    in.state = payload[1];
    in.address = payload[2];
    for (i = 0; i < N_PENDING; i++) {
        in.pending[i] = payload[3u + i];
        before[i] = m->global.pending[i];
    }
    before_state = m->global.state;
    dr_paper_merge(&m->global, &in, m->merge);
    if (m->global.state > before_state) {
        /* The recipient was taken over by the merge; hand the state over if it is ours (the
         * end's recipient 255 never is, even for a module without an address). */
        if (m->global.address == m->address && m->global.address != DR_ADDRESS_ALL) {
            m->mailbox = m->global.state;
        }
    } else if (m->restart_pending) {
        restart_check(m, before);
    }
}

/* Sends this module's copy of the global state (e.1) and schedules the next broadcast. */
static void broadcast(dr_module_t *m, uint32_t now_ms)
{
    uint8_t payload[DR_PAPER_PAYLOAD_FIXED + DR_CONF_MAX_PENDING];
    uint8_t frame[DR_PACKET_OVERHEAD + 3u + DR_CONF_MAX_PENDING];
    uint8_t len;
    uint8_t i;

    payload[0] = 0; /* alternate flag */
    payload[1] = m->global.state;
    payload[2] = m->global.address;
    for (i = 0; i < N_PENDING; i++) {
        payload[3u + i] = m->global.pending[i];
    }
    len = dr_packet_frame(frame, FRAME_LEN, &m->identity, DR_PACKET_PAPER_STATE,
                          payload, PAYLOAD_LEN);
    if (len != 0u) {
        dr_hal_broadcast(m, frame, len);
        m->packets_sent++;
    }
    m->next_broadcast_ms = now_ms + DR_CONF_BROADCAST_MS;
#if DR_CONF_BROADCAST_JITTER_MS > 0
    m->next_broadcast_ms += (uint32_t)(dr_hal_random(m) % (DR_CONF_BROADCAST_JITTER_MS + 1u));
#endif
}

void dr_module_step(dr_module_t *m)
{
    uint32_t now_ms;
    if (m->local_state == DR_STATE_IDLE) {
        m->local_state = m->mailbox; /* read and clear the one-slot mailbox (e.8) */
        m->mailbox = DR_STATE_IDLE;
    }
    m->program->step(m);
    now_ms = dr_hal_now_ms(m);
    if ((uint32_t)(now_ms - m->next_broadcast_ms) < 0x80000000u) { /* due, wrap-safe */
        broadcast(m, now_ms);
    }
}

/* An idle module (no local state, nothing in the mailbox) only broadcasts when due: the
 * generated switch has no case for DR_STATE_IDLE. Any other local state is stepped at every
 * step instant: what it polls (operations, pending states) is the generated code's. O(1). */
uint8_t dr_module_next_wakeup(dr_module_t *m, uint32_t *at_ms)
{
    *at_ms = m->next_broadcast_ms;
    if (m->local_state != DR_STATE_IDLE || m->mailbox != DR_STATE_IDLE) {
        *at_ms = dr_hal_now_ms(m);
    }
    return DR_WAKE_AT;
}

/* e.10, the part of init that every reset runs. Cost: O(N) plus address_of(). */
static void start(dr_module_t *m)
{
    uint8_t i;
    m->address = m->program->address_of(m);
    m->mailbox = DR_STATE_IDLE;
    dr_hal_leds(m, m->address);
    m->global.state = DR_STATE_INITIAL;
    m->global.address = 0;
    for (i = 0; i < N_PENDING; i++) {
        m->global.pending[i] = 0;
        m->started[i] = 0;
    }
    m->local_state = DR_STATE_IDLE;
    m->next_broadcast_ms = dr_hal_now_ms(m);
    /* The first module starts the run (state 0 falls through to 1). The original's
     * INIT_WAITTIME_MS is 0 at HEAD, so the test always holds: a reset first module restarts
     * the sequence from the beginning (a known flaw). */
    if (m->address == m->program->first_address && m->global.state == DR_STATE_INITIAL) {
        m->mailbox = DR_STATE_INITIAL;
    }
}

/* Power-on and every reset (e.10). Precondition, as for the lattice protocol: *m is zero or
 * left from an earlier init. A first init (m->program != program) sets the defaults (C-port
 * merge, options off, counters 0), to be changed after it; an init of a module already
 * running `program` is a reset: options and counters are kept and `resets` counts it. */
void dr_module_init(dr_module_t *m, const dr_paper_program_t *program, void *platform)
{
    if (m->program == program) {
        m->resets++;
    } else {
        m->program = program;
        m->merge = DR_MERGE_C_PORT;
        m->single_step_handover = 0;
        m->restart_pending = 0;
        m->packets_sent = 0;
        m->packets_received = 0;
        m->packets_malformed = 0;
        m->packets_foreign = 0;
        m->resets = 0;
    }
    m->platform = platform;
    m->identity.robot = DR_ROBOT_ID;
    m->identity.fingerprint = DR_PACKET_PROGRAM_WORD(program->fingerprint, DR_EXECUTION);
    start(m);
}

uint8_t dr_module_finished(const dr_module_t *m)
{
    return (uint8_t)(m->global.state == DR_STATE_END);
}
