/* dr_dissemination_adaptive.h - adaptive dissemination (DR_DISSEMINATION_ADAPTIVE, dr_conf.h;
 * README.md "Adaptive dissemination"), Trickle-like (RFC 6206): news and answers at the next
 * step, then an interval that doubles while nothing is new; retries toward a neighbour not
 * heard with our copy, as asking frames (DR_PACKET_LATTICE_ASK) sent on its channels only. The
 * hooks of dr_dissemination.h, which includes this file (twice: see there). */
#ifndef DR_DISSEMINATION_ADAPTIVE_H
#define DR_DISSEMINATION_ADAPTIVE_H

/* The fields of dr_module_t: the interval is DR_CONF_LATTICE_INTERVAL_MS << doublings;
 * `resends` the broadcasts left at the smallest interval while one is missing; `consistent`
 * the packets equal to our copy heard since our last broadcast (for suppression); `answer` a
 * neighbour was heard behind (or asking), or our copy grew: the next broadcast answers, never
 * suppressed; `acked` the channels heard with a copy at least ours since ours last changed (or
 * a neighbour was heard behind); `lagging` those heard behind and not heard with our copy
 * since; `asking` those heard asking (a retry) with our copy since our last broadcast: the next
 * one answers them; `issued_ms` when the running batch was last issued (low 16 bits): a failed
 * one is retried an interval on. */
#define DR_DISSEMINATION_STATE \
    uint8_t doublings;         \
    uint8_t resends;           \
    uint8_t consistent;        \
    uint8_t answer;            \
    dr_channels_t acked;       \
    dr_channels_t lagging;     \
    dr_channels_t asking;      \
    uint16_t issued_ms;

#elif defined(DR_DISSEMINATION_HOOKS) && !defined(DR_DISSEMINATION_ADAPTIVE_HOOKS)
#define DR_DISSEMINATION_ADAPTIVE_HOOKS

/* A retry goes out as an asking frame (DR_PACKET_LATTICE_ASK), answered at once. */
#define DR_DISSEMINATION_ASKS 1

typedef char dr_lattice_check_doublings[(DR_CONF_LATTICE_DOUBLINGS <= 16 &&
                                         DR_CONF_LATTICE_UNACKED_DOUBLINGS <=
                                             DR_CONF_LATTICE_DOUBLINGS &&
                                         DR_CONF_LATTICE_INTERVAL_MS >= 1 &&
                                         DR_CONF_LATTICE_INTERVAL_MS <= 0xFFFF &&
                                         DR_CONF_LATTICE_RESEND_SPREAD <= 100) ? 1 : -1];

/* The resend spread of the smallest interval, in whole milliseconds (rounded down); a try's
 * spread is it doubled with the interval. The largest (after DR_CONF_LATTICE_UNACKED_DOUBLINGS
 * doublings) fits 16 bits, so a spread is computed in 16 bits: no 32-bit multiplication and
 * division (libgcc helpers on an 8-bit core). */
#define SPREAD_BASE ((uint32_t)DR_CONF_LATTICE_INTERVAL_MS * DR_CONF_LATTICE_RESEND_SPREAD / 100u)
typedef char dr_lattice_check_spread[(SPREAD_BASE << DR_CONF_LATTICE_UNACKED_DOUBLINGS) < 0xFFFFu
                                         ? 1
                                         : -1];

/* Bits of m->answer: the next broadcast answers (it is never suppressed) ... */
#define ANSWER_THEM 1u /* ... a neighbour heard behind or asking: on its channel (with the others
                          still wanting our copy) */
#define ANSWER_NEWS 2u /* ... our copy grew: on every channel, the sender's too (the relay is
                          its acknowledgement) */

/* Sends the state now, as a frame of `kind` (DR_PACKET_LATTICE_ASK: a retry, answered at
 * once by a receiver that holds our copy): on every channel (`to` = 0), or only on the
 * channels of `to` (a retry or an answer that only some neighbours need costs one packet per
 * such neighbour, not one per channel). The schedule is set by disseminate, below.
 * O(DR_CONF_CHANNELS). */
static void send_state(dr_module_t *m, dr_channels_t to, uint8_t kind)
{
    uint8_t frame[FRAME];
    uint8_t len;
    /* Encoded in place: dr_packet_frame then copies each payload byte onto itself. */
#if DR_CONF_SYNC
    state_payload(m, frame + DR_PACKET_HEADER);
#else
    (void)dr_shared_encode(&m->shared, frame + DR_PACKET_HEADER, PAYLOAD);
#endif
    len = dr_packet_frame(frame, FRAME, &m->identity, kind, frame + DR_PACKET_HEADER, WIRE);
    if (to != 0u) {
        uint8_t c;
        for (c = 0; c < DR_CONF_CHANNELS; c++) {
            if ((to & (dr_channels_t)((dr_channels_t)1 << c)) != 0u) {
                dr_hal_send(m, c, frame, len);
            }
        }
    } else {
        dr_hal_broadcast(m, frame, len);
    }
    m->packets_sent++;
    m->asking = 0; /* answered */
}

