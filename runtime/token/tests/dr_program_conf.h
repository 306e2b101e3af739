/* dr_program_conf.h - sizes for the token runtime's tests (the real one is generated per
 * program). */
#ifndef DR_PROGRAM_CONF_H
#define DR_PROGRAM_CONF_H

#define DR_CONF_MAX_STATEMENTS 16
/* Exercise dr_hal_random: 100 ms plus 0-20 ms. */
#define DR_CONF_BROADCAST_JITTER_MS 20

#endif /* DR_PROGRAM_CONF_H */
