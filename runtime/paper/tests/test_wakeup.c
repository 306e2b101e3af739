/* test_wakeup.c - dr_module_next_wakeup: eight2car's first statements run with a step every
 * 5 ms on every module, packets delivered to every other module at the next step and
 * operations taking 50 ms; every step that the module's last answer let a tickless platform
 * skip is checked to change nothing (the module, and the fake hardware's record of sends,
 * operation starts and random draws). */
#include <stdio.h>
#include <string.h>
#include "harness.h"
#include "machines.h"

#define N 7u
#define TICK_MS 5u
#define OP_MS 50u
#define LIMIT_MS 60000u

typedef struct {
    uint8_t wake;
    uint32_t wake_at;
    uint32_t op_done_at;
    uint8_t inbox[DR_CONF_MAX_PACKET];
    uint8_t inbox_len;
} node_t;

static unsigned long skippable;
static unsigned long acted;

/* Whether the last answer lets a step of module i be skipped now. */
static uint8_t may_skip(const world_t *w, const node_t *n, uint8_t i)
{
    uint32_t now = w->fake[i].now_ms;
    if ((n->wake & DR_WAKE_AT) && (int32_t)(now - n->wake_at) >= 0) {
        return 0;
    }
    return (uint8_t)(!(n->wake & DR_WAKE_OP) || w->fake[i].status == DR_OP_RUNNING);
}

static void step(world_t *w, node_t *n, uint8_t i)
{
    uint8_t skip = may_skip(w, n, i);
    dr_module_t before = w->mod[i];
    fake_t fake_before = w->fake[i];
    uint16_t starts = w->fake[i].n_starts;
    dr_module_step(&w->mod[i]);
    if (w->fake[i].n_starts != starts) {
        n->op_done_at = w->fake[i].now_ms + OP_MS;
    }
    if (skip) {
        skippable++;
        if (memcmp(&before, &w->mod[i], sizeof before) != 0 ||
            memcmp(&fake_before, &w->fake[i], sizeof fake_before) != 0) {
            acted++;
        }
    }
    n->wake = dr_module_next_wakeup(&w->mod[i], &n->wake_at);
}

/* Hands module i's packet (if it sent one in the last step) to every other module; each
 * asks for its wake-up again. */
static void deliver(world_t *w, node_t *nodes, uint8_t i, uint32_t sent_before)
{
    uint8_t j;
    if (w->mod[i].packets_sent == sent_before) {
        return;
    }
    for (j = 0; j < N; j++) {
        if (j != i) {
            dr_module_receive(&w->mod[j], 0, w->fake[i].packet, w->fake[i].packet_len);
            nodes[j].wake = dr_module_next_wakeup(&w->mod[j], &nodes[j].wake_at);
        }
    }
}

static void run(uint8_t restart_pending, uint32_t phase)
{
    world_t w;
    node_t nodes[N];
    uint32_t t;
    uint32_t sent;
    uint8_t i;
    uint8_t all = 0;
    memset(nodes, 0, sizeof nodes);
    world_init(&w, N, &eight2car_program, DR_MERGE_C_PORT, 1, restart_pending);
    for (i = 0; i < N; i++) {
        nodes[i].wake = dr_module_next_wakeup(&w.mod[i], &nodes[i].wake_at);
    }
    for (t = 0; t < LIMIT_MS && !all; t += TICK_MS) {
        all = 1;
        for (i = 0; i < N; i++) {
            uint8_t k = (uint8_t)((i + phase) % N);
            w.fake[k].now_ms = t;
            if (w.fake[k].status == DR_OP_RUNNING && t >= nodes[k].op_done_at) {
                w.fake[k].status = DR_OP_DONE;
            }
            sent = w.mod[k].packets_sent;
            step(&w, &nodes[k], k);
            deliver(&w, nodes, k, sent);
            all = (uint8_t)(all && dr_module_finished(&w.mod[k]));
        }
    }
    CHECK(all);
}

int main(void)
{
    uint32_t phase;
    for (phase = 0; phase < N; phase++) {
        run(0, phase);
        run(1, phase);
    }
    /* Most steps are skippable (a broadcast every 100 ms, a step every 5). */
    CHECK(skippable > 5000ul);
    CHECK_EQ(acted, 0);
    printf("wakeup: %lu skippable steps checked\n", skippable);
    return harness_done("wakeup");
}
