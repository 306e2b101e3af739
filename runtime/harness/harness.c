/* harness.c - runs every module of a compiled sequence over a perfect network, with
 * operations that complete after a delay, and checks that no statement starts before every
 * statement it depends on is physically done.
 *
 * Build it together with a `dynarole compile` output directory:
 *   cc -std=c99 -I OUT OUT/(every .c file) harness.c -o harness
 * Run: ./harness [-f STATEMENT:TIMES]... ID...   (the IDs of the modules; one module per ID)
 * -f makes the first TIMES attempts of statement STATEMENT fail: each runs its time and ends
 * without effect, and the HAL answers DR_OP_FAILED (dr_hal.h), so the program's failure
 * policy (compile --on-failure, --retries) is what decides what follows.
 * Exit 0 when the sequence finished, every statement ran once and nothing ran early. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "dr_program.h"

#define MAX_MODULES 64
#define MAX_RUNNING 8
#define MAX_QUEUE 4096
#define STEP_MS 5u
#define TIMEOUT_MS 600000u
#define NV_BYTES 256
#define MAX_FAULTS 16

extern const uint16_t dr_meta_n_statements;
extern const uint8_t dr_meta_address[];
extern const uint8_t dr_meta_op[];
extern const uint8_t dr_meta_index[];
extern const uint8_t dr_meta_n_deps[];
extern const uint16_t dr_meta_deps[];
extern const char *const dr_meta_text[];

typedef struct {
    uint16_t id;
    uint16_t rng;
    uint8_t n_running;
    uint16_t running[MAX_RUNNING];
    uint32_t done_at[MAX_RUNNING];
    uint8_t failed; /* an attempt of the batch ended without effect */
    uint8_t nv[NV_BYTES];
} platform_t;

typedef struct {
    int from;
    uint8_t len;
    uint8_t bytes[DR_CONF_MAX_PACKET];
} packet_t;

static dr_module_t modules[MAX_MODULES];
static platform_t platforms[MAX_MODULES];
static int n_modules;
static uint32_t now_ms;
static packet_t queue[MAX_QUEUE];
static int queue_len;
static uint8_t started[DR_CONF_MAX_STATEMENTS];
static uint8_t done[DR_CONF_MAX_STATEMENTS];
static unsigned violations;
static unsigned reissues;
static unsigned long packets;
static uint16_t fault_statement[MAX_FAULTS]; /* -f: attempts of these statements fail */
static unsigned fault_times[MAX_FAULTS];
static int n_faults;
static unsigned failures;

static platform_t *platform_of(struct dr_module *m) { return (platform_t *)m->platform; }

uint32_t dr_hal_now_ms(struct dr_module *m) { (void)m; return now_ms; }

uint16_t dr_hal_random(struct dr_module *m)
{
    platform_t *p = platform_of(m);
    p->rng = (uint16_t)(p->rng ^ (uint16_t)(p->rng << 7));
    p->rng = (uint16_t)(p->rng ^ (uint16_t)(p->rng >> 9));
    p->rng = (uint16_t)(p->rng ^ (uint16_t)(p->rng << 8));
    return p->rng;
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    if (queue_len >= MAX_QUEUE || len > DR_CONF_MAX_PACKET) {
        return;
    }
    /* By the platform, not by `m`: the nesC build runs its own copy of each module
     * (runtime/nesc/harness_nesc.c). */
    queue[queue_len].from = (int)(platform_of(m) - platforms);
    queue[queue_len].len = len;
    memcpy(queue[queue_len].bytes, bytes, len);
    queue_len++;
    packets++;
}

/* The harness has no connectors (every module hears every other), so it cannot route the
 * token baseline's hand-overs: run that protocol in the simulator (dynarole simulate). */
void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    (void)m;
    (void)channel;
    (void)bytes;
    (void)len;
    fprintf(stderr, "harness: the token protocol needs connectors; use dynarole simulate\n");
    exit(2);
}

