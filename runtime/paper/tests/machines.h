/* machines.h - hand-written state machines in the shape the compiler generates (Fig. 2, e.9), for the tests. */
#ifndef MACHINES_H
#define MACHINES_H

#include "dr_paper.h"

/* Operation codes of the test plugin. */
#define OP_RETRACT 1u
#define OP_EXTEND 2u
#define OP_ROTATE 3u
#define OP_A 10u
#define OP_B 11u
#define OP_C 12u
#define OP_Z 13u

/* The first seven statements of eight2car (Fig. 5), states 0-17, then the end:
 *   1-3   M0.Connector[0].retract() &          (Fig. 2 states 1, 2, 3)
 *   4-5   M3.Connector[4].retract();           (Fig. 2 states 4, 5)
 *   6-7   M3.Joint.rotateFromToBy(0,324,false,150);
 *   8-9   M4.Joint.rotateFromToBy(0,108,true,150);   (9 falls through to 10: same module)
 *   10-12 M4.Connector[0].extend() &
 *   13-15 M1.Joint.rotateFromToBy(0,324,false,150) &
 *   16-17 M6.Connector[2].retract();           -> 254
 * Addresses are the module IDs 0-6. */
extern const dr_paper_program_t eight2car_program;
/* Fig. 4's view of module `address` right after it last executed `state` (the figure's rows
 * are numbered by the state executed). */
extern dr_paper_global_t eight2car_after[7][18];

/* `A & B; C;` on modules 0, 1, 2 of a line: A = states 1-3 (0), B = 4-5 (1), C = 6-7 (2). */
extern const dr_paper_program_t ab_c_program;
/* `Z; A & B; C;`: Z = 1-2 (module 1), A = 3-5 (0), B = 6-7 (1), C = 8-9 (2). */
extern const dr_paper_program_t z_ab_c_program;

#endif /* MACHINES_H */
