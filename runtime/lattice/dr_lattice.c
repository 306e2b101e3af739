/* dr_lattice.c - the lattice protocol: semilattice state, statement scheduling, persistence
 * (or, with DR_PROGRAM_NO_NV, the two rules that stand in for it). When to broadcast is the
 * dissemination policy's (fixed period or adaptive: DR_CONF_LATTICE_DISSEMINATION), whose
 * hooks (dr_dissemination.h) this file calls. */
#include "dr_lattice.h"
#include "dr_packet.h"
#if DR_CONF_SYNC
#include <stddef.h>
#endif

/* The module's program: with DR_CONF_ONE_PROGRAM the image's only one, whose fields are then
 * constants in the code (dr_module_init's precondition: it is passed that one). */
#if DR_CONF_ONE_PROGRAM
extern const dr_program_t dr_program;
#define PROGRAM(m) ((void)(m), &dr_program)
#else
#define PROGRAM(m) ((m)->program)
#endif


/* DR_PROGRAM_NO_NV: after a (re)start a module acts only once it has heard a packet from every
 * neighbour connected at that moment, however long that takes. There is no time-out: a
 * module that gave up on a silent neighbour (links blocked, neighbour powered off) would
 * act on the bottom state, i.e. re-issue operations that the neighbours know are done and
 * that later statements may have undone. Waiting is the only answer that is never wrong;
 * dr_module_describe shows it (`hear<channels>`). One exception keeps a module from waiting
 * for a neighbour it can no longer hear: a channel that is no longer connected (its own
 * retract, under way at the reset, completed; or the neighbour's) is forgotten, but only
 * once some neighbour has been heard, so a module never acts on the bottom state alone. */

#define W ((uint16_t)DR_CONF_WINDOW)
#define NBYTES ((uint8_t)(DR_CONF_WINDOW / 8))
/* Payload: epoch (2, big-endian), low (2, big-endian), done (W/8), and with DR_CONF_SYNC
 * ready (W/8). */
#define SETS ((uint8_t)(1u + (DR_CONF_SYNC ? 1u : 0u)))
#define PAYLOAD ((uint8_t)(DR_LATTICE_PAYLOAD_FIXED + SETS * NBYTES))
/* A state frame's payload: the state and, with DR_CONF_SYNC, the countdown (go). */
#define WIRE ((uint8_t)(PAYLOAD + (DR_CONF_SYNC ? DR_LATTICE_GO_BYTES : 0u)))
#define FRAME ((uint8_t)(WIRE + DR_PACKET_OVERHEAD))
/* NV record: program word, address, payload, CRC-16 (big-endian) over the bytes before it. */
#define RECORD ((uint8_t)(5u + PAYLOAD + 2u))
#define TOP_EPOCH 0xFFFFu

/* Compile-time checks of the configuration (a negative array size fails the build). */
typedef char dr_lattice_check_window[(DR_CONF_WINDOW % 8 == 0 && DR_CONF_WINDOW >= 8 &&
                                      DR_CONF_WINDOW <= 1000) ? 1 : -1];
typedef char dr_lattice_check_packet[(4 + (1 + DR_CONF_SYNC) * (DR_CONF_WINDOW / 8) +
                                      DR_CONF_SYNC * DR_LATTICE_GO_BYTES +
                                      DR_PACKET_OVERHEAD <= DR_CONF_MAX_PACKET) ? 1 : -1];
typedef char dr_lattice_check_channels[(DR_CONF_CHANNELS >= 1 && DR_CONF_CHANNELS <= 32) ? 1 : -1];
typedef char dr_lattice_check_counters[(DR_CONF_COUNTER_BITS == 16 || DR_CONF_COUNTER_BITS == 32) ? 1 : -1];
/* A batch's other statements are the bits of dr_module_t.batch (8). */
/* A failed batch is issued again at most DR_CONF_RETRIES times: below DR_GAVE_UP. */
typedef char dr_lattice_check_retries[(DR_CONF_RETRIES < 0xFF &&
                                       (DR_CONF_ON_FAILURE == DR_ON_FAILURE_STOP ||
                                        DR_CONF_ON_FAILURE == DR_ON_FAILURE_RETRY)) ? 1 : -1];
/* Whether the failure policy has no retry left for the running batch (stop: none at all;
 * decided by the preprocessor, so that a policy without retries has no comparison). */
#if DR_CONF_ON_FAILURE == DR_ON_FAILURE_RETRY && DR_CONF_RETRIES > 0
#define RETRIES_SPENT(m) ((m)->failures >= (uint8_t)DR_CONF_RETRIES)
#else
#define RETRIES_SPENT(m) ((void)(m), 1)
#endif
typedef char dr_lattice_check_batch[(DR_CONF_LATTICE_BATCH >= 1 && DR_CONF_LATTICE_BATCH <= 9) ? 1
                                                                                            : -1];

#if defined(__GNUC__)
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif

/* A counter for reports. One call where an inlined 32-bit increment would take about 26 B of
 * flash on an 8-bit core at each counter (kept out of line even under -flto). */
