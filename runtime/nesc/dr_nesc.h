/* dr_nesc.h - what TinyOS's headers would give a nesC program, for compiling dynarole's
 * component without TinyOS: pass it to nescc as -fnesc-include=dr_nesc.
 *
 * nesC expects these names (booleans, error codes, the atomic section hooks) from the
 * platform; on the ATmega128 an atomic section masks interrupts, on the host it is empty
 * (the host platforms call the component from one thread). */
#ifndef DR_NESC_H
#define DR_NESC_H

#include <stdint.h>
#include "dr_nesc_platform.h"

typedef uint8_t bool;
enum { FALSE = 0, TRUE = 1 };

typedef uint8_t error_t;
enum { SUCCESS = 0, FAIL = 1, EBUSY = 2 };

/* The precision tag of millisecond timers (Timer<TMilli>). */
typedef struct { int unused; } TMilli;

#if defined(__AVR__)
/* Saves the status register (the interrupt flag with it) and masks interrupts; the assembler
 * knows __SREG__ for every AVR, so no device header is needed. */
typedef uint8_t __nesc_atomic_t;
static inline __nesc_atomic_t __nesc_atomic_start(void)
{
    __nesc_atomic_t saved;
    __asm__ __volatile__("in %0, __SREG__\n\tcli" : "=r"(saved) : : "memory");
    return saved;
}
static inline void __nesc_atomic_end(__nesc_atomic_t saved)
{
    __asm__ __volatile__("out __SREG__, %0" : : "r"(saved) : "memory");
}
#else
typedef uint8_t __nesc_atomic_t;
static inline __nesc_atomic_t __nesc_atomic_start(void)
{
    return 0;
}
static inline void __nesc_atomic_end(__nesc_atomic_t saved)
{
    (void)saved;
}
#endif

#endif /* DR_NESC_H */
