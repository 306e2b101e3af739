/* harness.c - assertion helper, fake HAL (clock, operations, last packet) and world helpers for the tests. */
#include <stdio.h>
#include <string.h>
#include "harness.h"

static int n_checks;
static int n_failures;

int harness_check(int ok, const char *what, const char *file, int line)
{
    n_checks++;
    if (!ok) {
        n_failures++;
        printf("FAIL %s:%d: %s\n", file, line, what);
    }
    return ok;
}

int harness_check_eq(long a, long b, const char *sa, const char *sb, const char *file, int line)
{
    n_checks++;
    if (a != b) {
        n_failures++;
        printf("FAIL %s:%d: %s == %s (%ld != %ld)\n", file, line, sa, sb, a, b);
        return 0;
    }
    return 1;
}

static void print_global(const dr_paper_global_t *g)
{
    uint8_t i;
    const char *sep = "";
    printf("<%u,%u,{", (unsigned)g->state, (unsigned)g->address);
    for (i = 0; i < DR_CONF_MAX_PENDING; i++) {
        if (g->pending[i] != 0u) {
            printf("%s%u", sep, (unsigned)g->pending[i]);
            sep = ",";
        }
    }
    printf("}>");
}

int harness_check_triple(const dr_paper_global_t *g, uint8_t state, uint8_t address,
                         const uint8_t *pending, uint8_t n_pending, const char *file, int line)
{
    uint8_t i;
    uint8_t j;
    uint8_t n = 0;
    int ok = g->state == state && g->address == address;
    for (i = 0; i < DR_CONF_MAX_PENDING; i++) {
        if (g->pending[i] != 0u) {
            n++;
        }
    }
    ok = ok && n == n_pending;
    for (j = 0; ok && j < n_pending; j++) {
        uint8_t found = 0;
        for (i = 0; i < DR_CONF_MAX_PENDING; i++) {
            found = (uint8_t)(found || g->pending[i] == pending[j]);
        }
        ok = found;
    }
    n_checks++;
    if (!ok) {
        n_failures++;
        printf("FAIL %s:%d: got ", file, line);
        print_global(g);
        printf(", want <%u,%u,{", (unsigned)state, (unsigned)address);
        for (j = 0; j < n_pending; j++) {
            printf("%s%u", j ? "," : "", (unsigned)pending[j]);
        }
        printf("}>\n");
    }
    return ok;
}

int harness_done(const char *name)
{
    printf("%s: %d checks, %d failed\n", name, n_checks, n_failures);
    return n_failures == 0 ? 0 : 1;
}

/* ---- fake HAL: m->platform is a fake_t ---- */

static fake_t *fake(struct dr_module *m)
{
    return (fake_t *)m->platform;
}

uint32_t dr_hal_now_ms(struct dr_module *m)
{
    return fake(m)->now_ms;
}

uint16_t dr_hal_random(struct dr_module *m)
{
    fake_t *f = fake(m);
    f->random = (uint16_t)(f->random * 25173u + 13849u);
    return f->random;
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    fake_t *f = fake(m);
    memcpy(f->packet, bytes, len);
    f->packet_len = len;
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    fake_t *f = fake(m);
    uint8_t i;
    f->statement = statement;
    f->op = op;
    f->index = index;
    for (i = 0; i < DR_CONF_MAX_ARGS; i++) {
        f->args[i] = args != 0 ? args[i] : 0;
    }
    f->status = DR_OP_RUNNING;
    f->n_starts++;
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    return fake(m)->status;
}

uint16_t dr_hal_id(struct dr_module *m)
{
    return fake(m)->id;
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    (void)m;
    (void)connector;
    return 0;
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
    fake(m)->leds = value;
}

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    (void)m;
    (void)addr;
    memset(buf, 0xFF, len);
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    (void)m;
    (void)addr;
    (void)buf;
    (void)len;
}

/* ---- world ---- */

void world_init(world_t *w, uint8_t n, const dr_paper_program_t *program,
                enum dr_paper_merge merge, uint8_t single_step_handover, uint8_t restart_pending)
{
    uint8_t i;
    memset(w, 0, sizeof *w);
    w->n = n;
    for (i = 0; i < n; i++) {
        w->fake[i].id = i;
        w->fake[i].status = DR_OP_DONE; /* nothing running */
        w->fake[i].random = (uint16_t)(i + 1u);
        dr_module_init(&w->mod[i], program, &w->fake[i]);
        w->mod[i].merge = merge;
        w->mod[i].single_step_handover = single_step_handover;
        w->mod[i].restart_pending = restart_pending;
    }
}

void world_step(world_t *w, uint8_t i)
{
    w->fake[i].now_ms += DR_CONF_BROADCAST_MS + DR_CONF_BROADCAST_JITTER_MS;
    dr_module_step(&w->mod[i]);
}

void world_deliver(world_t *w, uint8_t from, uint8_t to)
{
    if (w->fake[from].packet_len != 0u) {
        dr_module_receive(&w->mod[to], 0, w->fake[from].packet, w->fake[from].packet_len);
    }
}

void world_complete(world_t *w, uint8_t i)
{
    if (w->fake[i].status == DR_OP_RUNNING) {
        w->fake[i].status = DR_OP_DONE;
    }
}

void world_reset(world_t *w, uint8_t i)
{
    w->fake[i].packet_len = 0; /* nothing in the air from before the reset */
    dr_module_init(&w->mod[i], w->mod[i].program, &w->fake[i]);
}

void world_round(world_t *w, uint16_t complete_mask)
{
    uint8_t i;
    uint8_t j;
    for (i = 0; i < w->n; i++) {
        if (complete_mask & (1u << i)) {
            world_complete(w, i);
        }
    }
    for (i = 0; i < w->n; i++) {
        world_step(w, i);
    }
    for (i = 0; i < w->n; i++) {
        for (j = 0; j < w->n; j++) {
            if (i != j) {
                world_deliver(w, i, j);
            }
        }
    }
}

void fig4_view(const dr_module_t *m, dr_paper_global_t *view)
{
    *view = m->global;
    if (m->local_state != DR_STATE_IDLE && m->local_state > view->state) {
        view->state = m->local_state;
    }
}
