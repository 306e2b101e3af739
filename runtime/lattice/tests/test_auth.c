/* test_auth.c - the keyed authentication tag (built with DR_CONF_PACKET_TAG 4 and 8): the
 * SipHash-2-4 reference vector, frames made with the key accepted, any change to a tagged
 * byte rejected even with the CRC made valid again, another robot's frame foreign, and a
 * frame of another execution (a recording of another launch) foreign and not made ours by
 * rewriting its program word. */
#include <stdio.h>
#include <string.h>

#include "dr_packet.h"

const uint8_t dr_packet_key[16] = { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15 };

static unsigned checks;
static unsigned failures;

#define CHECK(c)                                                                        \
    do {                                                                                \
        checks++;                                                                       \
        if (!(c)) {                                                                     \
            failures++;                                                                 \
            fprintf(stderr, "FAIL %s:%d: %s\n", __FILE__, __LINE__, #c);                \
        }                                                                               \
    } while (0)

/* Recomputes the CRC of a frame whose bytes were changed (as a deliberate forger would). */
static void recrc(uint8_t *frame, uint8_t len)
{
    uint16_t crc = dr_crc16(frame, (uint8_t)(len - 2u));
    frame[len - 2u] = (uint8_t)(crc >> 8);
    frame[len - 1u] = (uint8_t)(crc & 0xFFu);
}

static void test_reference_vector(void)
{
    /* The SipHash paper's Appendix A: key 00..0f, message 00..0e. */
    uint8_t message[15];
    uint8_t i;
    for (i = 0; i < sizeof message; i++) {
        message[i] = i;
    }
    CHECK(dr_siphash24(dr_packet_key, message, 15u) == 0xa129ca6149be45e5ULL);
}

static void test_frames(void)
{
    const dr_identity_t ours = { 3u, 0xCAFEF00DUL };
    const dr_identity_t other_robot = { 4u, 0xCAFEF00DUL };
    const uint8_t payload[6] = { 1, 2, 3, 4, 5, 6 };
    uint8_t frame[DR_CONF_MAX_PACKET];
    uint8_t bad[DR_CONF_MAX_PACKET];
    const uint8_t *got;
    uint8_t got_len = 0;
    uint8_t len;
    uint8_t i;
    len = dr_packet_frame(frame, sizeof frame, &ours, 1u, payload, sizeof payload);
    CHECK(len == sizeof payload + DR_PACKET_OVERHEAD);
    CHECK(DR_PACKET_OVERHEAD == 11u + DR_CONF_PACKET_TAG);
    CHECK(dr_packet_unframe(frame, len, &ours, 1u, &got, &got_len) == DR_PACKET_OK);
    CHECK(got_len == sizeof payload && memcmp(got, payload, sizeof payload) == 0);
    /* Every tagged byte changed, CRC repaired: the tag catches it. */
    for (i = 0; i < (uint8_t)(len - 2u); i++) {
        memcpy(bad, frame, len);
        bad[i] = (uint8_t)(bad[i] ^ 0x20u);
        recrc(bad, len);
        CHECK(dr_packet_unframe(bad, len, &ours, 1u, &got, &got_len) == DR_PACKET_MALFORMED);
    }
    /* Another robot with the same key and program: authentic, but not ours. */
    len = dr_packet_frame(frame, sizeof frame, &other_robot, 1u, payload, sizeof payload);
    CHECK(dr_packet_unframe(frame, len, &ours, 1u, &got, &got_len) == DR_PACKET_FOREIGN);
}

/* This robot and program in execution 7, and a frame recorded in execution 6 (the launch
 * before): authentic, but foreign; its program word rewritten to ours (CRC repaired), the tag
 * no longer matches. */
static void test_executions(void)
{
    const uint32_t fingerprint = 0xCAFEF00DUL;
    dr_identity_t ours;
    dr_identity_t before;
    const uint8_t payload[6] = { 6, 5, 4, 3, 2, 1 };
    uint8_t frame[DR_CONF_MAX_PACKET];
    const uint8_t *got;
    uint8_t got_len = 0;
    uint8_t len;
    ours.robot = 3u;
    ours.fingerprint = DR_PACKET_PROGRAM_WORD(fingerprint, 7u);
    before.robot = 3u;
    before.fingerprint = DR_PACKET_PROGRAM_WORD(fingerprint, 6u);
    len = dr_packet_frame(frame, sizeof frame, &before, 1u, payload, sizeof payload);
    CHECK(len == sizeof payload + DR_PACKET_OVERHEAD); /* no byte more on the air */
    CHECK(dr_packet_unframe(frame, len, &before, 1u, &got, &got_len) == DR_PACKET_OK);
    CHECK(dr_packet_unframe(frame, len, &ours, 1u, &got, &got_len) == DR_PACKET_FOREIGN);
    dr_put_be32(frame + 4, ours.fingerprint);
    recrc(frame, len);
    CHECK(dr_packet_unframe(frame, len, &ours, 1u, &got, &got_len) == DR_PACKET_MALFORMED);
    /* Execution 0 is the program's fingerprint itself (the frames of builds before it). */
    CHECK(DR_PACKET_PROGRAM_WORD(fingerprint, 0u) == fingerprint);
}

int main(void)
{
    test_reference_vector();
    test_frames();
    test_executions();
    printf("auth tests (tag %u bytes): %u checks, %u failed\n", (unsigned)DR_CONF_PACKET_TAG,
           checks, failures);
    return failures == 0u ? 0 : 1;
}
