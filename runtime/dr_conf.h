/* dr_conf.h - every tunable of the dynarole runtime, in one place.
 *
 * Each value can be overridden with -D on the compiler command line or by the generated
 * dr_program_conf.h (included first), which sets the sizes a given sequence needs. */
#ifndef DR_CONF_H
#define DR_CONF_H

/* Values of DR_CONF_LATTICE_DISSEMINATION (defined before the generated header, which may
 * choose one). */
#define DR_DISSEMINATION_FIXED 0
#define DR_DISSEMINATION_ADAPTIVE 1

#include "dr_program_conf.h"

/* Most statements a compiled program may have (the compiler checks and sets it). */
#ifndef DR_CONF_MAX_STATEMENTS
#define DR_CONF_MAX_STATEMENTS 255
#endif

/* Lattice protocol: statements tracked above the low-water mark, a multiple of 8. The
 * compiler computes the window the sequence needs and sets it; packets carry window / 8
 * bytes of the done set. */
#ifndef DR_CONF_WINDOW
#define DR_CONF_WINDOW 16
#endif

/* Lattice protocol: entries of the program's dependency table and rows of its argument
 * table (the compiler sets both; they choose the width of the statement table's indices). */
#ifndef DR_CONF_DEP_ENTRIES
#define DR_CONF_DEP_ENTRIES 65535
#endif
#ifndef DR_CONF_ARG_ROWS
#define DR_CONF_ARG_ROWS 65535
#endif

/* Lattice protocol: DR_CONF_LATTICE_BATCH, most statements a module runs at once (a batch,
 * started when none runs): its first startable statement and its startable ones among the
 * next BATCH - 1, 1 to 9 (1: one at a time). The meaning's dependencies keep the others in
 * order. No default here: the compiler decides it once (LATTICE_BATCH in the code generator's
 * c.rs) and writes it into the generated dr_program_conf.h and into the Promela model, so an
 * image and its model run the same batches; runtime/lattice/Makefile passes the same value to
 * the runtime's own tests. */

/* Lattice protocol: what a module does when an operation of its running batch fails (the
 * HAL says DR_OP_FAILED: a connector that did not latch, a joint that stalled).
 * DR_ON_FAILURE_RETRY (the default): the batch is issued again, at most DR_CONF_RETRIES
 * times (each at the retry pace of the dissemination policy); when those are spent the module
 * stops. DR_ON_FAILURE_STOP: it stops at the first failure. A module that stopped starts
 * nothing more, keeps sharing the state it holds, and says so (dr_module_finished answers
 * DR_END_STOPPED); a reset gives it its retries again. `dynarole compile --on-failure` and
 * `--retries` set both in the generated dr_program_conf.h. */
#define DR_ON_FAILURE_STOP 0
#define DR_ON_FAILURE_RETRY 1
#ifndef DR_CONF_ON_FAILURE
#define DR_CONF_ON_FAILURE DR_ON_FAILURE_RETRY
#endif
#ifndef DR_CONF_RETRIES
#define DR_CONF_RETRIES 3
#endif

/* Most arguments of one operation. */
#ifndef DR_CONF_MAX_ARGS
#define DR_CONF_MAX_ARGS 4
#endif

/* Paper protocol: slots of the pending set (the original used 5). */
#ifndef DR_CONF_MAX_PENDING
#define DR_CONF_MAX_PENDING 5
#endif

/* Period of the continuous broadcast, and the random jitter added to each period (ms). The
 * original simulator used 100 ms and no jitter; the nesC version 200 ms plus 0-127 ms. */
#ifndef DR_CONF_BROADCAST_MS
#define DR_CONF_BROADCAST_MS 100
#endif
#ifndef DR_CONF_BROADCAST_JITTER_MS
#define DR_CONF_BROADCAST_JITTER_MS 0
#endif

/* Lattice protocol: how the state is disseminated (`dynarole compile --dissemination` sets
 * it in dr_program_conf.h).
 * DR_DISSEMINATION_FIXED: a broadcast every DR_CONF_BROADCAST_MS (+ jitter) for the whole
 * run, and at once after a local start or completion (the behaviour before adaptive
 * dissemination existed; its object code is the same as then).
 * DR_DISSEMINATION_ADAPTIVE (the default): Trickle-like (RFC 6206). News (the copy grew: a
 * local completion, or a join that added something; a start is not news; relayed on every
 * channel, the sender's too, as its acknowledgement) and hearing a neighbour whose copy lacks
 * something ours has are sent at the next step, and bring the interval back to
 * DR_CONF_LATTICE_INTERVAL_MS. Once every connected neighbour has been heard with a copy at
 * least ours, the longest interval (INTERVAL << DR_CONF_LATTICE_DOUBLINGS); until then
 * DR_CONF_LATTICE_RESENDS broadcasts at the smallest interval, then at most
 * DR_CONF_LATTICE_UNACKED_DOUBLINGS doublings (each at a random time in the last
 * DR_CONF_LATTICE_RESEND_SPREAD % of its interval), and the smallest interval for as long as a
 * neighbour heard behind has not been heard with our copy. Such a retry is an asking frame
 * (DR_PACKET_LATTICE_ASK): a neighbour that holds our copy answers it at its next step, on
 * that channel. Measurements behind the values: runtime/lattice/README.md ("Adaptive
 * dissemination") and docs/benchmarks.md. */
