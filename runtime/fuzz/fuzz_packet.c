/* fuzz_packet.c - laws of the framing (dr_packet.h) checked on arbitrary bytes: what
 * dr_packet_unframe accepts lies inside the input and frames back to the same bytes; what
 * dr_packet_frame writes unframes to the same payload; one changed byte is never accepted.
 * This is the only file of the drivers that knows the framing's signatures. */
#include <string.h>
#include "fuzz.h"

static const uint8_t kinds[4] = {
    DR_PACKET_LATTICE_STATE, DR_PACKET_LATTICE_ASK, DR_PACKET_PAPER_STATE, DR_PACKET_TOKEN
};

/* Received bytes, for each kind: accepted means a payload inside them that frames back to
 * exactly them. */
static void check_unframe(const uint8_t *in, uint8_t len)
{
    dr_identity_t self;
    unsigned k;
    self.robot = DR_ROBOT_ID;
    self.fingerprint = DR_PACKET_PROGRAM_WORD(dr_program.fingerprint, DR_EXECUTION);
    for (k = 0; k < sizeof kinds; k++) {
        const uint8_t *payload = NULL;
        uint8_t payload_len = 0;
        uint8_t again[256];
        if (dr_packet_unframe(in, len, &self, kinds[k], &payload, &payload_len) !=
            DR_PACKET_OK) {
            continue;
        }
        if (payload < in || payload + payload_len > in + len ||
            payload_len + DR_PACKET_OVERHEAD != len) {
            fuzz_fail("dr_packet_unframe accepted a payload outside the frame");
        }
        if (dr_packet_frame(again, (uint8_t)(sizeof again - 1u), &self, kinds[k],
                            payload, payload_len) != len ||
            memcmp(again, in, len) != 0) {
            fuzz_fail("an accepted frame does not frame back to the same bytes");
        }
    }
}

/* data[0] picks an identity (robot and fingerprint), data[1] is a kind, the rest (up to a
 * packet) the payload. */
static void check_frame(const uint8_t *data, uint8_t len)
{
    dr_identity_t id;
    uint8_t frame[DR_CONF_MAX_PACKET];
    const uint8_t *payload = NULL;
    uint8_t payload_len = 0;
    uint8_t n;
    uint8_t body = (uint8_t)(len - 2u);
    uint8_t at;
    id.robot = data[0];
    id.fingerprint = dr_program.fingerprint ^ ((uint32_t)data[0] << 24);
    if (body > DR_CONF_MAX_PACKET - DR_PACKET_OVERHEAD) {
        body = (uint8_t)(DR_CONF_MAX_PACKET - DR_PACKET_OVERHEAD);
    }
    n = dr_packet_frame(frame, (uint8_t)sizeof frame, &id, data[1], data + 2, body);
    if (n == 0u) {
        fuzz_fail("dr_packet_frame refused a payload that fits");
    }
    if (dr_packet_unframe(frame, n, &id, data[1], &payload, &payload_len) != DR_PACKET_OK ||
        payload_len != body || memcmp(payload, data + 2, body) != 0) {
        fuzz_fail("a frame does not unframe to its payload");
    }
    at = (uint8_t)(data[len - 1u] % n);
    frame[at] ^= (uint8_t)(data[0] | 1u);
    if (dr_packet_unframe(frame, n, &id, data[1], &payload, &payload_len) == DR_PACKET_OK) {
        fuzz_fail("a frame with one byte changed was accepted");
    }
}

void fuzz_packet_check(const uint8_t *data, size_t size)
{
    uint8_t len = (uint8_t)(size > 255u ? 255u : size);
    if (len == 0u) {
        return;
    }
    check_unframe(data, len);
    if (len >= 2u) {
        check_frame(data, len);
    }
}
