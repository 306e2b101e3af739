/* test_packets.c - state encoding round trip; malformed and foreign packets rejected and
 * counted; NV records checked. */
#include <string.h>
#include "check.h"
#include "dr_packet.h"
#include "sim.h"

#define PAYLOAD_LEN (4u + DR_CONF_WINDOW / 8u)
#define FRAME_LEN (PAYLOAD_LEN + DR_PACKET_OVERHEAD)
#define N_STMT 12u

static dr_statement_t statements[N_STMT];
static const dr_dep_t no_deps[1] = { 0 };
static const dr_program_t program = { 0x5Au, N_STMT, statements, no_deps, sim_args, 3u,
                                      sim_address_of, 0u };
/* The program word of this program in this build's execution (dr_packet.h). */
#define OURS DR_PACKET_PROGRAM_WORD(program.fingerprint, DR_EXECUTION)

/* A frame of `payload` with any header bytes and a correct CRC. */
/* A frame written byte by byte (not through dr_packet_frame), so that each header field can
 * be wrong on its own while the length and CRC stay valid. */
static uint8_t frame_raw(uint8_t *out, uint8_t magic, uint16_t robot, uint32_t fingerprint,
                         uint8_t kind, const uint8_t *payload, uint8_t len)
{
    uint16_t crc;
    uint8_t total = (uint8_t)(len + DR_PACKET_OVERHEAD);
    out[0] = magic;
    out[1] = total;
    out[2] = (uint8_t)(robot >> 8);
    out[3] = (uint8_t)robot;
    out[4] = (uint8_t)(fingerprint >> 24);
    out[5] = (uint8_t)(fingerprint >> 16);
    out[6] = (uint8_t)(fingerprint >> 8);
    out[7] = (uint8_t)fingerprint;
    out[8] = kind;
    memcpy(out + DR_PACKET_HEADER, payload, len);
    crc = dr_crc16(out, (uint8_t)(total - 2u));
    out[total - 2u] = (uint8_t)(crc >> 8);
    out[total - 1u] = (uint8_t)(crc & 0xFFu);
    return total;
}

static void state_with(dr_shared_t *s, uint16_t epoch, uint16_t low, uint8_t done0)
{
    memset(s, 0, sizeof *s);
    s->epoch = epoch;
    s->low = (dr_stmt_t)low;
    s->done[0] = done0;
}

