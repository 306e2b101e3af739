/* dr_packet.c - frame and check packets (magic, length, robot, program word: fingerprint
 * and execution, kind, optional keyed tag, CRC-16). */
#include "dr_packet.h"

typedef char dr_packet_tag_is_0_4_or_8[(DR_CONF_PACKET_TAG == 0 || DR_CONF_PACKET_TAG == 4 ||
                                        DR_CONF_PACKET_TAG == 8) ? 1 : -1];
/* An execution wider than 32 bits would be cut silently by the program word's cast. */
typedef char dr_packet_execution_fits_32_bits[(DR_EXECUTION) <= 0xFFFFFFFFULL ? 1 : -1];

uint16_t dr_crc16(const uint8_t *bytes, uint8_t len)
{
    uint16_t crc = 0xFFFFu;
    uint8_t i;
    uint8_t bit;
    for (i = 0; i < len; i++) {
        crc ^= (uint16_t)((uint16_t)bytes[i] << 8);
        for (bit = 0; bit < 8u; bit++) {
            if (crc & 0x8000u) {
                crc = (uint16_t)((uint16_t)(crc << 1) ^ 0x1021u);
            } else {
                crc = (uint16_t)(crc << 1);
            }
        }
    }
    return crc;
}

#if DR_CONF_PACKET_TAG > 0
/* SipHash-2-4 (Aumasson and Bernstein, 2012), a keyed hash made for short messages: 64-bit
 * words, two rounds per 8-byte block, four to finish. Cost: O(len). */
#define ROTL(x, b) (uint64_t)(((x) << (b)) | ((x) >> (64 - (b))))

static void sip_round(uint64_t v[4])
{
    v[0] += v[1];
    v[1] = ROTL(v[1], 13);
    v[1] ^= v[0];
    v[0] = ROTL(v[0], 32);
    v[2] += v[3];
    v[3] = ROTL(v[3], 16);
    v[3] ^= v[2];
    v[0] += v[3];
    v[3] = ROTL(v[3], 21);
    v[3] ^= v[0];
    v[2] += v[1];
    v[1] = ROTL(v[1], 17);
    v[1] ^= v[2];
    v[2] = ROTL(v[2], 32);
}

static uint64_t load_le64(const uint8_t *p, uint8_t n)
{
    uint64_t w = 0;
    uint8_t i;
    for (i = 0; i < n; i++) {
        w |= (uint64_t)p[i] << (8u * i);
    }
    return w;
}

static void sip_block(uint64_t v[4], uint64_t m, uint8_t rounds)
{
    uint8_t r;
    v[3] ^= m;
    for (r = 0; r < rounds; r++) {
        sip_round(v);
    }
    v[0] ^= m;
}

uint64_t dr_siphash24(const uint8_t key[16], const uint8_t *in, uint8_t len)
{
    uint64_t k0 = load_le64(key, 8u);
    uint64_t k1 = load_le64(key + 8, 8u);
    uint64_t v[4];
    uint8_t at = 0;
    uint8_t r;
    v[0] = k0 ^ 0x736f6d6570736575ULL;
    v[1] = k1 ^ 0x646f72616e646f6dULL;
    v[2] = k0 ^ 0x6c7967656e657261ULL;
    v[3] = k1 ^ 0x7465646279746573ULL;
    while ((uint8_t)(len - at) >= 8u) {
        sip_block(v, load_le64(in + at, 8u), 2u);
        at = (uint8_t)(at + 8u);
    }
    sip_block(v, load_le64(in + at, (uint8_t)(len - at)) | ((uint64_t)len << 56), 2u);
    v[2] ^= 0xFFu;
    for (r = 0; r < 4u; r++) {
        sip_round(v);
    }
    return v[0] ^ v[1] ^ v[2] ^ v[3];
}

/* Writes the tag of the first `len` bytes of `frame` at frame + len. */
static void put_tag(uint8_t *frame, uint8_t len)
{
    uint64_t tag = dr_siphash24(dr_packet_key, frame, len);
    uint8_t i;
    for (i = 0; i < DR_CONF_PACKET_TAG; i++) {
        frame[len + i] = (uint8_t)(tag >> (8u * i));
    }
}

