/* fuzz_hal.c - the fuzz drivers' platform: every HAL call answered from the module's
 * fuzz_node_t (its `platform`), deterministic, with checks on what the runtime sends. */
#include <string.h>
#include "fuzz.h"

static fuzz_node_t *node_of(struct dr_module *m)
{
    return (fuzz_node_t *)m->platform;
}

void fuzz_node_reset(fuzz_node_t *node, uint16_t id)
{
    memset(node, 0, sizeof *node);
    node->id = id;
    node->rng = (uint16_t)(0xACE1u ^ id);
    node->op_status = (uint8_t)DR_OP_DONE;
    memset(node->nv, 0xFF, sizeof node->nv);
}

uint8_t fuzz_seal(uint8_t *bytes, uint8_t len, uint8_t cap)
{
    uint16_t crc;
    if ((unsigned)len + 2u > cap) {
        return len;
    }
    /* The header as a module of this robot and program writes it (the corpus was captured
     * from an older build: its fingerprint may differ; the program word of this build's
     * execution), then the CRC. */
    if (len >= 2u) {
        bytes[1] = (uint8_t)(len + 2u);
    }
    if (len >= DR_PACKET_HEADER) {
        bytes[2] = (uint8_t)(DR_ROBOT_ID >> 8);
        bytes[3] = (uint8_t)(DR_ROBOT_ID & 0xFFu);
        dr_put_be32(bytes + 4, DR_PACKET_PROGRAM_WORD(dr_program.fingerprint, DR_EXECUTION));
    }
    crc = dr_crc16(bytes, len);
    bytes[len] = (uint8_t)(crc >> 8);
    bytes[len + 1u] = (uint8_t)(crc & 0xFFu);
    return (uint8_t)(len + 2u);
}

uint32_t dr_hal_now_ms(struct dr_module *m)
{
    return node_of(m)->now_ms;
}

uint16_t dr_hal_random(struct dr_module *m)
{
    fuzz_node_t *n = node_of(m);
    n->rng = (uint16_t)(n->rng ^ (uint16_t)(n->rng << 7));
    n->rng = (uint16_t)(n->rng ^ (uint16_t)(n->rng >> 9));
    n->rng = (uint16_t)(n->rng ^ (uint16_t)(n->rng << 8));
    return n->rng;
}

/* Every frame a module sends must fit the packet buffers and pass its own checks. */
static void sent(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    fuzz_node_t *n = node_of(m);
    if (len == 0u || len > DR_CONF_MAX_PACKET) {
        fuzz_fail("a module sent a frame of length 0 or above DR_CONF_MAX_PACKET");
    }
    fuzz_packet_check(bytes, len);
    n->sent++;
    if (n->on_send != NULL) {
        n->on_send(n, bytes, len);
    }
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    sent(m, bytes, len);
}

void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    if (channel >= DR_CONF_CHANNELS) {
        fuzz_fail("a module sent on a channel it does not have");
    }
    sent(m, bytes, len);
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    (void)op;
    (void)index;
    (void)statement;
    if (args == NULL) {
        fuzz_fail("an operation started without arguments");
    }
    (void)m;
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    return (enum dr_op_status)node_of(m)->op_status;
}

uint16_t dr_hal_id(struct dr_module *m)
{
    return node_of(m)->id;
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    if (connector >= 8u) {
        return 0u;
    }
    return (uint8_t)(((unsigned)node_of(m)->connected >> connector) & 1u);
}

int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector)
{
    if (!dr_hal_connected(m, connector)) {
        return -1;
    }
    return (int16_t)((node_of(m)->id + connector + 1u) & 0x7Fu);
}

int16_t dr_hal_joint(struct dr_module *m, uint8_t joint)
{
    (void)m;
    return (int16_t)(joint * 108);
}

void dr_hal_leds(struct dr_module *m, uint8_t value)
{
    (void)m;
    (void)value;
}

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    if ((uint32_t)addr + len > FUZZ_NV_BYTES) {
        fuzz_fail("an NV read beyond the store");
    }
    memcpy(buf, node_of(m)->nv + addr, len);
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    if ((uint32_t)addr + len > FUZZ_NV_BYTES) {
        fuzz_fail("an NV write beyond the store");
    }
    memcpy(node_of(m)->nv + addr, buf, len);
}
