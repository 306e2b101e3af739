/* dr_avr_emu.c - an emulated hemisphere board around a simavr ATmega128
 * (dr_avr_emu.h says what the host sees; ../README.md and ../dr_avr_board.h describe the
 * board). simavr calls back here when the firmware writes PORTD (the controller's strobes),
 * PORTE (the status pins) or sends a byte on USART0; each becomes a log entry stamped with
 * the core's cycle count. Sleeping costs no wall time: simavr's sleep callback is replaced. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_irq.h>
#include <sim_io.h>
#include <avr_ioport.h>
#include <avr_uart.h>
#include <avr_eeprom.h>
#include <avr_extint.h>
#include "dr_avr_board.h"
#include "dr_avr_emu.h"

/* One byte on the infrared line (10 bits at DR_AVR_BAUD). */
#define CYCLES_PER_BYTE (DR_AVR_F_CPU * 10u / DR_AVR_BAUD)
/* The arbiter releases a frame by itself this long after its last byte (carrier gone) when
 * the firmware did not, so that a frame the firmware missed cannot block the next ones. */
#define ARBITER_MARGIN_BYTES 4u

struct rx_frame {
    uint8_t channel;
    uint8_t len;
    uint8_t bytes[DRAV_MAX_FRAME];
};

struct drav_core {
    avr_t *avr;
    elf_firmware_t firmware;
    uint16_t paint_from; /* first byte above .data and .bss (the linker's _end) */
    uint16_t description; /* address of dr_avr_description, 0 when the image has none */
    uint8_t porte;        /* PORTE as last written, for edge detection */
    uint8_t regs[DR_AVR_REGS];
    uint8_t reg;         /* the bus's current register address */
    uint8_t portd;       /* PORTD as last written, for edge detection */
    avr_irq_t *uart_in;
    avr_irq_t *pina[8];
    avr_irq_t *op_end; /* PD0 (INT0): the operation has ended */
    struct drav_event log[DRAV_EVENTS];
    uint32_t log_head;
    uint32_t log_count;
    int overflowed;
    struct rx_frame rx[DRAV_RX_QUEUE];
    uint32_t rx_head;
    uint32_t rx_count;
    int locked;          /* a frame is with the firmware (not released yet) */
    uint64_t lock_until; /* ... at most until this cycle (the frame's air time and a margin) */
    uint64_t sleep_cycles;
    uint8_t eeprom_save[4096]; /* the EEPROM across a reset (the ATmega128 has 4 KB) */
};

uint32_t drav_event_size(void)
{
    return (uint32_t)sizeof(struct drav_event);
}

static void note(struct drav_core *c, uint8_t kind, uint8_t a, uint8_t b)
{
    struct drav_event *e;
    if (c->log_count >= DRAV_EVENTS) {
        c->overflowed = 1;
        return;
    }
    e = &c->log[(c->log_head + c->log_count) % DRAV_EVENTS];
    memset(e, 0, sizeof *e);
    e->cycle = c->avr->cycle;
    e->kind = kind;
    e->a = a;
    e->b = b;
    c->log_count++;
}

static uint8_t port_value(struct drav_core *c, char name)
{
    avr_ioport_state_t state;
    if (avr_ioctl(c->avr, (uint32_t)AVR_IOCTL_IOPORT_GETSTATE(name), &state) != 0) {
        return 0;
    }
    return state.port;
}

/* Drives PINA (the controller's answer) pin by pin, as the board's bus drivers would. */
static void drive_pina(struct drav_core *c, uint8_t value)
{
    uint32_t i;
    for (i = 0; i < 8u; i++) {
        avr_raise_irq(c->pina[i], (value >> i) & 1u);
    }
}

/* The operation-end line follows the status register: low while an operation runs. */
static void drive_op_end(struct drav_core *c)
{
    if (c->avr) {
        avr_raise_irq(c->op_end, c->regs[DR_AVR_REG_STATUS] != 0u);
    }
}

/* A cycle timer that does nothing: it only bounds a sleeping core's jump (simavr sleeps
 * until its next timer event), so that the core stops where the host or the arbiter
 * needs it. */
static avr_cycle_count_t wake_only(struct avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)avr;
    (void)when;
    (void)param;
    return 0;
}