static uint8_t tag_ok(const uint8_t *frame, uint8_t len)
{
    uint64_t tag = dr_siphash24(dr_packet_key, frame, len);
    uint8_t diff = 0;
    uint8_t i;
    for (i = 0; i < DR_CONF_PACKET_TAG; i++) { /* no early exit: time does not leak where */
        diff = (uint8_t)(diff | (frame[len + i] ^ (uint8_t)(tag >> (8u * i))));
    }
    return (uint8_t)(diff == 0u);
}
#endif

void dr_put_be32(uint8_t *out, uint32_t value)
{
    /* Constant shifts: byte moves on an 8-bit core (a loop over a variable shift is not). */
    out[0] = (uint8_t)(value >> 24);
    out[1] = (uint8_t)(value >> 16);
    out[2] = (uint8_t)(value >> 8);
    out[3] = (uint8_t)value;
}

void dr_crc16_put(uint8_t *bytes, uint8_t len)
{
    uint16_t crc = dr_crc16(bytes, len);
    bytes[len] = (uint8_t)(crc >> 8);
    bytes[len + 1u] = (uint8_t)crc;
}

/* The identity's bytes of a frame (robot, program word: big endian) at out[0..5]. */
static void put_identity(uint8_t *out, const dr_identity_t *id)
{
    out[0] = (uint8_t)(id->robot >> 8);
    out[1] = (uint8_t)id->robot;
    dr_put_be32(out + 2, id->fingerprint);
}

uint8_t dr_packet_frame(uint8_t *out, uint8_t cap, const dr_identity_t *from, uint8_t kind,
                        const uint8_t *payload, uint8_t payload_len)
{
    uint16_t total = (uint16_t)(payload_len + DR_PACKET_OVERHEAD);
    uint8_t i;
    if (total > cap) {
        return 0;
    }
    for (i = 0; i < payload_len; i++) { /* first: payload may already sit at its place */
        out[DR_PACKET_HEADER + i] = payload[i];
    }
    out[0] = DR_PACKET_MAGIC;
    out[1] = (uint8_t)total;
    put_identity(out + 2, from);
    out[8] = kind;
#if DR_CONF_PACKET_TAG > 0
    put_tag(out, (uint8_t)(DR_PACKET_HEADER + payload_len));
#endif
    dr_crc16_put(out, (uint8_t)(total - 2u));
    return (uint8_t)total;
}

enum dr_packet_result dr_packet_unframe(const uint8_t *in, uint8_t len, const dr_identity_t *self,
                                        uint8_t kind, const uint8_t **payload,
                                        uint8_t *payload_len)
{
    uint8_t diff;
    /* The CRC over the frame with its own CRC appended is 0 exactly when the CRC matches. */
    if (len < DR_PACKET_OVERHEAD || in[0] != DR_PACKET_MAGIC || in[1] != len ||
        dr_crc16(in, len) != 0u) {
        return DR_PACKET_MALFORMED;
    }
#if DR_CONF_PACKET_TAG > 0
    if (!tag_ok(in, (uint8_t)(len - 2u - DR_CONF_PACKET_TAG))) {
        return DR_PACKET_MALFORMED;
    }
#endif
    /* The identity's bytes (as put_identity writes them) and the kind, each compared where
     * it is: constant shifts, no copy of the identity. */
    diff = (uint8_t)((in[2] ^ (uint8_t)(self->robot >> 8)) | (in[3] ^ (uint8_t)self->robot));
    diff = (uint8_t)(diff | (in[4] ^ (uint8_t)(self->fingerprint >> 24)) |
                     (in[5] ^ (uint8_t)(self->fingerprint >> 16)));
    diff = (uint8_t)(diff | (in[6] ^ (uint8_t)(self->fingerprint >> 8)) |
                     (in[7] ^ (uint8_t)self->fingerprint) | (in[8] ^ kind));
    if (diff != 0u) {
        return DR_PACKET_FOREIGN;
    }
    *payload = in + DR_PACKET_HEADER;
    *payload_len = (uint8_t)(len - DR_PACKET_OVERHEAD);
    return DR_PACKET_OK;
}
