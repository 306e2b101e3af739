/* dr_rofi.c - the platform of dr_hal.h on a RoFI universal module, over rofi_hal.h (a C
 * interface in the shape of RoFI's own HAL). README.md gives the semantics in full.
 *
 * - Joints: rotateFromToBy(from, to, increasing, speed) sends joint `index` (0 alpha, 1 beta,
 *   2 gamma) to `to` degrees at speed % of its top speed. No RoFI joint turns round: each is
 *   an absolute-position servo between its limits (gamma's too, +-0.9 pi on RoFI), so a turn
 *   is refused when `to` is beyond the limits or lies the other way from where the joint is
 *   than `increasing` says (for gamma: the turn would cross its stop at about +-162 degrees).
 *   A turn ends when the HAL's callback says so or the joint reads within
 *   DR_ROFI_TOLERANCE_DEG of its target (RoFI's ESP32 HAL does not call setPosition's
 *   callback), and fails on a joint error or a timeout.
 * - Connectors: connect extends, disconnect retracts; each is done once the HAL's state says
 *   connected (either side may hold the latch), or retracted and not connected; it fails
 *   after DR_ROFI_CONNECTOR_TIMEOUT_MS.
 * - Operations are idempotent (already in effect: done at once) and run several at a time,
 *   one per part: dr_hal_op_status is DONE once all started since the set began have taken
 *   effect, FAILED once all have ended and one failed; a start when none runs begins a set.
 * - Packets: dynarole's content type on RoFI's connectors; broadcast is a send on every
 *   connected connector. Neighbour IDs come from dr_rofi_set_neighbour (RoFI has no query).
 * - NV: the HAL's storage partition; the clock, random numbers and ID are the HAL's.
 *
 * Built with the generated program: cc -DDR_ROFI_PROGRAM -I OUT -I robots/rofi/runtime
 * OUT/dr_packet.c OUT/dr_<protocol>.c OUT/dr_program.c dr_rofi.c (Makefile, check-program). */
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "dr_conf.h"
#include "dr_hal.h"
#include "dr_module.h"
#include "dr_rofi.h"
#include "dr_rofi_ops.h"

#if DR_CONF_CHANNELS < 6
#error "the runtime must track RoFI's six connectors (DR_CONF_CHANNELS >= 6)"
#endif

#define PI_F 3.14159265f
#define RAD_PER_DEG (PI_F / 180.0f)
#define TOLERANCE_RAD (DR_ROFI_TOLERANCE_DEG * RAD_PER_DEG)
/* Slack on the limits themselves: the HAL's limits are floats (99 degrees on a shoe joint,
 * 1.1 pi / 2, is not exactly representable either side). */
#define LIMIT_SLACK_RAD 1e-4f

/* The initialised modules (one on a real module). */
static struct dr_rofi *modules;

static struct dr_rofi *rofi_of(struct dr_module *m)
{
    struct dr_rofi *r = modules;
    while (r != 0 && r->module != m) {
        r = r->next;
    }
    return r; /* dr_rofi_init must have run for m (dr_rofi.h) */
}

/* Takes record r, and any other record of module m, off the list (dr_rofi_init again). */
static void unlist(const struct dr_rofi *r, const struct dr_module *m)
{
    struct dr_rofi **at = &modules;
    while (*at != 0) {
        if (*at == r || (*at)->module == m) {
            *at = (*at)->next;
        } else {
            at = &(*at)->next;
        }
    }
}

static float absf(float x)
{
    return x < 0.0f ? -x : x;
}

/* Whether clock reading a is at or after b (the clock wraps). */
static uint8_t reached(uint32_t a, uint32_t b)
{
    return (uint8_t)((int32_t)(a - b) >= 0);
}

static uint32_t now(const struct dr_rofi *r)
{
    return r->hal->now_ms(r->hal->ctx);
}

static struct rofi_connector_state connector_state(const struct dr_rofi *r, uint8_t c)
{
    struct rofi_connector_state s;
    memset(&s, 0, sizeof s);
    r->hal->connector_get_state(r->hal->ctx, (int)c, &s);
    return s;
}

/* ---- the set of operations ---- */

static uint8_t any_running(const struct dr_rofi *r)
{
    uint8_t i;
    for (i = 0; i < DR_ROFI_JOINTS; i++) {
        if (r->joint[i].running) {
            return 1;
        }
    }
    for (i = 0; i < DR_ROFI_CONNECTORS; i++) {
        if (r->connector[i].running) {
            return 1;
        }
    }
    return 0;
}

