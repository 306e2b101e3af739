/* dr_fake.c - the one fake platform of the runtime's C tests (see dr_fake.h). */
#include <stdio.h>
#include <string.h>
#include "dr_fake.h"

unsigned long dr_fake_misuses;
unsigned long dr_fake_checks;
unsigned long dr_fake_failures;

static const dr_fake_hooks_t no_hooks = {0, 0, 0, 0, 0, 0, 0, 0};

void dr_fake_init(dr_fake_t *f, uint16_t id, const dr_fake_hooks_t *hooks)
{
    memset(f, 0, sizeof *f);
    f->hooks = hooks != 0 ? hooks : &no_hooks;
    f->id = id;
    f->random = (uint16_t)(id + 1u);
    f->status = DR_OP_DONE;
    memset(f->nv, 0xFF, sizeof f->nv);
}

static void misuse(struct dr_module *m, const char *what, uint32_t value)
{
    if (dr_fake_of(m)->hooks->misuse != 0) {
        dr_fake_of(m)->hooks->misuse(m, what, value);
        return;
    }
    dr_fake_misuses++;
    if (dr_fake_misuses <= 10u) {
        fprintf(stderr, "  fake platform: %s (%lu)\n", what, (unsigned long)value);
    }
}

/* ---- dr_hal.h ---- */

uint32_t dr_hal_now_ms(struct dr_module *m)
{
    dr_fake_t *f = dr_fake_of(m);
    return f->hooks->now_ms != 0 ? f->hooks->now_ms(m) : f->now_ms;
}

uint16_t dr_hal_random(struct dr_module *m)
{
    dr_fake_t *f = dr_fake_of(m);
    f->effects++;
    if (f->hooks->random != 0) {
        return f->hooks->random(m);
    }
    f->random = (uint16_t)(f->random * 25173u + 13849u);
    return f->random;
}

static void send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    dr_fake_t *f = dr_fake_of(m);
    f->effects++;
    if (len == 0u || len > DR_CONF_MAX_PACKET) {
        misuse(m, "packet of a bad length", len);
        return;
    }
    memcpy(f->packet, bytes, len);
    f->packet_len = len;
    f->packet_channel = channel;
    if (f->hooks->send != 0) {
        f->hooks->send(m, channel, bytes, len);
    }
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    send(m, DR_FAKE_BROADCAST, bytes, len);
}

void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    send(m, channel, bytes, len);
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    dr_fake_t *f = dr_fake_of(m);
    uint8_t i;
    f->effects++;
    f->statement = statement;
    f->op = op;
    f->index = index;
    for (i = 0; i < DR_CONF_MAX_ARGS; i++) {
        f->args[i] = args != 0 ? args[i] : 0;
    }
    f->status = DR_OP_RUNNING;
    f->n_starts++;
    if (f->hooks->op_start != 0) {
        f->hooks->op_start(m);
    }
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    dr_fake_t *f = dr_fake_of(m);
    return f->hooks->op_status != 0 ? f->hooks->op_status(m) : f->status;
}

uint16_t dr_hal_id(struct dr_module *m)
{
    return dr_fake_of(m)->id;
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    dr_fake_t *f = dr_fake_of(m);
    if (f->hooks->connected != 0) {
        return f->hooks->connected(m, connector);
    }
    return (uint8_t)(connector < 32u && ((f->connected >> connector) & 1u));
}

int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector)
{
    (void)m;
    (void)connector;
    return -1;
}

int16_t dr_hal_joint(struct dr_module *m, uint8_t joint)
{
    (void)m;
    (void)joint;
    return 0;
}

void dr_hal_leds(struct dr_module *m, uint8_t value)
{
    dr_fake_t *f = dr_fake_of(m);
    f->leds = value;
    f->effects++;
}

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    dr_fake_t *f = dr_fake_of(m);
    if ((uint32_t)addr + len > DR_FAKE_NV) {
        misuse(m, "NV read out of range", addr);
        return;
    }
    f->nv_reads++;
    memcpy(buf, f->nv + addr, len);
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    dr_fake_t *f = dr_fake_of(m);
    if ((uint32_t)addr + len > DR_FAKE_NV) {
        misuse(m, "NV write out of range", addr);
        return;
    }
    f->nv_writes++;
    f->effects++;
    if (f->hooks->nv_write != 0) {
        f->hooks->nv_write(m, addr, buf, len);
    }
    memcpy(f->nv + addr, buf, len);
}

/* ---- assertions ---- */

int dr_fake_check(int ok, const char *what, const char *file, int line)
{
    dr_fake_checks++;
    if (!ok) {
        dr_fake_fail();
        if (dr_fake_failures <= 30u) {
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", file, line, what);
        }
    }
    return ok;
}

int dr_fake_check_eq(long a, long b, const char *sa, const char *sb, const char *file, int line)
{
    dr_fake_checks++;
    if (a != b) {
        dr_fake_fail();
        if (dr_fake_failures <= 30u) {
            fprintf(stderr, "%s:%d: CHECK failed: %s == %s (%ld != %ld)\n", file, line, sa, sb,
                    a, b);
        }
        return 0;
    }
    return 1;
}

void dr_fake_fail(void)
{
    dr_fake_failures++;
}

int dr_fake_done(const char *name)
{
    printf("%s: %lu checks, %lu failed, %lu misuses of the platform\n", name, dr_fake_checks,
           dr_fake_failures, dr_fake_misuses);
    return dr_fake_failures == 0u && dr_fake_misuses == 0u ? 0 : 1;
}
