/* harness.c - the paper-protocol tests' world on the shared fake platform (see harness.h). */
#include <stdio.h>
#include <string.h>
#include "harness.h"

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
    dr_fake_checks++;
    if (!ok) {
        dr_fake_fail();
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
    return dr_fake_done(name);
}

/* ---- the platform: m->platform is the module's fake ---- */

dr_fake_t *dr_fake_of(struct dr_module *m)
{
    return (dr_fake_t *)m->platform;
}

/* ---- world ---- */

void world_init(world_t *w, uint8_t n, const dr_paper_program_t *program,
                enum dr_paper_merge merge, uint8_t single_step_handover, uint8_t restart_pending)
{
    uint8_t i;
    memset(w, 0, sizeof *w);
    w->n = n;
    for (i = 0; i < n; i++) {
        dr_fake_init(&w->fake[i], i, 0); /* nothing running */
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