static NOINLINE void count(dr_counter_t *counter)
{
    (*counter)++;
}

static uint8_t bit(const uint8_t *set, dr_stmt_t i)
{
    return (uint8_t)(((unsigned)set[i >> 3] >> (i & 7u)) & 1u);
}

static void set_bit(uint8_t *set, dr_stmt_t i)
{
    set[i >> 3] = (uint8_t)(set[i >> 3] | (1u << (i & 7u)));
}

/* Re-bases one set `k` statements higher (bits below the new base are dropped). O(W/8). */
static void shift_set(uint8_t *set, dr_stmt_t k)
{
    uint8_t i;
    uint8_t r = (uint8_t)(k & 7u);
    dr_stmt_t src;
    for (i = 0; i < NBYTES; i++) {
        src = (dr_stmt_t)(i + (k >> 3));
        if (src < NBYTES) {
            set[i] = (uint8_t)(set[src] >> r);
            if (r != 0u && src + 1u < NBYTES) {
                set[i] = (uint8_t)(set[i] | (set[src + 1u] << (8u - r)));
            }
        } else {
            set[i] = 0;
        }
    }
}

/* Re-bases the state's sets `k` statements higher. O(W/8). */
static void shift(dr_shared_t *s, dr_stmt_t k)
{
    shift_set(s->done, k);
#if DR_CONF_SYNC
    shift_set(s->ready, k);
#endif
}

/* Clears the bits of one set for statements at or above n_statements; returns whether
 * there were any. Precondition: low <= n_statements. O(W/8): a byte at a time. */
static uint8_t trim_set(uint8_t *set, dr_stmt_t low, uint16_t n_statements)
{
    uint16_t kept = (uint16_t)(n_statements - low); /* bits kept from here on */
    uint8_t k;
    uint8_t mask;
    uint8_t found = 0;
    for (k = 0; k < NBYTES; k++) {
        if (kept >= 8u) {
            kept = (uint16_t)(kept - 8u);
        } else {
            mask = (uint8_t)((1u << kept) - 1u);
            kept = 0;
            found = (uint8_t)(found | (set[k] & (uint8_t)~mask));
            set[k] = (uint8_t)(set[k] & mask);
        }
    }
    return found;
}

/* trim_set on each of the state's sets. */
static uint8_t trim(dr_shared_t *s, uint16_t n_statements)
{
    uint8_t found = trim_set(s->done, s->low, n_statements);
#if DR_CONF_SYNC
    found = (uint8_t)(found | trim_set(s->ready, s->low, n_statements));
#endif
    return found;
}

/* Cost: O(W). Result is canonical: bits only for statements below n_statements, low at the
 * first statement not done, and a complete epoch rolled over to the next one (epoch 0xFFFF,
 * the top, is never rolled over; with n_statements == 0 every state is the top). */
void dr_shared_normalise(dr_shared_t *s, uint16_t n_statements)
{
    dr_stmt_t i;
    if (n_statements == 0u) {
        s->epoch = TOP_EPOCH;
    }
    if (s->low > n_statements) {
        s->low = (dr_stmt_t)n_statements;
    }
    (void)trim(s, n_statements);
    /* The completed prefix (a done bit is of a statement below n_statements: trim). */
    for (i = 0; i < W && bit(s->done, i); i++) {
    }
    shift(s, i);
    s->low = (dr_stmt_t)(s->low + i); /* at most n_statements: trim */
    if (s->low == n_statements && s->epoch != TOP_EPOCH) {
        /* Everything complete in epoch e is the start of epoch e + 1. The done set is
         * already empty: its bits are of statements at or above low = n_statements, which
         * trim cleared. */
        s->epoch++;
        s->low = 0;
    }
}

/* Cost: O(W). Precondition: both states decoded or normalised for n_statements. */
void dr_shared_join(dr_shared_t *into, const dr_shared_t *other, uint16_t n_statements)
{
    dr_shared_t o = *other;
    uint8_t i;
    if (o.epoch > into->epoch) {
        *into = o;
    } else if (o.epoch == into->epoch) {
        if (o.low > into->low) {
            shift(into, (dr_stmt_t)(o.low - into->low));
            into->low = o.low;
        } else {
            shift(&o, (dr_stmt_t)(into->low - o.low));
        }
        for (i = 0; i < NBYTES; i++) {
            into->done[i] = (uint8_t)(into->done[i] | o.done[i]);
#if DR_CONF_SYNC
            into->ready[i] = (uint8_t)(into->ready[i] | o.ready[i]);
#endif
        }
    }
    dr_shared_normalise(into, n_statements);
}

/* Whether `statement` is complete in s's epoch. Cost: O(1). */
uint8_t dr_shared_is_done(const dr_shared_t *s, dr_stmt_t statement)
{
    if (statement < s->low) {
        return 1;
    }
    statement = (dr_stmt_t)(statement - s->low);
    return statement < W ? bit(s->done, statement) : 0u;
}