#ifndef DR_CONF_LATTICE_DISSEMINATION
#define DR_CONF_LATTICE_DISSEMINATION DR_DISSEMINATION_ADAPTIVE
#endif
/* Adaptive: the smallest interval (ms); also the pace of a failed operation's retries. */
#ifndef DR_CONF_LATTICE_INTERVAL_MS
#define DR_CONF_LATTICE_INTERVAL_MS 100
#endif
/* Adaptive: the longest interval is INTERVAL << DOUBLINGS (3.2 s): how often a module whose
 * neighbours all hold its copy still speaks (a cut-off module hears what it missed within
 * about that long once its link is back). */
#ifndef DR_CONF_LATTICE_DOUBLINGS
#define DR_CONF_LATTICE_DOUBLINGS 5
#endif
/* Adaptive: broadcasts at the smallest interval while a connected neighbour has not been
 * heard with a copy at least ours since ours last changed (its packet may have been lost).
 * 1 by measurement (README.md): 3 sent 22 % more packets at loss 0 for a median 6 % earlier
 * at loss 0.6 (measured with the cap at 400 ms and no spread). */
#ifndef DR_CONF_LATTICE_RESENDS
#define DR_CONF_LATTICE_RESENDS 1
#endif
/* Adaptive: after the resends, the most doublings while a connected neighbour still has not
 * been heard with our copy (3: every 400 to 800 ms with the spread below; a neighbour heard
 * behind, i.e. known to lack a fact, is tried every INTERVAL instead, as the fixed period
 * does across a link that passes almost nothing). Such a retry goes only to the channels
 * that still need it once some connected neighbour has our copy (with NV), and asks. 3 by
 * measurement (README.md, 200 seeds): since retries ask, an 800 ms cap spread over its last
 * half keeps every median earlier and every 95th percentile within 2 % of fixed's, with
 * 5.2x / 5.3x fewer packets than fixed at loss 0.6 (2, 400 ms: 4.8x / 5.0x; 3 with the
 * spread at 25 %: 95th percentile 7.7 % later on eight2car). */
#ifndef DR_CONF_LATTICE_UNACKED_DOUBLINGS
#define DR_CONF_LATTICE_UNACKED_DOUBLINGS 3
#endif
/* Adaptive: a broadcast toward an unacknowledged neighbour (a resend, or a try at the capped
 * or the smallest interval) goes out at a random time in the last this-many percent of its
 * interval, not at its end: modules that heard the same news at once would otherwise resend
 * in step and collide again (0: at the end). 50: the capped tries every 400 to 800 ms. The
 * smallest interval's spread is rounded down to whole milliseconds and doubles with the
 * interval; the largest must stay below 65,535 ms (checked at compile time). */
#ifndef DR_CONF_LATTICE_RESEND_SPREAD
#define DR_CONF_LATTICE_RESEND_SPREAD 50
#endif
/* Adaptive: news and answers go out at the next step plus 0 to this many ms at random, so
 * that neighbours hearing the same news do not all send at once (their packets would collide
 * at the modules between them). */
#ifndef DR_CONF_LATTICE_RELAY_JITTER_MS
#define DR_CONF_LATTICE_RELAY_JITTER_MS 30
#endif
/* Adaptive: k, the suppression threshold: a due broadcast is skipped when k packets with a
 * copy equal to ours were heard since the last one and every connected neighbour has our
 * copy (0: never skipped). */
#ifndef DR_CONF_LATTICE_SUPPRESS
#define DR_CONF_LATTICE_SUPPRESS 1
#endif

/* Lattice protocol: 1 when the program has synchronous groups (`sync { ... }`; the compiler
 * sets it in dr_program_conf.h). Each state packet then carries a second window of bits, the
 * statements whose modules are ready to start them, and each statement its group (README.md,
 * "Synchronous groups"); 0 leaves the build as it was without them. */
#ifndef DR_CONF_SYNC
#define DR_CONF_SYNC 0
#endif
/* With DR_CONF_SYNC: how long after a synchronous group is ready (its last member's module
 * set to start it) its members start, in ms: DR_CONF_SYNC_DELAY_MS, plus
 * DR_CONF_SYNC_DELAY_PER_MEMBER_MS for each member after the first. Every module learns the
 * instant with the age of the news, so all of them start at it but for the packets' transit
 * times; the delay is for the news to reach every member, retries included, before any of
 * them moves (a turning module's links break), and the members of a larger group are more
 * links apart (the members stand for the links: the runtime does not know the shape). */
