/* test_rofi.c - the RoFI platform (dr_rofi.c) over a fake RoFI module (fake_rofi.c): every
 * function of dr_hal.h, the operations' timing, limits and sets, connectors, packets and
 * neighbours. No protocol runtime is linked: the module's entry points the platform calls
 * (dr_module_step, dr_module_receive) are stubs here that record what they are given. */
#include <stdio.h>
#include <string.h>
#include "check.h"
#include "dr_hal.h"
#include "dr_module.h"
#include "dr_rofi.h"
#include "dr_rofi_ops.h"
#include "fake_rofi.h"

/* ---- assertions (check.h) ---- */

unsigned long checks;
unsigned long failures;

int check(int ok, const char *what, const char *file, int line)
{
    checks++;
    if (!ok) {
        failures++;
        fprintf(stderr, "%s:%d: CHECK failed: %s\n", file, line, what);
    }
    return ok;
}

int check_eq(long a, long b, const char *sa, const char *sb, const char *file, int line)
{
    checks++;
    if (a != b) {
        failures++;
        fprintf(stderr, "%s:%d: CHECK failed: %s == %s (%ld != %ld)\n", file, line, sa, sb, a,
                b);
        return 0;
    }
    return 1;
}

/* ---- the module's side: stubs of dr_module.h ---- */

struct dr_module {
    int unused; /* the platform never looks inside */
};

static unsigned steps;
static struct {
    struct dr_module *module;
    uint8_t channel;
    uint8_t len;
    uint8_t bytes[255];
} received[8];
static unsigned n_received;

void dr_module_step(struct dr_module *m)
{
    (void)m;
    steps++;
}

void dr_module_receive(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    if (n_received < 8u) {
        received[n_received].module = m;
        received[n_received].channel = channel;
        received[n_received].len = len;
        memcpy(received[n_received].bytes, bytes, len);
    }
    n_received++;
}

/* ---- the world: one module on one fake ---- */

static struct dr_module module;
static struct fake_rofi fake;
static struct dr_rofi rofi;

static void setup(void)
{
    CHECK_EQ(fake.lost, 0); /* the last test's queue and record were big enough */
    fake_rofi_init(&fake, 42);
    CHECK_EQ(dr_rofi_init(&rofi, &fake.hal, &module), 0);
    steps = 0;
    n_received = 0;
}

/* Time moves on by `ms`, the main loop polling at every millisecond. */
static void run(uint32_t ms)
{
    while (ms-- > 0u) {
        fake_rofi_advance(&fake, 1);
        dr_rofi_poll(&rofi);
    }
}

static void rotate(uint8_t joint, int16_t from, int16_t to, int16_t increasing, int16_t speed)
{
    int16_t args[4];
    args[0] = from;
    args[1] = to;
    args[2] = increasing;
    args[3] = speed;
    dr_hal_op_start(&module, 1, DR_OP_JOINT_ROTATEFROMTOBY, joint, args);
}

static void connector(uint8_t op, uint8_t c)
{
    dr_hal_op_start(&module, 2, op, c, 0);
}

static enum dr_op_status status(void)
{
    return dr_hal_op_status(&module);
}

static void put_joint(uint8_t j, double degrees)
{
    fake.joint[j].pos = fake_rofi_rad(degrees);
}

static int near(double a, double b)
{
    return a - b < 1e-3 && b - a < 1e-3;
}

/* ---- joints ---- */

/* A quarter turn at the top speed (2 pi rad/s) takes 250 ms: still running at 99 % of it
 * (a turn ends when the joint reads within 0.5 degrees), done at 250 ms. */
static void test_rotate_time(void)
{
    setup();
    CHECK_EQ(status(), DR_OP_DONE); /* nothing started yet */
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100);
    CHECK_EQ(status(), DR_OP_RUNNING);
    CHECK_EQ(fake.joint[0].set_calls, 1);
    CHECK(near(fake.joint[0].last_velocity, 2.0 * 3.14159265358979));
    CHECK(near(fake.joint[0].target, fake_rofi_rad(90.0)));
    run(247);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(3);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 90);
    /* 45 degrees down: 125 ms */
    rotate(DR_ROFI_ALPHA, 90, 45, 0, 100);
    run(123);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(2);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 45);
}

