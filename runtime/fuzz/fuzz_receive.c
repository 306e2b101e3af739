/* fuzz_receive.c - the libFuzzer entry point: an input is a script (README.md) that drives
 * one module of the generated program through dr_module_receive, interleaved with steps,
 * operation outcomes and resets. Each input starts from a fresh module. */
#include <string.h>
#include "fuzz.h"

static dr_module_t module;
static fuzz_node_t node;

unsigned long fuzz_frames_delivered;
unsigned long fuzz_frames_decoded;

/* A packet from the script: raw or with its CRC made right, so that mutations of a frame's
 * contents reach the decoders behind the checksum. */
static size_t deliver(const uint8_t *data, size_t size, size_t at, uint8_t sealed)
{
    uint8_t frame[256];
    uint8_t channel;
    uint8_t len;
    uint32_t refused;
    if (at + 2u > size) {
        return size;
    }
    channel = data[at];
    len = data[at + 1u];
    at += 2u;
    if ((size_t)len > size - at) {
        len = (uint8_t)(size - at);
    }
    memcpy(frame, data + at, len);
    at += len;
    if (sealed) {
        len = fuzz_seal(frame, len, (uint8_t)(sizeof frame - 1u));
    }
    fuzz_packet_check(frame, len);
    refused = module.packets_malformed + module.packets_foreign;
    dr_module_receive(&module, channel, frame, len);
    fuzz_frames_delivered++;
    if (module.packets_malformed + module.packets_foreign == refused) {
        fuzz_frames_decoded++;
    }
    return at;
}

/* The clock moves on by `ms` (x4) and the module steps once; the record's upper bits say how
 * its operation stands. */
static void step(uint8_t tag, uint8_t ms)
{
    static const uint8_t status[4] = {
        (uint8_t)DR_OP_DONE, (uint8_t)DR_OP_RUNNING, (uint8_t)DR_OP_FAILED, (uint8_t)DR_OP_DONE
    };
    node.now_ms += (uint32_t)ms * 4u;
    node.op_status = status[(tag >> 2) & 3u];
    dr_module_step(&module);
}

/* The module's description must fit and be terminated, whatever state the input left. */
static void describe(void)
{
    char text[200];
    uint8_t n = dr_module_describe(&module, text, (uint8_t)sizeof text);
    if (n >= sizeof text || text[n] != '\0') {
        fuzz_fail("dr_module_describe wrote past its capacity or left no terminator");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t at = 2u;
    unsigned records = 0u;
    if (size > FUZZ_MAX_INPUT) {
        size = FUZZ_MAX_INPUT;
    }
    fuzz_packet_check(data, size);
    if (size < 2u) {
        return 0;
    }
    fuzz_node_reset(&node, data[0]);
    node.connected = data[1];
    dr_program_init(&module, &node);
    while (at < size && records < FUZZ_MAX_RECORDS) {
        uint8_t tag = data[at++];
        records++;
        switch (tag & 3u) {
        case FUZZ_RECORD_RAW:
        case FUZZ_RECORD_SEALED:
            at = deliver(data, size, at, (uint8_t)((tag & 3u) == FUZZ_RECORD_SEALED));
            break;
        case FUZZ_RECORD_STEP:
            step(tag, at < size ? data[at] : 0u);
            at++;
            break;
        default:
            dr_program_init(&module, &node);
            break;
        }
    }
    step(0u, 255u);
    (void)dr_module_finished(&module);
    describe();
    return 0;
}
