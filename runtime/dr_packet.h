/* dr_packet.h - framing shared by every protocol: a magic/version byte, the frame's length,
 * the robot it belongs to, the program it was sent by, a kind byte, the payload, an optional
 * keyed authentication tag and a CRC-16, so that malformed packets, packets of another robot
 * (a second robot in infrared range) and packets of another program are recognised and
 * dropped, never trusted.
 *
 * Frame: [DR_PACKET_MAGIC] [length] [robot hi] [robot lo] [program word, 4 bytes, big endian]
 *        [kind] [payload ...] [tag, DR_CONF_PACKET_TAG bytes] [crc hi] [crc lo]
 * `length` is the whole frame's length, so a frame with bytes appended or cut is malformed.
 * The program word is the program's fingerprint XOR the execution (DR_PACKET_PROGRAM_WORD):
 * a frame of another program or of another launch of this one is foreign.
 * The tag (SipHash-2-4 under the 128-bit key dr_packet_key, truncated) covers every byte
 * before it, the execution's included; the CRC (CCITT, polynomial 0x1021, initial 0xFFFF)
 * covers every byte before it. The CRC catches noise; only the tag resists a sender that
 * means harm, and with the execution it refuses a recorded packet of another launch (a
 * replay within one launch adds nothing to the lattice's monotone state: docs/runtime.md). */
#ifndef DR_PACKET_H
#define DR_PACKET_H

#include <stdint.h>

#include "dr_conf.h"

/* High nibble: 0xD ("dynarole"); low nibble: format version. */
#define DR_PACKET_MAGIC 0xD2u
/* Bytes before the payload. */
#define DR_PACKET_HEADER 9u
/* Bytes of the CRC-16 that ends a frame. */
#define DR_PACKET_CRC 2u
#define DR_PACKET_OVERHEAD (DR_PACKET_HEADER + DR_CONF_PACKET_TAG + DR_PACKET_CRC)

/* Packet kinds. */
#define DR_PACKET_LATTICE_STATE 1u
#define DR_PACKET_PAPER_STATE 2u
#define DR_PACKET_TOKEN 3u
#define DR_PACKET_LATTICE_ASK 4u /* a lattice state that asks for the receiver's copy */

/* The 32-bit word a frame carries after the robot and the lattice NV record starts with:
 * the program's fingerprint (generated: a hash of the compiled sequence and the runtime)
 * XOR the execution (DR_EXECUTION, dr_conf.h). Two launches of one program differ in every
 * bit their executions differ in, so neither takes the other's frames or NV record; a
 * constant folded by the compiler where the fingerprint is one (an MCU image), so it costs
 * no code. Folded rather than carried beside the fingerprint: no byte more on the air, and a
 * frame of another (program, execution) pair passes only if the two words are equal, with
 * the same 2^-32 odds as two fingerprints before (docs/runtime.md). */
#define DR_PACKET_PROGRAM_WORD(fingerprint, execution)                                     \
    ((uint32_t)((uint32_t)(fingerprint) ^ (uint32_t)(execution)))

/* Who a packet belongs to: the robot (or swarm) identity, set at compile time (`dynarole
 * compile --robot-id`) or at flash time (-DDR_ROBOT_ID=N), and the program word (above) of
 * the program and this launch's execution. */
typedef struct {
    uint16_t robot;
    uint32_t fingerprint; /* DR_PACKET_PROGRAM_WORD(program fingerprint, DR_EXECUTION) */
} dr_identity_t;

enum dr_packet_result {
    DR_PACKET_OK = 0,
    DR_PACKET_MALFORMED = 1, /* wrong length, magic, checksum or authentication tag */
    DR_PACKET_FOREIGN = 2    /* well formed, but another robot, program, execution or kind */
};

#if DR_CONF_PACKET_TAG > 0
/* The shared key of a keyed build (generated into dr_program.c by `dynarole compile --key`). */
extern const uint8_t dr_packet_key[16];
/* SipHash-2-4 of `len` bytes under `key` (the tag is its first DR_CONF_PACKET_TAG bytes,
 * least significant first). Cost: O(len), about 2 rounds per 8 bytes. */
uint64_t dr_siphash24(const uint8_t key[16], const uint8_t *in, uint8_t len);
#endif

/* CRC-16/CCITT-FALSE of `len` bytes. Cost: O(len). Bytes followed by their own CRC (big
 * endian, as dr_crc16_put writes it) have a CRC of 0, and only then: a check is one call. */
uint16_t dr_crc16(const uint8_t *bytes, uint8_t len);
/* Writes the CRC of the first `len` bytes at bytes[len] and bytes[len + 1] (big endian). The
 * frames' and the lattice NV record's checksum: one piece of code for both. */
void dr_crc16_put(uint8_t *bytes, uint8_t len);
/* Writes `value` at out[0..3], big endian (the program word in frames and NV records). */
void dr_put_be32(uint8_t *out, uint32_t value);

/* Writes a frame around `payload` into `out` (capacity `cap`); returns the frame length, or
 * 0 when it does not fit. `payload` may point into `out` at DR_PACKET_HEADER (encoded in
 * place). Cost: O(length), plus the tag's O(length) when keyed. */
uint8_t dr_packet_frame(uint8_t *out, uint8_t cap, const dr_identity_t *from, uint8_t kind,
                        const uint8_t *payload, uint8_t payload_len);

/* Checks a received frame against this module's identity. On DR_PACKET_OK, *payload points
 * into `in` and *payload_len is set. Precondition: in != 0 when len > 0. Cost: as framing. */
enum dr_packet_result dr_packet_unframe(const uint8_t *in, uint8_t len, const dr_identity_t *self,
                                        uint8_t kind, const uint8_t **payload,
                                        uint8_t *payload_len);

#endif /* DR_PACKET_H */