/* speed % of the top speed: 50 % doubles the time, 25 % quadruples it. */
static void test_speed_percent(void)
{
    setup();
    rotate(DR_ROFI_BETA, 0, 90, 1, 50);
    CHECK(near(fake.joint[1].last_velocity, 3.14159265358979));
    run(495);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(5);
    CHECK_EQ(status(), DR_OP_DONE);
    rotate(DR_ROFI_BETA, 90, 0, 0, 25);
    CHECK(near(fake.joint[1].last_velocity, 3.14159265358979 / 2.0));
    run(990);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(10);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_BETA), 0);
}

/* The shoe joints stop at +-99 degrees (1.1 pi / 2): a target beyond fails at once, and the
 * joint is not asked to move. A target the other way than `increasing` fails too. */
static void test_shoe_limits(void)
{
    setup();
    rotate(DR_ROFI_ALPHA, 0, 100, 1, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_BETA, 0, -100, 0, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_ALPHA, 0, 45, 0, 100); /* 45 lies the increasing way */
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(fake.joint[0].set_calls + fake.joint[1].set_calls, 0);
    rotate(DR_ROFI_ALPHA, 0, 99, 1, 100); /* the limit itself */
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(300);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 99);
    rotate(DR_ROFI_BETA, 0, -90, 0, 100);
    run(250);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_BETA), -90);
}

/* Gamma is an absolute servo within +-162 degrees (0.9 pi): reaching `to` the increasing way
 * works when `to` is above where it is; from 90 to -90 increasing would cross the stop at
 * 162 / 180 / -162 and fails; decreasing works. */
static void test_gamma_direction(void)
{
    setup();
    rotate(DR_ROFI_GAMMA, 0, 90, 1, 100);
    run(250);
    CHECK_EQ(status(), DR_OP_DONE);
    rotate(DR_ROFI_GAMMA, 90, -90, 1, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(fake.joint[2].set_calls, 1);
    rotate(DR_ROFI_GAMMA, 90, -90, 0, 100);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(495);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(5);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), -90);
    /* beyond the stop: 170 either way */
    rotate(DR_ROFI_GAMMA, -90, 170, 1, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_GAMMA, -90, -170, 0, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    /* 150 to -150 the increasing way is 60 degrees for the model, across 180 for RoFI */
    put_joint(DR_ROFI_GAMMA, 150.0);
    rotate(DR_ROFI_GAMMA, 150, -150, 1, 100);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_GAMMA, 150, 160, 1, 100); /* within the stop */
    run(30);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.joint[2].set_calls, 3);
}

/* A turn whose joint is already within 0.5 degrees of `to` completes at once, unmoved. */
static void test_idempotent(void)
{
    setup();
    put_joint(DR_ROFI_ALPHA, 30.0);
    rotate(DR_ROFI_ALPHA, 0, 30, 1, 100);
    CHECK_EQ(status(), DR_OP_DONE);
    put_joint(DR_ROFI_ALPHA, 30.4);
    rotate(DR_ROFI_ALPHA, 0, 30, 1, 100); /* 0.4 below `increasing`: still there */
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.joint[0].set_calls, 0);
    put_joint(DR_ROFI_ALPHA, 30.6);
    rotate(DR_ROFI_ALPHA, 60, 30, 0, 100);
    CHECK_EQ(status(), DR_OP_RUNNING);
    CHECK_EQ(fake.joint[0].set_calls, 1);
    run(10);
    CHECK_EQ(status(), DR_OP_DONE);
    /* re-issued after it took effect */
    rotate(DR_ROFI_GAMMA, 0, -45, 0, 100);
    run(125);
    CHECK_EQ(status(), DR_OP_DONE);
    rotate(DR_ROFI_GAMMA, 0, -45, 0, 100);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.joint[2].set_calls, 1);
}

