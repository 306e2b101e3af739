/* dr_packet.h - framing shared by every protocol: a magic/version byte, the program id, a
 * kind byte, the payload and a CRC-16, so that malformed or foreign packets are recognised
 * and dropped, never trusted.
 *
 * Frame: [DR_PACKET_MAGIC] [program id] [kind] [payload ...] [crc hi] [crc lo]
 * The CRC (CCITT, polynomial 0x1021, initial 0xFFFF) covers every byte before it. */
#ifndef DR_PACKET_H
#define DR_PACKET_H

#include <stdint.h>

/* High nibble: 0xD ("dynarole"); low nibble: format version. */
#define DR_PACKET_MAGIC 0xD1u
#define DR_PACKET_OVERHEAD 5u

/* Packet kinds. */
#define DR_PACKET_LATTICE_STATE 1u
#define DR_PACKET_PAPER_STATE 2u
#define DR_PACKET_TOKEN 3u

enum dr_packet_result {
    DR_PACKET_OK = 0,
    DR_PACKET_MALFORMED = 1, /* wrong length, magic or checksum */
    DR_PACKET_FOREIGN = 2    /* well formed, but another program or kind */
};

/* CRC-16/CCITT-FALSE of `len` bytes. Cost: O(len). */
uint16_t dr_crc16(const uint8_t *bytes, uint8_t len);

/* Writes a frame around `payload` into `out` (capacity `cap`); returns the frame length, or
 * 0 when it does not fit. */
uint8_t dr_packet_frame(uint8_t *out, uint8_t cap, uint8_t program_id, uint8_t kind,
                        const uint8_t *payload, uint8_t payload_len);

/* Checks a received frame. On DR_PACKET_OK, *payload points into `in` and *payload_len is set.
 * Precondition: in != 0 when len > 0. */
enum dr_packet_result dr_packet_unframe(const uint8_t *in, uint8_t len, uint8_t program_id,
                                        uint8_t kind, const uint8_t **payload,
                                        uint8_t *payload_len);

#endif /* DR_PACKET_H */
