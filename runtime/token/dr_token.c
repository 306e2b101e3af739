/* dr_token.c - the token-passing baseline (see dr_token.h for the protocol). */
#include "dr_token.h"
#include "dr_packet.h"

/* Payload types. Token: [0][state:2][target:2] and, safe token, [counter][sender:2];
 * acknowledgement: [1][counter]; end: [2]. Multi-byte fields are big-endian. */
#define TYPE_TOKEN 0u
#define TYPE_ACK 1u
#define TYPE_END 2u
#define TOKEN_PLAIN_PAYLOAD 5u
#define TOKEN_SAFE_PAYLOAD DR_TOKEN_SAFE_PAYLOAD
#define ACK_PAYLOAD 2u
#define END_PAYLOAD 1u
#define FRAME (TOKEN_SAFE_PAYLOAD + DR_PACKET_OVERHEAD)

static void schedule_next_send(dr_module_t *m, uint32_t now)
{
    m->next_send_ms = now + DR_CONF_BROADCAST_MS;
#if DR_CONF_BROADCAST_JITTER_MS > 0
    m->next_send_ms += (uint32_t)(dr_hal_random(m) % (DR_CONF_BROADCAST_JITTER_MS + 1u));
#endif
}

static void put16(uint8_t *at, uint16_t v)
{
    at[0] = (uint8_t)(v >> 8);
    at[1] = (uint8_t)(v & 0xFFu);
}

static uint16_t get16(const uint8_t *at)
{
    return (uint16_t)(((uint16_t)at[0] << 8) | at[1]);
}

/* Frames `payload` and sends it on `channel`, or on every channel when channel is
 * DR_CONF_CHANNELS. */
static void send_payload(dr_module_t *m, uint8_t channel, const uint8_t *payload, uint8_t len)
{
    uint8_t frame[FRAME];
    uint8_t n = dr_packet_frame(frame, FRAME, &m->identity, DR_PACKET_TOKEN, payload,
                                len);
    if (channel >= DR_CONF_CHANNELS) {
        dr_hal_broadcast(m, frame, n);
    } else {
        dr_hal_send(m, channel, frame, n);
    }
    m->packets_sent++;
}

/* Statement `s` of the program, read from its table (in program memory on the AVR: dr_hal.h). */
static void statement(const dr_token_program_t *program, uint16_t s, dr_token_statement_t *out)
{
    dr_hal_table_read(out, &program->statements[s], sizeof *out);
}

static uint16_t holder(const dr_token_program_t *program, uint16_t s)
{
    dr_token_statement_t st;
    statement(program, s, &st);
    return st.holder;
}

/* Queues the token of `state` for sending on `channel`; the next step sends it at once. */
static void enqueue(dr_module_t *m, uint16_t state, uint8_t channel)
{
    dr_token_message_t *q;
    if (m->n_queued >= (uint8_t)DR_CONF_TOKEN_QUEUE) {
        m->messages_dropped++;
        return;
    }
    q = &m->queue[m->n_queued++];
    q->state = state;
    q->target = holder(m->program, state);
    q->channel = channel;
    q->counter = m->counter++;
    q->tries = 0;
    m->next_send_ms = dr_hal_now_ms(m);
}

static void remove_queued(dr_module_t *m, uint8_t i)
{
    uint8_t k;
    for (k = i; k + 1u < m->n_queued; k++) {
        m->queue[k] = m->queue[k + 1u];
    }
    m->n_queued--;
    if (m->next_queued > i) {
        m->next_queued--;
    }
    if (m->next_queued >= m->n_queued) {
        m->next_queued = 0;
    }
}

/* The connector this module sends the token of `state` on, when it is on the route into
 * `state`; DR_CONF_CHANNELS when it is not. */
static uint8_t route_channel(const dr_module_t *m, uint16_t state)
{
    dr_token_statement_t s;
    dr_token_hop_t hop;
    uint8_t i;
    statement(m->program, state, &s);
    for (i = 0; i < s.n_hops; i++) {
        dr_hal_table_read(&hop, &m->program->hops[s.first_hop + i], sizeof hop);
        if (hop.sender == m->id) {
            return hop.connector;
        }
    }
    return (uint8_t)DR_CONF_CHANNELS;
}

