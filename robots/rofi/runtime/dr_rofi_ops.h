/* dr_rofi_ops.h - the operation codes dr_rofi.c runs, and where they come from.
 *
 * The codes are the generated program's (dr_program.h: DR_OP_<PART>_<OPERATION>, numbered by
 * the code generator), so the platform must not assume their values:
 * - built with a program (-DDR_ROFI_PROGRAM, the program's directory on the include path:
 *   `make check-program`, a firmware), they are the program's own dr_program.h;
 * - built without one (the platform's tests), they come from dr_rofi_test_ops.h, which the
 *   tests' include path provides (tests/: numbers unlike the generator's, on purpose).
 * Either way the three must be defined; any of them may also be given with -D (a program of
 * another robot whose operations are named otherwise, for a compile check). */
#ifndef DR_ROFI_OPS_H
#define DR_ROFI_OPS_H

#ifdef DR_ROFI_PROGRAM
#include "dr_program.h"
#else
#include "dr_rofi_test_ops.h"
#endif

#if !defined(DR_OP_JOINT_ROTATEFROMTOBY) || !defined(DR_OP_CONNECTOR_CONNECT) || \
    !defined(DR_OP_CONNECTOR_DISCONNECT)
#error "dr_rofi.c needs DR_OP_JOINT_ROTATEFROMTOBY, DR_OP_CONNECTOR_CONNECT and DR_OP_CONNECTOR_DISCONNECT (a RoFI program's dr_program.h)"
#endif

#endif /* DR_ROFI_OPS_H */