/* The arbiter passes the next queued frame to the USART once the previous is released. */
static void feed(struct drav_core *c)
{
    const struct rx_frame *f;
    uint32_t i;
    if (!c->avr || c->locked || c->rx_count == 0u) {
        return;
    }
    f = &c->rx[c->rx_head];
    c->regs[DR_AVR_REG_RX_CHANNEL] = f->channel;
    for (i = 0; i < f->len; i++) {
        avr_raise_irq(c->uart_in, f->bytes[i]);
    }
    c->locked = 1;
    c->lock_until = c->avr->cycle + ((uint64_t)f->len + ARBITER_MARGIN_BYTES) * CYCLES_PER_BYTE;
    avr_cycle_timer_register(c->avr, c->lock_until - c->avr->cycle, wake_only, &c->lock_until);
    c->rx_head = (c->rx_head + 1u) % DRAV_RX_QUEUE;
    c->rx_count--;
}

static void on_portd(struct avr_irq_t *irq, uint32_t value, void *param)
{
    struct drav_core *c = param;
    uint8_t v = (uint8_t)value;
    uint8_t rising = (uint8_t)(v & ~c->portd);
    uint8_t data = port_value(c, 'B');
    (void)irq;
    c->portd = v;
    if (rising & (1u << DR_AVR_STROBE_ADDR)) {
        c->reg = (uint8_t)(data % DR_AVR_REGS);
    }
    if (rising & (1u << DR_AVR_STROBE_WRITE)) {
        c->regs[c->reg] = data;
        if (c->reg == DR_AVR_REG_GO) {
            c->regs[DR_AVR_REG_STATUS] = 0; /* running, until the host says otherwise */
            drive_op_end(c);
        }
        note(c, DRAV_EV_WRITE, c->reg, data);
        c->reg = (uint8_t)((c->reg + 1u) % DR_AVR_REGS);
    }
    if (rising & (1u << DR_AVR_STROBE_READ)) {
        drive_pina(c, c->regs[c->reg]);
        c->reg = (uint8_t)((c->reg + 1u) % DR_AVR_REGS);
    }
    if (rising & (1u << DR_AVR_STROBE_RELEASE)) {
        note(c, DRAV_EV_RELEASE, 0, 0);
        c->locked = 0;
        feed(c);
    }
}

/* The firmware's state description (a NUL-terminated string in its RAM), two characters a
 * log entry, ending with the entry that holds the NUL. */
static void note_description(struct drav_core *c)
{
    uint32_t i;
    uint32_t at = c->description;
    for (i = 0; i < DR_AVR_DESCRIPTION; i += 2u) {
        uint8_t a = c->avr->data[at + i];
        /* the buffer's last byte counts as its NUL */
        uint8_t b = (a == 0u || i + 2u >= DR_AVR_DESCRIPTION) ? 0u : c->avr->data[at + i + 1u];
        note(c, DRAV_EV_TEXT, a, b);
        if (a == 0u || b == 0u) {
            return;
        }
    }
}

static void on_porte(struct avr_irq_t *irq, uint32_t value, void *param)
{
    struct drav_core *c = param;
    uint8_t rising = (uint8_t)(value & ~c->porte);
    (void)irq;
    c->porte = (uint8_t)value;
    if (rising & (1u << DR_AVR_PIN_DESCRIBED)) {
        if (c->description != 0u) {
            note_description(c);
        }
        return;
    }
    note(c, DRAV_EV_PINS, (uint8_t)value, 0);
}

static void on_uart_out(struct avr_irq_t *irq, uint32_t value, void *param)
{
    struct drav_core *c = param;
    (void)irq;
    note(c, DRAV_EV_TX, (uint8_t)value, port_value(c, 'C'));
}

/* Sleeping advances the cycle count only (simavr jumps to its next timer event); no
 * wall-clock wait. The jump is counted as time asleep. */
static void no_sleep(avr_t *avr, avr_cycle_count_t how_long)
{
    struct drav_core *c = avr->custom.data;
    if (c) {
        c->sleep_cycles += 1u + how_long;
    }
}

/* simavr's messages go nowhere: the host reports what matters (a stopped core). */
static void quiet(avr_t *avr, const int level, const char *format, va_list ap)
{
    (void)avr;
    (void)level;
    (void)format;
    (void)ap;
}

static void paint(struct drav_core *c)
{
    uint32_t a;
    for (a = c->paint_from; a <= c->avr->ramend; a++) {
        c->avr->data[a] = DR_AVR_PAINT;
    }
}

/* The RAM address of data symbol `name` (simavr gives it with 0x800000 added), or 0. */
static uint16_t ram_symbol(const struct drav_core *c, const char *name)
{
    uint32_t i;
    for (i = 0; i < c->firmware.symbolcount; i++) {
        if (strcmp(c->firmware.symbol[i]->symbol, name) == 0) {
            return (uint16_t)(c->firmware.symbol[i]->addr & 0xFFFFu);
        }
    }
    return 0;
}

