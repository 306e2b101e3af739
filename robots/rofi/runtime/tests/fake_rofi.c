/* fake_rofi.c - a fake RoFI universal module behind rofi_hal.h (see fake_rofi.h). */
#include <string.h>
#include "fake_rofi.h"

#define PI 3.14159265358979323846

double fake_rofi_rad(double degrees)
{
    return degrees * PI / 180.0;
}

static struct fake_rofi *of(void *ctx)
{
    return ctx;
}

static struct fake_event *push(struct fake_rofi *f, enum fake_event_kind kind, int index)
{
    struct fake_event *e;
    if (f->queued >= FAKE_ROFI_QUEUE) {
        f->lost++;
        return 0;
    }
    e = &f->queue[f->queued++];
    memset(e, 0, sizeof *e);
    e->kind = kind;
    e->index = index;
    return e;
}

/* ---- RoFI ---- */

static int get_id(void *ctx)
{
    return of(ctx)->id;
}

static void get_descriptor(void *ctx, struct rofi_descriptor *out)
{
    *out = of(ctx)->descriptor;
}

/* ---- Joint ---- */

static void joint_capabilities(void *ctx, int joint, struct rofi_joint_capabilities *out)
{
    *out = of(ctx)->joint[joint].caps;
}

static float joint_get_position(void *ctx, int joint)
{
    return (float)of(ctx)->joint[joint].pos;
}

static void joint_set_position(void *ctx, int joint, float pos, float velocity,
                               rofi_joint_reached_fn done, void *user)
{
    struct fake_joint *j = &of(ctx)->joint[joint];
    j->set_calls++;
    j->last_velocity = velocity;
    j->moving = 1;
    j->from = j->pos;
    j->target = pos;
    j->velocity = velocity;
    j->since_ms = of(ctx)->now_ms;
    j->done = done; /* a new target drops the last one's callback, as RoFI's */
    j->done_user = user;
}

static void joint_on_error(void *ctx, int joint, rofi_joint_error_fn callback, void *user)
{
    of(ctx)->joint[joint].on_error = callback;
    of(ctx)->joint[joint].error_user = user;
}

/* One millisecond of joint j's move: where it is `since` ms in, its target once there. */
static void move_joint(struct fake_rofi *f, int index)
{
    struct fake_joint *j = &f->joint[index];
    double span = j->target > j->from ? j->target - j->from : j->from - j->target;
    double gone = j->velocity * (double)(f->now_ms - j->since_ms) / 1000.0;
    struct fake_event *e;
    if (!j->moving || j->stuck) {
        return;
    }
    if (gone >= span - 1e-9) {
        j->pos = j->target;
        j->moving = 0;
        if (!j->no_callback && j->done != 0 && (e = push(f, FAKE_REACHED, index)) != 0) {
            e->done = j->done;
            e->done_user = j->done_user;
        }
        return;
    }
    j->pos = j->from + (j->target > j->from ? gone : -gone);
}

void fake_rofi_joint_error(struct fake_rofi *f, int j)
{
    f->joint[j].moving = 0;
    (void)push(f, FAKE_JOINT_ERROR, j);
}

/* ---- Connector ---- */

/* Recomputes connector c's connection; a change is an event. */
static void relatch(struct fake_rofi *f, int c)
{
    struct fake_connector *k = &f->connector[c];
    uint8_t connected = (uint8_t)(k->mate && (k->extended || k->mate_holds));
    struct fake_event *e;
    if (connected != k->connected) {
        k->connected = connected;
        if ((e = push(f, FAKE_CONNECTOR_EVENT, c)) != 0) {
            e->detail = connected ? ROFI_CONNECTOR_CONNECTED : ROFI_CONNECTOR_DISCONNECTED;
        }
    }
}

void fake_rofi_set_mate(struct fake_rofi *f, int c, uint8_t mate, uint8_t mate_holds)
{
    f->connector[c].mate = mate;
    f->connector[c].mate_holds = mate_holds;
    relatch(f, c);
}

static void connector_get_state(void *ctx, int connector, struct rofi_connector_state *out)
{
    struct fake_connector *k = &of(ctx)->connector[connector];
    memset(out, 0, sizeof *out);
    out->position = k->extended ? ROFI_CONNECTOR_EXTENDED : ROFI_CONNECTOR_RETRACTED;
    out->connected = k->connected;
    out->orientation = k->orientation;
}

static void slide(struct fake_rofi *f, int c, uint8_t to)
{
    struct fake_connector *k = &f->connector[c];
    if (k->extended == to && !k->sliding) {
        return;
    }
    k->sliding = 1;
    k->slide_to = to;
    k->slide_end_ms = f->now_ms + FAKE_ROFI_SLIDE_MS;
}

static void connector_connect(void *ctx, int connector)
{
    of(ctx)->connector[connector].connect_calls++;
    slide(of(ctx), connector, 1);
}

static void connector_disconnect(void *ctx, int connector)
{
    of(ctx)->connector[connector].disconnect_calls++;
    slide(of(ctx), connector, 0);
}

static void connector_on_event(void *ctx, int connector, rofi_connector_event_fn callback,
                               void *user)
{
    of(ctx)->connector[connector].on_event = callback;
    of(ctx)->connector[connector].event_user = user;
}

static void connector_on_packet(void *ctx, int connector, rofi_packet_fn callback, void *user)
{
    of(ctx)->connector[connector].on_packet = callback;
    of(ctx)->connector[connector].packet_user = user;
}

