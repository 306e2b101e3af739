/* rofi_hal.h - a C99 interface to a RoFI universal module's hardware, in the shape of RoFI's
 * own C++ HAL (softwareComponents/rofiHalInc/include/rofi_hal.hpp), for dr_rofi.c.
 *
 * One `struct rofi_hal` per module: a context pointer and function pointers that each take it
 * (a table rather than plain functions, so that one process can hold several modules, as a
 * simulator does, and a test can put a fake behind it). Every function must be set. Each
 * group follows a class of RoFI's HAL:
 * - RoFI: getId, getDescriptor (how many joints and connectors);
 * - Joint: getCapabilities (limits and speeds), getPosition, setPosition(pos, velocity,
 *   callback), onError(callback);
 * - Connector: getState, connect, disconnect, send(contentType, packet), onPacket(callback),
 *   onConnectorEvent(callback);
 * - Partition: size, read and write at an offset;
 * - and what RoFI leaves to its platform (FreeRTOS, ESP-IDF): a millisecond clock and a
 *   random number.
 * Units are RoFI's: radians and radians per second, as float. Joints and connectors are
 * numbered as in RoFI's HAL (int indices from 0).
 *
 * Callbacks. RoFI calls its callbacks from its own tasks (a servo poller, the connector bus);
 * the module's runtime is not reentrant, so this interface requires every callback to be
 * called from within `dispatch` only: the glue over RoFI's HAL queues what RoFI reports and
 * runs the queue there, in the thread that runs the module (dr_rofi_poll calls dispatch). A
 * callback is a plain function with a `user` pointer, given back unchanged. */
#ifndef ROFI_HAL_H
#define ROFI_HAL_H

#include <stddef.h>
#include <stdint.h>

/* Joint::Implementation::Capabilities. */
struct rofi_joint_capabilities {
    float max_position; /* rad */
    float min_position; /* rad */
    float max_speed;    /* rad / s */
    float min_speed;    /* rad / s */
    float max_torque;   /* N m */
};

/* Joint::Error. */
enum rofi_joint_error {
    ROFI_JOINT_ERROR_COMMUNICATION = 0, /* cannot talk to the servo */
    ROFI_JOINT_ERROR_HARDWARE = 1       /* the servo reported an error */
};

/* ConnectorPosition, ConnectorOrientation. */
enum rofi_connector_position {
    ROFI_CONNECTOR_RETRACTED = 0,
    ROFI_CONNECTOR_EXTENDED = 1
};
enum rofi_connector_orientation {
    ROFI_ORIENTATION_NORTH = 0,
    ROFI_ORIENTATION_EAST = 1,
    ROFI_ORIENTATION_SOUTH = 2,
    ROFI_ORIENTATION_WEST = 3
};

/* The part of ConnectorState the platform reads (RoFI's also has voltages, currents and the
 * lidar, which dynarole does not use). */
struct rofi_connector_state {
    uint8_t position;    /* enum rofi_connector_position: this side's own */
    uint8_t internal;    /* the internal power bus is connected to the connector */
    uint8_t external;    /* the external power bus is connected to the connector */
    uint8_t connected;   /* a mating side is connected (either side may hold the latch) */
    uint8_t orientation; /* enum rofi_connector_orientation; meaningful when connected */
};

/* ConnectorEvent. */
enum rofi_connector_event {
    ROFI_CONNECTOR_CONNECTED = 0,
    ROFI_CONNECTOR_DISCONNECTED = 1,
    ROFI_CONNECTOR_POWER_CHANGED = 2
};

/* RoFI::Descriptor. */
struct rofi_descriptor {
    int joint_count;
    int connector_count;
};

/* setPosition's callback: `joint` reached the position it was sent to. As in RoFI, a later
 * setPosition on the same joint before then means this one is never called. */
typedef void (*rofi_joint_reached_fn)(void *user, int joint);
/* onError's callback (`message` may be 0). */
typedef void (*rofi_joint_error_fn)(void *user, int joint, enum rofi_joint_error error,
                                    const char *message);
/* onConnectorEvent's callback. */
typedef void (*rofi_connector_event_fn)(void *user, int connector,
                                        enum rofi_connector_event event);
/* onPacket's callback: `len` bytes of content type `content_type` from the mating side of
 * `connector` (the bytes are the HAL's: valid during the call only). */
typedef void (*rofi_packet_fn)(void *user, int connector, uint16_t content_type,
                               const uint8_t *data, size_t len);

struct rofi_hal {
    void *ctx; /* passed to every function below */

    /* --- RoFI --- */
    int (*get_id)(void *ctx);
    void (*get_descriptor)(void *ctx, struct rofi_descriptor *out);

    /* --- Joint --- */
    void (*joint_capabilities)(void *ctx, int joint, struct rofi_joint_capabilities *out);
    float (*joint_get_position)(void *ctx, int joint);
    /* Moves toward `pos` (within the capabilities' limits) at most at `velocity` (> 0) and
     * returns at once; `done` (may be 0) is called once the position is reached. */
    void (*joint_set_position)(void *ctx, int joint, float pos, float velocity,
                               rofi_joint_reached_fn done, void *user);
    /* Registers the joint's error callback (replaces the previous one). */
    void (*joint_on_error)(void *ctx, int joint, rofi_joint_error_fn callback, void *user);

    /* --- Connector --- */
    void (*connector_get_state)(void *ctx, int connector, struct rofi_connector_state *out);
    /* Extends the connector (returns at once; a mating side connects later, if any). */
    void (*connector_connect)(void *ctx, int connector);
    /* Retracts the connector (returns at once; the connection it held ends later). */
    void (*connector_disconnect)(void *ctx, int connector);
    void (*connector_on_event)(void *ctx, int connector, rofi_connector_event_fn callback,
                               void *user);
    void (*connector_on_packet)(void *ctx, int connector, rofi_packet_fn callback, void *user);
    /* Sends a packet to the mating side; discarded when there is none (as RoFI's send). */
    void (*connector_send)(void *ctx, int connector, uint16_t content_type, const uint8_t *data,
                           size_t len);

    /* --- Partition-shaped non-volatile storage: byte-addressable and rewritable (the glue
     * erases flash sectors as needed), erased bytes read 0xFF. Not the running firmware's
     * partition: a data partition of the module's own. read and write return 0, or -1 when
     * offset + len is beyond storage_size (RoFI throws std::out_of_range) or the flash
     * failed. --- */
    size_t (*storage_size)(void *ctx);
    int (*storage_read)(void *ctx, size_t offset, uint8_t *buf, size_t len);
    int (*storage_write)(void *ctx, size_t offset, const uint8_t *data, size_t len);

    /* --- the platform --- */
    uint32_t (*now_ms)(void *ctx); /* milliseconds since power-on, wrapping */
    uint32_t (*random)(void *ctx); /* e.g. esp_random() */
    /* Runs the callbacks queued since the last call (the only place callbacks run). */
    void (*dispatch)(void *ctx);
};

#endif /* ROFI_HAL_H */
