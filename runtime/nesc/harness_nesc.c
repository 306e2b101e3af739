/* harness_nesc.c - runs the nesC build of a compiled sequence in runtime/harness/harness.c:
 * one copy of the nesC application per module (the Makefile renames each copy's entry
 * points with a suffix _K), behind the harness's calls.
 *
 * The harness is compiled with its four calls into the protocol renamed to the functions
 * below, so it drives booting, time and packets exactly as for the C build and checks the
 * same things; each component instance runs its own dr_module_t, stepped by its own timer. */
#include <stdio.h>
#include <stdlib.h>
#include "dr_program.h"
#include "dr_nesc_harness_instances.h" /* generated: DR_NESC_INSTANCES(X) = X(0) X(1) ... */

/* What the harness's modules become (the harness is compiled with these names). */
void dr_nesc_harness_init(dr_module_t *key, void *platform);
void dr_nesc_harness_step(struct dr_module *key);
void dr_nesc_harness_receive(struct dr_module *key, uint8_t channel, const uint8_t *bytes,
                             uint8_t len);
uint8_t dr_nesc_harness_finished(const struct dr_module *key);

#define DR_NESC_DECLARE(k)                                                                  \
    void dr_nesc_boot_##k(void);                                                            \
    void dr_nesc_advance_ms_##k(uint32_t ms);                                               \
    void dr_platform_receive_##k(uint8_t channel, const uint8_t *bytes, uint8_t len);       \
    void dr_nesc_program_init_##k(dr_module_t *m, void *platform);
DR_NESC_INSTANCES(DR_NESC_DECLARE)

typedef struct {
    void (*boot)(void);
    void (*advance_ms)(uint32_t ms);
    void (*receive)(uint8_t channel, const uint8_t *bytes, uint8_t len);
} instance_entry_t;

#define DR_NESC_ENTRY(k) {dr_nesc_boot_##k, dr_nesc_advance_ms_##k, dr_platform_receive_##k},
static const instance_entry_t entries[] = {DR_NESC_INSTANCES(DR_NESC_ENTRY)};
#define N_INSTANCES (sizeof entries / sizeof entries[0])

typedef struct {
    const struct dr_module *key; /* the harness's module */
    dr_module_t *self;           /* the component's module (DynaRoleP's `self`) */
    void *platform;              /* the harness's platform of that module */
    uint32_t last_ms;            /* the harness's clock when the component last saw time pass */
} instance_t;

static instance_t instances[N_INSTANCES];
static unsigned n_instances;

/* DynaRoleP's dr_program_init(&self, 0) of copy k: the component has no platform context
 * (one module per chip), the harness needs its own, so it is put in here. */
#define DR_NESC_INIT(k)                                                                     \
    void dr_nesc_program_init_##k(dr_module_t *m, void *platform)                           \
    {                                                                                       \
        (void)platform;                                                                     \
        instances[k].self = m;                                                              \
        dr_program_init(m, instances[k].platform);                                          \
    }
DR_NESC_INSTANCES(DR_NESC_INIT)

static instance_t *instance_of(const struct dr_module *key)
{
    unsigned k;
    for (k = 0; k < n_instances; k++) {
        if (instances[k].key == key) {
            return &instances[k];
        }
    }
    fprintf(stderr, "harness_nesc: a module that was never initialised\n");
    exit(2);
}

void dr_nesc_harness_init(dr_module_t *key, void *platform)
{
    instance_t *it;
    if (n_instances >= N_INSTANCES) {
        fprintf(stderr, "harness_nesc: built for %u modules; rebuild with more IDS\n",
                (unsigned)N_INSTANCES);
        exit(2);
    }
    it = &instances[n_instances];
    it->key = key;
    it->platform = platform;
    n_instances++;
    entries[it - instances].boot();
    if (it->self == NULL) {
        fprintf(stderr, "harness_nesc: the component did not initialise its module at boot\n");
        exit(1);
    }
    it->last_ms = dr_hal_now_ms(it->self);
}

/* The harness steps every module at each tick of its clock: the component sees the time
 * that passed, and its step timer decides when to step. */
void dr_nesc_harness_step(struct dr_module *key)
{
    instance_t *it = instance_of(key);
    uint32_t now = dr_hal_now_ms(it->self);
    entries[it - instances].advance_ms(now - it->last_ms);
    it->last_ms = now;
}

void dr_nesc_harness_receive(struct dr_module *key, uint8_t channel, const uint8_t *bytes,
                             uint8_t len)
{
    entries[instance_of(key) - instances].receive(channel, bytes, len);
}

uint8_t dr_nesc_harness_finished(const struct dr_module *key)
{
    return dr_module_finished(instance_of(key)->self);
}
