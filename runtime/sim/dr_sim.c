/* dr_sim.c - the simulator's platform: every function of dr_hal.h forwards to a callback of
 * the host simulator (registered once with dr_sim_register), and protocol-agnostic entry
 * points let the host run any compiled program on many module contexts in one process
 * (init, step, receive, finished, address, describe: the protocol state as text, and
 * next_wakeup: when the module next needs a step, for the tickless stepping).
 *
 * Built by dynarole-sim together with a `dynarole compile` output directory into a shared
 * library:  cc -std=c99 -O2 -shared -fPIC -I OUT OUT/dr_packet.c OUT/dr_<protocol>.c
 *           OUT/dr_program.c dr_sim.c -o libdrsim.so
 * The context of a module is a zeroed buffer of dr_sim_module_size() bytes owned by the host;
 * `platform` is an opaque value (the simulator passes the module's index). */
#include <stddef.h>
#include <stdint.h>
#include "dr_program.h"

/* What the host provides; `platform` is the value given to dr_sim_init for this module. */
struct dr_sim_callbacks {
    uint32_t (*now_ms)(void *platform);
    uint16_t (*random)(void *platform);
    void (*broadcast)(void *platform, const uint8_t *bytes, uint8_t len);
    void (*op_start)(void *platform, uint8_t address, uint16_t statement, uint8_t op,
                     uint8_t index, const int16_t *args, uint8_t n_args);
    uint8_t (*op_status)(void *platform);
    uint16_t (*id)(void *platform);
    uint8_t (*connected)(void *platform, uint8_t connector);
    int16_t (*neighbour_id)(void *platform, uint8_t connector);
    int16_t (*joint)(void *platform, uint8_t joint);
    void (*leds)(void *platform, uint8_t value);
    void (*nv_read)(void *platform, uint16_t addr, uint8_t *buf, uint8_t len);
    void (*nv_write)(void *platform, uint16_t addr, const uint8_t *buf, uint8_t len);
    void (*send)(void *platform, uint8_t channel, const uint8_t *bytes, uint8_t len);
};

void dr_sim_register(const struct dr_sim_callbacks *callbacks);
uint32_t dr_sim_module_size(void);
uint32_t dr_sim_max_args(void);
void dr_sim_init(void *m, void *platform);
void dr_sim_step(void *m);
void dr_sim_receive(void *m, uint8_t channel, const uint8_t *bytes, uint8_t len);
uint8_t dr_sim_finished(void *m);
uint8_t dr_sim_address(void *m);
uint8_t dr_sim_describe(void *m, char *out, uint8_t cap);
uint8_t dr_sim_next_wakeup(void *m, uint32_t *at_ms);
uint8_t dr_sim_restamp(const uint8_t *in, uint8_t len, uint16_t robot, uint32_t execution,
                       uint8_t *out, uint8_t cap);

static const struct dr_sim_callbacks *host;

static void *platform_of(struct dr_module *m)
{
    return m->platform;
}

void dr_sim_register(const struct dr_sim_callbacks *callbacks)
{
    host = callbacks;
}

uint32_t dr_sim_module_size(void)
{
    return (uint32_t)sizeof(dr_module_t);
}

uint32_t dr_sim_max_args(void)
{
    return (uint32_t)DR_CONF_MAX_ARGS;
}

void dr_sim_init(void *m, void *platform)
{
    dr_program_init((dr_module_t *)m, platform);
}

void dr_sim_step(void *m)
{
    dr_module_step((dr_module_t *)m);
}

void dr_sim_receive(void *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    dr_module_receive((dr_module_t *)m, channel, bytes, len);
}

uint8_t dr_sim_finished(void *m)
{
    return dr_module_finished((const dr_module_t *)m);
}

uint8_t dr_sim_address(void *m)
{
    return ((const dr_module_t *)m)->address;
}

/* `in`, a frame a module of this program broadcast in this build's execution, as robot
 * `robot` running the same program in execution `execution` sends it (the scenario's
 * `foreign` packets: another robot, or a recording of another launch of this one): same
 * program, same payload, that identity (and, in a keyed build, the shared key's tag, as the
 * key's holder made it). Returns the frame's length in `out`, 0 when `in` is not a whole
 * frame or does not fit. */
uint8_t dr_sim_restamp(const uint8_t *in, uint8_t len, uint16_t robot, uint32_t execution,
                       uint8_t *out, uint8_t cap)
{
    dr_identity_t other;
    uint32_t word;
    if (len < DR_PACKET_OVERHEAD || in[1] != len) {
        return 0;
    }
    word = ((uint32_t)in[4] << 24) | ((uint32_t)in[5] << 16) | ((uint32_t)in[6] << 8) |
           (uint32_t)in[7];
    other.robot = robot;
    /* The program's fingerprint (this build's execution taken out), with the other one in. */
    other.fingerprint =
        DR_PACKET_PROGRAM_WORD(DR_PACKET_PROGRAM_WORD(word, DR_EXECUTION), execution);
    return dr_packet_frame(out, cap, &other, in[8], in + DR_PACKET_HEADER,
                           (uint8_t)(len - DR_PACKET_OVERHEAD));
}

/* The protocol state of a module, as text (dr_module_describe of its runtime). */
uint8_t dr_sim_describe(void *m, char *out, uint8_t cap)
{
    return dr_module_describe((const dr_module_t *)m, out, cap);
}

/* dr_module_next_wakeup of the module's runtime (dr_module.h): DR_WAKE_* bits. */
uint8_t dr_sim_next_wakeup(void *m, uint32_t *at_ms)
{
    return dr_module_next_wakeup((dr_module_t *)m, at_ms);
}

uint32_t dr_hal_now_ms(struct dr_module *m)
{
    return host ? host->now_ms(platform_of(m)) : 0u;
}

uint16_t dr_hal_random(struct dr_module *m)
{
    return host ? host->random(platform_of(m)) : 0u;
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    if (host) {
        host->broadcast(platform_of(m), bytes, len);
    }
}

void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    if (host) {
        host->send(platform_of(m), channel, bytes, len);
    }
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    if (host) {
        host->op_start(platform_of(m), m->address, statement, op, index, args,
                       (uint8_t)DR_CONF_MAX_ARGS);
    }
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    uint8_t status = host ? host->op_status(platform_of(m)) : (uint8_t)DR_OP_FAILED;
    if (status == (uint8_t)DR_OP_DONE) {
        return DR_OP_DONE;
    }
    return status == (uint8_t)DR_OP_RUNNING ? DR_OP_RUNNING : DR_OP_FAILED;
}

uint16_t dr_hal_id(struct dr_module *m)
{
    return host ? host->id(platform_of(m)) : 0u;
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    return host ? host->connected(platform_of(m), connector) : 0u;
}

int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector)
{
    return host ? host->neighbour_id(platform_of(m), connector) : (int16_t)-1;
}

int16_t dr_hal_joint(struct dr_module *m, uint8_t joint)
{
    return host ? host->joint(platform_of(m), joint) : (int16_t)0;
}

void dr_hal_leds(struct dr_module *m, uint8_t value)
{
    if (host) {
        host->leds(platform_of(m), value);
    }
}

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    uint8_t i;
    if (host) {
        host->nv_read(platform_of(m), addr, buf, len);
        return;
    }
    for (i = 0; i < len; i++) {
        buf[i] = 0xFFu;
    }
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    if (host) {
        host->nv_write(platform_of(m), addr, buf, len);
    }
}
