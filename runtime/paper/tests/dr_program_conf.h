/* dr_program_conf.h - the test programs need no sizes beyond the defaults of dr_conf.h. */
#ifndef DR_PROGRAM_CONF_H
#define DR_PROGRAM_CONF_H
#endif
