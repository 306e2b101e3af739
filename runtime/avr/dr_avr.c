/* dr_avr.c - the platform of dr_hal.h on a hemisphere board (ATmega128, 16 MHz), and
 * the firmware's main loop. README.md describes the board (dr_avr_board.h: pins, registers).
 *
 * - Time: Timer1 counts at 250 kHz (4 us a tick) in periods of exactly 256 ms (CTC mode,
 *   compare A) and interrupts only at a period's end; dr_hal_now_ms is 256 ms a period plus
 *   the whole milliseconds of the counter. Compare B wakes the MCU at the next step the
 *   module asked for.
 * - Infrared: USART0 at DR_AVR_BAUD; PORTC selects the transmitters (all for a broadcast, one
 *   for dr_hal_send). Frames go out from a small queue, a byte at each transmit-complete
 *   interrupt, so that the transmitter enables change only once the previous frame has
 *   left the shift register. Received frames are delimited by their length byte
 *   (dr_packet.h: byte 1) and kept in two slots.
 * - Operations and sensors: the board's controller, through an 8-bit bus (PORTB out, PINA
 *   in, strobes on PORTD). A bus transaction runs with interrupts off (the receive
 *   interrupt also uses the bus). The controller raises INT0 when an operation ends.
 * - Non-volatile storage: the EEPROM, through its registers (a byte is written only when it
 *   differs, as avr-libc's eeprom_update_block does).
 * - main: initialises, runs dr_module_receive for each frame, and dr_module_step only at the
 *   step instants (every DR_AVR_STEP_MS from the first) that dr_module_next_wakeup names;
 *   in between it sleeps (idle mode) until that instant's timer, a frame or an operation's
 *   end (dr_module.h: skipping the other instants gives the run that stepping at every
 *   instant gives).
 * - Flash: the short interrupt handlers and the start-up sit in unused vector slots, and a
 *   few parts are assembly where the compiler's code was larger (the USART interrupts, the
 *   step instants' arithmetic, the xorshift), each with the C it stands for in a comment
 *   (README.md, "Footprint": each choice with its bytes).
 *
 * Built with the generated program: avr-gcc -mmcu=atmega128 -Os -I OUT -I runtime/avr
 * OUT/dr_packet.c OUT/dr_<protocol>.c OUT/dr_program.c dr_avr.c (runtime/avr/Makefile). */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stddef.h>
#include <stdint.h>
#include "dr_avr_board.h"
#include "dr_program.h"
#ifdef DR_AVR_NESC
#include "dr_nesc_platform.h"
#endif

#if DR_CONF_MAX_ARGS > DR_AVR_MAX_ARGS
#error "the board takes at most DR_AVR_MAX_ARGS operation arguments"
#endif
#if DR_AVR_REG_OP != DR_AVR_REG_STATEMENT + 2u || DR_AVR_REG_INDEX != DR_AVR_REG_OP + 1u || \
    DR_AVR_REG_ADDRESS != DR_AVR_REG_INDEX + 1u || DR_AVR_REG_GO != DR_AVR_REG_ADDRESS + 1u
#error "dr_hal_op_start writes STATEMENT through GO in one transaction"
#endif

/* Frames waiting to be sent (a third send waits for the first to leave; tx_after alternates
 * between the two). */
#define TX_FRAMES 2u
/* Received frames waiting for dr_module_receive (a third waits at the board). */
#define RX_SLOTS 2u /* rx[0] and rx[1], named in the receive interrupt and any_received */
/* Timer1 ticks per millisecond (16 MHz / 64), and its period: it counts 0..PERIOD_TICKS - 1
 * (64,000 ticks, 256 ms), so that the clock is a whole number of periods plus the counter's
 * milliseconds, without carries between the two. */
#define TICKS_PER_MS ((uint16_t)(DR_AVR_F_CPU / 64u / 1000u))
#define PERIOD_MS 256u /* the clock's low byte: union clock */
#define PERIOD_TICKS ((uint16_t)(PERIOD_MS * TICKS_PER_MS))
/* Compare B's value when no step is to wake the MCU: beyond the counter's top (PERIOD_TICKS
 * - 1), so no match. Compare B's interrupt stays enabled: one store disarms it. */
#define NO_WAKE 0xFFFFu
/* A wake-up closer than this many ticks is waited for awake: the compare might be missed. */
#define MIN_SLEEP_TICKS 8u
#define UBRR_VALUE (DR_AVR_F_CPU / 16u / DR_AVR_BAUD - 1u)

struct tx_frame {
    uint8_t mask;
    uint8_t len;
    uint8_t pos; /* the next byte to send, once the frame is at the head */
    uint8_t bytes[DR_CONF_MAX_PACKET];
};

/* A received frame: its length is its byte 1 (dr_packet.h). */
struct rx_slot {
    volatile uint8_t full;
    uint8_t channel;
    uint8_t bytes[DR_CONF_MAX_PACKET];
};

/* The USART interrupts (assembly) take these fields at these offsets. */
typedef char dr_avr_frame_layout[(offsetof(struct tx_frame, len) == 1u &&
                                  offsetof(struct tx_frame, pos) == 2u &&
                                  offsetof(struct tx_frame, bytes) == 3u &&
                                  offsetof(struct rx_slot, channel) == 1u &&
                                  offsetof(struct rx_slot, bytes) == 2u)
                                     ? 1
                                     : -1];

#ifdef DR_AVR_NESC
/* The nesC component (`dynarole compile --target nesc`, compiled by runtime/nesc) owns the
 * module's context: DynaRoleP's `self`, so named by nescc with -fnesc-separator=__. */
