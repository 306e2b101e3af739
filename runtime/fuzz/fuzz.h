/* fuzz.h - the fuzz drivers' shared pieces: a fake platform (one node per module), the
 * libFuzzer entry point and the input format (see README.md). Built once per protocol, with
 * that protocol's runtime and a generated program (dr_program.h). */
#ifndef FUZZ_H
#define FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include "dr_packet.h"
#include "dr_program.h"

/* Largest input the drivers read or make (libFuzzer may pass more; the rest is ignored). */
#define FUZZ_MAX_INPUT 2048u
/* Bytes of non-volatile storage per node. */
#define FUZZ_NV_BYTES 512u
/* Records of one input that are run (bounds the work per input). */
#define FUZZ_MAX_RECORDS 256u
/* Record kinds: the low two bits of a record's first byte. */
#define FUZZ_RECORD_RAW 0u    /* [channel] [len] [len bytes]: delivered as they are */
#define FUZZ_RECORD_SEALED 1u /* [channel] [len] [len bytes]: a CRC-16 appended, then delivered */
#define FUZZ_RECORD_STEP 2u   /* [ms]: the clock moves on, then one step */
#define FUZZ_RECORD_RESET 3u  /* the module restarts (its NV store survives) */

/* What the platform knows of one module. */
typedef struct fuzz_node {
    uint16_t id;
    uint8_t connected;          /* bit c: connector c is latched */
    uint8_t op_status;          /* what dr_hal_op_status answers (enum dr_op_status) */
    uint16_t rng;
    uint32_t now_ms;
    uint32_t sent;
    uint8_t nv[FUZZ_NV_BYTES];
    /* Called with every frame the module sends (NULL: frames are only checked). */
    void (*on_send)(struct fuzz_node *node, const uint8_t *bytes, uint8_t len);
} fuzz_node_t;

/* Sets a node up: blank NV store, nothing connected, operations done at once. */
void fuzz_node_reset(fuzz_node_t *node, uint16_t id);

/* Appends the CRC-16 of bytes[0..len) after them (high byte first); returns the new length,
 * or `len` when there is no room within `cap`. */
uint8_t fuzz_seal(uint8_t *bytes, uint8_t len, uint8_t cap);

/* Framing laws on arbitrary bytes (fuzz_packet.c). Aborts when one is broken. */
void fuzz_packet_check(const uint8_t *data, size_t size);

/* Called by fuzz_fail before it aborts (the plain driver saves the input there). fuzz_fail.c
 * defines both: every other driver file may call them, and they call none of those files. */
extern void (*fuzz_failure_hook)(void);

/* A broken property: prints it and aborts (so libFuzzer and the sanitizers see a crash). */
void fuzz_fail(const char *what);

/* Frames the entry point delivered, and those the framing let through to the decoder. */
extern unsigned long fuzz_frames_delivered;
extern unsigned long fuzz_frames_decoded;

/* The libFuzzer entry point. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#endif /* FUZZ_H */
