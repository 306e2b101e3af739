dr_paper.pml - the paper's protocol in Promela: a transcription of dr_paper.c, beside it
(every inline names the C function it mirrors), and of the Fig. 2 switch that
crates/dynarole-codegen/src/paper.rs generates, as tables read by one inline
(program_step). Filled by crates/dynarole-codegen/src/promela/paper.rs, which says what is
abstracted and why.

Syntax: see ../dr_hal.pml (`@@ part`, `{{hole}}`, `{{#flag}}..{{/flag}}`, `{{^flag}}`).
Flags: restart (the Sec. III-C restart of an interrupted pending operation: the started
marks), late (late-packet slots). The `{{print_*}}` holes are trail events
(promela/events.rs); the `sw_*` constants are the switch's case numbers (promela/paper.rs).
program_step interprets the switch's tables one case per iteration; a C fall-through is
`t_go = 1`, `t_u` is the state, `t_v` the unit's pending state or the transfer's target.

@@ paper
#define P {{slots}}            /* DR_CONF_MAX_PENDING */
#define MERGE {{merge}}        /* 0 printed (> and), 1 Java (> or), 2 C port (>= or) */
#define SINGLE_STEP_HANDOVER {{single_step_handover}}
#define FIRST_ADDRESS {{first_address}}
#define STATE_END {{state_end}}
#define IDLE {{idle}}
#define ADDRESS_ALL {{address_all}}