/* The held statement is done: the next one runs here, or its token leaves on the route. */
static void hand_over(dr_module_t *m)
{
    uint16_t next = (uint16_t)(m->holding + 1u);
    uint8_t channel;
    m->running = 0;
    m->holding = DR_NONE;
    if (next >= m->program->n_statements) {
        m->finished = 1;
        m->next_send_ms = dr_hal_now_ms(m);
        return;
    }
    if (holder(m->program, next) == m->id) {
        m->holding = next;
        return;
    }
    channel = route_channel(m, next);
    if (channel < DR_CONF_CHANNELS) {
        enqueue(m, next, channel);
    }
}

void dr_module_init(dr_module_t *m, const dr_token_program_t *program, void *platform)
{
    uint16_t resets = (uint16_t)(m->program == program ? m->resets + 1u : 0u);
    uint8_t *bytes = (uint8_t *)m;
    uint16_t i;
    for (i = 0; i < (uint16_t)sizeof(dr_module_t); i++) {
        bytes[i] = 0;
    }
    m->platform = platform;
    m->program = program;
    m->identity.robot = DR_ROBOT_ID;
    m->identity.fingerprint = DR_PACKET_PROGRAM_WORD(program->fingerprint, DR_EXECUTION);
    m->resets = resets;
    m->address = program->address_of(m);
    m->id = dr_hal_id(m);
    m->holding = DR_NONE;
    if (program->n_statements > 0u && holder(program, 0) == m->id) {
        m->holding = 0; /* the first module (re)starts the whole sequence */
    }
    dr_hal_leds(m, m->address);
    schedule_next_send(m, dr_hal_now_ms(m));
}

static void run_held(dr_module_t *m)
{
    dr_token_statement_t s;
    enum dr_op_status status;
    if (m->holding == DR_NONE || m->holding >= m->program->n_statements) {
        return;
    }
    if (!m->running) {
        statement(m->program, m->holding, &s);
        dr_hal_op_start(m, m->holding, s.op, s.index, s.args);
        m->running = 1;
        return;
    }
    status = dr_hal_op_status(m);
    if (status == DR_OP_DONE) {
        hand_over(m);
    } else if (status == DR_OP_FAILED) {
        m->running = 0; /* retried at the next step */
    }
}

/* One packet per period: the next queued message (round robin), else an acknowledgement,
 * else, once finished, the end. */
static void send_due(dr_module_t *m, uint32_t now)
{
    uint8_t payload[TOKEN_SAFE_PAYLOAD];
    const dr_token_program_t *p = m->program;
    if (m->n_queued > 0u) {
        uint8_t i = m->next_queued;
        dr_token_message_t *q = &m->queue[i];
        payload[0] = TYPE_TOKEN;
        put16(payload + 1, q->state);
        put16(payload + 3, q->target);
        payload[5] = q->counter;
        put16(payload + 6, m->id);
        send_payload(m, q->channel, payload, p->reliable ? TOKEN_SAFE_PAYLOAD : TOKEN_PLAIN_PAYLOAD);
        q->tries++;
        if (!p->reliable || (p->max_tries != 0u && q->tries >= p->max_tries)) {
            if (p->reliable) {
                m->messages_dropped++; /* given up: never acknowledged */
            }
            remove_queued(m, i);
        } else {
            m->next_queued = (uint8_t)((i + 1u) % m->n_queued);
        }
    } else if (m->n_acks > 0u) {
        uint8_t k;
        payload[0] = TYPE_ACK;
        payload[1] = m->acks[0].counter;
        send_payload(m, m->acks[0].channel, payload, ACK_PAYLOAD);
        for (k = 1; k < m->n_acks; k++) {
            m->acks[k - 1u] = m->acks[k];
        }
        m->n_acks--;
    } else if (m->finished) {
        payload[0] = TYPE_END;
        send_payload(m, (uint8_t)DR_CONF_CHANNELS, payload, END_PAYLOAD);
    }
    schedule_next_send(m, now);
}

/* A held statement not started yet starts at the next step; a started one waits for its
 * operation (done: hand-over; failed: started again); the period's send is always due. O(1). */