extern dr_module_t DynaRoleP__self;
#define module DynaRoleP__self
#else
static dr_module_t module;
#endif
/* The clock (main only): the periods main has counted in its upper 24 bits (256 ms each,
 * PERIOD_MS), so that it is the millisecond at which the current period began; the clock
 * wraps after 2^32 ms either way. dr_avr_periods below: the periods the interrupt has seen
 * since (main reads the clock at least once a period: the period's interrupt wakes it). */
union clock {
    uint32_t ms;
    struct {
        uint8_t ms_in_period; /* the low byte (the AVR is little-endian) */
        __uint24 periods;
    } parts;
};
static union clock clock_start;
static uint16_t random_state;

static struct tx_frame tx[TX_FRAMES];
static struct tx_frame *volatile tx_head = &tx[0];
/* The frame the next send fills (main only): the two are filled in turn as the transmit
 * interrupt sends them in turn, so this is the head when none waits, the other when one
 * does. */
static struct tx_frame *tx_free = &tx[0];
static volatile uint8_t tx_count;

/* The slots, and a spare one where a frame goes when both are full (dropped). */
static struct rx_slot rx[RX_SLOTS + 1u];
/* The receive interrupt's own: bytes of the frame being received and its slot. */
static uint8_t rx_fill;
static struct rx_slot *rx_cur;

/* Set by the period's interrupt and by INT0 (an operation ended since main last looked),
 * whose handlers are assembly in the vector table below: global names that the table
 * refers to, kept under -flto. */
volatile uint8_t dr_avr_periods __attribute__((used, externally_visible));
volatile uint8_t dr_avr_op_ended __attribute__((used, externally_visible));

/* --- start-up (the image is linked with -nostartfiles) ---
 * avr-libc's start-up has all 35 vectors of the ATmega128; the firmware enables only
 * interrupts up to USART0_TX (vector 20), so its table stops there. The short handlers and
 * the start-up sit in the slots of vectors that are never enabled: no interrupt can reach
 * those slots, as the firmware sets no enable bit but OCIE1A and OCIE1B (TIMSK), INT0
 * (EIMSK), RXCIE0 and TXCIE0 (UCSR0B), and the others keep their reset value 0 (so there is
 * no restart on an unused vector, as avr-libc's __bad_interrupt does: none can be taken).
 * Each `.org` is a vector's address (4 bytes a vector): the assembler refuses the table if
 * a handler runs into the next vector used. The handlers:
 * - INT0 (an operation ended) sets dr_avr_op_ended: ldi and sts leave SREG alone;
 * - TIMER1_COMPA (the clock's period) counts the period, saving r24 and SREG (inc changes
 *   it); main adds the count to the clock (read_clock), so that the 32-bit clock arithmetic
 *   is in one place;
 * - TIMER1_COMPB (the next step) only wakes the MCU: main looks at the clock.
 * The start-up, as avr-libc's: r1 = 0 (the compiler's zero register), the stack at the top
 * of RAM (SREG is 0 after a reset, the only way here); libgcc's __do_copy_data and
 * __do_clear_bss (.init4, linked because the program has .data and .bss) initialise the RAM;
 * main never returns. */
#define DR_AVR_STR(x) #x
#define DR_AVR_XSTR(x) DR_AVR_STR(x)
__asm__(".pushsection .vectors,\"ax\",@progbits\n"
        ".global __vectors\n"
        "__vectors:\n"
        "rjmp __init\n"
        ".org 4\n" /* INT0, over the slots of INT1 and INT2 */
        "push r24\n"
        "ldi r24, 1\n"
        "sts dr_avr_op_ended, r24\n"
        "pop r24\n"
        "reti\n"
        "dr_avr_period:\n" /* TIMER1_COMPA's handler, over the slots of INT3..INT7, TIMER2_COMP */
        "push r24\n"
        "in r24, __SREG__\n"
        "push r24\n"
        "lds r24, dr_avr_periods\n"
        "inc r24\n"
        "sts dr_avr_periods, r24\n"
        "pop r24\n"
        "out __SREG__, r24\n"
        "pop r24\n"
        "reti\n"
        ".org 48\n" /* TIMER1_COMPA */
        "rjmp dr_avr_period\n"
        ".org 52\n" /* TIMER1_COMPB */
        "reti\n"
        "__init:\n" /* over the slots of TIMER1_OVF, TIMER0_COMP, TIMER0_OVF */
        "clr r1\n"
        "ldi r28, lo8(" DR_AVR_XSTR(RAMEND) ")\n"
        "ldi r29, hi8(" DR_AVR_XSTR(RAMEND) ")\n"
        "out __SP_H__, r29\n"
        "out __SP_L__, r28\n"
        "jmp dr_avr_init_ram\n"
        ".org 72\n" /* USART0_RX */
        "jmp __vector_18\n"
        ".org 80\n" /* USART0_TX (USART0_UDRE's slot, 76, holds nothing) */
        "jmp __vector_20\n"
        ".section .init0,\"ax\",@progbits\n"
        "dr_avr_init_ram:\n"
        ".popsection\n");
/* The start-up's last part (.init9, after libgcc's RAM set-up in .init4): the start-up runs
 * into it, no jump. Kept and named main under -flto; it never returns, so it saves no
 * registers (OS_main). */
int main(void) __attribute__((OS_main, used, externally_visible, section(".init9")));

/* --- the controller's bus (a transaction runs with interrupts off; read_u16 and write_u8
 * are called with them on, as the functions of dr_hal.h below) --- */

/* A rising edge on strobe `bit` of PORTD. Always inlined with a constant bit: one sbi and
 * one cbi. */
static inline __attribute__((always_inline)) void strobe(uint8_t bit)
{
    PORTD = (uint8_t)(PORTD | (1u << bit));
    PORTD = (uint8_t)(PORTD & ~(1u << bit));
}

static inline __attribute__((always_inline)) void bus_address(uint8_t reg)
{
    PORTB = reg;
    strobe(DR_AVR_STROBE_ADDR);
}