/* Two at once: DONE only when both are done (the shorter one first). */
static void test_two_at_once(void)
{
    setup();
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100); /* 250 ms */
    rotate(DR_ROFI_BETA, 0, 45, 1, 100);  /* 125 ms */
    run(130);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_BETA), 45);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(120);
    CHECK_EQ(status(), DR_OP_DONE);
    /* a joint and a connector: the connector's slide (280 ms) is the longer */
    fake_rofi_set_mate(&fake, 0, 1, 0);
    rotate(DR_ROFI_ALPHA, 90, 0, 0, 100);
    connector(DR_OP_CONNECTOR_CONNECT, 0);
    run(279);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 0);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(1);
    CHECK_EQ(status(), DR_OP_DONE);
}

/* One fails while the other runs: RUNNING until both have ended, then FAILED; the next start
 * begins a new set. */
static void test_one_fails(void)
{
    setup();
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100);
    rotate(DR_ROFI_BETA, 0, 45, 1, 100);
    run(50);
    fake_rofi_joint_error(&fake, DR_ROFI_BETA);
    run(1);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(199);
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 90);
    rotate(DR_ROFI_ALPHA, 90, 0, 0, 100);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(250);
    CHECK_EQ(status(), DR_OP_DONE);
    /* refused at the start while another runs: FAILED once that one ends */
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100);
    rotate(DR_ROFI_BETA, 0, -120, 0, 100);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(250);
    CHECK_EQ(status(), DR_OP_FAILED);
    /* a second turn of a joint whose turn still runs is refused; the first carries on */
    rotate(DR_ROFI_ALPHA, 90, 0, 0, 100);
    rotate(DR_ROFI_ALPHA, 0, 45, 1, 100);
    CHECK_EQ(fake.joint[0].set_calls, 4);
    run(250);
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 0);
    /* an error with no turn under way is only counted */
    fake_rofi_joint_error(&fake, DR_ROFI_GAMMA);
    run(1);
    CHECK_EQ(rofi.joint_errors, 1);
}

/* A joint that does not get there fails after twice its time plus the slack; one that never
 * calls back (as RoFI's ESP32 HAL) is done by its reading. */
static void test_joint_timeout_and_reading(void)
{
    setup();
    fake.joint[0].stuck = 1;
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100);
    run(2u * 250u + DR_ROFI_JOINT_SLACK_MS - 1u);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(1);
    CHECK_EQ(status(), DR_OP_FAILED);
    setup();
    fake.joint[1].no_callback = 1;
    rotate(DR_ROFI_BETA, 0, 90, 1, 100);
    run(247);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(3);
    CHECK_EQ(status(), DR_OP_DONE);
}

/* Operations this module does not have, and bad arguments: FAILED, nothing moved. */
static void test_refused(void)
{
    int16_t args[4] = {0, 45, 1, 100};
    setup();
    dr_hal_op_start(&module, 0, 99, 0, args);
    CHECK_EQ(status(), DR_OP_FAILED);
    dr_hal_op_start(&module, 0, DR_OP_JOINT_ROTATEFROMTOBY, 3, args);
    CHECK_EQ(status(), DR_OP_FAILED);
    dr_hal_op_start(&module, 0, DR_OP_CONNECTOR_CONNECT, 6, 0);
    CHECK_EQ(status(), DR_OP_FAILED);
    dr_hal_op_start(&module, 0, DR_OP_JOINT_ROTATEFROMTOBY, 0, 0);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_ALPHA, 0, 45, 1, 0);
    CHECK_EQ(status(), DR_OP_FAILED);
    rotate(DR_ROFI_ALPHA, 0, 45, 1, 101);
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(fake.joint[0].set_calls, 0);
    CHECK_EQ(fake.connector[0].connect_calls, 0);
    rotate(DR_ROFI_ALPHA, 0, 45, 1, 100); /* a new set */
    CHECK_EQ(status(), DR_OP_RUNNING);
}

/* ---- connectors ---- */

