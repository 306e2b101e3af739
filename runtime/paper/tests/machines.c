/* machines.c - hand-written state machines in the shape of Fig. 2 / e.9 (eight2car's first statements, two line scenarios). */
#include "machines.h"
#include "harness.h"

dr_paper_global_t eight2car_after[7][18];

static uint8_t address_by_id(struct dr_module *m)
{
    uint16_t id = dr_hal_id(m);
    return id < 7u ? (uint8_t)id : 127u; /* e.10: anything else gets 127 */
}

static uint8_t done(dr_module_t *m)
{
    return (uint8_t)(dr_hal_op_status(m) == DR_OP_DONE);
}

/* `statement`: the statement's number in the sequence (what a generated machine passes). */
static void op(dr_module_t *m, uint16_t statement, uint8_t code, uint8_t index, int16_t a0,
               int16_t a1, int16_t a2, int16_t a3)
{
    int16_t args[DR_CONF_MAX_ARGS] = {0};
    args[0] = a0;
    args[1] = a1;
    args[2] = a2;
    args[3] = a3;
    dr_hal_op_start(m, statement, code, index, args);
}

/* Leaving state s (by break or fall-through): record Fig. 4's view for the golden test. */
static void after(dr_module_t *m, uint8_t s)
{
    if (m->address < 7u && s < 18u) {
        fig4_view(m, &eight2car_after[m->address][s]);
    }
}

static void eight2car_step(dr_module_t *m)
{
    switch (m->local_state) {
    case 0:
        m->local_state = 1;
        /* fall-through */
    case 1: /* M0 */
        dr_paper_add_pending(m, 1);
        op(m, 0u, OP_RETRACT, 0, 0, 0, 0, 0);
        m->local_state = 2;
        after(m, 1);
        break;
    case 2:
        dr_paper_handover(m, 1, 4, 3); /* Fig. 2: sendState(4,3) */
        m->local_state = 3;
        after(m, 2);
        /* fall-through */
    case 3:
        if (!done(m)) {
            break;
        }
        dr_paper_remove_pending(m, 1);
        m->local_state = DR_STATE_IDLE;
        after(m, 3);
        break;
    case 4: /* M3 */
        op(m, 1u, OP_RETRACT, 4, 0, 0, 0, 0);
        m->local_state = 5;
        after(m, 4);
        break;
    case 5:
        if (dr_paper_has_pending(m)) {
            break;
        }
        if (!done(m)) {
            break;
        }
        m->local_state = 6;
        after(m, 5);
        /* fall-through */
    case 6: /* M3, sequential (e.9; Fig. 2's addPendingState(6) is not generated) */
        op(m, 2u, OP_ROTATE, 0, 0, 324, 0, 150);
        m->local_state = 7;
        after(m, 6);
        break;
    case 7:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, 8, 4);
        m->local_state = DR_STATE_IDLE;
        after(m, 7);
        break;
    case 8: /* M4 */
        op(m, 3u, OP_ROTATE, 0, 0, 108, 1, 150);
        m->local_state = 9;
        after(m, 8);
        break;
    case 9:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        m->local_state = 10; /* next statement on the same module */
        after(m, 9);
        /* fall-through */
    case 10: /* M4 */
        dr_paper_add_pending(m, 10);
        op(m, 4u, OP_EXTEND, 0, 0, 0, 0, 0);
        m->local_state = 11;
        after(m, 10);
        break;
    case 11:
        dr_paper_handover(m, 10, 13, 1);
        m->local_state = 12;
        after(m, 11);
        /* fall-through */
    case 12:
        if (!done(m)) {
            break;
        }
        dr_paper_remove_pending(m, 10);
        m->local_state = DR_STATE_IDLE;
        after(m, 12);
        break;
    case 13: /* M1 */
        dr_paper_add_pending(m, 13);
        op(m, 5u, OP_ROTATE, 0, 0, 324, 0, 150);
        m->local_state = 14;
        after(m, 13);
        break;
    case 14:
        dr_paper_handover(m, 13, 16, 6);
        m->local_state = 15;
        after(m, 14);
        /* fall-through */
    case 15:
        if (!done(m)) {
            break;
        }
        dr_paper_remove_pending(m, 13);
        m->local_state = DR_STATE_IDLE;
        after(m, 15);
        break;
    case 16: /* M6 */
        op(m, 6u, OP_RETRACT, 2, 0, 0, 0, 0);
        m->local_state = 17;
        after(m, 16);
        break;
    case 17:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, DR_STATE_END, DR_ADDRESS_ALL);
        m->local_state = DR_STATE_IDLE;
        after(m, 17);
        break;
    default:
        break;
    }
}