uint8_t dr_module_next_wakeup(dr_module_t *m, uint32_t *at_ms)
{
    uint8_t wake = DR_WAKE_AT;
    *at_ms = m->next_send_ms;
    if (m->holding != DR_NONE && m->holding < m->program->n_statements) {
        if (m->running) {
            wake = (uint8_t)(wake | DR_WAKE_OP);
        } else {
            *at_ms = dr_hal_now_ms(m);
        }
    }
    return wake;
}

void dr_module_step(dr_module_t *m)
{
    uint32_t now = dr_hal_now_ms(m);
    run_held(m);
    if ((uint32_t)(now - m->next_send_ms) < 0x80000000u) {
        send_due(m, now);
    }
}

/* Whether (sender, counter) was seen already; remembers it when not. */
static uint8_t seen_before(dr_module_t *m, uint16_t sender, uint8_t counter)
{
    uint8_t i;
    for (i = 0; i < m->n_seen; i++) {
        if (m->seen[i].sender == sender && m->seen[i].counter == counter) {
            return 1;
        }
    }
    m->seen[m->next_seen].sender = sender;
    m->seen[m->next_seen].counter = counter;
    m->next_seen = (uint8_t)((m->next_seen + 1u) % (uint8_t)DR_CONF_TOKEN_SEEN);
    if (m->n_seen < (uint8_t)DR_CONF_TOKEN_SEEN) {
        m->n_seen++;
    }
    return 0;
}

static void queue_ack(dr_module_t *m, uint8_t channel, uint8_t counter)
{
    if (m->n_acks >= (uint8_t)DR_CONF_TOKEN_ACKS) {
        return; /* the sender retries; its next copy is acknowledged then */
    }
    m->acks[m->n_acks].channel = channel;
    m->acks[m->n_acks].counter = counter;
    m->acks[m->n_acks].sender = 0;
    m->n_acks++;
}

static void receive_token(dr_module_t *m, uint8_t channel, const uint8_t *payload, uint8_t len)
{
    uint16_t state = get16(payload + 1);
    uint16_t target = get16(payload + 3);
    uint8_t out;
    if (m->program->reliable) {
        if (len != TOKEN_SAFE_PAYLOAD) {
            m->packets_malformed++;
            return;
        }
        queue_ack(m, channel, payload[5]);
        if (seen_before(m, get16(payload + 6), payload[5])) {
            return;
        }
    } else if (len != TOKEN_PLAIN_PAYLOAD) {
        m->packets_malformed++;
        return;
    }
    if (state >= m->program->n_statements) {
        m->packets_malformed++;
    } else if (target == m->id) {
        m->holding = state; /* adopted as it comes, like the original */
        m->running = 0;
    } else {
        out = route_channel(m, state);
        if (out < DR_CONF_CHANNELS) {
            enqueue(m, state, out);
        }
    }
}

static void receive_ack(dr_module_t *m, uint8_t channel, uint8_t counter)
{
    uint8_t i;
    for (i = 0; i < m->n_queued; i++) {
        if (m->queue[i].counter == counter && m->queue[i].channel == channel) {
            remove_queued(m, i);
            return;
        }
    }
}

void dr_module_receive(dr_module_t *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    /* Set only when the frame is ours; initialised because avr-gcc's link-time optimiser
     * cannot see that and would warn. */
    const uint8_t *payload = bytes;
    uint8_t payload_len = 0u;
    enum dr_packet_result r;
    m->packets_received++;
    r = dr_packet_unframe(bytes, len, &m->identity, DR_PACKET_TOKEN, &payload,
                          &payload_len);
    if (r == DR_PACKET_FOREIGN) {
        m->packets_foreign++;
    } else if (r != DR_PACKET_OK || payload_len == 0u) {
        m->packets_malformed++;
    } else if (payload[0] == TYPE_TOKEN && payload_len >= TOKEN_PLAIN_PAYLOAD) {
        receive_token(m, channel, payload, payload_len);
    } else if (payload[0] == TYPE_ACK && payload_len == ACK_PAYLOAD && m->program->reliable) {
        receive_ack(m, channel, payload[1]);
    } else if (payload[0] == TYPE_END && payload_len == END_PAYLOAD) {
        m->finished = 1;
    } else {
        m->packets_malformed++;
    }
}

uint8_t dr_module_finished(const dr_module_t *m)
{
    return m->finished;
}