/* Writes one byte to the addressed register (the address then advances by one). */
static inline __attribute__((always_inline)) void bus_put(uint8_t v)
{
    PORTB = v;
    strobe(DR_AVR_STROBE_WRITE);
}

/* Reads the addressed register (the address then advances by one). */
static inline __attribute__((always_inline)) uint8_t bus_get(void)
{
    strobe(DR_AVR_STROBE_READ);
    __asm__ __volatile__("nop"); /* the input synchroniser's latency */
    return PINA;
}

/* Registers reg and reg + 1 as a little-endian value (a one-byte register is the low byte:
 * reads have no side effect on the board). */
static uint16_t read_u16(uint8_t reg)
{
    uint8_t lo;
    uint8_t hi;
    cli();
    bus_address(reg);
    lo = bus_get();
    hi = bus_get();
    sei();
    return (uint16_t)(lo | (uint16_t)((uint16_t)hi << 8));
}

static uint8_t read_u8(uint8_t reg)
{
    return (uint8_t)read_u16(reg);
}

#ifdef DR_AVR_DESCRIBE
/* The module's state as text, for the simulator's trace: the emulated board copies it at
 * each pulse of PE5. The context's own layout is the AVR compiler's, so the runtime's
 * dr_module_describe makes the text here, where a host run makes it on the host. */
char dr_avr_description[DR_AVR_DESCRIPTION];
static uint8_t describing; /* from the end of dr_program_init: a host run shows - before */

static void describe(void)
{
    if (describing) {
        (void)dr_module_describe(&module, dr_avr_description,
                                 (uint8_t)sizeof dr_avr_description);
        PORTE = (uint8_t)(PORTE | (1u << DR_AVR_PIN_DESCRIBED));
        PORTE = (uint8_t)(PORTE & ~(1u << DR_AVR_PIN_DESCRIBED));
    }
}
#else
static void describe(void)
{
}
#endif

static void write_u8(uint8_t reg, uint8_t v)
{
    cli();
    bus_address(reg);
    bus_put(v);
    sei();
}

/* --- interrupts --- */

/* The counter as read_clock read it last (main only). */
static uint16_t clock_count;

/* Milliseconds since power-on (and the counter read, in clock_count). Called with
 * interrupts off (main only). First adds the periods counted since the last call, and the
 * one whose interrupt is still pending when the counter had restarted before it was read
 * (its flag is cleared: the interrupt would count it again). The milliseconds into the
 * period are the low byte, set as a byte: no 32-bit arithmetic. */
static uint32_t read_clock(void)
{
    union clock now;
    uint16_t count = TCNT1;
    uint8_t n = dr_avr_periods;
    if ((TIFR & (1u << OCF1A)) && count < PERIOD_TICKS / 2u) {
        TIFR = (uint8_t)(1u << OCF1A);
        n++;
    }
    dr_avr_periods = 0;
    clock_start.parts.periods += n;
    clock_count = count;
    now = clock_start;
    now.parts.ms_in_period = (uint8_t)(count / TICKS_PER_MS);
    return now.ms;
}

/* The frame after `f` in the queue: the other of the two, the sum of both addresses less
 * f's (no comparison and branches: 6 bytes fewer). */
static inline __attribute__((always_inline)) struct tx_frame *tx_after(struct tx_frame *f)
{
    return (struct tx_frame *)((uintptr_t)&tx[0] + (uintptr_t)&tx[1] - (uintptr_t)f);
}

/* Enables the transmitters of frame `f`, the head of the queue, and puts its first byte on
 * the line. Interrupts are off. */
static inline __attribute__((always_inline)) void tx_start(struct tx_frame *f)
{
    PORTC = f->mask;
    UDR0 = f->bytes[0];
    f->pos = 1;
}

/* The two USART interrupts are naked, in assembly: they save only the registers they use
 * (r24, r25, Z and SREG), where the compiler's prologue also saved r0, r1 and RAMPZ, and
 * they save them alike, so that they share the code that restores them. They cannot take
 * r1 as zero (an interrupt may come between a `mul` and the `clr r1` after it), so they
 * use none. */
#define USART_ISR_SAVE \
    "push r24\n\t" \
    "in r24, __SREG__\n\t" \
    "push r24\n\t" \
    "push r25\n\t" \
    "push r30\n\t" \
    "push r31\n\t" /* popped in reverse at dr_avr_usart_return */

/* A byte has left and the USART holds no other: the frame's next byte, or, after its last,
 * the transmitters off and the next frame (the other of the two, tx_after). Only this
 * interrupt feeds the USART, one byte at a time, so the enables change only once a frame's
 * last bit has left. As C:
 *     f = tx_head; p = f->pos;
 *     if (p < f->len) { f->pos = p + 1; UDR0 = f->bytes[p]; return; }
 *     PORTC = 0; f = tx_after(f); tx_head = f;
 *     if (--tx_count != 0) tx_start(f); */