#if DR_CONF_SYNC
/* Cost: O(1). */
uint8_t dr_shared_is_ready(const dr_shared_t *s, dr_stmt_t statement)
{
    dr_stmt_t i;
    if (statement < s->low) {
        return 1;
    }
    i = (dr_stmt_t)(statement - s->low);
    return i < W ? (uint8_t)(bit(s->ready, i) | bit(s->done, i)) : 0u;
}
#endif

/* Returns the payload length (PAYLOAD), or 0 when cap is too small. */
uint8_t dr_shared_encode(const dr_shared_t *s, uint8_t *out, uint8_t cap)
{
    uint8_t i;
    if (cap < PAYLOAD) {
        return 0;
    }
    out[0] = (uint8_t)(s->epoch >> 8);
    out[1] = (uint8_t)(s->epoch & 0xFFu);
    out[2] = (uint8_t)(s->low >> 8);
    out[3] = (uint8_t)(s->low & 0xFFu);
    for (i = 0; i < NBYTES; i++) {
        out[4u + i] = s->done[i];
#if DR_CONF_SYNC
        out[4u + NBYTES + i] = s->ready[i];
#endif
    }
    return PAYLOAD;
}

/* Returns 1 and fills s (not normalised) when the payload is well formed: the right length,
 * low <= n_statements, no bit for a statement at or above n_statements. Cost: O(W). */
uint8_t dr_shared_decode(dr_shared_t *s, const uint8_t *in, uint8_t len, uint16_t n_statements)
{
    uint8_t i;
    uint16_t low;
    if (len != PAYLOAD) {
        return 0;
    }
    s->epoch = (uint16_t)((in[0] << 8) | in[1]);
    low = (uint16_t)((in[2] << 8) | in[3]);
    if (low > n_statements) {
        return 0;
    }
    s->low = (dr_stmt_t)low;
    for (i = 0; i < NBYTES; i++) {
        s->done[i] = in[4u + i];
#if DR_CONF_SYNC
        s->ready[i] = in[4u + NBYTES + i];
#endif
    }
    return (uint8_t)!trim(s, n_statements);
}


/* The program word of this program and launch (dr_packet.h): a constant in an MCU image. */
#define WORD(m) DR_PACKET_PROGRAM_WORD(PROGRAM(m)->fingerprint, DR_EXECUTION)

/* The NV record: the program word (big endian: a module flashed with another program, or
 * with the same one for another launch, ignores the record the old one left), the address,
 * the payload, and the CRC-16 of the bytes before it (dr_crc16_put, the frames' own code). */
static void record(const dr_module_t *m, uint8_t *rec)
{
    dr_put_be32(rec, WORD(m));
    rec[4] = m->address;
    (void)dr_shared_encode(&m->shared, rec + 5, PAYLOAD);
    dr_crc16_put(rec, (uint8_t)(RECORD - 2u));
}

/* Writes the address and the state twice (copy A, then copy B), so that a reset during a
 * write leaves one copy intact: the old state (the completion was not yet announced) or the
 * new one. */
static void persist(dr_module_t *m)
{
    uint8_t rec[RECORD];
    uint8_t copy;
    record(m, rec);
    for (copy = 0; copy < 2u; copy++) {
        dr_hal_nv_write(m, (uint16_t)(DR_CONF_LATTICE_NV_ADDR + copy * RECORD), rec, RECORD);
    }
}

/* Joins every valid copy of the persisted state into m->shared and takes the address it
 * records; returns whether there was one. A copy is valid when its CRC matches (the CRC of
 * the whole record is then 0) and it names this program and this execution. */
static uint8_t restore(dr_module_t *m)
{
    uint8_t rec[RECORD];
    uint8_t word[4];
    dr_shared_t s;
    uint8_t copy;
    uint8_t found = 0;
    dr_put_be32(word, WORD(m));
    for (copy = 0; copy < 2u; copy++) {
        dr_hal_nv_read(m, (uint16_t)(DR_CONF_LATTICE_NV_ADDR + copy * RECORD), rec, RECORD);
        if (dr_crc16(rec, RECORD) == 0u && rec[0] == word[0] && rec[1] == word[1] &&
            rec[2] == word[2] && rec[3] == word[3] &&
            dr_shared_decode(&s, rec + 5, PAYLOAD, PROGRAM(m)->n_statements)) {
            dr_shared_join(&m->shared, &s, PROGRAM(m)->n_statements);
            m->address = rec[4];
            found = 1;
        }
    }
    return found;
}

/* The channels with a neighbour latched to them now. O(DR_CONF_CHANNELS). */
static dr_channels_t connected(dr_module_t *m)
{
    dr_channels_t set = 0;
    uint8_t c;
    for (c = 0; c < DR_CONF_CHANNELS; c++) {
        if (dr_hal_connected(m, c)) {
            set = (dr_channels_t)(set | ((dr_channels_t)1 << c));
        }
    }
    return set;
}

/* Whether this build runs without NV storage: fixed by DR_CONF_NV (dr_conf.h), so the other
 * mode's code is left out of the image, or read from the program when the build has both. */