static int find_symbols(struct drav_core *c)
{
    c->paint_from = ram_symbol(c, "_end");
    c->description = ram_symbol(c, "dr_avr_description");
    if (c->description != 0u && (uint32_t)c->description + DR_AVR_DESCRIPTION > c->avr->ramend) {
        c->description = 0;
    }
    return c->paint_from > 0x100u && c->paint_from <= c->avr->ramend;
}

static int wire(struct drav_core *c)
{
    avr_irq_t *portd = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_IOPORT_GETIRQ('D'), IOPORT_IRQ_REG_PORT);
    avr_irq_t *porte = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_IOPORT_GETIRQ('E'), IOPORT_IRQ_REG_PORT);
    avr_irq_t *out = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT);
    uint32_t i;
    c->uart_in = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    c->op_end = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_IOPORT_GETIRQ('D'), DR_AVR_PIN_OP_END);
    for (i = 0; i < 8u; i++) {
        c->pina[i] = avr_io_getirq(c->avr, (uint32_t)AVR_IOCTL_IOPORT_GETIRQ('A'), (int)i);
        if (!c->pina[i]) {
            return 0;
        }
    }
    if (!portd || !porte || !out || !c->uart_in || !c->op_end) {
        return 0;
    }
    avr_irq_register_notify(portd, on_portd, c);
    avr_irq_register_notify(porte, on_porte, c);
    avr_irq_register_notify(out, on_uart_out, c);
    return 1;
}

static void message(char *err, uint32_t cap, const char *what, const char *path)
{
    if (cap > 0u) {
        snprintf(err, cap, "%s: %s", path, what);
    }
}

/* A fresh ATmega128 with the image in its flash, wired to the board. */
static int boot(struct drav_core *c)
{
    uint32_t i;
    c->avr = avr_make_mcu_by_name("atmega128");
    if (!c->avr) {
        return 0;
    }
    avr_init(c->avr);
    c->avr->log = 0;
    avr_load_firmware(c->avr, &c->firmware);
    c->avr->frequency = (uint32_t)DR_AVR_F_CPU;
    c->avr->sleep = no_sleep;
    c->avr->custom.data = c;
    /* simavr polls a low-level external interrupt pin every cycle while it is low, whether
     * or not the interrupt is enabled (INT4 is PE4, a status output here): a sleeping core
     * would then advance one cycle at a time. The firmware enables only edge-triggered
     * external interrupts, so level triggering is reduced to its edge. */
    for (i = 0; i < 8u; i++) {
        avr_extint_set_strict_lvl_trig(c->avr, (uint8_t)i, 0);
    }
    return wire(c);
}

static uint8_t *eeprom_bytes(struct drav_core *c);

struct drav_core *drav_open(const char *path, char *err, uint32_t cap)
{
    struct drav_core *c = calloc(1, sizeof *c);
    FILE *f = fopen(path, "rb");
    avr_global_logger_set(quiet);
    if (!f) {
        message(err, cap, "cannot open this file", path);
        free(c);
        return NULL;
    }
    fclose(f);
    if (!c) {
        message(err, cap, "out of memory", path);
        return NULL;
    }
    if (elf_read_firmware(path, &c->firmware) != 0) {
        message(err, cap, "cannot read this ELF image", path);
        free(c);
        return NULL;
    }
    if (!boot(c) || !find_symbols(c)) {
        message(err, cap, "not a runtime/avr image for simavr's atmega128 (no _end symbol, or the board cannot be wired)",
                path);
        drav_close(c);
        return NULL;
    }
    paint(c);
    return c;
}

void drav_close(struct drav_core *c)
{
    if (!c) {
        return;
    }
    if (c->avr) {
        avr_terminate(c->avr);
        free(c->avr);
    }
    free(c);
}

/* simavr's avr_reset leaves the core unable to sleep (an interrupt stays pending), so a
 * reset replaces the core by a fresh one with the same image, EEPROM and cycle count. */
void drav_reset(struct drav_core *c)
{
    uint64_t cycle = c->avr->cycle;
    uint8_t *ee = eeprom_bytes(c);
    uint32_t ee_size = (uint32_t)c->avr->e2end + 1u;
    if (ee_size > sizeof c->eeprom_save) {
        ee_size = sizeof c->eeprom_save;
    }
    if (ee) {
        memcpy(c->eeprom_save, ee, ee_size);
    }
    avr_terminate(c->avr);
    free(c->avr);
    c->avr = NULL;
    if (!boot(c)) {
        return;
    }
    ee = eeprom_bytes(c);
    if (ee) {
        memcpy(ee, c->eeprom_save, ee_size);
    }
    c->avr->cycle = cycle;
    c->reg = 0;
    c->portd = 0;
    c->porte = 0;
    c->rx_head = 0;
    c->rx_count = 0;
    c->locked = 0;
    c->regs[DR_AVR_REG_RX_CHANNEL] = 0;
    drive_op_end(c);
    paint(c);
}

