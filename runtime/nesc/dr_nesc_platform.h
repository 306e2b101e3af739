/* dr_nesc_platform.h - what a platform calls in a nesC build of a compiled sequence
 * (runtime/nesc/ stands in for TinyOS's MainC, TimerMilliC and scheduler).
 *
 * At power-on and after a reset: dr_nesc_boot(). Then, as time passes (from the timer
 * interrupt's bottom half, or a host loop): dr_nesc_advance_ms(elapsed), which fires the due
 * timers and runs the posted tasks. For every packet the infrared driver received:
 * dr_platform_receive() (defined by the generated DynaRoleP). Plain C, no nesC types, so a
 * platform written in C can include it. */
#ifndef DR_NESC_PLATFORM_H
#define DR_NESC_PLATFORM_H

#include <stdint.h>

/* Signals Boot.booted and runs the tasks it posted. */
void dr_nesc_boot(void);
/* `ms` milliseconds have passed: signals every due timer (from a task, as TinyOS does) and
 * runs posted tasks, at most DR_NESC_MAX_TASK_RUNS of them (the others wait for the next
 * call), so one call is bounded even if a task keeps posting itself. */
void dr_nesc_advance_ms(uint32_t ms);
/* How many milliseconds may pass before the next dr_nesc_advance_ms has work (a timer due):
 * 0 when it has work now (a timer due, tasks left waiting), DR_NESC_NEVER when no timer
 * runs. A platform that sleeps between calls sleeps that long at most (frames aside). */
uint32_t dr_nesc_until_due_ms(void);
#define DR_NESC_NEVER 0xFFFFFFFFul

/* The generated component's receive path (DynaRoleP.nc). */
void dr_platform_receive(uint8_t channel, const uint8_t *bytes, uint8_t len);

#ifndef DR_NESC_MAX_TASK_RUNS
#define DR_NESC_MAX_TASK_RUNS 32u
#endif

#endif /* DR_NESC_PLATFORM_H */
