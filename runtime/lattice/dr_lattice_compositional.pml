dr_lattice_compositional.pml - the compositional model of the lattice protocol (`dynarole verify
--method compositional`): one module runs dr_lattice.pml (the transcription of dr_lattice.c)
against an abstract robot in which every packet is any state the robot has already reached.
Filled by crates/dynarole-codegen/src/promela/compositional.rs, which gives the soundness
argument (docs/verification.md has it in full).

Syntax: see ../dr_hal.pml (`@@ part`, `{{hole}}`, `{{#flag}}..{{/flag}}`, `{{^flag}}`). The
`{{print_*}}` holes are trail events (promela/events.rs). The model is: truth, the lattice
transcription, guarantee, processes, module, hear, news, fair_news, waits_recorded, env (one
per other module with statements), env_radio, the checked module's actuator, resets, ltl,
init.

@@ truth
/* ---- The truth T: the join of every copy any module ever held (ghost) ---- */
bit t_rec[N_STATEMENTS];  /* recorded: some module's copy holds it done */
bit t_end;                /* every statement recorded: T is in epoch 1 */
byte t_stage;             /* the first statement not recorded */
bit e_pend[N_STATEMENTS]; /* the other modules' statements started and not recorded yet
                            (running, or done and not polled) */

/* Every statement s waits for (dr_program_deps) is recorded. Sets t_ok. */
inline waits_recorded(s) {
    t_ok = 1;
    t_y = waits_first[s];
    do
    :: t_y < waits_first[s + 1] -> t_ok = t_ok && t_rec[waits_list[t_y]]; t_y++
    :: else -> break
    od;
    skip
}

/* Module m marks s done in its copy: T takes it. G4: only what is physically done, and
 * only once everything it waits for is recorded. */
inline record(m, s) {
    {{print_record}};
    waits_recorded(s);
    if
    :: !g_done[s] || !t_ok -> {{print_g4}}; assert(false)
    :: else -> skip
    fi;
    t_rec[s] = 1;
    do
    :: t_stage < N_STATEMENTS && t_rec[t_stage] -> t_stage++
    :: else -> break
    od;
    if
    :: t_stage == N_STATEMENTS -> t_end = 1
    :: else -> skip
    fi
}

@@ guarantee
/* What the module under check guarantees to the others (they were assumed to do the
 * same): G1 its copy is below T; G2 its copy is closed under dependencies; G3 its copy
 * keeps every statement it recorded itself. */
inline guarantee(m) {
    if
    :: epoch[m] >= N_EPOCHS && !t_end -> {{print_g1_end}}; assert(false)
    :: else -> skip
    fi;
    t_j = 0;
    do
    :: t_j < N_STATEMENTS && epoch[m] < N_EPOCHS ->
        if
        :: IS_DONE(m, t_j) && !t_rec[t_j] -> {{print_g1}}; assert(false)
        :: else -> skip
        fi;
        if
        :: IS_DONE(m, t_j) ->
            deps_done(m, t_j);
            if
            :: !t_ok -> {{print_g2}}; assert(false)
            :: else -> skip
            fi
        :: else -> skip
        fi;
        if
        :: ST_ADDR(t_j) == ADDR(m) && t_rec[t_j] && !IS_DONE(m, t_j) -> {{print_g3}}; assert(false)
        :: else -> skip
        fi;
        t_j++
    :: else -> break
    od;
    skip /* the break must land inside the d_step */
}

@@ module
/* ---- Processes (compositional: module {{c}}, {{name}}, is the one checked) ---- */
/* Module {{c}}: dr_module_step, one call per step; then its guarantees. */
proctype module_{{c}}() {
    do
    :: d_step { step({{c}}); print_copy({{c}}); guarantee({{c}}) }
    od
}

@@ news
/* The checked module hears a packet holding the state (e, l, d) (dr_module_receive, then
 * its guarantees). */
inline hear(e, l, d) {
    in_epoch = e;
    in_low = l;
    in_done = d;
    {{print_hear}};
    join({{c}});
    end_check({{c}});
    print_copy({{c}});
    guarantee({{c}})
}

/* Any packet: any state below T that is closed under dependencies, i.e. the join of some
 * states ↓s (s and all it waits for, transitively) with s in T. Delivered one ↓s at a time,
 * in any order, any number of times, or never: losses, delays, duplicates, any topology. */
proctype news() {
    do
{{down_sets}}
    :: d_step { t_end -> hear(1, 0, 0) } /* the end */
    od
}

@@ fair_news
#ifdef LIVENESS
/* What the links that surely exist carry to the checked module, eventually (weak fairness): the
 * dependencies of its next statements in the stages where every module that runs one of them
 * reaches it, and the end when every module that runs statements reaches it at the end. */
proctype fair_news() {
    do
{{waits}}
{{#end_reaches}}
    :: d_step { t_end && epoch[{{c}}] < N_EPOCHS -> hear(1, 0, 0) } /* the end */
{{/end_reaches}}
{{^end_reaches}}
    :: false -> skip /* nothing is carried surely */
{{/end_reaches}}
    od
}
#endif

@@ waits_recorded
{{defines}}

@@ env
/* Module {{k}} ({{name}}), abstracted: it starts any of its statements that is not in T,
 * not started already and whose dependencies are all in T (its copy is below T and keeps
 * its own completions), several at once (a batch; or one at a time), each operation
 * finishes after an unknown time (its actuator: one process with the module), and it
 * records each finished statement in T (a batch recorded at once is these records one after
 * the other). Every step starts, finishes or records one of its statements, so between
 * resets it takes finitely many: weak fairness per process makes each step that stays
 * enabled happen. With LIVENESS, a start is fair only in the stages where the links that
 * surely exist carry the dependencies to it. */
proctype env_{{k}}() {
    do
{{starts}}
{{finishes}}
{{records}}
    od
}

@@ env_start
    :: d_step {
#ifdef LIVENESS
        {{stages}} &&
#endif
        {{start}} }
@@ env_radio
#ifdef LIVENESS
/* Starts that no link that surely exists justifies (a link may still deliver): unfair. */
proctype env_radio() {
    do
{{starts}}
    od
}
#endif

@@ resets
/* Resets: at most RESETS, of any module, at any moment (mid-operation too). */
proctype resets() {
    byte left = RESETS;
    do
{{resets}}
    :: break
    od
}

@@ init
/* L: eventually module {{c}} knows the end, for good. */
ltl finishes { <> [] FINISHED({{c}}) }

init {
{{tables}}    d_step { initialise() };
    atomic {
        run module_{{c}}();
        run news();
{{runs}}
{{#resets}}
        run resets();
{{/resets}}
#ifdef LIVENESS
        run fair_news();
{{#others}}
        run env_radio();
{{/others}}
#endif
    }
}