/* How long an operation takes: the original simulator's connector times, a fast joint. */
static uint32_t duration_ms(uint8_t op)
{
    return 500u + 250u * (uint32_t)op;
}

void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    platform_t *p = platform_of(m);
    uint16_t s = statement;
    uint8_t d;
    (void)args;
    if (s >= dr_meta_n_statements || dr_meta_address[s] != m->address || dr_meta_op[s] != op ||
        dr_meta_index[s] != index) {
        violations++;
        printf("%7lu ms  VIOLATION: module %u started statement %u, which is not its operation\n",
               (unsigned long)now_ms, (unsigned)m->address, (unsigned)s);
        return;
    }
    if (p->n_running == 0u) {
        p->failed = 0; /* a new batch, or a failed one issued again */
    }
    if (started[s]) {
        reissues++;
        return;
    }
    for (d = 0; d < dr_meta_n_deps[s]; d++) {
        uint16_t first = 0;
        uint16_t k;
        for (k = 0; k < s; k++) {
            first = (uint16_t)(first + dr_meta_n_deps[k]);
        }
        if (!done[dr_meta_deps[first + d]]) {
            violations++;
            printf("%7lu ms  VIOLATION: %s started before %s finished\n", (unsigned long)now_ms,
                   dr_meta_text[s], dr_meta_text[dr_meta_deps[first + d]]);
        }
    }
    started[s] = 1;
    if (p->n_running < MAX_RUNNING) {
        p->running[p->n_running] = s;
        p->done_at[p->n_running] = now_ms + duration_ms(op);
        p->n_running++;
    }
    printf("%7lu ms  start  %s\n", (unsigned long)now_ms, dr_meta_text[s]);
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    platform_t *p = platform_of(m);
    if (p->n_running != 0u) {
        return DR_OP_RUNNING;
    }
    return p->failed ? DR_OP_FAILED : DR_OP_DONE;
}

/* Whether this attempt of statement `s` is one that -f makes fail (and counts it). */
static int attempt_fails(uint16_t s)
{
    int f;
    for (f = 0; f < n_faults; f++) {
        if (fault_statement[f] == s && fault_times[f] > 0u) {
            fault_times[f]--;
            return 1;
        }
    }
    return 0;
}

uint16_t dr_hal_id(struct dr_module *m) { return platform_of(m)->id; }
uint8_t dr_hal_connected(struct dr_module *m, uint8_t c) { (void)m; (void)c; return 0; }
int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t c) { (void)m; (void)c; return -1; }
int16_t dr_hal_joint(struct dr_module *m, uint8_t j) { (void)m; (void)j; return 0; }
void dr_hal_leds(struct dr_module *m, uint8_t value) { (void)m; (void)value; }

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    platform_t *p = platform_of(m);
    uint8_t i;
    for (i = 0; i < len; i++) {
        buf[i] = (uint16_t)(addr + i) < NV_BYTES ? p->nv[addr + i] : 0xFFu;
    }
}

void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    platform_t *p = platform_of(m);
    uint8_t i;
    for (i = 0; i < len; i++) {
        if ((uint16_t)(addr + i) < NV_BYTES) {
            p->nv[addr + i] = buf[i];
        }
    }
}

/* Operations whose time has come take effect. */
static void complete_operations(void)
{
    int i;
    for (i = 0; i < n_modules; i++) {
        platform_t *p = &platforms[i];
        uint8_t k = 0;
        while (k < p->n_running) {
            if (p->done_at[k] <= now_ms) {
                uint16_t s = p->running[k];
                if (attempt_fails(s)) {
                    /* No effect: the statement may be started again, as a new attempt. */
                    started[s] = 0;
                    p->failed = 1;
                    failures++;
                    printf("%7lu ms  failed %s\n", (unsigned long)now_ms, dr_meta_text[s]);
                } else {
                    done[s] = 1;
                    printf("%7lu ms  done   %s\n", (unsigned long)now_ms, dr_meta_text[s]);
                }
                p->running[k] = p->running[p->n_running - 1];
                p->done_at[k] = p->done_at[p->n_running - 1];
                p->n_running--;
            } else {
                k++;
            }
        }
    }
}

