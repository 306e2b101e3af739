/* dr_program_conf.h - the platform's tests build without a program; the runtime's defaults
 * (dr_conf.h) are the sizes they need. */
#ifndef DR_PROGRAM_CONF_H
#define DR_PROGRAM_CONF_H

#endif /* DR_PROGRAM_CONF_H */