static void test_connect_disconnect(void)
{
    setup();
    fake_rofi_set_mate(&fake, 1, 1, 0); /* a free connector in front, not extended */
    run(1);
    CHECK_EQ(dr_hal_connected(&module, 1), 0);
    connector(DR_OP_CONNECTOR_CONNECT, 1);
    CHECK_EQ(status(), DR_OP_RUNNING);
    CHECK_EQ(fake.connector[1].connect_calls, 1);
    run(279);
    CHECK_EQ(status(), DR_OP_RUNNING);
    CHECK_EQ(dr_hal_connected(&module, 1), 0);
    run(1);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_connected(&module, 1), 1);
    connector(DR_OP_CONNECTOR_CONNECT, 1); /* again: at once */
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.connector[1].connect_calls, 1);
    connector(DR_OP_CONNECTOR_DISCONNECT, 1);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(280);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(dr_hal_connected(&module, 1), 0);
    connector(DR_OP_CONNECTOR_DISCONNECT, 1); /* again: at once */
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.connector[1].disconnect_calls, 1);
    /* the other side holds the latch: connected already, and our retract cannot release it */
    fake_rofi_set_mate(&fake, 2, 1, 1);
    connector(DR_OP_CONNECTOR_CONNECT, 2);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.connector[2].connect_calls, 0);
    CHECK_EQ(dr_hal_connected(&module, 2), 1);
    connector(DR_OP_CONNECTOR_DISCONNECT, 2);
    run(DR_ROFI_CONNECTOR_TIMEOUT_MS - 1u);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(1);
    CHECK_EQ(status(), DR_OP_FAILED);
    /* nothing in front: the connect times out, the connector left extended; a disconnect
     * retracts it */
    connector(DR_OP_CONNECTOR_CONNECT, 3);
    run(DR_ROFI_CONNECTOR_TIMEOUT_MS);
    CHECK_EQ(status(), DR_OP_FAILED);
    CHECK_EQ(fake.connector[3].extended, 1);
    connector(DR_OP_CONNECTOR_DISCONNECT, 3);
    CHECK_EQ(status(), DR_OP_RUNNING);
    run(280);
    CHECK_EQ(status(), DR_OP_DONE);
    CHECK_EQ(fake.connector[3].extended, 0);
    CHECK_EQ(dr_hal_connected(&module, 6), 0);
}

/* Broadcast: every connected connector, nothing else; send: the one connector asked. */
static void test_broadcast_and_send(void)
{
    static const uint8_t bytes[5] = {1, 5, 9, 8, 7};
    setup();
    fake_rofi_set_mate(&fake, 0, 1, 1);
    fake_rofi_set_mate(&fake, 4, 1, 1);
    fake_rofi_set_mate(&fake, 5, 1, 0); /* in front but not latched */
    dr_hal_broadcast(&module, bytes, 5);
    CHECK_EQ(fake.n_sent, 2);
    CHECK_EQ(fake.sent[0].connector, 0);
    CHECK_EQ(fake.sent[1].connector, 4);
    CHECK_EQ(fake.sent[0].content_type, DR_ROFI_CONTENT_TYPE);
    CHECK_EQ(fake.sent[1].len, 5);
    CHECK(memcmp(fake.sent[1].bytes, bytes, 5) == 0);
    dr_hal_send(&module, 3, bytes, 2);
    CHECK_EQ(fake.n_sent, 3);
    CHECK_EQ(fake.sent[2].connector, 3);
    CHECK_EQ(fake.sent[2].len, 2);
    dr_hal_send(&module, 6, bytes, 2);
    dr_hal_send(&module, 255, bytes, 2);
    CHECK_EQ(fake.n_sent, 3);
}

/* Neighbour IDs: -1 until the module's discovery sets one, kept while connected, forgotten
 * at a disconnect (the next module there may be another). */
static void test_neighbours(void)
{
    uint8_t c;
    setup();
    fake_rofi_set_mate(&fake, 0, 1, 1);
    run(1);
    for (c = 0; c < 7u; c++) {
        CHECK_EQ(dr_hal_neighbour_id(&module, c), -1);
    }
    CHECK_EQ(dr_rofi_set_neighbour(&module, 0, 17), 1);
    CHECK_EQ(dr_hal_neighbour_id(&module, 0), 17);
    CHECK_EQ(dr_rofi_set_neighbour(&module, 1, 18), 0); /* not connected */
    CHECK_EQ(dr_hal_neighbour_id(&module, 1), -1);
    CHECK_EQ(dr_rofi_set_neighbour(&module, 6, 18), 0);
    fake_rofi_set_mate(&fake, 0, 0, 0); /* the mate leaves */
    run(1);
    CHECK_EQ(dr_hal_neighbour_id(&module, 0), -1);
    fake_rofi_set_mate(&fake, 0, 1, 1); /* another comes */
    run(1);
    CHECK_EQ(dr_hal_neighbour_id(&module, 0), -1);
    /* a disconnect not yet dispatched: the state already says so */
    CHECK_EQ(dr_rofi_set_neighbour(&module, 0, 21), 1);
    fake.connector[0].connected = 0;
    CHECK_EQ(dr_hal_neighbour_id(&module, 0), -1);
}