static void connector_send(void *ctx, int connector, uint16_t content_type, const uint8_t *data,
                           size_t len)
{
    struct fake_rofi *f = of(ctx);
    struct fake_sent *s;
    if (f->n_sent >= FAKE_ROFI_SENT || len > FAKE_ROFI_PACKET) {
        f->lost++;
        return;
    }
    s = &f->sent[f->n_sent++];
    s->connector = connector;
    s->content_type = content_type;
    s->len = len;
    memcpy(s->bytes, data, len);
}

void fake_rofi_deliver(struct fake_rofi *f, int c, uint16_t content_type, const uint8_t *data,
                       size_t len)
{
    struct fake_event *e;
    if (len > FAKE_ROFI_PACKET || (e = push(f, FAKE_PACKET, c)) == 0) {
        f->lost++;
        return;
    }
    e->content_type = content_type;
    e->len = len;
    memcpy(e->bytes, data, len);
}

/* ---- Partition ---- */

static size_t storage_size(void *ctx)
{
    (void)ctx;
    return FAKE_ROFI_STORAGE;
}

static int storage_read(void *ctx, size_t offset, uint8_t *buf, size_t len)
{
    struct fake_rofi *f = of(ctx);
    if (f->storage_fails || offset + len > FAKE_ROFI_STORAGE) {
        return -1;
    }
    memcpy(buf, f->storage + offset, len);
    return 0;
}

static int storage_write(void *ctx, size_t offset, const uint8_t *data, size_t len)
{
    struct fake_rofi *f = of(ctx);
    if (f->storage_fails || offset + len > FAKE_ROFI_STORAGE) {
        return -1;
    }
    memcpy(f->storage + offset, data, len);
    return 0;
}

/* ---- the platform ---- */

static uint32_t now_ms(void *ctx)
{
    return of(ctx)->now_ms;
}

static uint32_t random_number(void *ctx)
{
    struct fake_rofi *f = of(ctx);
    f->rng = f->rng * 1103515245u + 12345u;
    return f->rng;
}

/* Runs the queue in order (a callback's own events, if any, run in the same call). */
static void dispatch(void *ctx)
{
    struct fake_rofi *f = of(ctx);
    unsigned i;
    f->dispatches++;
    for (i = 0; i < f->queued; i++) {
        struct fake_event *e = &f->queue[i];
        struct fake_joint *j = &f->joint[e->index % FAKE_ROFI_JOINTS];
        struct fake_connector *k = &f->connector[e->index % FAKE_ROFI_CONNECTORS];
        switch (e->kind) {
        case FAKE_REACHED:
            e->done(e->done_user, e->index);
            break;
        case FAKE_JOINT_ERROR:
            if (j->on_error != 0) {
                j->on_error(j->error_user, e->index, ROFI_JOINT_ERROR_HARDWARE, "overload");
            }
            break;
        case FAKE_CONNECTOR_EVENT:
            if (k->on_event != 0) {
                k->on_event(k->event_user, e->index, (enum rofi_connector_event)e->detail);
            }
            break;
        case FAKE_PACKET:
            if (k->on_packet != 0) {
                k->on_packet(k->packet_user, e->index, e->content_type, e->bytes, e->len);
            }
            break;
        }
    }
    f->queued = 0;
}

void fake_rofi_advance(struct fake_rofi *f, uint32_t ms)
{
    int i;
    while (ms-- > 0u) {
        f->now_ms++;
        for (i = 0; i < FAKE_ROFI_JOINTS; i++) {
            move_joint(f, i);
        }
        for (i = 0; i < FAKE_ROFI_CONNECTORS; i++) {
            struct fake_connector *k = &f->connector[i];
            if (k->sliding && f->now_ms == k->slide_end_ms) {
                k->sliding = 0;
                k->extended = k->slide_to;
                relatch(f, i);
            }
        }
    }
}

void fake_rofi_init(struct fake_rofi *f, int id)
{
    static const struct rofi_hal functions = {
        0,
        get_id,
        get_descriptor,
        joint_capabilities,
        joint_get_position,
        joint_set_position,
        joint_on_error,
        connector_get_state,
        connector_connect,
        connector_disconnect,
        connector_on_event,
        connector_on_packet,
        connector_send,
        storage_size,
        storage_read,
        storage_write,
        now_ms,
        random_number,
        dispatch,
    };
    int i;
    memset(f, 0, sizeof *f);
    f->hal = functions;
    f->hal.ctx = f;
    f->id = id;
    f->descriptor.joint_count = FAKE_ROFI_JOINTS;
    f->descriptor.connector_count = FAKE_ROFI_CONNECTORS;
    f->rng = (uint32_t)id + 1u;
    /* RoFI's ESP32 capabilities: shoes +-pi/2 * 1.1, the body +-0.9 pi, 2 pi rad/s. */
    for (i = 0; i < FAKE_ROFI_JOINTS; i++) {
        struct rofi_joint_capabilities *c = &f->joint[i].caps;
        c->max_position = (float)(i == 2 ? 0.9 * PI : PI / 2.0 * 1.1);
        c->min_position = -c->max_position;
        c->max_speed = (float)(2.0 * PI);
        c->min_speed = c->max_speed;
        c->max_torque = 1.2f;
    }
    memset(f->storage, 0xFF, sizeof f->storage);
}