ISR(USART0_TX_vect, ISR_NAKED)
{
    __asm__ __volatile__(
        USART_ISR_SAVE
        "lds r30, %[head]\n\t"
        "lds r31, %[head]+1\n\t"
        "ldd r24, Z+2\n\t" /* f->pos */
        "ldd r25, Z+1\n\t" /* f->len */
        "cp r24, r25\n\t"
        "brsh 1f\n\t"
        "inc r24\n\t"
        "std Z+2, r24\n\t"
        "add r30, r24\n\t" /* f + p + 1 */
        "clr r25\n\t"
        "adc r31, r25\n\t"
        "ldd r25, Z+2\n\t" /* f->bytes[p], at f + 3 + p */
        "out %[udr], r25\n\t"
        "rjmp 4f\n"
        "1:\n\t"
        "clr r25\n\t"
        "out %[portc], r25\n\t"
        "ldi r24, lo8(%[tx0])\n\t" /* tx_after(f): &tx[0] - f + &tx[1] */
        "ldi r25, hi8(%[tx0])\n\t"
        "sub r24, r30\n\t"
        "sbc r25, r31\n\t"
        "subi r24, lo8(-(%[tx1]))\n\t"
        "sbci r25, hi8(-(%[tx1]))\n\t"
        "movw r30, r24\n\t"
        "sts %[head], r30\n\t"
        "sts %[head]+1, r31\n\t"
        "lds r24, %[count]\n\t"
        "dec r24\n\t"
        "sts %[count], r24\n\t"
        "breq 4f\n\t"
        "ld r24, Z\n\t" /* tx_start: the enables, the first byte */
        "out %[portc], r24\n\t"
        "ldd r24, Z+3\n\t"
        "out %[udr], r24\n\t"
        "ldi r24, 1\n\t"
        "std Z+2, r24\n"
        "4:\n\t"
        "jmp dr_avr_usart_return" /* the receive interrupt's end: the same registers */
        :
        : [head] "i"(&tx_head), [count] "i"(&tx_count), [tx0] "i"(&tx[0]),
          [tx1] "i"(&tx[1]), [udr] "I"(_SFR_IO_ADDR(UDR0)), [portc] "I"(_SFR_IO_ADDR(PORTC))
        : "memory");
}

/* Receives one byte. The first byte of a frame picks a free slot (none: the spare slot,
 * whose frames are dropped) and reads its channel from the arbiter; the second is its
 * length (a frame with an impossible one is dropped: README.md, framing). At a frame's end
 * the arbiter is released, so that it may pass the next one. As C:
 *     b = UDR0; n = rx_fill; s = rx_cur;
 *     if (n == 0) { s = first of rx[0], rx[1] not full, else rx[RX_SLOTS]; rx_cur = s;
 *                   s->channel = the RX_CHANNEL register; }
 *     s->bytes[n] = b; rx_fill = ++n;
 *     if (n < 2) return;
 *     if (n == 2 && (b < 2 || b > DR_CONF_MAX_PACKET)) goto end;
 *     if (n < s->bytes[1]) return;
 *     s->full = 1;  (the spare slot's flag is never read)
 *     end: rx_fill = 0; strobe(DR_AVR_STROBE_RELEASE); */
ISR(USART0_RX_vect, ISR_NAKED)
{
    __asm__ __volatile__(
        USART_ISR_SAVE
        "in r25, %[udr]\n\t"
        "lds r24, %[fill]\n\t"
        "lds r30, %[cur]\n\t"
        "lds r31, %[cur]+1\n\t"
        "tst r24\n\t"
        "brne 2f\n\t"
        "ldi r30, lo8(%[rx])\n\t"
        "ldi r31, hi8(%[rx])\n\t"
        "ld r24, Z\n\t" /* rx[0].full */
        "tst r24\n\t"
        "breq 1f\n\t"
        "subi r30, lo8(-(%[size]))\n\t"
        "sbci r31, hi8(-(%[size]))\n\t"
        "ld r24, Z\n\t" /* rx[1].full */
        "tst r24\n\t"
        "breq 1f\n\t"
        "subi r30, lo8(-(%[size]))\n\t"
        "sbci r31, hi8(-(%[size]))\n" /* the spare slot */
        "1:\n\t"
        "sts %[cur], r30\n\t"
        "sts %[cur]+1, r31\n\t"
        "ldi r24, %[reg]\n\t" /* bus_address(RX_CHANNEL), bus_get() */
        "out %[portb], r24\n\t"
        "sbi %[portd], %[addr]\n\t"
        "cbi %[portd], %[addr]\n\t"
        "sbi %[portd], %[read]\n\t"
        "cbi %[portd], %[read]\n\t"
        "nop\n\t" /* the input synchroniser's latency */
        "in r24, %[pina]\n\t"
        "std Z+1, r24\n\t" /* s->channel */
        "clr r24\n"
        "2:\n\t"
        "add r30, r24\n\t"
        "brcc 3f\n\t"
        "inc r31\n"
        "3:\n\t"
        "std Z+2, r25\n\t" /* s->bytes[n] = b */
        "sub r30, r24\n\t"
        "sbci r31, 0\n\t"
        "inc r24\n\t"
        "sts %[fill], r24\n\t"
        "cpi r24, 2\n\t"
        "brlo 5f\n\t"
        "brne 4f\n\t"
        "subi r25, 2\n\t" /* n == 2: b - 2 >= DR_CONF_MAX_PACKET - 1, unsigned: dropped */
        "cpi r25, %[max1]\n\t"
        "brsh 6f\n"
        "4:\n\t"
        "ldd r25, Z+3\n\t" /* s->bytes[1], the length */
        "cp r24, r25\n\t"
        "brlo 5f\n\t"
        "ldi r24, 1\n\t"
        "st Z, r24\n" /* s->full */
        "6:\n\t"
        "clr r24\n\t"
        "sts %[fill], r24\n\t"
        "sbi %[portd], %[release]\n\t"
        "cbi %[portd], %[release]\n"
        "5:\n"
        ".global dr_avr_usart_return\n" /* also the transmit interrupt's end */
        "dr_avr_usart_return:\n\t"
        "pop r31\n\t"
        "pop r30\n\t"
        "pop r25\n\t"
        "pop r24\n\t"
        "out __SREG__, r24\n\t"
        "pop r24\n\t"
        "reti"
        :
        : [fill] "i"(&rx_fill), [cur] "i"(&rx_cur), [rx] "i"(&rx[0]),
          [size] "n"(sizeof(struct rx_slot)), [max1] "M"(DR_CONF_MAX_PACKET - 1),
          [reg] "M"(DR_AVR_REG_RX_CHANNEL), [udr] "I"(_SFR_IO_ADDR(UDR0)),
          [portb] "I"(_SFR_IO_ADDR(PORTB)), [portd] "I"(_SFR_IO_ADDR(PORTD)),
          [pina] "I"(_SFR_IO_ADDR(PINA)), [addr] "I"(DR_AVR_STROBE_ADDR),
          [read] "I"(DR_AVR_STROBE_READ), [release] "I"(DR_AVR_STROBE_RELEASE)
        : "memory");
}