int drav_run(struct drav_core *c, uint64_t cycle)
{
    if (!c->avr) {
        return 1; /* a reset could not boot a new core */
    }
    if (cycle > c->avr->cycle) {
        avr_cycle_timer_register(c->avr, cycle - c->avr->cycle, wake_only, c);
    }
    while (c->avr->cycle < cycle) {
        int state = c->avr->state;
        if (state != cpu_Running && state != cpu_Sleeping) {
            return 1;
        }
        avr_run(c->avr);
        if (c->locked && c->avr->cycle >= c->lock_until) {
            c->locked = 0;
            feed(c);
        }
    }
    avr_cycle_timer_cancel(c->avr, wake_only, c);
    return 0;
}

uint64_t drav_cycle(const struct drav_core *c)
{
    return c->avr ? c->avr->cycle : 0u;
}

uint64_t drav_sleep_cycles(const struct drav_core *c)
{
    return c->sleep_cycles;
}

void drav_set_reg(struct drav_core *c, uint8_t reg, uint8_t value)
{
    uint8_t r = (uint8_t)(reg % DR_AVR_REGS);
    uint8_t changed = (uint8_t)(c->regs[r] != value);
    c->regs[r] = value;
    if (r == DR_AVR_REG_STATUS && changed) {
        drive_op_end(c);
    }
}

uint32_t drav_take(struct drav_core *c, struct drav_event *out, uint32_t cap)
{
    uint32_t n = 0;
    while (n < cap && c->log_count > 0u) {
        out[n++] = c->log[c->log_head];
        c->log_head = (c->log_head + 1u) % DRAV_EVENTS;
        c->log_count--;
    }
    return n;
}

int drav_overflowed(const struct drav_core *c)
{
    return c->overflowed;
}

int drav_rx(struct drav_core *c, uint8_t channel, const uint8_t *bytes, uint32_t len)
{
    struct rx_frame *f;
    if (len == 0u || len > DRAV_MAX_FRAME || c->rx_count >= DRAV_RX_QUEUE) {
        return -1;
    }
    f = &c->rx[(c->rx_head + c->rx_count) % DRAV_RX_QUEUE];
    f->channel = channel;
    f->len = (uint8_t)len;
    memcpy(f->bytes, bytes, len);
    c->rx_count++;
    feed(c);
    return 0;
}

uint32_t drav_stack_high_water(const struct drav_core *c)
{
    uint32_t a;
    if (!c->avr) {
        return 0;
    }
    for (a = c->paint_from; a <= c->avr->ramend; a++) {
        if (c->avr->data[a] != DR_AVR_PAINT) {
            return c->avr->ramend - a + 1u;
        }
    }
    return 0;
}

/* The EEPROM's bytes: simavr's ioctl gives them with a NULL buffer (its copying variants
 * print to stdout and refuse the last byte). */
static uint8_t *eeprom_bytes(struct drav_core *c)
{
    avr_eeprom_desc_t desc;
    if (!c->avr) {
        return NULL;
    }
    desc.ee = NULL;
    desc.offset = 0;
    desc.size = 0;
    avr_ioctl(c->avr, (uint32_t)AVR_IOCTL_EEPROM_GET, &desc);
    return desc.ee;
}

static int in_eeprom(const struct drav_core *c, uint16_t addr, uint32_t len)
{
    return len > 0u && (uint32_t)addr + len <= (uint32_t)c->avr->e2end + 1u;
}

int drav_eeprom_read(struct drav_core *c, uint16_t addr, uint8_t *out, uint32_t len)
{
    uint8_t *ee = eeprom_bytes(c);
    if (!ee || !in_eeprom(c, addr, len)) {
        return -1;
    }
    memcpy(out, ee + addr, len);
    return 0;
}

int drav_eeprom_write(struct drav_core *c, uint16_t addr, const uint8_t *bytes, uint32_t len)
{
    uint8_t *ee = eeprom_bytes(c);
    if (!ee || !in_eeprom(c, addr, len)) {
        return -1;
    }
    memcpy(ee + addr, bytes, len);
    return 0;
}