static void end_op(struct dr_rofi *r, struct dr_rofi_op *op, uint8_t ok)
{
    op->running = 0;
    if (!ok) {
        r->failed = 1;
    }
}

/* ---- joints ---- */

/* Whether joint j can reach `target` from `pos` going the `increasing` way: within its limits,
 * and on that side of where it is (no RoFI joint turns round, gamma included). */
static uint8_t turn_possible(const struct dr_rofi *r, uint8_t j, float pos, float target,
                             uint8_t increasing)
{
    const struct rofi_joint_capabilities *caps = &r->caps[j];
    if (target > caps->max_position + LIMIT_SLACK_RAD ||
        target < caps->min_position - LIMIT_SLACK_RAD) {
        return 0;
    }
    return (uint8_t)(increasing ? target >= pos - TOLERANCE_RAD : target <= pos + TOLERANCE_RAD);
}

/* The HAL's setPosition callback. */
static void joint_reached(void *user, int joint)
{
    struct dr_rofi *r = user;
    if (joint >= 0 && joint < (int)DR_ROFI_JOINTS && r->joint[joint].running) {
        end_op(r, &r->joint[joint], 1);
    }
}

/* The HAL's onError callback: the turn under way fails (the servo will not get there). */
static void joint_error(void *user, int joint, enum rofi_joint_error error, const char *message)
{
    struct dr_rofi *r = user;
    (void)error;
    (void)message;
    if (joint >= 0 && joint < (int)DR_ROFI_JOINTS && r->joint[joint].running) {
        end_op(r, &r->joint[joint], 0);
    } else {
        r->joint_errors++;
    }
}

/* rotateFromToBy: args from, to (degrees), increasing (0/1), speed (% of the top speed).
 * `from` is not used: the turn starts where the joint is (a retry after a reset finds it part
 * of the way). */
static void rotate(struct dr_rofi *r, uint8_t j, const int16_t *args)
{
    struct dr_rofi_op *op = &r->joint[j];
    float pos;
    float target;
    float velocity;
    uint32_t expected_ms;
    if (args == 0 || args[3] < 1 || args[3] > 100) {
        r->failed = 1;
        return;
    }
    pos = r->hal->joint_get_position(r->hal->ctx, (int)j);
    target = (float)args[1] * RAD_PER_DEG;
    if (!turn_possible(r, j, pos, target, (uint8_t)(args[2] != 0))) {
        r->failed = 1;
        return;
    }
    if (absf(target - pos) <= TOLERANCE_RAD) {
        return; /* already there: done at once */
    }
    velocity = r->caps[j].max_speed * (float)args[3] / 100.0f;
    if (!(velocity > 0.0f)) {
        r->failed = 1; /* a HAL without a top speed: it cannot be asked to move */
        return;
    }
    expected_ms = (uint32_t)(absf(target - pos) * 1000.0f / velocity);
    op->running = 1;
    op->target = target;
    op->deadline_ms = now(r) + 2u * expected_ms + DR_ROFI_JOINT_SLACK_MS;
    r->hal->joint_set_position(r->hal->ctx, (int)j, target, velocity, joint_reached, r);
}

/* A running turn is done when the joint reads at its target (the HAL may never call back),
 * failed when its time is up. */
static void poll_joint(struct dr_rofi *r, uint8_t j, uint32_t t)
{
    struct dr_rofi_op *op = &r->joint[j];
    if (!op->running) {
        return;
    }
    if (absf(r->hal->joint_get_position(r->hal->ctx, (int)j) - op->target) <= TOLERANCE_RAD) {
        end_op(r, op, 1);
    } else if (reached(t, op->deadline_ms)) {
        end_op(r, op, 0);
    }
}

/* ---- connectors ---- */

/* Whether connect (or disconnect) has taken effect on connector c. */
static uint8_t connector_in_effect(const struct dr_rofi *r, uint8_t c, uint8_t connect)
{
    struct rofi_connector_state s = connector_state(r, c);
    if (connect) {
        return s.connected;
    }
    return (uint8_t)(!s.connected && s.position == ROFI_CONNECTOR_RETRACTED);
}