/* --- dr_hal.h ---
 * Interrupts are on whenever a function of dr_hal.h runs (main turns them on before the
 * runtime's init, and no interrupt calls the runtime), so a bus transaction, a clock reading
 * or an EEPROM write turns them off and back on (cli, sei) rather than saving SREG. */

/* Not inlined: -flto would, at a cost in flash (measured). */
__attribute__((noinline)) uint32_t dr_hal_now_ms(struct dr_module *m)
{
    uint32_t v;
    (void)m;
    cli();
    v = read_clock();
    sei();
    return v;
}

uint16_t dr_hal_random(struct dr_module *m)
{
    /* xorshift16 (7, 9, 8): period 65535 over the non-zero states; x ^= x << 7,
     * x ^= x >> 9, x ^= x << 8, byte by byte in assembly (the compiler's 16-bit shifts and
     * xors took 18 more bytes; the two agree on all 65,536 states, checked on simavr):
     * hi ^= hi << 7 | lo >> 1 (the carry out of `lsr` goes in with `ror`), lo ^= lo << 7
     * (the carry left by that `ror`: the bit lo >> 1 dropped), lo ^= hi >> 1, hi ^= lo. */
    uint16_t x = random_state;
    uint8_t t;
    (void)m;
    __asm__("mov %[t], %B[x]\n\t"
            "lsr %[t]\n\t"
            "mov %[t], %A[x]\n\t"
            "ror %[t]\n\t"
            "eor %B[x], %[t]\n\t" /* eor and mov leave the carry alone */
            "mov %[t], __zero_reg__\n\t"
            "ror %[t]\n\t"
            "eor %A[x], %[t]\n\t"
            "mov %[t], %B[x]\n\t"
            "lsr %[t]\n\t"
            "eor %A[x], %[t]\n\t"
            "eor %B[x], %A[x]"
            : [x] "+r"(x), [t] "=&r"(t));
    random_state = x;
    return x;
}

static void enqueue(uint8_t mask, const uint8_t *bytes, uint8_t len)
{
    struct tx_frame *f;
    uint8_t *to;
    uint8_t n;
    if (len == 0u || len > DR_CONF_MAX_PACKET) {
        return;
    }
    while (tx_count >= TX_FRAMES) {
        /* the transmit interrupt frees a frame within its air time */
    }
    f = tx_free;
    tx_free = tx_after(f);
    f->mask = mask;
    f->len = len;
    for (to = f->bytes, n = len; n != 0u; n--) {
        *to++ = *bytes++;
    }
    cli();
    n = (uint8_t)(tx_count + 1u);
    tx_count = n;
    if (n == 1u) {
        tx_start(tx_head); /* f: none was waiting */
    }
    sei();
}

void dr_hal_broadcast(struct dr_module *m, const uint8_t *bytes, uint8_t len)
{
    (void)m;
    describe(); /* the state the trace shows next to this frame, as in a host run */
    enqueue((uint8_t)((1u << DR_AVR_CHANNELS) - 1u), bytes, len);
}

void dr_hal_send(struct dr_module *m, uint8_t channel, const uint8_t *bytes, uint8_t len)
{
    (void)m;
    describe();
    if (channel < DR_AVR_CHANNELS) {
        enqueue((uint8_t)(1u << channel), bytes, len);
    }
}

/* One transaction for the arguments, then one from STATEMENT through GO (the registers
 * follow each other: statement, op, index, address, GO). The arguments' bytes go as they
 * are in memory: the AVR is little-endian, as the board's registers. */
void dr_hal_op_start(struct dr_module *m, uint16_t statement, uint8_t op, uint8_t index,
                     const int16_t *args)
{
    const uint8_t *a = (const uint8_t *)args;
    uint8_t i;
    describe();
    cli();
    bus_address(DR_AVR_REG_ARGS);
    for (i = 0; i < 2u * DR_CONF_MAX_ARGS; i++) {
        bus_put(a[i]);
    }
    bus_address(DR_AVR_REG_STATEMENT);
    bus_put((uint8_t)statement);
    bus_put((uint8_t)(statement >> 8));
    bus_put(op);
    bus_put(index);
    bus_put(m->address);
    bus_put((uint8_t)statement); /* GO: any value */
    sei();
}

enum dr_op_status dr_hal_op_status(struct dr_module *m)
{
    uint8_t s;
    (void)m;
    s = read_u8(DR_AVR_REG_STATUS);
    if (s == (uint8_t)DR_OP_DONE) {
        return DR_OP_DONE;
    }
    return s == (uint8_t)DR_OP_RUNNING ? DR_OP_RUNNING : DR_OP_FAILED;
}

uint16_t dr_hal_id(struct dr_module *m)
{
    (void)m;
    return read_u16(DR_AVR_REG_ID);
}

uint8_t dr_hal_connected(struct dr_module *m, uint8_t connector)
{
    (void)m;
    if (connector >= DR_AVR_CHANNELS) {
        return 0;
    }
    return (uint8_t)((uint8_t)(read_u8(DR_AVR_REG_CONNECTED) >> connector) & 1u);
}

