//! The lattice protocol in Promela: a transcription of `runtime/lattice/dr_lattice.c`
//! (every inline names the C function it mirrors), with the statement tables from the IR.
//!
//! Abstractions, each exact for what the runtime decides: the `started` bits are left out (the
//! C carries and describes them but never reads them to decide anything); a packet is the
//! sender's `(epoch, low, done)` (framing, CRC and decoding are assumed to drop what is
//! corrupted, which is a loss); the periodic broadcast is "a link may deliver the sender's
//! current copy at any time"; operations never fail (`DR_OP_FAILED` is not modelled); the NV
//! record is written atomically (the runtime's two copies make a reset during the write the
//! same as a reset just before or just after it). Adaptive dissemination changes only when
//! packets go out, so safety is checked as before (any link may deliver at any time); for L
//! the fair links owe only the deliveries the C makes sure of (`WANTS`).

use super::{Fault, Gen};
use std::fmt::Write;

pub(crate) fn write(g: &Gen, out: &mut String) {
    let w = g.ir.window;
    let no_nv = g.options.compile.no_nv;
    let nv = !no_nv && g.options.resets > 0;
    let _ = writeln!(out, "#define W {w}\n#define WMASK {}\n", (1u64 << w) - 1);
    out.push_str("/* ---- Module state: dr_module_t (the `started` bits are never read by the runtime) ---- */\n");
    out.push_str("byte epoch[N_MODULES];         /* shared.epoch */\nbyte low[N_MODULES];           /* shared.low */\nint done[N_MODULES];           /* shared.done: bit i = statement low + i */\nbyte running[N_MODULES] = NONE;\nbyte running_epoch[N_MODULES];\n");
    if nv {
        out.push_str("/* The NV record (address and state; written at each completion). */\nbyte nv_epoch[N_MODULES];\nbyte nv_low[N_MODULES];\nint nv_done[N_MODULES];\n");
    }
    if no_nv {
        out.push_str("/* DR_PROGRAM_NO_NV: rule 1 (neighbours not heard since the restart: bit k = module k) and\n * rule 2 (own completion not echoed yet). */\nint unheard[N_MODULES];\nbyte unechoed[N_MODULES] = NONE;\n");
    }
    if g.options.late > 0 {
        out.push_str("/* Late packets: a copy of a sender's state, in flight. */\nbit l_full[LATE];\nbyte l_from[LATE];\nbyte l_to[LATE];\nbyte l_epoch[LATE];\nbyte l_low[LATE];\nint l_done[LATE];\n");
    }
    out.push_str("/* The incoming packet (scratch: only used inside one d_step). */\nhidden byte in_epoch, in_low;\nhidden int in_done;\nhidden int j_low, j_done;\n\n");

    // dr_program_deps: every statement's waits_for(), checked on module m's copy.
    out.push_str("/* dr_shared_is_done(&m's copy, d) */\n#define IS_DONE(m, d) ((d) < low[m] || ((d) - low[m] < W && ((done[m] >> ((d) - low[m])) & 1)))\n");
    out.push_str("/* dr_shared_is_done(&in, d) */\n#define IN_IS_DONE(d) ((d) < in_low || ((d) - in_low < W && ((in_done >> ((d) - in_low)) & 1)))\n\n");
    out.push_str("/* The deps loop of start_next: every statement s waits for (dr_program_deps) is done in\n * module m's copy. Sets t_ok. */\ninline deps_done(m, s) {\n    t_ok = 1;\n    t_y = waits_first[s];\n    do\n    :: t_y < waits_first[s + 1] -> t_ok = t_ok && IS_DONE(m, waits_list[t_y]); t_y++\n    :: else -> break\n    od;\n    skip\n}\n\n");

    // shift, trim, normalise, join: dr_lattice.c.
    out.push_str("/* shift(): re-base a set k statements higher (bits below the new base dropped). */\n#define SHIFT(x, k) ((k) >= W -> 0 : (((x) >> (k)) & WMASK))\n\n");
    out.push_str("/* dr_shared_normalise(&m's copy): trim the bits at or above N_STATEMENTS, advance low over\n * the completed prefix, roll a complete epoch over to the next one. (N_STATEMENTS > 0 and\n * the epoch never reaches 0xFFFF, the top, in a model.) */\ninline normalise(m) {\n    if\n    :: low[m] > N_STATEMENTS -> low[m] = N_STATEMENTS\n    :: else -> skip\n    fi;\n    t_k = N_STATEMENTS - low[m];\n    if\n    :: t_k < W -> done[m] = done[m] & ((1 << t_k) - 1)\n    :: else -> skip\n    fi;\n    t_k = 0;\n    do\n    :: t_k < W && low[m] + t_k < N_STATEMENTS && ((done[m] >> t_k) & 1) -> t_k++\n    :: else -> break\n    od;\n    done[m] = SHIFT(done[m], t_k);\n    low[m] = low[m] + t_k;\n    if\n    :: low[m] == N_STATEMENTS ->\n        epoch[m]++;\n        low[m] = 0;\n        done[m] = 0\n    :: else -> skip\n    fi\n}\n\n");
    let union = match g.options.fault {
        Some(Fault::JoinDropsDone) => {
            "/* FAULT (deliberately broken): the other copy's bit of the lowest incomplete\n         * statement is dropped. */\n        done[m] = done[m] | (j_done & ~1)"
        }
        _ => "done[m] = done[m] | j_done",
    };
    let rebase = match g.options.fault {
        Some(Fault::JoinNoRebase) => {
            "/* FAULT (deliberately broken): low is raised without re-basing this copy. */\n            low[m] = in_low"
        }
        _ => "done[m] = SHIFT(done[m], in_low - low[m]);\n            low[m] = in_low",
    };
    let _ = writeln!(
        out,
        "/* dr_shared_join(&m's copy, &in): the higher epoch wins wholesale; equal epochs: low = max,\n * both re-based on it and united; then normalise. */\ninline join(m) {{\n    if\n    :: in_epoch > epoch[m] ->\n        epoch[m] = in_epoch;\n        low[m] = in_low;\n        done[m] = in_done\n    :: in_epoch == epoch[m] ->\n        j_low = in_low;\n        j_done = in_done;\n        if\n        :: j_low > low[m] ->\n            {rebase}\n        :: else ->\n            j_done = SHIFT(j_done, low[m] - j_low)\n        fi;\n        {union}\n    :: else -> skip\n    fi;\n    normalise(m)\n}}\n"
    );

    // start_next
    out.push_str("/* start_next(): the first statement of module m in [low, low + W) that is not done and\n * whose dependencies are all done; starts it (the `started` bit is not modelled). */\ninline start_next(m) {\n    if\n    :: ADDR(m) >= MANY_ADDRESSES || epoch[m] >= N_EPOCHS -> skip\n    :: else ->\n        t_i = 0;\n        do\n        :: t_i >= W || low[m] + t_i >= N_STATEMENTS -> break\n        :: else ->\n            t_s = low[m] + t_i;\n            if\n            :: ST_ADDR(t_s) != ADDR(m) || ((done[m] >> t_i) & 1) -> t_i++\n            :: else ->\n                deps_done(m, t_s);\n                if\n                :: t_ok ->\n                    running[m] = t_s;\n                    running_epoch[m] = epoch[m];\n                    issue(m, t_s, epoch[m]);\n                    break\n                :: else -> t_i++\n                fi\n            fi\n        od\n    fi\n}\n\n");

    // persist
    if nv {
        out.push_str("/* persist(): the NV record := the state (atomic: see the file's header). */\ninline persist(m) {\n    nv_epoch[m] = epoch[m];\n    nv_low[m] = low[m];\n    nv_done[m] = done[m]\n}\n\n");
    }
    // connected(): the in-links that exist throughout (assumed to deliver in every stage).
    if no_nv {
        let connected = g.per_module("m", |k| {
            let mask: u64 = g
                .topology
                .links
                .iter()
                .filter(|l| l.to == k && (0..=g.n()).all(|t| l.fair_stages.contains(&t)))
                .fold(0, |acc, l| acc | (1u64 << l.from));
            mask.to_string()
        });
        let _ = writeln!(
            out,
            "/* connected(m): the neighbours latched to m throughout the reconfiguration (bit k =\n * module k). */\n#define CONNECTED(m) {connected}\n"
        );
    }

    // The full model's fair links (the compositional one has its own delivery rule).
    if g.options.compile.dissemination == crate::Dissemination::Adaptive && g.checked.is_none() {
        wants(no_nv, out);
    }

    // dr_module_step
    let on_done = if no_nv {
        "if\n            :: CONNECTED(m) != 0 -> unechoed[m] = running[m] /* rule 2 */\n            :: else -> skip\n            fi;"
    } else if nv {
        "persist(m);"
    } else {
        "/* persist(): not observable without resets (no NV in the model) */"
    };
    // The compositional model: what the module marks done, the truth records.
    let record = if g.checked.is_some() {
        "record(m, running[m]);"
    } else {
        ""
    };
    let may_start = if no_nv {
        "running[m] == NONE && unheard[m] == 0 && unechoed[m] == NONE"
    } else {
        "running[m] == NONE"
    };
    let _ = writeln!(
        out,
        "/* dr_module_step(m): poll the running operation (a completion from an older epoch is\n * dropped; a completion sets the done bit, normalises, persists), then start the next\n * statement if nothing runs here. The broadcast is the links' business. */\ninline step(m) {{\n    if\n    :: running[m] != NONE && !p_run[running[m]] ->\n        if\n        :: running_epoch[m] != epoch[m] ->\n            running[m] = NONE\n        :: else ->\n            t_i = running[m] - low[m];\n            if\n            :: running[m] >= low[m] && t_i < W -> done[m] = done[m] | (1 << t_i)\n            :: else -> skip\n            fi;\n            normalise(m);\n            {on_done}\n            printf(\"@complete %d %d\\n\", m, running[m]);\n            {record}\n            running[m] = NONE\n        fi\n    :: else -> skip\n    fi;\n    if\n    :: {may_start} -> start_next(m)\n    :: else -> skip\n    fi;\n    end_check(m)\n}}\n"
    );

    // dr_module_receive
    let rules = if no_nv {
        "unheard[to] = unheard[to] & ~(1 << from);\n    if\n    :: in_epoch > running_epoch[to] || (in_epoch == running_epoch[to] && unechoed[to] != NONE && IN_IS_DONE(unechoed[to])) ->\n        unechoed[to] = NONE\n    :: else -> skip\n    fi;\n    "
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "/* dr_module_receive(to, packet from `from` in in_*): well formed (a corrupted packet is\n * dropped by the CRC: a loss); join. */\ninline receive(from, to) {{\n    {rules}join(to);\n    end_check(to)\n}}\n\n/* A link delivers the sender's current copy. */\ninline deliver(from, to) {{\n    in_epoch = epoch[from];\n    in_low = low[from];\n    in_done = done[from];\n    printf(\"@deliver %d %d %d %d %d\\n\", from, to, in_epoch, in_low, in_done);\n    receive(from, to);\n    print_copy(to)\n}}\n\n/* For the counterexample: module m's copy now. */\ninline print_copy(m) {{\n    printf(\"@copy %d %d %d %d\\n\", m, epoch[m], low[m], done[m])\n}}\n"
    );
    if g.options.late > 0 {
        out.push_str("inline capture(slot, from, to) {\n    l_full[slot] = 1;\n    l_from[slot] = from;\n    l_to[slot] = to;\n    l_epoch[slot] = epoch[from];\n    l_low[slot] = low[from];\n    l_done[slot] = done[from]\n}\n\ninline deliver_late(slot) {\n    in_epoch = l_epoch[slot];\n    in_low = l_low[slot];\n    in_done = l_done[slot];\n    printf(\"@deliver %d %d %d %d %d\\n\", l_from[slot], l_to[slot], in_epoch, in_low, in_done);\n    receive(l_from[slot], l_to[slot]);\n    print_copy(l_to[slot])\n}\n\n");
    }

    // dr_module_init (a reset)
    let restore = if no_nv {
        let mut s = String::from("unheard[m] = CONNECTED(m); /* rule 1: hear every neighbour connected now (no time-out) */\n    unechoed[m] = NONE;\n");
        if g.options.late > 0 {
            s.push_str("    /* Assumption (b): no packet crosses a reset. */\n");
            for slot in 0..g.options.late {
                let _ = writeln!(
                    s,
                    "    if\n    :: l_from[{slot}] == m || l_to[{slot}] == m -> l_full[{slot}] = 0\n    :: else -> skip\n    fi;"
                );
            }
        }
        s
    } else if nv {
        "/* restore(): join the NV record */\n    in_epoch = nv_epoch[m];\n    in_low = nv_low[m];\n    in_done = nv_done[m];\n    join(m);\n".to_string()
    } else {
        String::new()
    };
    let _ = writeln!(
        out,
        "/* dr_module_init after a reset: the state from the bottom, restored from NV (or, without\n * NV, the rules' bookkeeping), nothing running; the actuator stops. */\ninline reset(m) {{\n    interrupt(m);\n    epoch[m] = 0;\n    low[m] = 0;\n    done[m] = 0;\n    normalise(m);\n    {restore}    running[m] = NONE;\n    running_epoch[m] = 0\n}}\n"
    );
    // The first init of every module.
    let mut init = String::new();
    if no_nv {
        for k in 0..g.m() {
            let _ = writeln!(init, "    unheard[{k}] = CONNECTED({k});");
        }
    }
    let _ = writeln!(
        out,
        "/* The first dr_module_init of every module: the bottom state (zero), nothing running. */\ninline initialise() {{\n{init}    skip\n}}\n"
    );
}