/* ---- Module state: dr_module_t ---- */
byte g_state[N_MODULES];       /* global.state */
byte g_addr[N_MODULES];        /* global.address */
byte pend[N_MODULES * P];      /* global.pending, slot k of module m at m * P + k; 0 = empty */
byte lstate[N_MODULES] = IDLE; /* local_state, the switch's state */
byte mailbox[N_MODULES] = IDLE;
{{#restart}}
byte mark[N_MODULES * P];      /* started: pending states started since the reset */
{{/restart}}
{{#late}}
bit l_full[LATE];
byte l_from[LATE];
byte l_to[LATE];
byte l_state[LATE];
byte l_addr[LATE];
byte l_pend[LATE * P];
{{/late}}
/* Scratch, only used inside one d_step: the incoming packet, the merge's output. */
hidden byte in_state, in_addr;
hidden byte in_pend[P];
hidden byte t_out[P];
hidden byte t_before[P];
hidden byte t_p, t_bound, t_n, t_before_state;
hidden byte t_eq, t_first_local, t_has, t_known, t_keep, t_go;

/* set_has(t_out, s): whether s is in the P slots. Sets t_has. */
inline set_has_out(m, s) {
    t_has = 0;
    t_j = 0;
    do
    :: t_j < P -> if :: t_out[0 + t_j] == s -> t_has = 1 :: else -> skip fi; t_j++
    :: else -> break
    od
}

/* set_has(in_pend, s): whether s is in the P slots. Sets t_has. */
inline set_has_in(m, s) {
    t_has = 0;
    t_j = 0;
    do
    :: t_j < P -> if :: in_pend[0 + t_j] == s -> t_has = 1 :: else -> skip fi; t_j++
    :: else -> break
    od
}

/* set_has(pend, s): whether s is in the P slots. Sets t_has. */
inline set_has_pend(m, s) {
    t_has = 0;
    t_j = 0;
    do
    :: t_j < P -> if :: pend[m * P + t_j] == s -> t_has = 1 :: else -> skip fi; t_j++
    :: else -> break
    od
}

{{#restart}}
/* set_has(mark, s): whether s is in the P slots. Sets t_has. */
inline set_has_mark(m, s) {
    t_has = 0;
    t_j = 0;
    do
    :: t_j < P -> if :: mark[m * P + t_j] == s -> t_has = 1 :: else -> skip fi; t_j++
    :: else -> break
    od
}

{{/restart}}
/* dr_paper_merge(&m's global, &in, MERGE) (Fig. 3, e.3): keep from the first set whatever
 * passes the bound or is also in the second set; equal states intersect. */
inline merge(m) {
    t_eq = 0;
    if
    :: g_state[m] == in_state -> t_eq = 1; t_first_local = 1; t_bound = g_state[m]
    :: g_state[m] > in_state -> t_first_local = 1; t_bound = in_state
    :: else -> t_first_local = 0; t_bound = g_state[m]
    fi;
    t_i = 0;
    do
    :: t_i < P -> t_out[t_i] = 0; t_i++
    :: else -> break
    od;
    t_n = 0;
    t_i = 0;
    do
    :: t_i >= P -> break
    :: else ->
        t_p = (t_first_local -> pend[m * P + t_i] : in_pend[t_i]);
        set_has_out(m, t_p);
        if
        :: t_p == 0 || t_has -> skip /* empty slot, or a duplicate from a packet */
        :: else ->
            if
            :: t_first_local -> set_has_in(m, t_p)
            :: else -> set_has_pend(m, t_p)
            fi;
            t_known = t_has;
            if
            :: t_eq -> t_keep = t_known
            :: else ->
                t_has = (MERGE == 2 -> t_p >= t_bound : t_p > t_bound); /* above */
                t_keep = (MERGE == 0 -> (t_has && t_known) : (t_has || t_known))
            fi;
            if
            :: t_keep -> t_out[t_n] = t_p; t_n++
            :: else -> skip
            fi
        fi;
        t_i++
    od;
    if
    :: g_state[m] < in_state -> g_state[m] = in_state; g_addr[m] = in_addr
    :: else -> skip
    fi;
    t_i = 0;
    do
    :: t_i < P -> pend[m * P + t_i] = t_out[t_i]; t_i++
    :: else -> break
    od
}

{{#restart}}
/* mark_started(m, s): remember that m started pending state s; when full, the lowest mark
 * gives way. */
inline mark_started(m, s) {
    set_has_mark(m, s);
    if
    :: t_has -> skip
    :: else ->
        t_k = 0; /* the lowest mark */
        t_j = 0;
        do
        :: t_j < P && mark[m * P + t_j] == 0 -> mark[m * P + t_j] = s; break
        :: t_j < P && mark[m * P + t_j] != 0 ->
            if :: mark[m * P + t_j] < mark[m * P + t_k] -> t_k = t_j :: else -> skip fi;
            t_j++
        :: else -> mark[m * P + t_k] = s; break
        od
    fi
}

{{/restart}}
/* dr_paper_add_pending(m, s): no-op when present; silently nothing when full. */
inline add_pending(m, s) {
    if
    :: s == 0 -> skip
    :: else ->
{{#restart}}
        mark_started(m, s);
{{/restart}}
        set_has_pend(m, s);
        if
        :: !t_has ->
            t_j = 0;
            do
            :: t_j < P && pend[m * P + t_j] == 0 -> pend[m * P + t_j] = s; break
            :: t_j < P && pend[m * P + t_j] != 0 -> t_j++
            :: else -> break
            od
        :: else -> skip
        fi
    fi
}

/* dr_paper_remove_pending(m, s): clears the first matching slot. */
inline remove_pending(m, s) {
    t_j = 0;
    do
    :: s != 0 && t_j < P && pend[m * P + t_j] == s -> pend[m * P + t_j] = 0; break
    :: s != 0 && t_j < P && pend[m * P + t_j] != s -> t_j++
    :: else -> break
    od
}

/* dr_paper_has_pending(m) */
#define HAS_PENDING(m) ({{has_pending}})

/* dr_paper_send_state(m, s, a): only a higher state changes the copy. */
inline send_state(m, s, a) {
    if
    :: s > g_state[m] -> g_state[m] = s; g_addr[m] = a
    :: else -> skip
    fi
}

/* dr_paper_handover(m, pending, next, address): state S+1 of a parallel statement. */
inline handover(m, pending, s, a) {
    if
    :: SINGLE_STEP_HANDOVER -> add_pending(m, pending)
    :: else -> skip
    fi;
    send_state(m, s, a)
}

/* dr_program_responsible(a, p) (checkPendingStateResponsibility, generated) */
#define RESPONSIBLE(a, p) ({{responsible}})

{{#restart}}
/* restart_check(m) (e.6): a pending state present before and after the merge, that m is
 * responsible for and has not started since its reset, goes into the mailbox. */
inline restart_check(m) {
    t_i = 0;
    do
    :: t_i >= P -> break
    :: else ->
        t_p = t_before[t_i];
        t_keep = 0;
        if
        :: t_p != 0 ->
            set_has_pend(m, t_p);
            t_known = t_has;
            set_has_mark(m, t_p);
            t_keep = t_known && !t_has && RESPONSIBLE(ADDR(m), t_p)
        :: else -> skip
        fi;
        if
        :: t_keep -> mailbox[m] = t_p; break
        :: else -> t_i++
        fi
    od
}

{{/restart}}
/* dr_module_receive(to, packet in in_*): merge; if the state rose and names this module, the
 * mailbox gets it; otherwise the pending restart (option). */
inline receive(from, to) {
    t_i = 0;
    do
    :: t_i < P -> t_before[t_i] = pend[to * P + t_i]; t_i++
    :: else -> break
    od;
    t_before_state = g_state[to];
    merge(to);
    if
    :: g_state[to] > t_before_state ->
        if
        :: g_addr[to] == ADDR(to) && g_addr[to] != ADDRESS_ALL -> mailbox[to] = g_state[to]
        :: else -> skip
        fi
    :: else -> {{#restart}}restart_check(to){{/restart}}{{^restart}}skip /* no pending restart */{{/restart}}
    fi;
    end_check(to)
}

/* A link delivers the sender's current copy. */
inline deliver(from, to) {
    in_state = g_state[from];
    in_addr = g_addr[from];
    t_i = 0;
    do
    :: t_i < P -> in_pend[t_i] = pend[from * P + t_i]; t_i++
    :: else -> break
    od;
    {{print_deliver}};
    receive(from, to);
    print_copy(to)
}

/* For the counterexample: module m's copy now. */
inline print_copy(m) {
    {{print_copy}}
}

{{#late}}
/* The environment, no C: slot takes a copy of `from`'s state for `to` (a packet sent now,
 * to be delivered late: dr_hal_broadcast's packet held in the air). */
inline capture(slot, from, to) {
    l_full[slot] = 1;
    l_from[slot] = from;
    l_to[slot] = to;
    l_state[slot] = g_state[from];
    l_addr[slot] = g_addr[from];
    t_i = 0;
    do
    :: t_i < P -> l_pend[slot * P + t_i] = pend[from * P + t_i]; t_i++
    :: else -> break
    od
}

/* The held packet arrives (dr_module_receive of a stale copy), as deliver does. */
inline deliver_late(slot) {
    in_state = l_state[slot];
    in_addr = l_addr[slot];
    t_i = 0;
    do
    :: t_i < P -> in_pend[t_i] = l_pend[slot * P + t_i]; t_i++
    :: else -> break
    od;
    {{print_deliver_late}};
    receive(l_from[slot], l_to[slot]);
    print_copy(l_to[slot])
}

{{/late}}
/* The switch's layout (paper.rs): first state, kind, module address, statements. */
{{layout}}
#define SW_STATES {{sw_states}}
#define SW_PARALLEL_START {{sw_parallel_start}}
#define SW_HANDOVER {{sw_handover}}
#define SW_PARALLEL_WAIT {{sw_parallel_wait}}
#define SW_START {{sw_start}}
#define SW_SEQUENTIAL_WAIT {{sw_sequential_wait}}
#define SW_BLOCK_WAIT {{sw_block_wait}}
/* State t's case (SW_*, 0: none), the statements it starts (sw_issue[sw_issue_first[t] ..
 * sw_issue_first[t + 1])), where control goes next (state, address) and whether by falling
 * through (the next unit is on the same module). */
hidden byte sw_kind[SW_STATES];
hidden short sw_issue_first[SW_STATES + 1];
hidden byte sw_issue[{{sw_issue_size}}];
hidden byte sw_next[SW_STATES];
hidden byte sw_next_addr[SW_STATES];
hidden byte sw_local[SW_STATES];
hidden byte t_u, t_v;
hidden short t_w;

/* dr_program_step(m): the generated switch, case for case from the tables. */
inline program_step(m) {
    t_go = 1;
    do
    :: !t_go -> break
    :: else ->
        t_go = 0;
        t_u = lstate[m];
        if
        :: t_u == 0 -> lstate[m] = 1; t_go = 1 /* entry */
        :: t_u != 0 && t_u < SW_STATES && (sw_kind[t_u] == SW_PARALLEL_START || sw_kind[t_u] == SW_START) ->
            if
            :: sw_kind[t_u] == SW_PARALLEL_START -> t_v = t_u; add_pending(m, t_v)
            :: else -> skip
            fi;
            t_w = sw_issue_first[t_u];
            do
            :: t_w < sw_issue_first[t_u + 1] -> issue(m, sw_issue[t_w], 0); t_w++
            :: else -> break
            od;
            lstate[m] = t_u + 1
        :: t_u != 0 && t_u < SW_STATES && sw_kind[t_u] == SW_HANDOVER ->
            t_v = t_u - 1;
            handover(m, t_v, sw_next[t_u], sw_next_addr[t_u]);
            lstate[m] = t_u + 1;
            t_go = 1
        :: t_u != 0 && t_u < SW_STATES && sw_kind[t_u] == SW_PARALLEL_WAIT ->
            if
            :: BUSY(m) -> skip
            :: else -> t_v = t_u - 2; remove_pending(m, t_v); lstate[m] = IDLE
            fi
        :: t_u != 0 && t_u < SW_STATES && (sw_kind[t_u] == SW_SEQUENTIAL_WAIT || sw_kind[t_u] == SW_BLOCK_WAIT) ->
            if
            :: sw_kind[t_u] == SW_SEQUENTIAL_WAIT && (HAS_PENDING(m) || BUSY(m)) -> skip
            :: sw_kind[t_u] == SW_BLOCK_WAIT && BUSY(m) -> skip /* a block does not look at the pending set */
            :: else ->
                t_v = sw_next[t_u];
                if
                :: sw_local[t_u] -> lstate[m] = t_v; t_go = 1
                :: else -> send_state(m, t_v, sw_next_addr[t_u]); lstate[m] = IDLE
                fi
            fi
        :: else -> skip
        fi
    od
}

/* dr_module_step(m): an idle module takes the mailbox, then one step of the switch. */
inline step(m) {
    if
    :: lstate[m] == IDLE -> lstate[m] = mailbox[m]; mailbox[m] = IDLE
    :: else -> skip
    fi;
    program_step(m);
    end_check(m)
}

/* start() (e.10, every init and reset): copy <0, 0, {}>, idle, mailbox empty; the first
 * module puts state 0 in its mailbox. */
inline paper_start(m) {
    mailbox[m] = IDLE;
    g_state[m] = 0;
    g_addr[m] = 0;
    t_j = 0;
    do
    :: t_j < P -> pend[m * P + t_j] = 0; t_j++
    :: else -> break
    od;
{{#restart}}
    t_j = 0;
    do
    :: t_j < P -> mark[m * P + t_j] = 0; t_j++
    :: else -> break
    od;
{{/restart}}
    lstate[m] = IDLE;
    if
    :: ADDR(m) == FIRST_ADDRESS && g_state[m] == 0 -> mailbox[m] = 0
    :: else -> skip
    fi
}

/* dr_module_init after a reset: the actuator stops, then start() again. */
inline reset(m) {
    interrupt(m);
    paper_start(m)
}

/* The first dr_module_init of every module. */
inline initialise() {
{{starts}}
    skip
}