int16_t dr_hal_neighbour_id(struct dr_module *m, uint8_t connector)
{
    (void)m;
    if (connector >= DR_AVR_CHANNELS) {
        return -1;
    }
    return (int16_t)read_u16((uint8_t)(DR_AVR_REG_NEIGHBOUR + 2u * connector));
}

int16_t dr_hal_joint(struct dr_module *m, uint8_t joint)
{
    (void)m;
    if (joint >= DR_AVR_JOINTS) {
        return 0;
    }
    return (int16_t)read_u16((uint8_t)(DR_AVR_REG_JOINT + 2u * joint));
}

void dr_hal_leds(struct dr_module *m, uint8_t value)
{
    (void)m;
    describe();
    write_u8(DR_AVR_REG_LEDS, value);
}

/* Whether [addr, addr + len) lies in the EEPROM (E2END + 1 - len cannot wrap: len < 256). */
static uint8_t in_eeprom(uint16_t addr, uint8_t len)
{
    return (uint8_t)(addr <= (uint16_t)(E2END + 1u - len));
}

/* Byte `addr` of the EEPROM, once its last write has finished. */
static uint8_t eeprom_get(uint16_t addr)
{
    while (EECR & (1u << EEWE)) {
    }
    EEAR = addr;
    /* EECR |= 1 << EERE as an `sbi` whatever the options (the compiler's read-modify-write
     * through X, here and inlined in dr_hal_nv_write, took 16 B more under DR_MCU_FLAGS); no
     * timing matters here. */
    __asm__ __volatile__("sbi %[eecr], %[eere]"
                         :
                         : [eecr] "I"(_SFR_IO_ADDR(EECR)), [eere] "I"(EERE)
                         : "memory");
    return EEDR;
}

/* Writes `byte` to the EEPROM at EEAR (set by the eeprom_get just before: no write is under
 * way). The datasheet's timed sequence: EEMWE set, then EEWE within four cycles, or the chip
 * ignores EEWE and writes nothing. In assembly, as avr-libc's eeprom_write_byte does it, so
 * that no compiler option can spread it: two read-modify-writes of EECR in C come out as
 * `sbi` only when the optimiser finds it (-fno-gcse alone, one of DR_MCU_FLAGS, makes each an
 * ld/ori/st through X, EEWE 5 cycles after EEMWE, and no record was ever written). The two
 * `sbi` are consecutive (EEWE 2 cycles after EEMWE) with interrupts off (an interrupt
 * between them would take longer than four cycles); interrupts are on when any function of
 * dr_hal.h runs, so `sei` restores them. `make -C runtime/avr test` checks every image's
 * disassembly for the two consecutive `sbi`. */
static void eeprom_put(uint8_t byte)
{
    __asm__ __volatile__("out %[eedr], %[byte]\n\t"
                         "cli\n\t"
                         "sbi %[eecr], %[eemwe]\n\t"
                         "sbi %[eecr], %[eewe]\n\t"
                         "sei"
                         :
                         : [byte] "r"(byte), [eedr] "I"(_SFR_IO_ADDR(EEDR)),
                           [eecr] "I"(_SFR_IO_ADDR(EECR)), [eemwe] "I"(EEMWE), [eewe] "I"(EEWE)
                         : "memory");
}

void dr_hal_nv_read(struct dr_module *m, uint16_t addr, uint8_t *buf, uint8_t len)
{
    uint8_t ok = in_eeprom(addr, len);
    uint8_t i;
    (void)m;
    for (i = 0; i < len; i++) {
        buf[i] = ok ? eeprom_get((uint16_t)(addr + i)) : 0xFFu;
    }
}

/* Writes only the bytes that differ (an EEPROM cell takes about 100,000 writes). */
void dr_hal_nv_write(struct dr_module *m, uint16_t addr, const uint8_t *buf, uint8_t len)
{
    uint8_t i;
    (void)m;
    if (!in_eeprom(addr, len)) {
        return;
    }
    for (i = 0; i < len; i++) {
        if (eeprom_get((uint16_t)(addr + i)) != buf[i]) {
            eeprom_put(buf[i]);
        }
    }
}

/* --- main --- */

/* From the reset values (the start-up runs only after a reset): port A an input, the
 * transmitter enables (PORTC) off, TCCR1A 0 (the waveform bits of CTC mode 4 are in TCCR1B),
 * the USART framed 8N1, the interrupts off. */
static void board_init(void)
{
    DDRB = 0xFF;
    DDRC = 0xFF;
    DDRD = (uint8_t)((1u << DR_AVR_STROBE_ADDR) | (1u << DR_AVR_STROBE_WRITE) |
                     (1u << DR_AVR_STROBE_READ) | (1u << DR_AVR_STROBE_RELEASE));
    DDRE = (uint8_t)((1u << DR_AVR_PIN_STEP) | (1u << DR_AVR_PIN_RECEIVE) |
                     (1u << DR_AVR_PIN_FINISHED) | (1u << DR_AVR_PIN_STOPPED));
    /* Timer1 in CTC mode 4 (TOP = OCR1A): compare A ends each period, compare B wakes the
     * MCU for its next step. */
    OCR1A = (uint16_t)(PERIOD_TICKS - 1u);
    TCCR1B = (uint8_t)((1u << WGM12) | (1u << CS11) | (1u << CS10));
    TIMSK = (uint8_t)((1u << OCIE1A) | (1u << OCIE1B));
    /* INT0 on its rising edge: an operation ended. */
    EICRA = (uint8_t)((1u << ISC01) | (1u << ISC00));
    EIFR = (uint8_t)(1u << INTF0);
    EIMSK = (uint8_t)(1u << INT0);
#if UBRR_VALUE > 0xFFu
    UBRR0H = (uint8_t)(UBRR_VALUE >> 8);
#endif
    UBRR0L = (uint8_t)(UBRR_VALUE & 0xFFu);
    UCSR0B = (uint8_t)((1u << RXEN0) | (1u << TXEN0) | (1u << RXCIE0) | (1u << TXCIE0));
    /* Idle sleep mode (SM2..SM0 = 0: the timer and the USART keep running), sleep enabled
     * once for all (sleep_until_work is the only sleep instruction). */
    MCUCR = (uint8_t)(1u << SE);
}