/* Back to the smallest interval, with every resend allowed again. */
static void restart_interval(dr_module_t *m)
{
    m->doublings = 0;
    m->resends = DR_CONF_LATTICE_RESENDS;
}

/* The broadcast and the schedule, called when a broadcast is due or the own copy changed
 * (`changed`: a local completion, always sent and a restart of the interval). A due
 * broadcast may be suppressed (DR_CONF_LATTICE_SUPPRESS). Then the next one is scheduled:
 * toward a connected neighbour heard behind and not heard with our copy since, the smallest
 * interval (a near-dead link: try as often as the fixed period does); while another
 * connected neighbour has not been heard with our copy, first the resends at the smallest
 * interval, then at most DR_CONF_LATTICE_UNACKED_DOUBLINGS doublings (its packets may be
 * lost; a silent neighbour costs one packet per such interval); once all have, the longest
 * interval (nothing is left to tell them: the broadcasts only keep the links alive). */
static void disseminate(dr_module_t *m, uint32_t now, uint8_t changed)
{
    dr_channels_t linked = connected(m);
    dr_channels_t unacked = (dr_channels_t)(linked & (dr_channels_t)~m->acked);
    dr_channels_t wanting = (dr_channels_t)(unacked | m->lagging | m->asking);
    dr_channels_t to = 0;
    /* A retry (nothing new, nothing to answer, a connected neighbour not heard with our copy)
     * asks: a receiver that holds our copy answers at once. */
    uint8_t kind = (uint8_t)((!changed && m->answer == 0u && unacked != 0u)
                                 ? DR_PACKET_LATTICE_ASK
                                 : DR_PACKET_LATTICE_STATE);
#if DR_CONF_LATTICE_RESEND_SPREAD > 0
    uint16_t spread;
#endif
    if (changed) {
        restart_interval(m);
    }
    /* A retry or an answer that only some neighbours need (the others have been heard with
     * our copy and did not ask) goes to those channels only. News and the quiet broadcasts go
     * on every channel: they are also for neighbours facing us without a latch; and without
     * NV every send does (a neighbour in its rule-1 wait must hear us). */
    if (!changed && (m->answer & ANSWER_NEWS) == 0u && !no_nv(m) && wanting != 0u &&
        (linked & (dr_channels_t)~wanting) != 0u) {
        to = wanting;
    }
#if DR_CONF_LATTICE_SUPPRESS > 0
    /* Never without NV: a neighbour in its rule-1 wait (or awaiting an echo) must hear us
     * even when our copy is the same as its own. */
    if (changed || m->answer || unacked != 0u || m->consistent < DR_CONF_LATTICE_SUPPRESS ||
        no_nv(m)) {
        send_state(m, to, kind);
    }
#else
    send_state(m, to, kind);
#endif
    m->consistent = 0;
    m->answer = 0;
    if ((unacked & m->lagging) != 0u) {
        m->doublings = 0; /* a neighbour known to lack a fact: again soon */
    } else if (unacked != 0u && m->resends > 0u) {
        /* A neighbour may have missed it: again after the smallest interval. */
        m->resends--;
        m->doublings = 0;
    } else if (unacked != 0u) {
        /* Still unacknowledged after the resends: less often, up to the cap. */
        m->doublings = (uint8_t)(m->doublings < DR_CONF_LATTICE_UNACKED_DOUBLINGS
                                     ? m->doublings + 1u
                                     : DR_CONF_LATTICE_UNACKED_DOUBLINGS);
    } else {
        m->doublings = DR_CONF_LATTICE_DOUBLINGS;
    }
    m->next_broadcast_ms = now + ((uint32_t)DR_CONF_LATTICE_INTERVAL_MS << m->doublings);
#if DR_CONF_LATTICE_RESEND_SPREAD > 0
    if (unacked != 0u) {
        /* A try toward an unacknowledged neighbour at a random time in the last SPREAD % of
         * its interval: the modules that heard the same news at the same time would
         * otherwise resend in step and collide again. */
        spread = (uint16_t)((uint16_t)SPREAD_BASE << m->doublings); /* doublings <= UNACKED */
        m->next_broadcast_ms -= spread;
        m->next_broadcast_ms += (uint32_t)(dr_hal_random(m) % (uint16_t)(spread + 1u));
    }
#endif
#if DR_CONF_BROADCAST_JITTER_MS > 0
    m->next_broadcast_ms += (uint32_t)(dr_hal_random(m) % (DR_CONF_BROADCAST_JITTER_MS + 1u));
#endif
}

