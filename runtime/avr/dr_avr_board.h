/* dr_avr_board.h - the hemisphere board as the ATmega128 firmware sees it: which pins
 * and registers of the board's controller do what (README.md describes it). One definition
 * for both sides: the firmware (dr_avr.c) and the emulated board around the emulated MCU
 * (the simulator's simavr shim) include this file. Plain constants, no AVR headers. */
#ifndef DR_AVR_BOARD_H
#define DR_AVR_BOARD_H

/* Clock and timing. */
#define DR_AVR_F_CPU 16000000UL
/* The infrared serial line: 19200 baud, 8N1 on USART0 (the simulator's network model uses
 * the same rate). */
#define DR_AVR_BAUD 19200UL
/* Period of dr_module_step (the simulator's host platform uses the same). */
#define DR_AVR_STEP_MS 5u

/* Ports. Port B: the controller's data bus, MCU to board. Port A: its data bus, board to
 * MCU. Port D: strobes to the controller, active on the rising edge. Port C: infrared
 * transmitter enables, bit c = channel c (the USART's TX line reaches every transmitter whose
 * enable is set). Port E: status outputs for measurement (PE0 and PE1 are USART0's RXD and
 * TXD). */
#define DR_AVR_STROBE_ADDR 4    /* PD4: PORTB is the next register address */
#define DR_AVR_STROBE_WRITE 5   /* PD5: PORTB goes into the addressed register (address + 1) */
#define DR_AVR_STROBE_READ 6    /* PD6: the addressed register appears on PINA (address + 1) */
#define DR_AVR_STROBE_RELEASE 7 /* PD7: the frame being received is taken; the next may come */
#define DR_AVR_PIN_OP_END 0     /* PD0 (INT0), from the controller: high once the operation
                                 * started last has ended (status no longer RUNNING), low
                                 * while one runs; its rising edge wakes the MCU */
#define DR_AVR_PIN_STEP 2       /* PE2: high while dr_module_step runs */
#define DR_AVR_PIN_RECEIVE 3    /* PE3: high while dr_module_receive runs */
#define DR_AVR_PIN_FINISHED 4   /* PE4: high once the module knows the sequence has ended */
#define DR_AVR_PIN_STOPPED 6    /* PE6: high once the module's failure policy stopped it
                                 * (dr_module_finished answers DR_END_STOPPED) */
#define DR_AVR_PIN_DESCRIBED 5  /* PE5: a pulse once dr_avr_description holds the module's
                                 * state (images built with DR_AVR_DESCRIBE, for traces) */

/* The controller's registers. Multi-byte values are little-endian. */
#define DR_AVR_REG_STATEMENT 0x00u /* w: 2 bytes, the statement of the next operation */
#define DR_AVR_REG_OP 0x02u        /* w: its operation code */
#define DR_AVR_REG_INDEX 0x03u     /* w: its part (connector or joint) */
#define DR_AVR_REG_ADDRESS 0x04u   /* w: the module's address (role), for the board's log */
#define DR_AVR_REG_GO 0x05u        /* w: any value starts the operation described above */
#define DR_AVR_REG_LEDS 0x06u      /* w: the LEDs */
#define DR_AVR_REG_STATUS 0x10u    /* r: enum dr_op_status of the operations started */
#define DR_AVR_REG_ID 0x11u        /* r: 2 bytes, the module's ID (board configuration) */
#define DR_AVR_REG_CONNECTED 0x13u /* r: bit c set when connector c is latched */
#define DR_AVR_REG_RX_CHANNEL 0x14u /* r: channel of the frame being received */
#define DR_AVR_REG_NEIGHBOUR 0x20u /* r: 2 bytes per connector, the latched neighbour's ID or -1 */
#define DR_AVR_REG_JOINT 0x30u     /* r: 2 bytes per joint, its position */
#define DR_AVR_REG_ARGS 0x40u      /* w: 2 bytes per argument of the next operation */
#define DR_AVR_REGS 0x60u          /* registers in all (addresses wrap) */

#define DR_AVR_CHANNELS 8u    /* connectors (infrared channels) the board has */
#define DR_AVR_JOINTS 8u      /* joints whose positions it reports */
#define DR_AVR_MAX_ARGS 16u   /* operation arguments it takes */

/* Size of dr_avr_description, the module's state as dr_module_describe writes it (the
 * simulator keeps as much for a host-compiled module). */
#define DR_AVR_DESCRIPTION 64u

/* Bytes above the .bss that the emulator paints at reset to measure the stack's depth. */
#define DR_AVR_PAINT 0xC5u

#endif /* DR_AVR_BOARD_H */