static uint8_t no_nv(const dr_module_t *m)
{
    if (DR_CONF_NV == DR_CONF_NV_EITHER) {
        return (uint8_t)(PROGRAM(m)->options & DR_PROGRAM_NO_NV);
    }
    return (uint8_t)(DR_CONF_NV == DR_CONF_NV_NONE);
}

/* Whether the two rules without NV hold the module back: a neighbour connected at the (re)start
 * not heard yet (rule 1), or its own completion not echoed yet (rule 2). Never with the NV
 * record (both fields stay 0 and DR_NONE), so an NV-only build has no code for them. */
static uint8_t held_back(const dr_module_t *m)
{
    return (uint8_t)(no_nv(m) && (m->unheard != 0u || m->unechoed != DR_NONE));
}

#if DR_CONF_SYNC
/* How long after a group of `size` members is ready its members start: the news crosses
 * more links in a larger group (README.md, "Synchronous groups"). O(1). */
static uint32_t sync_delay(uint8_t size)
{
    return DR_CONF_SYNC_DELAY_MS + (uint32_t)(size - 1u) * DR_CONF_SYNC_DELAY_PER_MEMBER_MS;
}

/* The state payload and the countdown (the group and the age of its news, 0xFFFF for none),
 * in `out` (WIRE bytes). */
static void state_payload(dr_module_t *m, uint8_t *out)
{
    uint32_t age = 0;
    uint16_t group = 0xFFFFu;
    dr_statement_t st;
    (void)dr_shared_encode(&m->shared, out, PAYLOAD);
    if (m->go_group != DR_NONE) {
        group = (uint16_t)m->go_group;
        dr_hal_table_read(&st, &PROGRAM(m)->statements[m->go_group], sizeof st);
        age = dr_hal_now_ms(m) + sync_delay(st.sync_size) - m->go_at_ms;
        if (age >= 0x80000000u) {
            age = 0; /* a start later than the delay from now: a clock step back */
        } else if (age > 0xFFFEu) {
            age = 0xFFFEu;
        }
    }
    out[PAYLOAD] = (uint8_t)(group >> 8);
    out[PAYLOAD + 1u] = (uint8_t)(group & 0xFFu);
    out[PAYLOAD + 2u] = (uint8_t)(age >> 8);
    out[PAYLOAD + 3u] = (uint8_t)(age & 0xFFu);
}
#endif

/* The dissemination policy's hooks (dr_dissemination.h, which dr_lattice.h included for the
 * policy's fields): here, after the helpers they may use and before the functions that call
 * them. */
#define DR_DISSEMINATION_HOOKS
#include "dr_dissemination.h"

/* The running batch as a set relative to `running`: bit k = statement running + k. */
static uint16_t members(const dr_module_t *m)
{
    return (uint16_t)(((uint16_t)m->batch << 1) | 1u);
}

/* Starts (again) every operation of the running batch: the HAL reports DONE once all have
 * taken effect, FAILED once all have ended and one failed (operations are idempotent, so a
 * failure re-issues them all). */
static void issue(dr_module_t *m)
{
    dr_statement_t st;
    int16_t args[DR_CONF_MAX_ARGS];
    dr_stmt_t s = m->running;
    uint16_t in;
    for (in = members(m); in != 0u; in >>= 1, s++) {
        if ((in & 1u) != 0u) {
            dr_hal_table_read(&st, &PROGRAM(m)->statements[s], sizeof st);
            dr_hal_table_read(args, &PROGRAM(m)->args[st.args * DR_CONF_MAX_ARGS], sizeof args);
            dr_hal_op_start(m, s, st.op, st.index, args);
        }
    }
    dissemination_issued(m);
}

#if DR_CONF_SYNC
/* Whether every member of the synchronous group of statement `s` (row `st`) is ready: the
 * instant a module learns it is the group's agreed start (README.md, "Synchronous groups").
 * O(group). */
static uint8_t group_ready(const dr_shared_t *sh, dr_stmt_t s, const dr_statement_t *st)
{
    dr_stmt_t first = (dr_stmt_t)(s - st->sync_index);
    uint8_t k;
    for (k = 0; k < st->sync_size; k++) {
        if (!dr_shared_is_ready(sh, (dr_stmt_t)(first + k))) {
            return 0;
        }
    }
    return 1;
}

/* Whether every member of the group that starts at statement `first` (`size` members) is
 * done. O(group). */
static uint8_t group_done(const dr_shared_t *sh, dr_stmt_t first, uint8_t size)
{
    uint8_t k;
    for (k = 0; k < size; k++) {
        if (!dr_shared_is_done(sh, (dr_stmt_t)(first + k))) {
            return 0;
        }
    }
    return 1;
}

/* Whether this module may start member `s` (row `st`) now: its group is ready and the
 * countdown to the group's start is over. */
static uint8_t may_start_member(const dr_module_t *m, dr_stmt_t s, const dr_statement_t *st)
{
    return (uint8_t)(m->go_open && m->go_group == (dr_stmt_t)(s - st->sync_index) &&
                     m->go_epoch == m->shared.epoch && group_ready(&m->shared, s, st));
}