#ifndef DR_CONF_SYNC_DELAY_MS
#define DR_CONF_SYNC_DELAY_MS 400
#endif
#ifndef DR_CONF_SYNC_DELAY_PER_MEMBER_MS
#define DR_CONF_SYNC_DELAY_PER_MEMBER_MS 40
#endif
/* With DR_CONF_SYNC: while a module counts down, it sends its state and the countdown again
 * at a random time between half this and this many ms after the last time, until the start:
 * a neighbour that missed the news (two neighbours answering it at once collide at its
 * half-duplex side, again and again) hears it on one of several independent tries within the
 * delay. 0: only when it is news. */
#ifndef DR_CONF_SYNC_REPEAT_MS
#define DR_CONF_SYNC_REPEAT_MS 60
#endif

/* Largest packet, in bytes (receive buffers are this big). */
#ifndef DR_CONF_MAX_PACKET
#define DR_CONF_MAX_PACKET 48
#endif

/* Bytes of the keyed authentication tag on every packet (dr_packet.h): 0 (no tag, the
 * default), or 4 or 8 for a build with a key (`dynarole compile --key` sets it). */
#ifndef DR_CONF_PACKET_TAG
#define DR_CONF_PACKET_TAG 0
#endif

/* The robot (or swarm) identity every packet carries; packets of another robot are dropped.
 * Set at compile time (`dynarole compile --robot-id`, in dr_program_conf.h) or at flash time
 * (-DDR_ROBOT_ID=N). */
#ifndef DR_ROBOT_ID
#define DR_ROBOT_ID 0u
#endif

/* The execution: a 32-bit value chosen anew for every launch of the robot, so that a packet
 * recorded in another launch of the same program (replayed under this robot's identity) and
 * the NV record another launch left are refused (dr_packet.h, DR_PACKET_PROGRAM_WORD). One
 * execution covers every sequence and epoch of one launch and every reset within it. Set at
 * compile time (`dynarole compile --execution`, in dr_program_conf.h) or at flash time
 * (-DDR_EXECUTION=N); every module of a robot must have the same one. */
#ifndef DR_EXECUTION
#define DR_EXECUTION 0UL
#endif

/* Connectors (infrared channels) per module. */
#ifndef DR_CONF_CHANNELS
#define DR_CONF_CHANNELS 8
#endif

/* Lattice protocol: how a module survives a reset, fixed at compile time so that an image
 * carries one way only: DR_CONF_NV_RECORD (its state kept in non-volatile storage),
 * DR_CONF_NV_NONE (no NV storage: DR_PROGRAM_NO_NV's rules, the neighbours' copies), or
 * DR_CONF_NV_EITHER (both, chosen per program at run time by DR_PROGRAM_NO_NV; the runtime's
 * own tests). The compiler sets the one its program needs in dr_program_conf.h. */
#define DR_CONF_NV_EITHER 0
#define DR_CONF_NV_RECORD 1
#define DR_CONF_NV_NONE 2
#ifndef DR_CONF_NV
#define DR_CONF_NV DR_CONF_NV_EITHER
#endif

/* Lattice protocol: width of the report counters (packets sent, received, malformed,
 * foreign), 16 or 32 bits. Only reports read them (the simulator keeps its own counts): on an
 * 8-bit core 16 bits save 8 B of RAM per module and the 32-bit increments' flash (they wrap
 * after 65,536 packets). */
#ifndef DR_CONF_COUNTER_BITS
#if defined(__AVR__)
#define DR_CONF_COUNTER_BITS 16
#else
#define DR_CONF_COUNTER_BITS 32
#endif
#endif

/* Lattice protocol: whether the image holds one program only, the generated `dr_program`
 * (dr_program.c). The runtime then reads the program's fields as constants the compiler folds
 * into the code, not through the module's pointer. An MCU's firmware is one program; the
 * simulator and the C tests link several. */
#ifndef DR_CONF_ONE_PROGRAM
#if defined(__AVR__)
#define DR_CONF_ONE_PROGRAM 1
#else
#define DR_CONF_ONE_PROGRAM 0
#endif
#endif

/* Lattice protocol: where the persisted state lives in non-volatile storage (two copies, one
 * after the other). */
#ifndef DR_CONF_LATTICE_NV_ADDR
#define DR_CONF_LATTICE_NV_ADDR 0
#endif

/* Token baseline: messages a module keeps until acknowledged. The original's queue was
 * unbounded; two neighbours whose messages wait for each other's acknowledgement never
 * acknowledge (see runtime/token/README.md), so with unlimited tries messages pile up: a full
 * queue drops new ones. */
#ifndef DR_CONF_TOKEN_QUEUE
#define DR_CONF_TOKEN_QUEUE 16
#endif
/* Token baseline: (sender, counter) pairs remembered to drop duplicates (the original kept 64). */
#ifndef DR_CONF_TOKEN_SEEN
#define DR_CONF_TOKEN_SEEN 64
#endif
/* Token baseline: acknowledgements waiting to be sent. */
#ifndef DR_CONF_TOKEN_ACKS
#define DR_CONF_TOKEN_ACKS 6
#endif

#endif /* DR_CONF_H */