/* ---- readings, storage, packets, the rest ---- */

/* Whole degrees, rounded half away from zero; (-180, 180]. */
static void test_joint_reading(void)
{
    setup();
    put_joint(DR_ROFI_ALPHA, 44.6);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 45);
    put_joint(DR_ROFI_ALPHA, 44.4);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_ALPHA), 44);
    put_joint(DR_ROFI_BETA, -44.6);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_BETA), -45);
    put_joint(DR_ROFI_BETA, -0.4);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_BETA), 0);
    put_joint(DR_ROFI_GAMMA, 190.0);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), -170);
    put_joint(DR_ROFI_GAMMA, -190.0);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 170);
    put_joint(DR_ROFI_GAMMA, -180.0);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 180);
    put_joint(DR_ROFI_GAMMA, 179.6);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 180);
    put_joint(DR_ROFI_GAMMA, -179.6);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 180);
    put_joint(DR_ROFI_GAMMA, -179.4);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), -179);
    put_joint(DR_ROFI_GAMMA, 540.0);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 180);
    put_joint(DR_ROFI_GAMMA, 1e9);
    CHECK_EQ(dr_hal_joint(&module, DR_ROFI_GAMMA), 0);
    CHECK_EQ(dr_hal_joint(&module, 3), 0);
}

static void test_nv(void)
{
    static const uint8_t record[4] = {0xDE, 0xAD, 0x00, 0x42};
    uint8_t buf[4];
    setup();
    dr_hal_nv_read(&module, 100, buf, 4);
    CHECK(buf[0] == 0xFF && buf[3] == 0xFF);
    dr_hal_nv_write(&module, 100, record, 4);
    memset(buf, 0, sizeof buf);
    dr_hal_nv_read(&module, 100, buf, 4);
    CHECK(memcmp(buf, record, 4) == 0);
    CHECK_EQ(fake.storage[103], 0x42);
    CHECK_EQ(rofi.nv_errors, 0);
    dr_hal_nv_write(&module, FAKE_ROFI_STORAGE - 2u, record, 4); /* beyond the partition */
    CHECK_EQ(fake.storage[FAKE_ROFI_STORAGE - 2u], 0xFF);
    memset(buf, 0, sizeof buf);
    dr_hal_nv_read(&module, FAKE_ROFI_STORAGE - 2u, buf, 4);
    CHECK(buf[0] == 0xFF && buf[1] == 0xFF);
    CHECK_EQ(rofi.nv_errors, 2);
    fake.storage_fails = 1;
    memset(buf, 0, sizeof buf);
    dr_hal_nv_read(&module, 100, buf, 4);
    CHECK(buf[0] == 0xFF && buf[3] == 0xFF);
    dr_hal_nv_write(&module, 100, buf, 4);
    CHECK_EQ(rofi.nv_errors, 4);
}

/* Packets of dynarole's content type reach dr_module_receive at dispatch, with the connector
 * as the channel; others are dropped. */