/* The first synchronous group with a member in the window that is ready and not done, as
 * its first statement (with its size in *size); DR_NONE when there is none. O(W * group). */
static dr_stmt_t ready_group(const dr_module_t *m, uint8_t *size)
{
    const dr_program_t *p = PROGRAM(m);
    const dr_shared_t *sh = &m->shared;
    dr_statement_t st;
    dr_stmt_t i;
    dr_stmt_t s = sh->low;
    dr_stmt_t end = (p->n_statements - sh->low < W) ? (dr_stmt_t)(p->n_statements - sh->low) : W;
    for (i = 0; i < end; i++, s++) {
        dr_hal_table_read(&st, &p->statements[s], sizeof st);
        if (st.sync_size != 0u && !bit(sh->done, i) && group_ready(sh, s, &st)) {
            *size = st.sync_size;
            return (dr_stmt_t)(s - st.sync_index);
        }
    }
    return DR_NONE;
}

/* Whether the module counts down to a group that is done, or of an older epoch. */
static uint8_t go_stale(const dr_module_t *m)
{
    dr_statement_t st;
    if (m->go_group == DR_NONE) {
        return 0;
    }
    dr_hal_table_read(&st, &PROGRAM(m)->statements[m->go_group], sizeof st);
    return (uint8_t)(m->go_epoch != m->shared.epoch ||
                     group_done(&m->shared, m->go_group, st.sync_size));
}

/* Keeps the countdown: drops a group that is done (or of an older epoch), takes the first
 * ready group when there is none, starting its countdown now (`now` + the delay) unless a
 * packet gave an earlier start, and opens it once the start has come. Returns whether the
 * module took a group: news, passed on at once. O(W * group). */
static uint8_t go_update(dr_module_t *m, uint32_t now)
{
    uint8_t size = 0;
    dr_stmt_t first;
    if (go_stale(m)) {
        m->go_group = DR_NONE;
    }
    m->go_open = 0;
    if (m->go_group == DR_NONE) {
        first = ready_group(m, &size);
        if (first == DR_NONE) {
            return 0;
        }
        m->go_group = first;
        m->go_epoch = m->shared.epoch;
        m->go_at_ms = now + sync_delay(size);
        return 1;
    }
    m->go_open = (uint8_t)((uint32_t)(now - m->go_at_ms) < 0x80000000u);
    return 0;
}

/* Whether the countdown is to be sent now: it is news, or the module counts down and its
 * repeat is due; then the next repeat is drawn, between half DR_CONF_SYNC_REPEAT_MS and all
 * of it from now (random, so that two neighbours do not repeat in step). O(1). */
static uint8_t go_repeat(dr_module_t *m, uint32_t now, uint8_t news)
{
#if DR_CONF_SYNC_REPEAT_MS > 0
    uint8_t due = (uint8_t)((uint32_t)(now - m->go_repeat_ms) < 0x80000000u);
    if (m->go_group == DR_NONE || m->go_open || (!news && !due)) {
        return news;
    }
    m->go_repeat_ms = now + DR_CONF_SYNC_REPEAT_MS / 2u +
                      (uint32_t)(dr_hal_random(m) % (DR_CONF_SYNC_REPEAT_MS / 2u + 1u));
    return 1;
#else
    (void)m;
    (void)now;
    return news;
#endif
}

/* A packet's countdown: group `group` was ready `age` ms before it was sent. Taken when this
 * module knows the group ready too (after the join), for its own group or as its group when
 * it has none; the earliest start wins: every estimate is late by the transit times of the
 * packets that carried it, never early. */
static void go_heard(dr_module_t *m, uint16_t group, uint16_t age, uint32_t now)
{
    const dr_program_t *p = PROGRAM(m);
    dr_statement_t st;
    uint32_t at;
    if (group >= p->n_statements) {
        return;
    }
    dr_hal_table_read(&st, &p->statements[group], sizeof st);
    at = now - age + sync_delay(st.sync_size);
    if (st.sync_size == 0u || st.sync_index != 0u || !group_ready(&m->shared, (dr_stmt_t)group, &st) ||
        group_done(&m->shared, (dr_stmt_t)group, st.sync_size)) {
        return;
    }
    if (m->go_group == DR_NONE) {
        m->go_group = (dr_stmt_t)group;
        m->go_epoch = m->shared.epoch;
        m->go_at_ms = at;
        m->relay = 1;
    } else if (m->go_group == (dr_stmt_t)group && (uint32_t)(at - m->go_at_ms) >= 0x80000000u) {
        m->go_at_ms = at;
    }
}

/* This module's statements of synchronous groups whose dependencies are done and that are
 * not done: returns whether one is not ready yet, setting its bit in `arm` (the module's own
 * ready set, or NULL to only ask); or, with `waiting`, whether one is ready but its group is
 * not (the module then starts nothing else: it is set to start with the group). Nothing while
 * the module has no single address or the last epoch is over. O(W * (deps + group)). */