/// `WANTS(f, t)`: the deliveries from f to t that adaptive dissemination makes sure of, the
/// timers abstracted. A copy that holds something the other lacks goes out eventually (news is
/// sent at once and resent while a neighbour has not been heard with it; a neighbour heard
/// behind is answered). Without NV also: a module in its rule-1 wait hears each neighbour
/// (broadcasts never stop: at worst one per longest interval, and never suppressed without NV),
/// and one awaiting an echo hears the neighbour that learnt its completion (news to that one).
fn wants(no_nv: bool, out: &mut String) {
    out.push_str("/* Adaptive dissemination (DR_DISSEMINATION_ADAPTIVE), timers abstracted: AHEAD(f, t) =\n * f's copy holds a fact t's lacks (news f sends, or t is behind and is answered). */\n#define AHEAD(f, t) (epoch[f] > epoch[t] || (epoch[f] == epoch[t] && (low[f] > low[t] || (SHIFT(done[f], low[t] - low[f]) & ~done[t]) != 0)))\n");
    if no_nv {
        out.push_str("/* Without NV: t waits to hear f (rule 1) or for an echo (rule 2). */\n#define WANTS(f, t) (AHEAD(f, t) || ((unheard[t] >> (f)) & 1) || unechoed[t] != NONE)\n\n");
    } else {
        out.push_str("#define WANTS(f, t) AHEAD(f, t)\n\n");
    }
}