static void connector_op(struct dr_rofi *r, uint8_t c, uint8_t connect)
{
    struct dr_rofi_op *op = &r->connector[c];
    if (connector_in_effect(r, c, connect)) {
        return; /* already connected (by either side) or released: done at once */
    }
    op->running = 1;
    op->connect = connect;
    op->deadline_ms = now(r) + DR_ROFI_CONNECTOR_TIMEOUT_MS;
    if (connect) {
        r->hal->connector_connect(r->hal->ctx, (int)c);
    } else {
        r->hal->connector_disconnect(r->hal->ctx, (int)c);
    }
}

static void poll_connector(struct dr_rofi *r, uint8_t c, uint32_t t)
{
    struct dr_rofi_op *op = &r->connector[c];
    if (!op->running) {
        return;
    }
    if (connector_in_effect(r, c, op->connect)) {
        end_op(r, op, 1);
    } else if (reached(t, op->deadline_ms)) {
        end_op(r, op, 0);
    }
}

/* The HAL's onConnectorEvent callback: a connection that ends takes its neighbour's ID with
 * it (the next one there may be another module). */
static void connector_event(void *user, int connector, enum rofi_connector_event event)
{
    struct dr_rofi *r = user;
    if (event == ROFI_CONNECTOR_DISCONNECTED && connector >= 0 &&
        connector < (int)DR_ROFI_CONNECTORS) {
        r->neighbour[connector] = -1;
    }
}

/* ---- dr_rofi.h ---- */

int dr_rofi_init(struct dr_rofi *r, const struct rofi_hal *hal, struct dr_module *m)
{
    struct rofi_descriptor d;
    uint8_t i;
    memset(&d, 0, sizeof d);
    hal->get_descriptor(hal->ctx, &d);
    if (d.joint_count < (int)DR_ROFI_JOINTS || d.connector_count < (int)DR_ROFI_CONNECTORS) {
        return -1;
    }
    unlist(r, m);
    memset(r, 0, sizeof *r);
    r->hal = hal;
    r->module = m;
    for (i = 0; i < DR_ROFI_JOINTS; i++) {
        hal->joint_capabilities(hal->ctx, (int)i, &r->caps[i]);
        hal->joint_on_error(hal->ctx, (int)i, joint_error, r);
    }
    for (i = 0; i < DR_ROFI_CONNECTORS; i++) {
        r->neighbour[i] = -1;
        hal->connector_on_event(hal->ctx, (int)i, connector_event, r);
        hal->connector_on_packet(hal->ctx, (int)i, dr_rofi_packet_arrived, r);
    }
    r->next = modules;
    modules = r;
    return 0;
}

void dr_rofi_poll(struct dr_rofi *r)
{
    uint32_t t;
    uint8_t i;
    r->hal->dispatch(r->hal->ctx);
    t = now(r);
    for (i = 0; i < DR_ROFI_JOINTS; i++) {
        poll_joint(r, i, t);
    }
    for (i = 0; i < DR_ROFI_CONNECTORS; i++) {
        poll_connector(r, i, t);
    }
    if (!r->stepped || reached(t, r->last_step_ms + DR_ROFI_STEP_MS)) {
        r->stepped = 1;
        r->last_step_ms = t;
        dr_module_step(r->module);
    }
}

void dr_rofi_packet_arrived(void *user, int connector, uint16_t content_type,
                            const uint8_t *data, size_t len)
{
    struct dr_rofi *r = user;
    if (content_type != DR_ROFI_CONTENT_TYPE || connector < 0 ||
        connector >= (int)DR_ROFI_CONNECTORS || len == 0u || len > 255u) {
        r->dropped++; /* not ours, or not a frame dr_module_receive can be given */
        return;
    }
    dr_module_receive(r->module, (uint8_t)connector, data, (uint8_t)len);
}

uint8_t dr_rofi_set_neighbour(struct dr_module *m, uint8_t connector, int16_t id)
{
    struct dr_rofi *r = rofi_of(m);
    if (connector >= DR_ROFI_CONNECTORS || !connector_state(r, connector).connected) {
        return 0;
    }
    r->neighbour[connector] = id;
    return 1;
}

/* ---- dr_hal.h ---- */

uint32_t dr_hal_now_ms(struct dr_module *m)
{
    return now(rofi_of(m));
}

uint16_t dr_hal_random(struct dr_module *m)
{
    const struct rofi_hal *hal = rofi_of(m)->hal;
    return (uint16_t)hal->random(hal->ctx);
}