static uint8_t sync_scan(const dr_module_t *m, uint8_t waiting, uint8_t *arm)
{
    const dr_program_t *p = PROGRAM(m);
    dr_statement_t st;
    const dr_shared_t *sh = &m->shared;
    dr_stmt_t i;
    dr_stmt_t s = sh->low;
    dr_stmt_t end = (p->n_statements - sh->low < W) ? (dr_stmt_t)(p->n_statements - sh->low) : W;
    dr_dep_t dep;
    uint8_t d;
    uint8_t found = 0;
    if (m->address >= DR_MANY_ADDRESSES || dr_module_finished(m)) {
        return 0;
    }
    for (i = 0; i < end; i++, s++) {
        dr_hal_table_read(&st, &p->statements[s], sizeof st);
        if (st.address != m->address || st.sync_size == 0u || bit(sh->done, i)) {
            continue;
        }
        if (bit(sh->ready, i)) {
            found = (uint8_t)(found | (waiting && !may_start_member(m, s, &st)));
            continue;
        }
        for (d = 0; d < st.n_deps; d++) {
            dr_hal_table_read(&dep, &p->deps[st.first_dep + d], sizeof dep);
            if (!dr_shared_is_done(sh, dep)) {
                break;
            }
        }
        if (d == st.n_deps && !waiting) {
            found = 1;
            if (arm != NULL) {
                set_bit(arm, i);
            }
        }
    }
    return found;
}
#endif

/* This module's first statement at or above offset `from` of the window that is not done and
 * whose dependencies are all done, as its offset from the low-water mark; W when there is
 * none (or the module has no single address, or the last epoch is over). With DR_CONF_SYNC,
 * a member of a synchronous group also waits for its whole group to be ready, and while one
 * of the module's members waits so, nothing else starts here. Reads *m only.
 * O(W * deps). */
static dr_stmt_t next_startable(const dr_module_t *m, dr_stmt_t from)
{
    const dr_program_t *p = PROGRAM(m);
    dr_statement_t st;
    const dr_shared_t *sh = &m->shared;
    dr_stmt_t i;
    dr_stmt_t s = (dr_stmt_t)(sh->low + from);
    /* The window's offsets that are statements: below W and below n_statements - low. */
    dr_stmt_t end = (p->n_statements - sh->low < W) ? (dr_stmt_t)(p->n_statements - sh->low) : W;
    dr_dep_t dep;
    uint8_t d;
#if DR_CONF_SYNC
    uint8_t set_to_start = sync_scan(m, 1, NULL);
#endif
    if (m->address >= DR_MANY_ADDRESSES || dr_module_finished(m)) {
        return W;
    }
    for (i = from; i < end; i++, s++) {
        /* The tables may be in program memory: read through the HAL (dr_hal.h). */
        dr_hal_table_read(&st, &p->statements[s], sizeof st);
        if (st.address != m->address || bit(sh->done, i)) {
            continue;
        }
        for (d = 0; d < st.n_deps; d++) {
            dr_hal_table_read(&dep, &p->deps[st.first_dep + d], sizeof dep);
            if (!dr_shared_is_done(sh, dep)) {
                break;
            }
        }
#if DR_CONF_SYNC
        if (d == st.n_deps && st.sync_size != 0u && !may_start_member(m, s, &st)) {
            continue;
        }
        if (d == st.n_deps && st.sync_size == 0u && set_to_start) {
            continue;
        }
#endif
        if (d == st.n_deps) {
            return i;
        }
    }
    return W;
}

/* Starts a batch: next_startable's statement and the module's other startable statements
 * among the DR_CONF_LATTICE_BATCH - 1 after it, all at once (their dependencies are done, so
 * the sequence lets them overlap). After a reset this re-enters the interrupted ones. Called
 * only when nothing runs here: a statement's completion never waits for a later one. */
static uint8_t start_next(dr_module_t *m)
{
    dr_stmt_t i = next_startable(m, 0);
    dr_stmt_t j;
    uint16_t in = 0;
    if (i == W) {
        return 0;
    }
    m->running = (dr_stmt_t)(m->shared.low + i);
    m->running_epoch = m->shared.epoch;
    for (j = i; j < W && j - i < DR_CONF_LATTICE_BATCH; j = next_startable(m, (dr_stmt_t)(j + 1u))) {
        in = (uint16_t)(in | (1u << (j - i)));
    }
    m->batch = (uint8_t)(in >> 1);
    m->failures = 0;
    issue(m);
    return 1;
}

/* Cost: O(W) plus a read of the NV store (and a write when it holds no valid record); with
 * DR_PROGRAM_NO_NV no NV access but O(DR_CONF_CHANNELS) calls of dr_hal_connected.
 * Precondition: the fields of *m other than the protocol state are zero or left from an
 * earlier init (counters are kept; `resets` counts the inits of a module already running
 * `program`). The address comes from the NV record when there is one: role predicates
 * evaluated again after a reset, in a changed configuration, could give another answer
 * (with DR_PROGRAM_NO_NV there is no record: they are evaluated at every (re)start). */
