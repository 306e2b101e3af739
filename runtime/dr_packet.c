/* dr_packet.c - frame and check packets (magic, program id, kind, CRC-16). */
#include "dr_packet.h"

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

uint8_t dr_packet_frame(uint8_t *out, uint8_t cap, uint8_t program_id, uint8_t kind,
                        const uint8_t *payload, uint8_t payload_len)
{
    uint16_t total = (uint16_t)(payload_len + DR_PACKET_OVERHEAD);
    uint16_t crc;
    uint8_t i;
    if (total > cap) {
        return 0;
    }
    out[0] = DR_PACKET_MAGIC;
    out[1] = program_id;
    out[2] = kind;
    for (i = 0; i < payload_len; i++) {
        out[3 + i] = payload[i];
    }
    crc = dr_crc16(out, (uint8_t)(total - 2u));
    out[total - 2u] = (uint8_t)(crc >> 8);
    out[total - 1u] = (uint8_t)(crc & 0xFFu);
    return (uint8_t)total;
}

enum dr_packet_result dr_packet_unframe(const uint8_t *in, uint8_t len, uint8_t program_id,
                                        uint8_t kind, const uint8_t **payload,
                                        uint8_t *payload_len)
{
    uint16_t crc;
    if (len < DR_PACKET_OVERHEAD || in[0] != DR_PACKET_MAGIC) {
        return DR_PACKET_MALFORMED;
    }
    crc = dr_crc16(in, (uint8_t)(len - 2u));
    if (in[len - 2u] != (uint8_t)(crc >> 8) || in[len - 1u] != (uint8_t)(crc & 0xFFu)) {
        return DR_PACKET_MALFORMED;
    }
    if (in[1] != program_id || in[2] != kind) {
        return DR_PACKET_FOREIGN;
    }
    *payload = in + 3;
    *payload_len = (uint8_t)(len - DR_PACKET_OVERHEAD);
    return DR_PACKET_OK;
}
