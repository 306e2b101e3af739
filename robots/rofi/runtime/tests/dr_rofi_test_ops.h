/* dr_rofi_test_ops.h - operation codes for the platform's tests (dr_rofi_ops.h), in place of
 * a generated dr_program.h: unlike the code generator's numbering (which counts from 0 in the
 * plugin's order), so that a platform that assumed its values would fail the tests. */
#ifndef DR_ROFI_TEST_OPS_H
#define DR_ROFI_TEST_OPS_H

#define DR_OP_CONNECTOR_CONNECT 7u
#define DR_OP_CONNECTOR_DISCONNECT 3u
#define DR_OP_JOINT_ROTATEFROMTOBY 5u

#endif /* DR_ROFI_TEST_OPS_H */