static void test_packets(void)
{
    static uint8_t bytes[FAKE_ROFI_PACKET];
    setup();
    bytes[0] = 0xA5;
    bytes[1] = 3;
    bytes[2] = 0x5A;
    fake_rofi_deliver(&fake, 2, DR_ROFI_CONTENT_TYPE, bytes, 3);
    CHECK_EQ(n_received, 0); /* only at dispatch */
    run(1);
    CHECK_EQ(n_received, 1);
    CHECK(received[0].module == &module);
    CHECK_EQ(received[0].channel, 2);
    CHECK_EQ(received[0].len, 3);
    CHECK(memcmp(received[0].bytes, bytes, 3) == 0);
    fake_rofi_deliver(&fake, 5, DR_ROFI_CONTENT_TYPE, bytes, 255);
    fake_rofi_deliver(&fake, 4, (uint16_t)(DR_ROFI_CONTENT_TYPE + 1u), bytes, 3);
    fake_rofi_deliver(&fake, 4, DR_ROFI_CONTENT_TYPE, bytes, 256);
    fake_rofi_deliver(&fake, 4, DR_ROFI_CONTENT_TYPE, bytes, 0);
    run(1);
    CHECK_EQ(n_received, 2);
    CHECK_EQ(received[1].channel, 5);
    CHECK_EQ(received[1].len, 255);
    CHECK_EQ(rofi.dropped, 3);
    dr_rofi_packet_arrived(&rofi, 6, DR_ROFI_CONTENT_TYPE, bytes, 3);
    dr_rofi_packet_arrived(&rofi, -1, DR_ROFI_CONTENT_TYPE, bytes, 3);
    CHECK_EQ(n_received, 2);
    CHECK_EQ(rofi.dropped, 5);
}

/* dr_rofi_poll steps at once, then every DR_ROFI_STEP_MS; the HAL's queue runs at each. */
static void test_poll(void)
{
    setup();
    dr_rofi_poll(&rofi);
    CHECK_EQ(steps, 1);
    dr_rofi_poll(&rofi);
    CHECK_EQ(steps, 1);
    fake_rofi_advance(&fake, DR_ROFI_STEP_MS - 1u);
    dr_rofi_poll(&rofi);
    CHECK_EQ(steps, 1);
    fake_rofi_advance(&fake, 1);
    dr_rofi_poll(&rofi);
    CHECK_EQ(steps, 2);
    run(100);
    CHECK_EQ(steps, 2u + 100u / DR_ROFI_STEP_MS);
    CHECK_EQ(fake.dispatches, 104);
}

/* ID, clock, random numbers, LEDs; a module the HAL says is smaller is refused; two modules
 * in one process keep apart. */
static void test_rest(void)
{
    static struct fake_rofi other_fake;
    static struct dr_rofi other_rofi;
    static struct dr_module other;
    static struct fake_rofi small;
    static struct dr_rofi small_rofi;
    uint16_t a;
    setup();
    CHECK_EQ(dr_hal_id(&module), 42);
    fake_rofi_advance(&fake, 1234);
    CHECK_EQ(dr_hal_now_ms(&module), 1234);
    a = dr_hal_random(&module);
    CHECK(a != dr_hal_random(&module));
    dr_hal_leds(&module, 3);
    fake_rofi_init(&small, 9);
    small.descriptor.connector_count = 2;
    CHECK_EQ(dr_rofi_init(&small_rofi, &small.hal, &other), -1);
    fake_rofi_init(&other_fake, 7);
    CHECK_EQ(dr_rofi_init(&other_rofi, &other_fake.hal, &other), 0);
    CHECK_EQ(dr_rofi_init(&rofi, &fake.hal, &module), 0); /* again: no second entry */
    CHECK_EQ(dr_hal_id(&other), 7);
    CHECK_EQ(dr_hal_id(&module), 42);
    rotate(DR_ROFI_ALPHA, 0, 90, 1, 100);
    CHECK_EQ(dr_hal_op_status(&other), DR_OP_DONE);
    CHECK_EQ(fake.joint[0].set_calls, 1);
    CHECK_EQ(other_fake.joint[0].set_calls, 0);
}

int main(void)
{
    test_rotate_time();
    test_speed_percent();
    test_shoe_limits();
    test_gamma_direction();
    test_idempotent();
    test_two_at_once();
    test_one_fails();
    test_joint_timeout_and_reading();
    test_refused();
    test_connect_disconnect();
    test_broadcast_and_send();
    test_neighbours();
    test_joint_reading();
    test_nv();
    test_packets();
    test_poll();
    test_rest();
    CHECK_EQ(fake.lost, 0);
    printf("test_rofi: %lu checks, %lu failed\n", checks, failures);
    return failures == 0u ? 0 : 1;
}
