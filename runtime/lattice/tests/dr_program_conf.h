/* dr_program_conf.h - sizes for the lattice runtime's tests (the real one is generated per
 * program). The Makefile builds the tests once per window with -DDR_CONF_WINDOW=W, and with
 * the compiler's batch size, -DDR_CONF_LATTICE_BATCH (read where the compiler decides it). */
#ifndef DR_PROGRAM_CONF_H
#define DR_PROGRAM_CONF_H

#ifndef DR_CONF_MAX_STATEMENTS
#define DR_CONF_MAX_STATEMENTS 64
#endif
#ifndef DR_CONF_WINDOW
#define DR_CONF_WINDOW 16
#endif
/* Exercise dr_hal_random: 100 ms plus 0-20 ms. */
#ifndef DR_CONF_BROADCAST_JITTER_MS
#define DR_CONF_BROADCAST_JITTER_MS 20
#endif

#endif /* DR_PROGRAM_CONF_H */
