/* fake_rofi.h - a fake RoFI universal module behind rofi_hal.h, for the platform's tests.
 *
 * Time moves only when the test says (fake_rofi_advance). Joints move from where they are to
 * their target at the velocity they were given; connectors slide in FAKE_ROFI_SLIDE_MS and
 * latch onto a mate the test put in front of them. Callbacks are queued as the hardware's
 * would be and run at dispatch (rofi_hal.h). Failures are injected by the test: a joint that
 * is stuck or errs, a joint that never calls back (as RoFI's ESP32 HAL), no mate in front of
 * a connector, a mate that holds the latch itself, storage that fails. Every packet sent is
 * recorded. */
#ifndef FAKE_ROFI_H
#define FAKE_ROFI_H

#include <stddef.h>
#include <stdint.h>
#include "rofi_hal.h"

#define FAKE_ROFI_JOINTS 3
#define FAKE_ROFI_CONNECTORS 6
#define FAKE_ROFI_SLIDE_MS 280u
#define FAKE_ROFI_QUEUE 32u
#define FAKE_ROFI_SENT 32u
#define FAKE_ROFI_PACKET 300u /* longer than dr_module_receive takes, to test the drop */
#define FAKE_ROFI_STORAGE 512u

struct fake_joint {
    double pos; /* rad */
    /* the move under way */
    uint8_t moving;
    double from;
    double target;
    double velocity;
    uint32_t since_ms;
    rofi_joint_reached_fn done;
    void *done_user;
    /* injections */
    uint8_t stuck;       /* it does not move */
    uint8_t no_callback; /* it reaches its target without calling back */
    /* the error callback */
    rofi_joint_error_fn on_error;
    void *error_user;
    struct rofi_joint_capabilities caps;
    unsigned set_calls;
    float last_velocity;
};

struct fake_connector {
    uint8_t extended; /* this side's position, once a slide ends */
    uint8_t sliding;
    uint8_t slide_to; /* 1: extending */
    uint32_t slide_end_ms;
    uint8_t mate;       /* a free connector faces this one */
    uint8_t mate_holds; /* the mate is extended: connected whatever this side does */
    uint8_t connected;
    uint8_t orientation;
    rofi_connector_event_fn on_event;
    void *event_user;
    rofi_packet_fn on_packet;
    void *packet_user;
    unsigned connect_calls;
    unsigned disconnect_calls;
};

enum fake_event_kind { FAKE_REACHED, FAKE_JOINT_ERROR, FAKE_CONNECTOR_EVENT, FAKE_PACKET };

struct fake_event {
    enum fake_event_kind kind;
    int index;
    int detail; /* the connector event */
    rofi_joint_reached_fn done;
    void *done_user;
    uint16_t content_type;
    size_t len;
    uint8_t bytes[FAKE_ROFI_PACKET];
};

struct fake_sent {
    int connector;
    uint16_t content_type;
    size_t len;
    uint8_t bytes[FAKE_ROFI_PACKET];
};

struct fake_rofi {
    struct rofi_hal hal; /* ctx: this fake */
    int id;
    struct rofi_descriptor descriptor;
    uint32_t now_ms;
    uint32_t rng;
    struct fake_joint joint[FAKE_ROFI_JOINTS];
    struct fake_connector connector[FAKE_ROFI_CONNECTORS];
    struct fake_event queue[FAKE_ROFI_QUEUE];
    unsigned queued;
    struct fake_sent sent[FAKE_ROFI_SENT];
    unsigned n_sent;
    uint8_t storage[FAKE_ROFI_STORAGE]; /* erased: 0xFF */
    uint8_t storage_fails;              /* injection: every read and write fails */
    unsigned dispatches;
    unsigned lost; /* events or packets beyond the queue or the record (fails the test) */
};

/* Module `id`: joints at 0 with RoFI's capabilities (shoes +-1.1 pi / 2, gamma +-0.9 pi, all
 * 2 pi rad/s), connectors retracted with nothing in front, storage erased. */
void fake_rofi_init(struct fake_rofi *f, int id);
/* Moves time on by `ms`, a millisecond at a time. */
void fake_rofi_advance(struct fake_rofi *f, uint32_t ms);
/* A packet from connector c's mate, delivered at the next dispatch. */
void fake_rofi_deliver(struct fake_rofi *f, int c, uint16_t content_type, const uint8_t *data,
                       size_t len);
/* Puts a free connector in front of c (or takes it away), and says whether it holds the
 * latch itself; connection events follow. */
void fake_rofi_set_mate(struct fake_rofi *f, int c, uint8_t mate, uint8_t mate_holds);
/* Joint j's servo reports an error: it stops where it is. */
void fake_rofi_joint_error(struct fake_rofi *f, int j);
/* Degrees to the fake's radians, for positions set by hand. */
double fake_rofi_rad(double degrees);

#endif /* FAKE_ROFI_H */
