/* dr_rofi.h - the RoFI platform of dr_hal.h (dr_rofi.c): its state per module and its own
 * entry points, for the firmware's main loop and the glue over RoFI's HAL (rofi_hal.h).
 *
 * A module's firmware:
 *     static struct dr_rofi rofi;  static dr_module_t module;
 *     dr_rofi_init(&rofi, &hal, &module);   (hal: a struct rofi_hal over RoFI's HAL)
 *     dr_program_init(&module, &rofi);      (generated: dr_program.h)
 *     for (;;) { dr_rofi_poll(&rofi); sleep about DR_ROFI_STEP_MS; }
 * The platform finds a module's struct dr_rofi from the module pointer the runtime passes to
 * dr_hal.h (a list of the initialised ones, one entry on a real module), so it needs nothing
 * of the protocol's dr_module_t. */
#ifndef DR_ROFI_H
#define DR_ROFI_H

#include <stddef.h>
#include <stdint.h>
#include "rofi_hal.h"

struct dr_module;

/* The universal module: joints alpha, beta, gamma (RoFI's HAL order) and connectors
 * 3 * side + dock (robots/rofi/rofi.robot.toml). */
#define DR_ROFI_JOINTS 3u
#define DR_ROFI_CONNECTORS 6u
#define DR_ROFI_ALPHA 0u
#define DR_ROFI_BETA 1u
#define DR_ROFI_GAMMA 2u

/* The content type of dynarole's packets on a RoFICoM (RoFI's send and onPacket carry one);
 * packets of any other type are other software's and are left alone. */
#ifndef DR_ROFI_CONTENT_TYPE
#define DR_ROFI_CONTENT_TYPE 0x4452u /* "DR" */
#endif
/* dr_rofi_poll steps the module at most once per this many ms. */
#ifndef DR_ROFI_STEP_MS
#define DR_ROFI_STEP_MS 5u
#endif
/* A joint counts as at a position within this many degrees: a turn whose target is that
 * close completes at once (idempotence), and a running turn is done once the joint reads
 * that close. */
#ifndef DR_ROFI_TOLERANCE_DEG
#define DR_ROFI_TOLERANCE_DEG 0.5f
#endif
/* A turn fails when it has not ended within twice its expected time plus this. */
#ifndef DR_ROFI_JOINT_SLACK_MS
#define DR_ROFI_JOINT_SLACK_MS 500u
#endif
/* A connect or disconnect fails when it has not taken effect within this (a RoFICoM slides
 * in about 0.3 s). */
#ifndef DR_ROFI_CONNECTOR_TIMEOUT_MS
#define DR_ROFI_CONNECTOR_TIMEOUT_MS 3000u
#endif

/* One operation in flight on a joint or a connector. */
struct dr_rofi_op {
    uint8_t running;
    uint8_t connect;      /* connectors: 1 connect, 0 disconnect */
    float target;         /* joints: rad */
    uint32_t deadline_ms; /* it fails if still running then */
};

struct dr_rofi {
    const struct rofi_hal *hal;
    struct dr_module *module;
    struct rofi_joint_capabilities caps[DR_ROFI_JOINTS]; /* read once: constants on RoFI */
    struct dr_rofi_op joint[DR_ROFI_JOINTS];
    struct dr_rofi_op connector[DR_ROFI_CONNECTORS];
    uint8_t failed;                        /* an operation of the current set failed */
    int16_t neighbour[DR_ROFI_CONNECTORS]; /* dr_rofi_set_neighbour's, -1: unknown */
    uint8_t stepped;                       /* the module has been stepped once */
    uint32_t last_step_ms;
    /* Counters, for a debugger: packets dropped (another content type, a bad connector, too
     * long for dr_module_receive), NV accesses refused, joint errors outside an operation. */
    uint32_t dropped;
    uint32_t nv_errors;
    uint32_t joint_errors;
    struct dr_rofi *next; /* the list of initialised modules */
};

/* Binds module `m` to the hardware `hal` (kept by pointer: it must outlive r), registers the
 * platform's callbacks with every joint and connector, and reads the joints' capabilities.
 * Nothing runs, no neighbour is known. Call it before dr_program_init, and again after a
 * reset. Returns 0, or -1 when the HAL's module has fewer joints or connectors than a
 * universal module (then r is not used). */
int dr_rofi_init(struct dr_rofi *r, const struct rofi_hal *hal, struct dr_module *m);

/* The main loop's call, every few ms: runs the HAL's queued callbacks (packets go to
 * dr_module_receive as they are delivered), ends the operations that took effect, failed or
 * timed out, then steps the module if DR_ROFI_STEP_MS passed since its last step. */
void dr_rofi_poll(struct dr_rofi *r);

/* The HAL's packet callback (registered by dr_rofi_init on every connector, `user` being the
 * struct dr_rofi): a packet of DR_ROFI_CONTENT_TYPE is handed to dr_module_receive with the
 * connector as its channel; others are dropped. */
void dr_rofi_packet_arrived(void *user, int connector, uint16_t content_type,
                            const uint8_t *data, size_t len);

/* RoFI's HAL does not say which module is on a connector's other side, and a dynarole frame
 * does not carry its sender's ID, so the module's own discovery code says it: `id` is the
 * module latched to `connector`. Kept only while the connector is connected (refused, 0
 * returned, when it is not); forgotten when it disconnects. Returns 1 when kept. */
uint8_t dr_rofi_set_neighbour(struct dr_module *m, uint8_t connector, int16_t id);

#endif /* DR_ROFI_H */