void test_packets(void)
{
    uint8_t payload[PAYLOAD_LEN + 4u];
    uint8_t frame[FRAME_LEN + 8u];
    uint8_t bad[FRAME_LEN + 8u];
    uint8_t len;
    uint8_t flen;
    uint16_t b;
    uint32_t before;
    dr_shared_t s, d;
    dr_module_t *m;
    uint8_t address = 0xFFu;
    uint8_t i;

    for (i = 0; i < N_STMT; i++) {
        sim_statement(&statements[i], 0, i, 0, 0);
    }
    sim_setup(&program, 1, &address, 7u);
    m = &sim.nodes[0].mod;
    CHECK_EQ(sim.nodes[0].fake.leds, 0xFF); /* no address: shown on the LEDs */

    /* Round trip, size. */
    state_with(&s, 0x0102u, 3u, 0x1Au); /* statements 4, 6 and 7 done */
    len = dr_shared_encode(&s, payload, sizeof payload);
    CHECK_EQ(len, PAYLOAD_LEN);
    CHECK_EQ(payload[0], 0x01);
    CHECK_EQ(payload[1], 0x02);
    CHECK_EQ(payload[2], 0x00);
    CHECK_EQ(payload[3], 0x03);
    CHECK_EQ(payload[4], 0x1A);
    CHECK(dr_shared_decode(&d, payload, len, N_STMT));
    CHECK(d.epoch == s.epoch && d.low == s.low && memcmp(d.done, s.done, sizeof d.done) == 0);
    CHECK_EQ(dr_shared_encode(&s, payload, (uint8_t)(PAYLOAD_LEN - 1u)), 0);
    CHECK(!dr_shared_decode(&d, payload, (uint8_t)(len - 1u), N_STMT));
    CHECK(!dr_shared_decode(&d, payload, (uint8_t)(len + 1u), N_STMT));
    /* Inconsistent: low beyond the statements; bits beyond the statements. */
    CHECK(!dr_shared_decode(&d, payload, len, 2u));
    CHECK(!dr_shared_decode(&d, payload, len, 4u)); /* done bit 1 is statement 4 */
    CHECK(dr_shared_decode(&d, payload, len, 8u));  /* ... bits up to statement 7 fit in 8 */
    CHECK(!dr_shared_decode(&d, payload, len, 7u));

    /* A valid packet is received and joined. */
    flen = dr_packet_frame(frame, sizeof frame, &m->identity, DR_PACKET_LATTICE_STATE,
                           payload, len);
    CHECK_EQ(flen, FRAME_LEN);
    state_with(&s, 1u, 2u, 0x01u); /* epoch 1, statements 0-2 done */
    len = dr_shared_encode(&s, payload, sizeof payload);
    flen = dr_packet_frame(frame, sizeof frame, &m->identity, DR_PACKET_LATTICE_STATE,
                           payload, len);
    dr_module_receive(m, 0, frame, flen);
    CHECK_EQ(m->packets_received, 1);
    CHECK_EQ(m->packets_malformed + m->packets_foreign, 0);
    CHECK_EQ(m->shared.epoch, 1);
    CHECK_EQ(m->shared.low, 3);
    CHECK(dr_shared_is_done(&m->shared, 2) && !dr_shared_is_done(&m->shared, 3));

    /* Every single bit flip is malformed. */
    before = m->packets_malformed;
    for (b = 0; b < 8u * flen; b++) {
        memcpy(bad, frame, flen);
        bad[b / 8u] = (uint8_t)(bad[b / 8u] ^ (1u << (b % 8u)));
        dr_module_receive(m, 0, bad, flen);
    }
    CHECK_EQ(m->packets_malformed - before, 8u * flen);
    CHECK_EQ(m->packets_foreign, 0);
    /* Every truncation is malformed (and so is an empty packet). */
    before = m->packets_malformed;
    for (b = 0; b < flen; b++) {
        dr_module_receive(m, 0, frame, (uint8_t)b);
    }
    CHECK_EQ(m->packets_malformed - before, flen);
    /* Wrong magic, with a valid CRC: malformed. */
    before = m->packets_malformed;
    dr_module_receive(m, 0, bad, frame_raw(bad, 0xD1u, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    CHECK_EQ(m->packets_malformed - before, 1);
    /* A valid frame with a byte appended (zero or not): malformed. */
    flen = frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                     DR_PACKET_LATTICE_STATE, payload, len);
    bad[flen] = 0u;
    dr_module_receive(m, 0, bad, (uint8_t)(flen + 1u));
    CHECK_EQ(m->packets_malformed - before, 2);
    flen = FRAME_LEN;
    /* Another robot, another program (even one differing only in the fingerprint's top
     * byte), this program in another execution (a recording of another launch), or another
     * kind: foreign. */
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID,
                                            DR_PACKET_PROGRAM_WORD(program.fingerprint,
                                                                   DR_EXECUTION ^ 1u),
                                            DR_PACKET_LATTICE_STATE, payload, len));
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, (uint16_t)(DR_ROBOT_ID + 1u),
                                            OURS, DR_PACKET_LATTICE_STATE,
                                            payload, len));
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID,
                                            OURS ^ 0x01000000UL,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID,
                                            DR_PACKET_PROGRAM_WORD(0x5Bu, DR_EXECUTION),
                                            DR_PACKET_LATTICE_STATE, payload, len));
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_PAPER_STATE, payload, len));
    CHECK_EQ(m->packets_foreign, 5);
    /* Valid frame, wrong payload size: malformed. */
    before = m->packets_malformed;
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload,
                                            (uint8_t)(len - 1u)));
    /* Valid frame, low > n_statements: malformed. */
    state_with(&s, 1u, (uint16_t)(N_STMT + 1u), 0u);
    (void)dr_shared_encode(&s, payload, sizeof payload);
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    /* Valid frame, a bit for a statement that does not exist: malformed. */
    state_with(&s, 1u, (uint16_t)(N_STMT - 1u), 0x02u);
    (void)dr_shared_encode(&s, payload, sizeof payload);
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    /* Valid frame, an epoch beyond the end (3 epochs: 3 is the end, 4 cannot exist). */
    state_with(&s, 4u, 0u, 0u);
    (void)dr_shared_encode(&s, payload, sizeof payload);
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    CHECK_EQ(m->packets_malformed - before, 4);
    /* None of that changed the state. */
    CHECK_EQ(m->shared.epoch, 1);
    CHECK_EQ(m->shared.low, 3);
    /* The end itself is accepted and is final. */
    state_with(&s, 3u, 0u, 0u);
    (void)dr_shared_encode(&s, payload, sizeof payload);
    dr_module_receive(m, 0, bad, frame_raw(bad, DR_PACKET_MAGIC, DR_ROBOT_ID, OURS,
                                            DR_PACKET_LATTICE_STATE, payload, len));
    CHECK(dr_module_finished(m));
    CHECK_EQ(m->packets_received, 8u * flen + flen + 1u + 1u + 1u + 5u + 4u + 1u);

    /* A module with no address sends its state but starts nothing. */
    sim.time += 1000u;
    dr_module_step(m);
    CHECK_EQ(sim.total_starts, 0);
    CHECK(m->packets_sent >= 1u);
}
