/* test_packet.c - the paper-state packet: layout, round trip, and rejection of corrupted and foreign packets. */
#include <string.h>
#include "harness.h"
#include "machines.h"
#include "dr_packet.h"

#define FRAME 19u /* 11 bytes of framing (9 header, 2 CRC) + 3 + DR_CONF_MAX_PENDING (5) */

static void deliver_bytes(world_t *w, uint8_t to, const uint8_t *bytes, uint8_t len)
{
    dr_module_receive(&w->mod[to], 0, bytes, len);
}

static void test_layout_and_round_trip(void)
{
    world_t w;
    const uint8_t p16[2] = {1, 6};
    const uint8_t *f;
    world_init(&w, 2, &eight2car_program, DR_MERGE_C_PORT, 0, 0);
    w.mod[0].mailbox = DR_STATE_IDLE; /* keep module 0 still */
    w.mod[0].global.state = 7;
    w.mod[0].global.address = 3;
    w.mod[0].global.pending[0] = 1;
    w.mod[0].global.pending[2] = 6;
    world_step(&w, 0);
    f = w.fake[0].packet;
    CHECK_EQ(w.fake[0].packet_len, FRAME);
    CHECK_EQ(w.mod[0].packets_sent, 1);
    CHECK_EQ(f[0], DR_PACKET_MAGIC);
    CHECK_EQ(f[1], FRAME);                 /* the frame's length */
    CHECK_EQ((f[2] << 8) | f[3], DR_ROBOT_ID);
    CHECK_EQ(f[4], 0);                     /* program fingerprint, big endian */
    CHECK_EQ(f[5], 0);
    CHECK_EQ(f[6], 0);
    CHECK_EQ(f[7], 42);
    CHECK_EQ(f[8], DR_PACKET_PAPER_STATE);
    CHECK_EQ(f[9], 0);                     /* alternate flag */
    CHECK_EQ(f[10], 7);                    /* global state */
    CHECK_EQ(f[11], 3);                    /* recipient */
    CHECK_EQ(f[12], 1);                    /* pending slots as they are */
    CHECK_EQ(f[13], 0);
    CHECK_EQ(f[14], 6);
    CHECK_EQ(f[15], 0);
    CHECK_EQ(f[16], 0);
    CHECK_EQ((f[17] << 8) | f[18], dr_crc16(f, 17));

    world_deliver(&w, 0, 1);
    CHECK_TRIPLE(&w.mod[1].global, 7, 3, p16, 2);
    CHECK_EQ(w.mod[1].packets_received, 1);
    CHECK_EQ(w.mod[1].mailbox, DR_STATE_IDLE); /* recipient 3 is not module 1 */

    /* recipient -1 (the end) goes out as 255 and is nobody's mailbox, not even a module
     * without an address (DR_NO_ADDRESS is 255 too) */
    dr_paper_send_state(&w.mod[0], DR_STATE_END, DR_ADDRESS_ALL);
    world_step(&w, 0);
    CHECK_EQ(w.fake[0].packet[10], 254);
    CHECK_EQ(w.fake[0].packet[11], 255);
    w.mod[1].address = DR_NO_ADDRESS;
    world_deliver(&w, 0, 1);
    CHECK(dr_module_finished(&w.mod[1]));
    CHECK_EQ(w.mod[1].mailbox, DR_STATE_IDLE);
}

static void test_rejections(void)
{
    world_t w;
    uint8_t good[DR_CONF_MAX_PACKET];
    uint8_t bad[DR_CONF_MAX_PACKET];
    uint8_t payload[16];
    uint8_t len;
    uint8_t good_len;
    uint8_t i;
    uint8_t bit;
    uint32_t n_bad = 0;
    dr_paper_global_t before;
    dr_identity_t ours;
    dr_identity_t other_program;
    dr_identity_t other_robot;
    world_init(&w, 2, &eight2car_program, DR_MERGE_C_PORT, 0, 0);
    ours = w.mod[1].identity;
    other_program = ours;
    other_program.fingerprint ^= 0x00010000UL;
    other_robot = ours;
    other_robot.robot = (uint16_t)(ours.robot + 7u);
    w.mod[0].mailbox = DR_STATE_IDLE;
    w.mod[0].global.state = 9;
    w.mod[0].global.address = 4;
    w.mod[0].global.pending[0] = 1;
    world_step(&w, 0);
    len = w.fake[0].packet_len;
    good_len = len;
    memcpy(good, w.fake[0].packet, len);
    before = w.mod[1].global;

    /* every single-bit error is caught (CRC-16) */
    for (i = 0; i < len; i++) {
        for (bit = 0; bit < 8u; bit++) {
            memcpy(bad, good, len);
            bad[i] = (uint8_t)(bad[i] ^ (1u << bit));
            deliver_bytes(&w, 1, bad, len);
            n_bad++;
        }
    }
    deliver_bytes(&w, 1, good, (uint8_t)(len - 1u)); /* truncated */
    memcpy(bad, good, len);
    bad[len] = 0;
    deliver_bytes(&w, 1, bad, (uint8_t)(len + 1u));  /* trailing byte */
    deliver_bytes(&w, 1, good, 0);                   /* empty */
    deliver_bytes(&w, 1, good, 4);                   /* shorter than any frame */
    n_bad += 4;
    /* a well-formed frame whose payload has the wrong size (another N) */
    memcpy(payload, good + DR_PACKET_HEADER, 8);
    len = dr_packet_frame(bad, sizeof bad, &ours, DR_PACKET_PAPER_STATE, payload, 7);
    deliver_bytes(&w, 1, bad, len);
    n_bad++;
    CHECK_EQ(w.mod[1].packets_malformed, n_bad);
    CHECK_EQ(w.mod[1].packets_foreign, 0);

    /* foreign: another program, another robot running this one, another kind, the other alternate-sequence flag */
    len = dr_packet_frame(bad, sizeof bad, &other_program, DR_PACKET_PAPER_STATE,
                          good + DR_PACKET_HEADER, 8);
    deliver_bytes(&w, 1, bad, len);
    len = dr_packet_frame(bad, sizeof bad, &other_robot, DR_PACKET_PAPER_STATE,
                          good + DR_PACKET_HEADER, 8);
    deliver_bytes(&w, 1, bad, len);
    len = dr_packet_frame(bad, sizeof bad, &ours, DR_PACKET_LATTICE_STATE, good + DR_PACKET_HEADER, 8);
    deliver_bytes(&w, 1, bad, len);
    memcpy(payload, good + DR_PACKET_HEADER, 8);
    payload[0] = 1;
    len = dr_packet_frame(bad, sizeof bad, &ours, DR_PACKET_PAPER_STATE, payload, 8);
    deliver_bytes(&w, 1, bad, len);
    CHECK_EQ(w.mod[1].packets_foreign, 4);
    CHECK_EQ(w.mod[1].packets_malformed, n_bad);
    CHECK_EQ(w.mod[1].packets_received, n_bad + 4u);

    /* none of them changed anything */
    CHECK_TRIPLE(&w.mod[1].global, before.state, before.address, before.pending, 0);
    CHECK_EQ(w.mod[1].mailbox, DR_STATE_IDLE);

    /* the good one still goes through */
    deliver_bytes(&w, 1, good, good_len);
    CHECK_TRIPLE(&w.mod[1].global, 9, 4, good + DR_PACKET_HEADER + 3, 1);
}

int main(void)
{
    test_layout_and_round_trip();
    test_rejections();
    return harness_done("test_packet");
}