/* Every queued packet reaches every other module (a perfect network). */
static void deliver(void)
{
    int q;
    int i;
    int n = queue_len;
    for (q = 0; q < n; q++) {
        for (i = 0; i < n_modules; i++) {
            if (i != queue[q].from) {
                dr_module_receive(&modules[i], 0, queue[q].bytes, queue[q].len);
            }
        }
    }
    memmove(queue, queue + n, (size_t)(queue_len - n) * sizeof(packet_t));
    queue_len -= n;
}

/* Whether some module answers `end` from dr_module_finished (DR_END_*, dr_module.h). */
static int any_ended(uint8_t end)
{
    int i;
    for (i = 0; i < n_modules; i++) {
        if (dr_module_finished(&modules[i]) == end) {
            return 1;
        }
    }
    return 0;
}

/* Reads the -f options at the front of argv; returns the index of the first ID, or 0 for a
 * malformed option. */
static int read_faults(int argc, char **argv)
{
    int a = 1;
    while (a + 1 < argc && strcmp(argv[a], "-f") == 0) {
        unsigned long statement;
        unsigned long times;
        char *end;
        statement = strtoul(argv[a + 1], &end, 10);
        if (end == argv[a + 1] || *end != ':' || n_faults >= MAX_FAULTS) {
            return 0;
        }
        times = strtoul(end + 1, &end, 10);
        if (*end != '\0' || statement >= dr_meta_n_statements || times > 1000u) {
            return 0;
        }
        fault_statement[n_faults] = (uint16_t)statement;
        fault_times[n_faults] = (unsigned)times;
        n_faults++;
        a += 2;
    }
    return a;
}

int main(int argc, char **argv)
{
    int i;
    int first = read_faults(argc, argv);
    uint16_t s;
    unsigned n_done = 0;
    const char *verdict;
    if (first == 0 || argc - first < 1 || argc - first > MAX_MODULES) {
        fprintf(stderr,
                "usage: %s [-f STATEMENT:TIMES]... ID... (1 to %d module IDs; at most %d -f, "
                "each a statement below %u failing at most 1000 times)\n",
                argv[0], MAX_MODULES, MAX_FAULTS, (unsigned)dr_meta_n_statements);
        return 2;
    }
    n_modules = argc - first;
    for (i = 0; i < n_modules; i++) {
        platforms[i].id = (uint16_t)atoi(argv[first + i]);
        platforms[i].rng = (uint16_t)(0x1234u + (unsigned)i * 77u);
        memset(platforms[i].nv, 0xFF, NV_BYTES);
        dr_program_init(&modules[i], &platforms[i]);
    }
    for (now_ms = 0; now_ms < TIMEOUT_MS && !any_ended(DR_END_GOAL); now_ms += STEP_MS) {
        complete_operations();
        for (i = 0; i < n_modules; i++) {
            dr_module_step(&modules[i]);
        }
        deliver();
    }
    for (s = 0; s < dr_meta_n_statements; s++) {
        n_done += done[s];
    }
    /* The harness's clock is not the robot's: say so next to the time, which otherwise
     * reads as a contradiction of `dynarole simulate`'s (faults, the robot's durations). */
    /* A stopped module (its failure policy gave up) leaves the others waiting: the run goes
     * on to the timeout and says which it was. */
    verdict = any_ended(DR_END_GOAL) ? "finished" : any_ended(DR_END_STOPPED) ? "STOPPED" : "TIMEOUT";
    printf("%s at %lu ms (harness clock: perfect network, each operation 0.5 s + 0.25 s per "
           "operation code): %u of %u statements done, %u violations, %u re-issued, %lu packets, "
           "%u attempts failed\n",
           verdict, (unsigned long)now_ms, n_done, (unsigned)dr_meta_n_statements, violations,
           reissues, packets, failures);
    return any_ended(DR_END_GOAL) && n_done == dr_meta_n_statements && violations == 0 ? 0 : 1;
}
