/* capture.c - writes the receive corpus of one protocol: runs the modules of a compiled
 * program (ids 0 to N-1) over a perfect network where everyone hears everyone, and saves a
 * few of the frames they send (the 1st, 2nd, 4th, 8th, ...), each wrapped as a fuzz input
 * (README.md) for the module with id TO.
 *   capture N TO PREFIX
 * writes PREFIX-raw-K (the frame as sent), PREFIX-sealed-K (the frame without its CRC, in a
 * record that recomputes it, so mutations reach the decoder) and PREFIX-trailing-zero (the
 * first frame followed by a zero byte). Exit 0, or 2 on bad usage or a write error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "fuzz.h"

#define MAX_MODULES 16u
#define MAX_QUEUE 256u
#define SAVED_FRAMES 6u
#define TICK_MS 10u
#define RUN_MS 60000u

typedef struct {
    uint8_t from;
    uint8_t len;
    uint8_t bytes[DR_CONF_MAX_PACKET];
} packet_t;

static dr_module_t modules[MAX_MODULES];
static fuzz_node_t nodes[MAX_MODULES];
static packet_t queue[MAX_QUEUE];
static unsigned n_queue;
static unsigned n_sent;
static unsigned n_saved;
static uint16_t to_id;
static const char *prefix;
static int failed;

/* Writes one fuzz input: header, a step, the record, another step. */
static void save(const char *name, uint8_t record, uint8_t channel, const uint8_t *bytes,
                 uint8_t len)
{
    char path[512];
    uint8_t script[8 + 256];
    size_t n = 0;
    FILE *f;
    script[n++] = (uint8_t)to_id;
    script[n++] = 0xFFu;
    script[n++] = FUZZ_RECORD_STEP;
    script[n++] = 0u;
    script[n++] = record;
    script[n++] = channel;
    script[n++] = len;
    memcpy(script + n, bytes, len);
    n += len;
    script[n++] = FUZZ_RECORD_STEP;
    script[n++] = 30u;
    snprintf(path, sizeof path, "%s-%s", prefix, name);
    f = fopen(path, "wb");
    if (f == NULL || fwrite(script, 1, n, f) != n) {
        fprintf(stderr, "capture: %s: cannot write\n", path);
        failed = 1;
    }
    if (f != NULL) {
        fclose(f);
    }
}

/* Keeps the 1st, 2nd, 4th, 8th... frame sent (frames from further into the run). */
static void on_send(fuzz_node_t *node, const uint8_t *bytes, uint8_t len)
{
    char name[32];
    uint8_t channel = (uint8_t)((node - nodes) % DR_CONF_CHANNELS);
    uint8_t padded[DR_CONF_MAX_PACKET + 1u];
    n_sent++;
    if (n_queue < MAX_QUEUE) {
        queue[n_queue].from = (uint8_t)(node - nodes);
        queue[n_queue].len = len;
        memcpy(queue[n_queue].bytes, bytes, len);
        n_queue++;
    }
    if (n_saved >= SAVED_FRAMES || (n_sent & (n_sent - 1u)) != 0u || len < 2u) {
        return;
    }
    snprintf(name, sizeof name, "raw-%u", n_saved);
    save(name, FUZZ_RECORD_RAW, channel, bytes, len);
    snprintf(name, sizeof name, "sealed-%u", n_saved);
    save(name, FUZZ_RECORD_SEALED, channel, bytes, (uint8_t)(len - 2u));
    if (n_saved == 0u) {
        memcpy(padded, bytes, len);
        padded[len] = 0u;
        save("trailing-zero", FUZZ_RECORD_RAW, channel, padded, (uint8_t)(len + 1u));
    }
    n_saved++;
}

/* Delivers the queued frames to every other module. */
static void deliver(unsigned n_modules)
{
    unsigned q;
    unsigned i;
    unsigned pending = n_queue;
    for (q = 0; q < pending; q++) {
        for (i = 0; i < n_modules; i++) {
            if (i != queue[q].from) {
                dr_module_receive(&modules[i], (uint8_t)(queue[q].from % DR_CONF_CHANNELS),
                                  queue[q].bytes, queue[q].len);
            }
        }
    }
    memmove(queue, queue + pending, (n_queue - pending) * sizeof queue[0]);
    n_queue -= pending;
}

int main(int argc, char **argv)
{
    unsigned long n_modules;
    unsigned i;
    uint32_t t;
    if (argc != 4 || (n_modules = strtoul(argv[1], NULL, 10)) == 0ul ||
        n_modules > MAX_MODULES) {
        fprintf(stderr, "usage: capture N TO PREFIX (1 <= N <= %u)\n", MAX_MODULES);
        return 2;
    }
    to_id = (uint16_t)strtoul(argv[2], NULL, 10);
    prefix = argv[3];
    for (i = 0; i < n_modules; i++) {
        fuzz_node_reset(&nodes[i], (uint16_t)i);
        nodes[i].connected = 0xFFu;
        nodes[i].on_send = on_send;
        dr_program_init(&modules[i], &nodes[i]);
    }
    for (t = 0; t < RUN_MS && n_saved < SAVED_FRAMES; t += TICK_MS) {
        for (i = 0; i < n_modules; i++) {
            nodes[i].now_ms = t;
            dr_module_step(&modules[i]);
        }
        deliver((unsigned)n_modules);
    }
    printf("capture: %u frames sent, %u saved as %s-*\n", n_sent, n_saved, prefix);
    return failed ? 2 : 0;
}