void dr_module_init(dr_module_t *m, const dr_program_t *program, void *platform)
{
    uint8_t i;
    if (m->program == program) {
        m->resets++;
    }
    m->platform = platform;
    m->program = program;
    m->identity.robot = DR_ROBOT_ID;
    m->identity.fingerprint = WORD(m);
    m->shared.epoch = 0;
    m->shared.low = 0;
    for (i = 0; i < NBYTES; i++) {
        m->shared.done[i] = 0;
#if DR_CONF_SYNC
        m->shared.ready[i] = 0;
#endif
    }
#if DR_CONF_SYNC
    m->relay = 0;
    m->go_open = 0;
    m->go_group = DR_NONE;
    m->go_epoch = 0;
    m->go_at_ms = 0;
    m->go_repeat_ms = 0;
#endif
    dr_shared_normalise(&m->shared, PROGRAM(m)->n_statements);
    m->unechoed = DR_NONE;
    m->unheard = 0;
    m->heard = 0;
    if (no_nv(m)) {
        /* Rule 1: act only once every neighbour connected now has been heard. */
        m->address = PROGRAM(m)->address_of(m);
        m->unheard = connected(m);
    } else if (!restore(m)) {
        m->address = PROGRAM(m)->address_of(m);
        persist(m);
    }
    dr_hal_leds(m, m->address);
    m->running = DR_NONE;
    m->running_epoch = 0;
    m->batch = 0;
    m->failures = 0;
    m->next_broadcast_ms = dr_hal_now_ms(m);
    dissemination_init(m);
}

/* Cost: O(W * deps) plus, on a completion, an NV write (with DR_PROGRAM_NO_NV: a scan of the
 * channels instead, and one at each step while a neighbour is still awaited after another
 * was heard); at most one packet sent. */
void dr_module_step(dr_module_t *m)
{
    uint32_t now = dr_hal_now_ms(m);
    uint8_t due = (uint8_t)((uint32_t)(now - m->next_broadcast_ms) < 0x80000000u);
    uint8_t changed = 0;
    uint8_t retrying = 0; /* a failed batch awaits its retry */
    dr_stmt_t i;
    dr_stmt_t s;
    uint16_t in;
    enum dr_op_status status;
    if (m->running != DR_NONE) {
        status = dr_hal_op_status(m);
        if (status != DR_OP_RUNNING) {
            if (m->running_epoch != m->shared.epoch) {
                m->running = DR_NONE; /* a completion from an older epoch: dropped */
            } else if (status == DR_OP_DONE) {
                /* The whole batch: one normalise, one persist, one news. */
                s = m->running;
                for (in = members(m); in != 0u; in >>= 1, s++) {
                    i = (dr_stmt_t)(s - m->shared.low);
                    if ((in & 1u) != 0u && s >= m->shared.low && i < W) {
                        set_bit(m->shared.done, i);
                    }
                }
                dr_shared_normalise(&m->shared, PROGRAM(m)->n_statements);
                if (!no_nv(m)) {
                    persist(m);
                } else if (connected(m)) {
                    /* Rule 2: not acted on (nothing starts here) until a neighbour echoes it;
                     * the broadcast below still carries it. running_epoch keeps its epoch.
                     * One member stands for the batch: all became done in this one update,
                     * so a copy that holds one descends from it and holds all. */
                    m->unechoed = m->running;
                }
                m->running = DR_NONE;
                changed = 1;
                dissemination_completed(m);
            } else if (RETRIES_SPENT(m)) {
                /* Failed, and the failure policy's retries are spent: the module stops where
                 * it is (it keeps sharing what it holds; dr_module_finished says it). */
                m->running = DR_NONE;
                m->failures = DR_GAVE_UP;
            } else if (due) {
                /* Failed: re-issued when the dissemination policy says (operations are
                 * idempotent), as many times as the failure policy allows. */
                retrying = 1;
                if (dissemination_retry_now(m, now)) {
                    m->failures++;
                    issue(m);
                }
            }
        }
    }
    if (no_nv(m) && m->unheard != 0u && m->heard) {
        m->unheard = (dr_channels_t)(m->unheard & connected(m)); /* unlatched meanwhile */
    }
#if DR_CONF_SYNC
    /* Set to start its synchronous groups' members: a new fact, sent at once. Then the
     * countdown to a ready group's start, kept by every module (taking one is news, passed
     * on at once, as ready bits heard are, and sent again until the start: the countdown
     * must reach every member before the first moves). */
    if (m->running == DR_NONE && !held_back(m)) {
        changed = (uint8_t)(changed | sync_scan(m, 0, m->shared.ready));
    }
    changed = (uint8_t)(changed | go_repeat(m, now, (uint8_t)(go_update(m, now) | m->relay)));
    m->relay = 0;
#endif
    if (m->running == DR_NONE && !held_back(m)) {
        changed = (uint8_t)(changed | dissemination_start_is_news(start_next(m)));
    }
    if (changed || due) {
        dissemination_send(m, now, changed, retrying);
    }
}

/* What the next dr_module_step looks at, in its order: the running batch's status (it
 * waits for it: DR_WAKE_OP, a failed one retried when the broadcast is due), the channels
 * still awaited once a neighbour was heard (re-read at every step: a step at once), a
 * statement it could start now (at once), and the broadcast deadline (always). Cost:
 * O(W * deps), one dr_hal_now_ms. */