/* checkPendingStateResponsibility (e.12). */
static uint8_t eight2car_responsible(uint8_t address, uint8_t state)
{
    return (uint8_t)((address == 0u && state == 1u) || (address == 4u && state == 10u) ||
                     (address == 1u && state == 13u));
}

const dr_paper_program_t eight2car_program = {
    42, 0, address_by_id, eight2car_step, eight2car_responsible
};

/* ---- `A & B; C;` ---- */

static void ab_c_step(dr_module_t *m)
{
    switch (m->local_state) {
    case 0:
        m->local_state = 1;
        /* fall-through */
    case 1: /* module 0: A & (state S) */
        dr_paper_add_pending(m, 1);
        op(m, 0u, OP_A, 0, 0, 0, 0, 0);
        m->local_state = 2;
        break;
    case 2: /* S+1: transfer */
        dr_paper_handover(m, 1, 4, 1);
        m->local_state = 3;
        /* fall-through */
    case 3:
        if (!done(m)) {
            break;
        }
        dr_paper_remove_pending(m, 1);
        m->local_state = DR_STATE_IDLE;
        break;
    case 4: /* module 1: B; */
        op(m, 1u, OP_B, 0, 0, 0, 0, 0);
        m->local_state = 5;
        break;
    case 5:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, 6, 2);
        m->local_state = DR_STATE_IDLE;
        break;
    case 6: /* module 2: C; */
        op(m, 2u, OP_C, 0, 0, 0, 0, 0);
        m->local_state = 7;
        break;
    case 7:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, DR_STATE_END, DR_ADDRESS_ALL);
        m->local_state = DR_STATE_IDLE;
        break;
    default:
        break;
    }
}

static uint8_t ab_c_responsible(uint8_t address, uint8_t state)
{
    return (uint8_t)(address == 0u && state == 1u);
}

const dr_paper_program_t ab_c_program = {
    43, 0, address_by_id, ab_c_step, ab_c_responsible
};

/* ---- `Z; A & B; C;` ---- */

static void z_ab_c_step(dr_module_t *m)
{
    switch (m->local_state) {
    case 0:
        m->local_state = 1;
        /* fall-through */
    case 1: /* module 1: Z; */
        op(m, 0u, OP_Z, 0, 0, 0, 0, 0);
        m->local_state = 2;
        break;
    case 2:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, 3, 0);
        m->local_state = DR_STATE_IDLE;
        break;
    case 3: /* module 0: A & */
        dr_paper_add_pending(m, 3);
        op(m, 1u, OP_A, 0, 0, 0, 0, 0);
        m->local_state = 4;
        break;
    case 4:
        dr_paper_handover(m, 3, 6, 1);
        m->local_state = 5;
        /* fall-through */
    case 5:
        if (!done(m)) {
            break;
        }
        dr_paper_remove_pending(m, 3);
        m->local_state = DR_STATE_IDLE;
        break;
    case 6: /* module 1: B; */
        op(m, 2u, OP_B, 0, 0, 0, 0, 0);
        m->local_state = 7;
        break;
    case 7:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, 8, 2);
        m->local_state = DR_STATE_IDLE;
        break;
    case 8: /* module 2: C; */
        op(m, 3u, OP_C, 0, 0, 0, 0, 0);
        m->local_state = 9;
        break;
    case 9:
        if (dr_paper_has_pending(m) || !done(m)) {
            break;
        }
        dr_paper_send_state(m, DR_STATE_END, DR_ADDRESS_ALL);
        m->local_state = DR_STATE_IDLE;
        break;
    default:
        break;
    }
}

static uint8_t z_ab_c_responsible(uint8_t address, uint8_t state)
{
    return (uint8_t)(address == 0u && state == 3u);
}

const dr_paper_program_t z_ab_c_program = {
    44, 1, address_by_id, z_ab_c_step, z_ab_c_responsible
};
