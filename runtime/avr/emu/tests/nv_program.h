/* nv_program.h - what nv_program.c (the EEPROM test's firmware) and test_nv.c (its harness
 * on the emulated board) agree on: the records' size and place, and the LEDs' values. */
#ifndef NV_PROGRAM_H
#define NV_PROGRAM_H

#define NV_RECORD 12u          /* bytes of a record; one at the EEPROM's start, one at its end */
#define NV_EEPROM_SIZE 4096u   /* the ATmega128's EEPROM */
/* The two records: B as A in some bytes (the write leaves those alone), 0xFF (the erased
 * value) among the others. */
#define NV_RECORD_A {0x00, 0x01, 0x5A, 0xA5, 0x80, 0x7F, 0x12, 0x34, 0xFE, 0x00, 0xC3, 0x3C}
#define NV_RECORD_B {0x00, 0x11, 0x5A, 0xFF, 0x80, 0x7E, 0x12, 0x35, 0xFE, 0x01, 0xC3, 0x3D}

/* The LEDs after a start: what the firmware found in its EEPROM and what it did. */
#define NV_WROTE_A 0x0Au /* nothing: record A written (and read back) */
#define NV_WROTE_B 0x0Bu /* record A: record B written over it */
#define NV_FOUND_B 0xB0u /* record B: nothing written */
#define NV_LOST 0xE1u    /* a record written did not read back */
#define NV_BOUNDS 0xE2u  /* a write past the EEPROM's end changed its last byte */

#endif /* NV_PROGRAM_H */