/* Whether two normalised copies hold the same facts (epoch, low, done). O(W/8). */
static uint8_t same_facts(const dr_shared_t *a, const dr_shared_t *b)
{
    uint8_t i;
    uint8_t same = (uint8_t)(a->epoch == b->epoch && a->low == b->low);
    for (i = 0; i < NBYTES; i++) {
        same = (uint8_t)(same && a->done[i] == b->done[i]);
#if DR_CONF_SYNC
        same = (uint8_t)(same && a->ready[i] == b->ready[i]);
#endif
    }
    return same;
}

/* A broadcast at the next step plus 0..DR_CONF_LATTICE_RELAY_JITTER_MS ms, unless one is due
 * sooner. */
static void send_soon(dr_module_t *m)
{
    uint32_t soon = dr_hal_now_ms(m);
#if DR_CONF_LATTICE_RELAY_JITTER_MS > 0
    soon += (uint32_t)(dr_hal_random(m) % (DR_CONF_LATTICE_RELAY_JITTER_MS + 1u));
#endif
    if ((uint32_t)(m->next_broadcast_ms - soon) < 0x80000000u) {
        m->next_broadcast_ms = soon;
    }
}

/* After the join of a packet `in` heard on `channel` (`before`: our copy before it). News
 * (our copy grew: relayed on every channel, the sender's too) and a sender that lacks
 * something we hold (it is behind: answer it) are sent at the next step, with the interval
 * back to the smallest; a packet equal to our copy acknowledges that channel, and when it
 * asks (`asked`: a DR_PACKET_LATTICE_ASK frame, a retry) it is answered at the next step on
 * that channel: the sender retries because it has not heard us with its copy (our packet
 * was lost), and nothing else would make us speak. O(W). */
static void dissemination_heard(dr_module_t *m, uint8_t channel, const dr_shared_t *before,
                                dr_shared_t *in, uint8_t asked)
{
    dr_channels_t bit_c = 0;
    uint8_t grew = (uint8_t)!same_facts(before, &m->shared);
    uint8_t behind;
    dr_shared_normalise(in, PROGRAM(m)->n_statements);
    behind = (uint8_t)!same_facts(in, &m->shared);
    if (channel < DR_CONF_CHANNELS) {
        bit_c = (dr_channels_t)((dr_channels_t)1 << channel);
    }
    if (grew || behind) {
        restart_interval(m);
        send_soon(m);
        if (grew) {
            m->acked = 0;
            m->answer = ANSWER_NEWS;
        }
    }
    if (behind) {
        m->answer = (uint8_t)(m->answer | ANSWER_THEM);
        m->acked = (dr_channels_t)(m->acked & (dr_channels_t)~bit_c);
        m->lagging = (dr_channels_t)(m->lagging | bit_c);
    } else {
        m->acked = (dr_channels_t)(m->acked | bit_c);
        m->lagging = (dr_channels_t)(m->lagging & (dr_channels_t)~bit_c);
        if (!grew) {
            if (asked) {
                m->answer = (uint8_t)(m->answer | ANSWER_THEM);
                m->asking = (dr_channels_t)(m->asking | bit_c);
                send_soon(m);
            }
            if (m->consistent < 0xFFu) {
                m->consistent++;
            }
            /* Heard nothing new: the interval doubles (the broadcast already scheduled keeps
             * its time; the next one is scheduled with the longer interval). */
            if (m->doublings < DR_CONF_LATTICE_DOUBLINGS) {
                m->doublings++;
            }
        }
    }
}

static void dissemination_init(dr_module_t *m)
{
    /* Speak at once (a restarted module's copy may be behind: its neighbours answer). */
    restart_interval(m);
    m->consistent = 0;
    m->answer = 0;
    m->acked = 0;
    m->lagging = 0;
    m->asking = 0;
}

static void dissemination_issued(dr_module_t *m)
{
    m->issued_ms = (uint16_t)dr_hal_now_ms(m);
}

static void dissemination_completed(dr_module_t *m)
{
    m->acked = 0; /* a new fact: no neighbour is known to hold our copy */
}

/* Failed: retried at the smallest interval, however soon an answer or news is due (the start
 * itself was not broadcast; dissemination_send keeps the deadline at that interval). */
static uint8_t dissemination_retry_now(dr_module_t *m, uint32_t now)
{
    return (uint8_t)((uint16_t)((uint16_t)now - m->issued_ms) >= DR_CONF_LATTICE_INTERVAL_MS);
}

static uint8_t dissemination_start_is_news(uint8_t started)
{
    (void)started; /* not news: a start changes no shared fact */
    return 0;
}

static void dissemination_send(dr_module_t *m, uint32_t now, uint8_t changed, uint8_t retrying)
{
    disseminate(m, now, changed);
    if (retrying) {
        m->next_broadcast_ms = now + DR_CONF_LATTICE_INTERVAL_MS;
    }
}

#endif /* DR_DISSEMINATION_ADAPTIVE_H, then the hooks */