/* RoFI's send discards a packet with no mating side; sending only where one is connected
 * saves the bus transactions. */
void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    struct dr_rofi *r = rofi_of(m);
    uint8_t c;
    for (c = 0; c < DR_ROFI_CONNECTORS; c++) {
        if (connector_state(r, c).connected) {
            r->hal->connector_send(r->hal->ctx, (int)c, DR_ROFI_CONTENT_TYPE, bytes, len);
        }
    }
}

void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    const struct rofi_hal *hal = rofi_of(m)->hal;
    if (channel < DR_ROFI_CONNECTORS) {
        hal->connector_send(hal->ctx, (int)channel, DR_ROFI_CONTENT_TYPE, bytes, len);
    }
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    struct dr_rofi *r = rofi_of(m);
    (void)statement;
    if (!any_running(r)) {
        r->failed = 0; /* the last set has ended: this start begins a new one */
    }
    if (op == DR_OP_JOINT_ROTATEFROMTOBY && index < DR_ROFI_JOINTS && !r->joint[index].running) {
        rotate(r, index, args);
    } else if ((op == DR_OP_CONNECTOR_CONNECT || op == DR_OP_CONNECTOR_DISCONNECT) &&
               index < DR_ROFI_CONNECTORS && !r->connector[index].running) {
        connector_op(r, index, (uint8_t)(op == DR_OP_CONNECTOR_CONNECT));
    } else {
        /* Not an operation of this module, or a second one on a part whose first still runs
         * (the first keeps running): refused. */
        r->failed = 1;
    }
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    struct dr_rofi *r = rofi_of(m);
    if (any_running(r)) {
        return DR_OP_RUNNING;
    }
    return r->failed ? DR_OP_FAILED : DR_OP_DONE;
}

/* RoFI's ID is an int; dynarole's are 16 bits (the low 16 of RoFI's). */
uint16_t dr_hal_id(struct dr_module *m)
{
    const struct rofi_hal *hal = rofi_of(m)->hal;
    return (uint16_t)hal->get_id(hal->ctx);
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    if (connector >= DR_ROFI_CONNECTORS) {
        return 0;
    }
    return (uint8_t)(connector_state(rofi_of(m), connector).connected != 0u);
}

/* The ID kept by dr_rofi_set_neighbour, while the connector is still connected (a missed
 * disconnect event cannot show an old neighbour). */
int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector)
{
    struct dr_rofi *r = rofi_of(m);
    if (connector >= DR_ROFI_CONNECTORS || !connector_state(r, connector).connected) {
        return -1;
    }
    return r->neighbour[connector];
}

/* The joint's position in whole degrees, rounded half away from zero, in (-180, 180]. An
 * absurd reading (NaN, or beyond a million degrees) reads 0. */
int16_t dr_hal_joint(struct dr_module *m, uint8_t joint)
{
    const struct rofi_hal *hal = rofi_of(m)->hal;
    float deg;
    long whole;
    if (joint >= DR_ROFI_JOINTS) {
        return 0;
    }
    deg = hal->joint_get_position(hal->ctx, (int)joint) / RAD_PER_DEG;
    if (!(deg > -1e6f && deg < 1e6f)) {
        return 0;
    }
    whole = (long)(deg < 0.0f ? deg - 0.5f : deg + 0.5f) % 360L;
    if (whole > 180L) {
        whole -= 360L;
    } else if (whole <= -180L) {
        whole += 360L;
    }
    return (int16_t)whole;
}

/* A RoFI module has no LEDs the HAL drives. */
void dr_hal_leds(struct dr_module *m, uint8_t value)
{
    (void)m;
    (void)value;
}

/* Storage beyond the partition, or a failed read, reads as never written (0xFF). */
void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    struct dr_rofi *r = rofi_of(m);
    const struct rofi_hal *hal = r->hal;
    if ((size_t)addr + len > hal->storage_size(hal->ctx) ||
        hal->storage_read(hal->ctx, addr, buf, len) != 0) {
        r->nv_errors++;
        memset(buf, 0xFF, len);
    }
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    struct dr_rofi *r = rofi_of(m);
    const struct rofi_hal *hal = r->hal;
    if ((size_t)addr + len > hal->storage_size(hal->ctx) ||
        hal->storage_write(hal->ctx, addr, buf, len) != 0) {
        r->nv_errors++;
    }
}