/* Hands every received frame to the runtime (PE3 high meanwhile). Not inlined (nor
 * instant_from): -flto would, at a cost in flash (measured). */
__attribute__((noinline)) static void receive_all(void)
{
    struct rx_slot *s;
    for (s = rx; s != rx + RX_SLOTS; s++) {
        if (s->full) {
            PORTE = (uint8_t)(PORTE | (1u << DR_AVR_PIN_RECEIVE));
#ifdef DR_AVR_NESC
            dr_platform_receive(s->channel, s->bytes, s->bytes[1]);
#else
            dr_module_receive(&module, s->channel, s->bytes, s->bytes[1]);
#endif
            PORTE = (uint8_t)(PORTE & ~(1u << DR_AVR_PIN_RECEIVE));
            s->full = 0;
            describe();
        }
    }
}

static uint8_t any_received(void)
{
    return (uint8_t)(rx[0].full | rx[1].full);
}

/* One step (PE2 high meanwhile); PE4 shows whether the module knows the sequence ended, PE6
 * whether its failure policy stopped it (dr_module_finished's two answers, dr_module.h).
 * Under nesC, the component's clock advances by `elapsed` ms instead: its timer runs the
 * steps (every 5 ms from boot) and the tasks. */
static void step(uint32_t elapsed)
{
    uint8_t end;
    PORTE = (uint8_t)(PORTE | (1u << DR_AVR_PIN_STEP));
#ifdef DR_AVR_NESC
    dr_nesc_advance_ms(elapsed);
#else
    (void)elapsed;
    dr_module_step(&module);
#endif
    end = dr_module_finished(&module);
    PORTE = (uint8_t)((PORTE & ~((1u << DR_AVR_PIN_FINISHED) | (1u << DR_AVR_PIN_STOPPED))) |
                      (end == DR_END_GOAL ? (1u << DR_AVR_PIN_FINISHED) : 0u) |
                      (end == DR_END_STOPPED ? (1u << DR_AVR_PIN_STOPPED) : 0u));
    PORTE = (uint8_t)(PORTE & ~(1u << DR_AVR_PIN_STEP));
    describe();
}

/* --- when to step --- */

static uint32_t due;        /* the instant of the next step, when has_due */
static uint8_t has_due;
static uint8_t op_wait;     /* a step is wanted once the operation has ended */

/* Arms compare B to wake the MCU when the clock reaches `at` (ms), if that is in the current
 * period; the period's end wakes it anyway. False when `at` has passed or is too close to
 * sleep. Interrupts are off. */
static uint8_t arm_wake(uint32_t at)
{
    /* `at` from the current period's start: negative when before it (passed) */
    uint32_t offset = at - (read_clock() & ~(uint32_t)(PERIOD_MS - 1u));
    uint16_t target;
    OCR1B = NO_WAKE;
    if (!has_due) {
        return 1;
    }
    /* Not in the current period (its upper 24 bits not 0: tested by bytes, where a 32-bit
     * comparison with PERIOD_MS took 8 more bytes): in a later one, or passed (negative). */
    if ((uint16_t)(offset >> 16) != 0u || (uint8_t)(offset >> 8) != 0u) {
        return (uint8_t)((int32_t)offset >= 0);
    }
    target = (uint16_t)((uint8_t)offset * (uint16_t)TICKS_PER_MS);
    if (target < (uint16_t)(clock_count + MIN_SLEEP_TICKS)) {
        return 0; /* passed, or too close */
    }
    OCR1B = target;
    TIFR = (uint8_t)(1u << OCF1B);
    return 1;
}

/* Sleeps until the next interrupt unless there is work; sei takes effect after the next
 * instruction, so no wake-up is lost between the checks and the sleep. */
static void sleep_until_work(void)
{
    cli();
    if (!any_received() && !(op_wait && dr_avr_op_ended) && arm_wake(due)) {
        sei();
        sleep_cpu();
    }
    sei();
}

/* Power-on and reset: the board, the random generator's seed from the module's ID. */
static void start(void)
{
    uint16_t seed;
    board_init();
    sei();
    seed = (uint16_t)(read_u16(DR_AVR_REG_ID) ^ 0xACE1u);
    random_state = seed != 0u ? seed : 1u; /* xorshift would stay at 0 */
}

/* After the runtime's init: the trace's description, the address for the board's log. */
static void started(void)
{
#ifdef DR_AVR_DESCRIBE
    describing = 1;
#endif
    describe();
    write_u8(DR_AVR_REG_ADDRESS, module.address);
}

#ifdef DR_AVR_NESC

/* The component's timers need its clock only when one is due (dr_nesc_until_due_ms): the
 * MCU sleeps until then, or until a frame. */
int main(void)
{
    uint32_t last;
    uint32_t now;
    uint32_t until;
    start();
    dr_nesc_boot();
    started();
    last = dr_hal_now_ms(&module);
    for (;;) {
        receive_all();
        now = dr_hal_now_ms(&module);
        if (now != last) {
            step(now - last);
            last = now;
        }
        until = dr_nesc_until_due_ms();
        has_due = (uint8_t)(until != DR_NESC_NEVER);
        due = last + (until == 0u ? 1u : until);
        sleep_until_work();
    }
}

#else

/* Whether clock reading a comes before b (the clock wraps after 49 days). */
static uint8_t before(uint32_t a, uint32_t b)
{
    return (uint8_t)((int32_t)(a - b) < 0);
}

