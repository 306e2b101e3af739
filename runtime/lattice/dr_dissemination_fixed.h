/* dr_dissemination_fixed.h - fixed-period dissemination (DR_DISSEMINATION_FIXED, dr_conf.h): a
 * broadcast every DR_CONF_BROADCAST_MS (+ jitter) for the whole run, and at once after a
 * local start or completion; a failed batch is re-issued at each broadcast. What a module
 * learns from others goes out at its next periodic broadcast. The hooks of
 * dr_dissemination.h, which includes this file (twice: see there). */
#ifndef DR_DISSEMINATION_FIXED_H
#define DR_DISSEMINATION_FIXED_H

/* No state of its own: next_broadcast_ms, the protocol's timer, is the whole schedule. */
#define DR_DISSEMINATION_STATE

#elif defined(DR_DISSEMINATION_HOOKS) && !defined(DR_DISSEMINATION_FIXED_HOOKS)
#define DR_DISSEMINATION_FIXED_HOOKS

/* Every frame is DR_PACKET_LATTICE_STATE. */
#define DR_DISSEMINATION_ASKS 0

/* Sends the state now and schedules the next periodic broadcast. */
static void broadcast(dr_module_t *m, uint32_t now)
{
    uint8_t frame[FRAME];
    uint8_t len;
    /* Encoded in place: dr_packet_frame then copies each payload byte onto itself. */
#if DR_CONF_SYNC
    state_payload(m, frame + DR_PACKET_HEADER);
#else
    (void)dr_shared_encode(&m->shared, frame + DR_PACKET_HEADER, PAYLOAD);
#endif
    len = dr_packet_frame(frame, FRAME, &m->identity, DR_PACKET_LATTICE_STATE,
                          frame + DR_PACKET_HEADER, WIRE);
    dr_hal_broadcast(m, frame, len);
    m->packets_sent++;
    m->next_broadcast_ms = now + DR_CONF_BROADCAST_MS;
#if DR_CONF_BROADCAST_JITTER_MS > 0
    m->next_broadcast_ms += (uint32_t)(dr_hal_random(m) % (DR_CONF_BROADCAST_JITTER_MS + 1u));
#endif
}

static void dissemination_init(dr_module_t *m)
{
    (void)m; /* the first broadcast is at the first step: next_broadcast_ms = now */
}

static void dissemination_issued(dr_module_t *m)
{
    (void)m;
}

static void dissemination_completed(dr_module_t *m)
{
    (void)m; /* sent at once: dissemination_send with `changed` */
}

static uint8_t dissemination_retry_now(dr_module_t *m, uint32_t now)
{
    (void)m;
    (void)now;
    return 1; /* failed: retry, at the pace of the periodic broadcast */
}

static uint8_t dissemination_start_is_news(uint8_t started)
{
    return started; /* a start is broadcast at once, as a completion is */
}

static void dissemination_send(dr_module_t *m, uint32_t now, uint8_t changed, uint8_t retrying)
{
    (void)changed;  /* every broadcast is the same */
    (void)retrying; /* a retry waits for the next period */
    broadcast(m, now);
}

static void dissemination_heard(dr_module_t *m, uint8_t channel, const dr_shared_t *before,
                                dr_shared_t *in, uint8_t asked)
{
    /* Nothing to schedule: the next periodic broadcast carries what was learnt. */
    (void)m;
    (void)channel;
    (void)before;
    (void)in;
    (void)asked;
}

#endif /* DR_DISSEMINATION_FIXED_H, then the hooks */