uint8_t dr_module_next_wakeup(dr_module_t *m, uint32_t *at_ms)
{
    uint8_t wake = DR_WAKE_AT;
    uint32_t now = dr_hal_now_ms(m);
#if DR_CONF_SYNC
    uint8_t size = 0;
    uint32_t at;
#endif
    *at_ms = m->next_broadcast_ms;
    if (m->running != DR_NONE) {
        wake = (uint8_t)(wake | DR_WAKE_OP);
    }
    if ((no_nv(m) && m->unheard != 0u && m->heard) ||
        (m->running == DR_NONE && !held_back(m) &&
         next_startable(m, 0) != W)) {
        *at_ms = now;
    }
#if DR_CONF_SYNC
    if (m->relay || (m->running == DR_NONE && !held_back(m) && sync_scan(m, 0, NULL))) {
        *at_ms = now;
    }
    /* A group to take or to drop is the next step's to see, the countdown's end its step. */
    at = *at_ms;
    if (m->go_group == DR_NONE) {
        if (ready_group(m, &size) != DR_NONE) {
            at = now;
        }
    } else if (go_stale(m)) {
        at = now;
    } else if (!m->go_open) {
        at = m->go_at_ms;
#if DR_CONF_SYNC_REPEAT_MS > 0
        if ((uint32_t)(m->go_repeat_ms - at) >= 0x80000000u) {
            at = m->go_repeat_ms; /* a repeat before the start */
        }
#endif
    }
    if ((uint32_t)(at - *at_ms) >= 0x80000000u) {
        *at_ms = at;
    }
#endif
    return wake;
}

#if DR_CONF_SYNC
/* Whether `after` holds a ready statement that `before` (an earlier copy of the same module)
 * does not. O(W). */
static uint8_t ready_news(const dr_shared_t *before, const dr_shared_t *after)
{
    dr_stmt_t i;
    dr_stmt_t s = after->low;
    if (after->epoch != before->epoch) {
        return 1;
    }
    for (i = 0; i < W; i++, s++) {
        if (bit(after->ready, i) && !dr_shared_is_ready(before, s)) {
            return 1;
        }
    }
    return 0;
}
#endif

/* Cost: O(len + W). */
void dr_module_receive(dr_module_t *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    const dr_program_t *p = PROGRAM(m);
    const uint8_t *payload;
    uint8_t payload_len;
    dr_shared_t in;
    dr_shared_t before;
    enum dr_packet_result r;
    uint8_t kind = DR_PACKET_LATTICE_STATE;
    count(&m->packets_received);
    if (DR_DISSEMINATION_ASKS && len >= DR_PACKET_HEADER &&
        bytes[DR_PACKET_HEADER - 1u] == DR_PACKET_LATTICE_ASK) {
        kind = DR_PACKET_LATTICE_ASK; /* a retry: its sender awaits our copy */
    }
    r = dr_packet_unframe(bytes, len, &m->identity, kind, &payload, &payload_len);
    if (r == DR_PACKET_FOREIGN) {
        count(&m->packets_foreign);
    } else if (r != DR_PACKET_OK || payload_len != WIRE ||
               !dr_shared_decode(&in, payload, PAYLOAD, p->n_statements) ||
               (p->n_epochs != 0u && in.epoch > p->n_epochs)) {
        count(&m->packets_malformed);
    } else {
        if (no_nv(m)) {
            /* Rule 1: a neighbour heard; rule 2: the own completion echoed (held by two
             * modules now, so it may be acted on). */
            if (channel < DR_CONF_CHANNELS) {
                m->unheard = (dr_channels_t)(m->unheard & ~((dr_channels_t)1 << channel));
            }
            m->heard = 1;
            if (in.epoch > m->running_epoch ||
                (in.epoch == m->running_epoch && dr_shared_is_done(&in, m->unechoed))) {
                m->unechoed = DR_NONE; /* (is_done of DR_NONE is 0) */
            }
        }
        before = m->shared;
        dr_shared_join(&m->shared, &in, p->n_statements);
#if DR_CONF_SYNC
        m->relay = (uint8_t)(m->relay | ready_news(&before, &m->shared));
        go_heard(m, (uint16_t)((payload[PAYLOAD] << 8) | payload[PAYLOAD + 1u]),
                 (uint16_t)((payload[PAYLOAD + 2u] << 8) | payload[PAYLOAD + 3u]),
                 dr_hal_now_ms(m));
#endif
        dissemination_heard(m, channel, &before, &in, (uint8_t)(kind == DR_PACKET_LATTICE_ASK));
    }
}

/* Cost: O(1). */
uint8_t dr_module_finished(const dr_module_t *m)
{
    if (PROGRAM(m)->n_epochs != 0u && m->shared.epoch >= PROGRAM(m)->n_epochs) {
        return DR_END_GOAL;
    }
    return (uint8_t)(m->failures == DR_GAVE_UP ? DR_END_STOPPED : DR_END_NONE);
}