#if 255 % DR_AVR_STEP_MS != 0
#error "instant_from: DR_AVR_STEP_MS must divide 255"
#endif

/* The first instant not stepped yet: the instants are every DR_AVR_STEP_MS from the first
 * step, so this one and those after it. */
static uint32_t next_free;

/* The first instant at or after `t` that has not been stepped: next_free when `t` is not
 * after it, else t rounded up to an instant, t + (-d mod DR_AVR_STEP_MS) with d = t -
 * next_free. The remainder in 8 bits, as 255 - d is 0 - d modulo any divisor of 255: the
 * sum of d's bytes (256 leaves 1 in that division) with each carry out of the byte added
 * back in (256 again), taken from 255, then DR_AVR_STEP_MS taken away while it goes (at
 * most 51 times for 5 ms). Assembly in call-clobbered registers only, no division call (the
 * compiler's version, with a 16-bit sum and `%`, saved six registers and took 54 more
 * bytes; the two agree on 300,000 cases, checked on simavr). As C:
 *     d = t - next_free; if ((int32_t)d <= 0) return next_free;
 *     return next_free + d + (255 - byte sum of d, carries added back) % DR_AVR_STEP_MS; */
__attribute__((noinline)) static uint32_t instant_from(uint32_t t)
{
    __asm__("lds r18, %[nf]\n\t"
            "lds r19, %[nf]+1\n\t"
            "lds r20, %[nf]+2\n\t"
            "lds r21, %[nf]+3\n\t"
            "sub %A[t], r18\n\t" /* d */
            "sbc %B[t], r19\n\t"
            "sbc %C[t], r20\n\t"
            "sbc %D[t], r21\n\t"
            "brmi 2f\n\t" /* d < 0 */
            "breq 2f\n\t" /* d == 0 (each sbc keeps Z only while the result is 0) */
            "mov r26, %A[t]\n\t"
            "add r26, %B[t]\n\t"
            "adc r26, __zero_reg__\n\t"
            "add r26, %C[t]\n\t"
            "adc r26, __zero_reg__\n\t"
            "add r26, %D[t]\n\t"
            "adc r26, __zero_reg__\n\t"
            "com r26\n"
            "1:\n\t"
            "subi r26, %[k]\n\t"
            "brcc 1b\n\t"
            "subi r26, -%[k]\n\t"
            "add %A[t], r26\n\t" /* d + the distance to the next instant */
            "adc %B[t], __zero_reg__\n\t"
            "adc %C[t], __zero_reg__\n\t"
            "adc %D[t], __zero_reg__\n\t"
            "add r18, %A[t]\n\t" /* + next_free */
            "adc r19, %B[t]\n\t"
            "adc r20, %C[t]\n\t"
            "adc r21, %D[t]\n"
            "2:\n\t"
            "movw %A[t], r18\n\t"
            "movw %C[t], r20"
            : [t] "+r"(t)
            : [nf] "i"(&next_free), [k] "M"(DR_AVR_STEP_MS)
            : "r18", "r19", "r20", "r21", "r26");
    return t;
}

/* A step is wanted at the first free instant from `t` (or earlier, if one is). */
static void want_step_from(uint32_t t)
{
    uint32_t at = instant_from(t);
    /* As C: if (!has_due || before(at, due)) { due = at; has_due = 1; }. Assembly in
     * call-clobbered registers (the compiler's saved six registers: 28 more bytes). */
    __asm__ __volatile__("lds r18, %[has]\n\t"
                         "tst r18\n\t"
                         "breq 1f\n\t"
                         "lds r18, %[due]\n\t"
                         "lds r19, %[due]+1\n\t"
                         "lds r20, %[due]+2\n\t"
                         "lds r21, %[due]+3\n\t"
                         "cp %A[at], r18\n\t" /* at - due */
                         "cpc %B[at], r19\n\t"
                         "cpc %C[at], r20\n\t"
                         "cpc %D[at], r21\n\t"
                         "brpl 2f\n" /* its sign: at is not before due */
                         "1:\n\t"
                         "sts %[due], %A[at]\n\t"
                         "sts %[due]+1, %B[at]\n\t"
                         "sts %[due]+2, %C[at]\n\t"
                         "sts %[due]+3, %D[at]\n\t"
                         "ldi r18, 1\n\t"
                         "sts %[has], r18\n"
                         "2:"
                         :
                         : [at] "r"(at), [has] "i"(&has_due), [due] "i"(&due)
                         : "r18", "r19", "r20", "r21", "memory");
}

/* Asks the module when it next needs a step (after its init, a step or a frame). */
static void plan(void)
{
    uint32_t at;
    uint8_t answer = dr_module_next_wakeup(&module, &at);
    has_due = 0;
    op_wait = 0;
    if (answer & DR_WAKE_AT) {
        want_step_from(at);
    }
    if (answer & DR_WAKE_OP) {
        dr_avr_op_ended = 0; /* cleared first: an end after the read below still sets it */
        if (dr_hal_op_status(&module) != DR_OP_RUNNING) {
            want_step_from(dr_hal_now_ms(&module));
        } else {
            op_wait = 1;
        }
    }
}

int main(void)
{
    start();
    dr_program_init(&module, 0);
    started();
    next_free = dr_hal_now_ms(&module);
    want_step_from(next_free); /* the first step: at once */
    for (;;) {
        uint32_t now;
        if (any_received()) {
            receive_all();
            plan();
        }
        now = dr_hal_now_ms(&module);
        if (op_wait && dr_avr_op_ended) {
            op_wait = 0;
            want_step_from(now);
        }
        if (has_due && !before(now, due)) {
            /* Instants that passed while the MCU was busy are not stepped (fell behind). */
            next_free = instant_from(now + 1u);
            step(0);
            plan();
        }
        sleep_until_work();
    }
}

#endif
