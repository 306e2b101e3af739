dr_lattice.pml - the lattice protocol in Promela: a transcription of dr_lattice.c, beside it
(every inline names the C function it mirrors), filled by
crates/dynarole-codegen/src/promela/lattice.rs (which says what is abstracted and why).

Syntax: see ../dr_hal.pml (`@@ part`, `{{hole}}`, `{{#flag}}..{{/flag}}`, `{{^flag}}`).
Flags: nv (NV storage and resets: the NV record, persist, restore), no_nv (DR_PROGRAM_NO_NV:
rules 1 and 2), no_persist (neither: persist is not observable), late (late-packet slots),
fault_drops_done and fault_no_rebase (deliberately broken joins, to show the checks can fail),
wants (adaptive dissemination: what the fair links owe), record (the compositional model: the
truth records each completion). The `{{print_*}}` holes are trail events (promela/events.rs).

@@ lattice
#define W {{w}}
#define WMASK {{wmask}}
#define BATCH {{batch}}         /* DR_CONF_LATTICE_BATCH */

/* ---- Module state: dr_module_t ---- */
byte epoch[N_MODULES];         /* shared.epoch */
byte low[N_MODULES];           /* shared.low */
int done[N_MODULES];           /* shared.done: bit i = statement low + i */
byte running[N_MODULES] = NONE; /* the batch's first statement */
byte running_epoch[N_MODULES];
byte batch[N_MODULES];         /* the batch's others: bit k = statement running + 1 + k */
{{#nv}}
/* The NV record (address and state; written at each completion). */
byte nv_epoch[N_MODULES];
byte nv_low[N_MODULES];
int nv_done[N_MODULES];
{{/nv}}
{{#no_nv}}
/* DR_PROGRAM_NO_NV: rule 1 (neighbours not heard since the restart: bit k = module k) and
 * rule 2 (own completion not echoed yet). */
int unheard[N_MODULES];
byte unechoed[N_MODULES] = NONE;
{{/no_nv}}
{{#late}}
/* Late packets: a copy of a sender's state, in flight. */
bit l_full[LATE];
byte l_from[LATE];
byte l_to[LATE];
byte l_epoch[LATE];
byte l_low[LATE];
int l_done[LATE];
{{/late}}
/* The incoming packet (scratch: only used inside one d_step). */
hidden byte in_epoch, in_low;
hidden int in_done;
hidden int j_low, j_done;

/* dr_shared_is_done(&m's copy, d) */
#define IS_DONE(m, d) ((d) < low[m] || ((d) - low[m] < W && ((done[m] >> ((d) - low[m])) & 1)))
/* dr_shared_is_done(&in, d) */
#define IN_IS_DONE(d) ((d) < in_low || ((d) - in_low < W && ((in_done >> ((d) - in_low)) & 1)))

/* The deps loop of start_next: every statement s waits for (dr_program_deps) is done in
 * module m's copy. Sets t_ok. */
inline deps_done(m, s) {
    t_ok = 1;
    t_y = waits_first[s];
    do
    :: t_y < waits_first[s + 1] -> t_ok = t_ok && IS_DONE(m, waits_list[t_y]); t_y++
    :: else -> break
    od;
    skip
}

/* shift(): re-base a set k statements higher (bits below the new base dropped). */
#define SHIFT(x, k) ((k) >= W -> 0 : (((x) >> (k)) & WMASK))

/* dr_shared_normalise(&m's copy): trim the bits at or above N_STATEMENTS, advance low over
 * the completed prefix, roll a complete epoch over to the next one. (N_STATEMENTS > 0 and
 * the epoch never reaches 0xFFFF, the top, in a model.) */
inline normalise(m) {
    if
    :: low[m] > N_STATEMENTS -> low[m] = N_STATEMENTS
    :: else -> skip
    fi;
    t_k = N_STATEMENTS - low[m];
    if
    :: t_k < W -> done[m] = done[m] & ((1 << t_k) - 1)
    :: else -> skip
    fi;
    t_k = 0;
    do
    :: t_k < W && low[m] + t_k < N_STATEMENTS && ((done[m] >> t_k) & 1) -> t_k++
    :: else -> break
    od;
    done[m] = SHIFT(done[m], t_k);
    low[m] = low[m] + t_k;
    if
    :: low[m] == N_STATEMENTS ->
        epoch[m]++;
        low[m] = 0;
        done[m] = 0
    :: else -> skip
    fi
}

/* dr_shared_join(&m's copy, &in): the higher epoch wins wholesale; equal epochs: low = max,
 * both re-based on it and united; then normalise. */
inline join(m) {
    if
    :: in_epoch > epoch[m] ->
        epoch[m] = in_epoch;
        low[m] = in_low;
        done[m] = in_done
    :: in_epoch == epoch[m] ->
        j_low = in_low;
        j_done = in_done;
        if
        :: j_low > low[m] ->
{{#fault_no_rebase}}
            /* FAULT (deliberately broken): low is raised without re-basing this copy. */
            low[m] = in_low
{{/fault_no_rebase}}
{{^fault_no_rebase}}
            done[m] = SHIFT(done[m], in_low - low[m]);
            low[m] = in_low
{{/fault_no_rebase}}
        :: else ->
            j_done = SHIFT(j_done, low[m] - j_low)
        fi;
{{#fault_drops_done}}
        /* FAULT (deliberately broken): the other copy's bit of the lowest incomplete
         * statement is dropped. */
        done[m] = done[m] | (j_done & ~1)
{{/fault_drops_done}}
{{^fault_drops_done}}
        done[m] = done[m] | j_done
{{/fault_drops_done}}
    :: else -> skip
    fi;
    normalise(m)
}

/* start_next() with next_startable() and issue(): a batch, the first statement of module m
 * in [low, low + W) that is not done and whose dependencies are all done, and the others
 * such among the BATCH - 1 after it; starts them all, in order (the `started` bits are not
 * modelled). Called only when nothing runs on m. */
inline start_next(m) {
    if
    :: ADDR(m) >= MANY_ADDRESSES || epoch[m] >= N_EPOCHS -> skip
    :: else ->
        t_i = 0;
        do
        :: t_i >= W || low[m] + t_i >= N_STATEMENTS ||
           (running[m] != NONE && low[m] + t_i - running[m] >= BATCH) -> break
        :: else ->
            t_s = low[m] + t_i;
            if
            :: ST_ADDR(t_s) != ADDR(m) || ((done[m] >> t_i) & 1) -> skip
            :: else ->
                deps_done(m, t_s);
                if
                :: t_ok && running[m] == NONE ->
                    running[m] = t_s;
                    running_epoch[m] = epoch[m];
                    batch[m] = 0;
                    issue(m, t_s, epoch[m])
                :: t_ok && running[m] != NONE ->
                    batch[m] = batch[m] | (1 << (t_s - running[m] - 1));
                    issue(m, t_s, epoch[m])
                :: else -> skip
                fi
            fi;
            t_i++
        od
    fi
}

{{#nv}}
/* persist(): the NV record := the state (atomic: see the file's header). */
inline persist(m) {
    nv_epoch[m] = epoch[m];
    nv_low[m] = low[m];
    nv_done[m] = done[m]
}

{{/nv}}
{{#no_nv}}
/* connected(m): the neighbours latched to m throughout the reconfiguration (bit k =
 * module k). */
#define CONNECTED(m) {{connected}}

{{/no_nv}}
{{#wants}}
/* Adaptive dissemination (DR_DISSEMINATION_ADAPTIVE), timers abstracted: AHEAD(f, t) =
 * f's copy holds a fact t's lacks (news f sends, or t is behind and is answered). */
#define AHEAD(f, t) (epoch[f] > epoch[t] || (epoch[f] == epoch[t] && (low[f] > low[t] || (SHIFT(done[f], low[t] - low[f]) & ~done[t]) != 0)))
{{#no_nv}}
/* Without NV: t waits to hear f (rule 1) or for an echo (rule 2). */
#define WANTS(f, t) (AHEAD(f, t) || ((unheard[t] >> (f)) & 1) || unechoed[t] != NONE)

{{/no_nv}}
{{^no_nv}}
#define WANTS(f, t) AHEAD(f, t)

{{/no_nv}}
{{/wants}}
/* dr_module_step(m): poll the running batch (dr_hal_op_status: DONE once none of m's
 * operations runs; a completion from an older epoch is dropped; a completion sets the done
 * bits of the whole batch, normalises, persists once), then start the next batch if nothing
 * runs here. The broadcast is the links' business. */
inline step(m) {
    if
    :: running[m] != NONE && !BUSY(m) ->
        if
        :: running_epoch[m] != epoch[m] ->
            running[m] = NONE
        :: else ->
            t_i = 0;
            do
            :: t_i < BATCH ->
                t_s = running[m] + t_i;
                if
                :: t_i == 0 || ((batch[m] >> (t_i - 1)) & 1) ->
                    if
                    :: t_s >= low[m] && t_s - low[m] < W -> done[m] = done[m] | (1 << (t_s - low[m]))
                    :: else -> skip
                    fi;
                    {{print_complete}};
{{#record}}
                    record(m, t_s);
{{/record}}
                    skip
                :: else -> skip
                fi;
                t_i++
            :: else -> break
            od;
            normalise(m);
{{#no_nv}}
            if
            :: CONNECTED(m) != 0 -> unechoed[m] = running[m] /* rule 2 */
            :: else -> skip
            fi;
{{/no_nv}}
{{#nv}}
            persist(m);
{{/nv}}
{{#no_persist}}
            /* persist(): not observable without resets (no NV in the model) */
{{/no_persist}}
            running[m] = NONE
        fi
    :: else -> skip
    fi;
    if
    :: running[m] == NONE{{#no_nv}} && unheard[m] == 0 && unechoed[m] == NONE{{/no_nv}} -> start_next(m)
    :: else -> skip
    fi;
    end_check(m)
}

/* dr_module_receive(to, packet from `from` in in_*): well formed (a corrupted packet is
 * dropped by the CRC: a loss); join. */
inline receive(from, to) {
{{#no_nv}}
    unheard[to] = unheard[to] & ~(1 << from);
    if
    :: in_epoch > running_epoch[to] || (in_epoch == running_epoch[to] && unechoed[to] != NONE && IN_IS_DONE(unechoed[to])) ->
        unechoed[to] = NONE
    :: else -> skip
    fi;
{{/no_nv}}
    join(to);
    end_check(to)
}

/* A link delivers the sender's current copy. */
inline deliver(from, to) {
    in_epoch = epoch[from];
    in_low = low[from];
    in_done = done[from];
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
    l_epoch[slot] = epoch[from];
    l_low[slot] = low[from];
    l_done[slot] = done[from]
}

/* The held packet arrives (dr_module_receive of a stale copy), as deliver does. */
inline deliver_late(slot) {
    in_epoch = l_epoch[slot];
    in_low = l_low[slot];
    in_done = l_done[slot];
    {{print_deliver_late}};
    receive(l_from[slot], l_to[slot]);
    print_copy(l_to[slot])
}

{{/late}}
/* dr_module_init after a reset: the state from the bottom, restored from NV (or, without
 * NV, the rules' bookkeeping), nothing running; the actuator stops. */
inline reset(m) {
    interrupt(m);
    epoch[m] = 0;
    low[m] = 0;
    done[m] = 0;
    normalise(m);
{{#no_nv}}
    unheard[m] = CONNECTED(m); /* rule 1: hear every neighbour connected now (no time-out) */
    unechoed[m] = NONE;
{{#late}}
    /* Assumption (b): no packet crosses a reset. */
{{crossing}}
{{/late}}
{{/no_nv}}
{{#nv}}
    /* restore(): join the NV record */
    in_epoch = nv_epoch[m];
    in_low = nv_low[m];
    in_done = nv_done[m];
    join(m);
{{/nv}}
    running[m] = NONE;
    running_epoch[m] = 0;
    batch[m] = 0
}

/* The first dr_module_init of every module: the bottom state (zero), nothing running. */
inline initialise() {
{{#no_nv}}
{{unheard}}
{{/no_nv}}
    skip
}

