//! The paper's protocol in Promela: a transcription of `runtime/paper/dr_paper.c` (every
//! inline names the C function it mirrors) and of the Fig. 2 switch that `paper.rs` generates,
//! state for state, from the same layout (`Ir::paper_layout`), so that the model splits steps
//! exactly as the generated C does.
//!
//! Abstractions: a packet is the sender's (state, address, pending slots) (the alternate flag
//! is always 0, framing and CRC drop what is corrupted: a loss); the periodic broadcast is "a
//! link may deliver the sender's current copy at any time"; the "started" marks (e.2) are
//! modelled only with the pending restart, the one thing that reads them.

use super::Gen;
use crate::c::PaperMerge;
use dynarole_core::lower::{LimitError, PaperUnit, PaperUnitKind};
use std::fmt::Write;

pub(crate) fn write(
    g: &Gen,
    out: &mut String,
    slots: usize,
) -> Result<Vec<(u8, Vec<usize>)>, LimitError> {
    let units = g.ir.paper_layout()?;
    let o = &g.options.compile;
    let merge = match o.merge {
        PaperMerge::Printed => 0,
        PaperMerge::Java => 1,
        PaperMerge::CPort => 2,
    };
    let first_address = g.ir.statements.first().map_or(0, |s| s.address);
    let _ = writeln!(
        out,
        "#define P {slots}            /* DR_CONF_MAX_PENDING */\n#define MERGE {merge}        /* 0 printed (> and), 1 Java (> or), 2 C port (>= or) */\n#define SINGLE_STEP_HANDOVER {}\n#define FIRST_ADDRESS {first_address}\n#define STATE_END 254\n#define IDLE 255\n#define ADDRESS_ALL 255\n",
        u8::from(o.single_step_handover)
    );
    out.push_str("/* ---- Module state: dr_module_t ---- */\nbyte g_state[N_MODULES];       /* global.state */\nbyte g_addr[N_MODULES];        /* global.address */\nbyte pend[N_MODULES * P];      /* global.pending, slot k of module m at m * P + k; 0 = empty */\nbyte lstate[N_MODULES] = IDLE; /* local_state, the switch's state */\nbyte mailbox[N_MODULES] = IDLE;\n");
    if o.restart_pending {
        out.push_str("byte mark[N_MODULES * P];      /* started: pending states started since the reset */\n");
    }
    if g.options.late > 0 {
        out.push_str("bit l_full[LATE];\nbyte l_from[LATE];\nbyte l_to[LATE];\nbyte l_state[LATE];\nbyte l_addr[LATE];\nbyte l_pend[LATE * P];\n");
    }
    out.push_str("/* Scratch, only used inside one d_step: the incoming packet, the merge's output. */\nhidden byte in_state, in_addr;\nhidden byte in_pend[P];\nhidden byte t_out[P];\nhidden byte t_before[P];\nhidden byte t_p, t_bound, t_n, t_before_state;\nhidden byte t_eq, t_first_local, t_has, t_known, t_keep, t_go;\n\n");

    // set_has, merge
    // set_has(): Promela cannot pass arrays, so one inline per set.
    for (name, set, base) in [
        ("out", "t_out", "0"),
        ("in", "in_pend", "0"),
        ("pend", "pend", "m * P"),
        ("mark", "mark", "m * P"),
    ] {
        if name == "mark" && !o.restart_pending {
            continue;
        }
        let _ = writeln!(
            out,
            "/* set_has({set}, s): whether s is in the P slots. Sets t_has. */\ninline set_has_{name}(m, s) {{\n    t_has = 0;\n    t_j = 0;\n    do\n    :: t_j < P -> if :: {set}[{base} + t_j] == s -> t_has = 1 :: else -> skip fi; t_j++\n    :: else -> break\n    od\n}}\n"
        );
    }
    out.push_str("/* dr_paper_merge(&m's global, &in, MERGE) (Fig. 3, e.3): keep from the first set whatever\n * passes the bound or is also in the second set; equal states intersect. */\ninline merge(m) {\n    t_eq = 0;\n    if\n    :: g_state[m] == in_state -> t_eq = 1; t_first_local = 1; t_bound = g_state[m]\n    :: g_state[m] > in_state -> t_first_local = 1; t_bound = in_state\n    :: else -> t_first_local = 0; t_bound = g_state[m]\n    fi;\n    t_i = 0;\n    do\n    :: t_i < P -> t_out[t_i] = 0; t_i++\n    :: else -> break\n    od;\n    t_n = 0;\n    t_i = 0;\n    do\n    :: t_i >= P -> break\n    :: else ->\n        t_p = (t_first_local -> pend[m * P + t_i] : in_pend[t_i]);\n        set_has_out(m, t_p);\n        if\n        :: t_p == 0 || t_has -> skip /* empty slot, or a duplicate from a packet */\n        :: else ->\n            if\n            :: t_first_local -> set_has_in(m, t_p)\n            :: else -> set_has_pend(m, t_p)\n            fi;\n            t_known = t_has;\n            if\n            :: t_eq -> t_keep = t_known\n            :: else ->\n                t_has = (MERGE == 2 -> t_p >= t_bound : t_p > t_bound); /* above */\n                t_keep = (MERGE == 0 -> (t_has && t_known) : (t_has || t_known))\n            fi;\n            if\n            :: t_keep -> t_out[t_n] = t_p; t_n++\n            :: else -> skip\n            fi\n        fi;\n        t_i++\n    od;\n    if\n    :: g_state[m] < in_state -> g_state[m] = in_state; g_addr[m] = in_addr\n    :: else -> skip\n    fi;\n    t_i = 0;\n    do\n    :: t_i < P -> pend[m * P + t_i] = t_out[t_i]; t_i++\n    :: else -> break\n    od\n}\n\n");
    if o.restart_pending {
        out.push_str("/* mark_started(m, s): remember that m started pending state s; when full, the lowest mark\n * gives way. */\ninline mark_started(m, s) {\n    set_has_mark(m, s);\n    if\n    :: t_has -> skip\n    :: else ->\n        t_k = 0; /* the lowest mark */\n        t_j = 0;\n        do\n        :: t_j < P && mark[m * P + t_j] == 0 -> mark[m * P + t_j] = s; break\n        :: t_j < P && mark[m * P + t_j] != 0 ->\n            if :: mark[m * P + t_j] < mark[m * P + t_k] -> t_k = t_j :: else -> skip fi;\n            t_j++\n        :: else -> mark[m * P + t_k] = s; break\n        od\n    fi\n}\n\n");
    }
    let mark = if o.restart_pending {
        "mark_started(m, s);\n        "
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "/* dr_paper_add_pending(m, s): no-op when present; silently nothing when full. */\ninline add_pending(m, s) {{\n    if\n    :: s == 0 -> skip\n    :: else ->\n        {mark}set_has_pend(m, s);\n        if\n        :: !t_has ->\n            t_j = 0;\n            do\n            :: t_j < P && pend[m * P + t_j] == 0 -> pend[m * P + t_j] = s; break\n            :: t_j < P && pend[m * P + t_j] != 0 -> t_j++\n            :: else -> break\n            od\n        :: else -> skip\n        fi\n    fi\n}}\n"
    );
    out.push_str("/* dr_paper_remove_pending(m, s): clears the first matching slot. */\ninline remove_pending(m, s) {\n    t_j = 0;\n    do\n    :: s != 0 && t_j < P && pend[m * P + t_j] == s -> pend[m * P + t_j] = 0; break\n    :: s != 0 && t_j < P && pend[m * P + t_j] != s -> t_j++\n    :: else -> break\n    od\n}\n\n");
    let has_pending: Vec<String> = (0..slots)
        .map(|k| format!("pend[m * P + {k}] != 0"))
        .collect();
    let _ = writeln!(
        out,
        "/* dr_paper_has_pending(m) */\n#define HAS_PENDING(m) ({})\n",
        has_pending.join(" || ")
    );
    out.push_str("/* dr_paper_send_state(m, s, a): only a higher state changes the copy. */\ninline send_state(m, s, a) {\n    if\n    :: s > g_state[m] -> g_state[m] = s; g_addr[m] = a\n    :: else -> skip\n    fi\n}\n\n");
    out.push_str("/* dr_paper_handover(m, pending, next, address): state S+1 of a parallel statement. */\ninline handover(m, pending, s, a) {\n    if\n    :: SINGLE_STEP_HANDOVER -> add_pending(m, pending)\n    :: else -> skip\n    fi;\n    send_state(m, s, a)\n}\n\n");

    // checkPendingStateResponsibility
    let responsible: Vec<String> = units
        .iter()
        .filter(|u| u.kind == PaperUnitKind::Parallel)
        .map(|u| format!("(p == {} && a == {})", u.first_state, u.address))
        .collect();
    let _ = writeln!(
        out,
        "/* dr_program_responsible(a, p) (checkPendingStateResponsibility, generated) */\n#define RESPONSIBLE(a, p) ({})\n",
        if responsible.is_empty() {
            "0".to_string()
        } else {
            responsible.join(" || ")
        }
    );
    if o.restart_pending {
        out.push_str("/* restart_check(m) (e.6): a pending state present before and after the merge, that m is\n * responsible for and has not started since its reset, goes into the mailbox. */\ninline restart_check(m) {\n    t_i = 0;\n    do\n    :: t_i >= P -> break\n    :: else ->\n        t_p = t_before[t_i];\n        t_keep = 0;\n        if\n        :: t_p != 0 ->\n            set_has_pend(m, t_p);\n            t_known = t_has;\n            set_has_mark(m, t_p);\n            t_keep = t_known && !t_has && RESPONSIBLE(ADDR(m), t_p)\n        :: else -> skip\n        fi;\n        if\n        :: t_keep -> mailbox[m] = t_p; break\n        :: else -> t_i++\n        fi\n    od\n}\n\n");
    }
    let restart = if o.restart_pending {
        "restart_check(to)"
    } else {
        "skip /* no pending restart */"
    };
    let _ = writeln!(
        out,
        "/* dr_module_receive(to, packet in in_*): merge; if the state rose and names this module, the\n * mailbox gets it; otherwise the pending restart (option). */\ninline receive(from, to) {{\n    t_i = 0;\n    do\n    :: t_i < P -> t_before[t_i] = pend[to * P + t_i]; t_i++\n    :: else -> break\n    od;\n    t_before_state = g_state[to];\n    merge(to);\n    if\n    :: g_state[to] > t_before_state ->\n        if\n        :: g_addr[to] == ADDR(to) && g_addr[to] != ADDRESS_ALL -> mailbox[to] = g_state[to]\n        :: else -> skip\n        fi\n    :: else -> {restart}\n    fi;\n    end_check(to)\n}}\n"
    );
    let pend_print: Vec<String> = (0..slots).map(|_| "%d".to_string()).collect();
    let pend_args: Vec<String> = (0..slots).map(|k| format!("in_pend[{k}]")).collect();
    let print = format!(
        "printf(\"@deliver %d %d %d %d {}\\n\", from, to, in_state, in_addr, {})",
        pend_print.join(" "),
        pend_args.join(", ")
    );
    let copy_args: Vec<String> = (0..slots).map(|k| format!("pend[m * P + {k}]")).collect();
    let print_copy = format!(
        "printf(\"@copy %d %d %d {}\\n\", m, g_state[m], g_addr[m], {})",
        pend_print.join(" "),
        copy_args.join(", ")
    );
    let _ = writeln!(
        out,
        "/* A link delivers the sender's current copy. */\ninline deliver(from, to) {{\n    in_state = g_state[from];\n    in_addr = g_addr[from];\n    t_i = 0;\n    do\n    :: t_i < P -> in_pend[t_i] = pend[from * P + t_i]; t_i++\n    :: else -> break\n    od;\n    {print};\n    receive(from, to);\n    print_copy(to)\n}}\n\n/* For the counterexample: module m's copy now. */\ninline print_copy(m) {{\n    {print_copy}\n}}\n"
    );
    if g.options.late > 0 {
        let print_late = print.replace(", from, to,", ", l_from[slot], l_to[slot],");
        let _ = writeln!(
            out,
            "inline capture(slot, from, to) {{\n    l_full[slot] = 1;\n    l_from[slot] = from;\n    l_to[slot] = to;\n    l_state[slot] = g_state[from];\n    l_addr[slot] = g_addr[from];\n    t_i = 0;\n    do\n    :: t_i < P -> l_pend[slot * P + t_i] = pend[from * P + t_i]; t_i++\n    :: else -> break\n    od\n}}\n\ninline deliver_late(slot) {{\n    in_state = l_state[slot];\n    in_addr = l_addr[slot];\n    t_i = 0;\n    do\n    :: t_i < P -> in_pend[t_i] = l_pend[slot * P + t_i]; t_i++\n    :: else -> break\n    od;\n    {print_late};\n    receive(l_from[slot], l_to[slot]);\n    print_copy(l_to[slot])\n}}\n"
        );
    }

    // The generated switch (paper.rs), one case per state, fall-through as a loop.
    out.push_str("/* dr_program_step(m): the Fig. 2 switch that paper.rs generates for this sequence, case for\n * case (a C fall-through there is t_go = 1 here). */\ninline program_step(m) {\n    t_go = 1;\n    do\n    :: !t_go -> break\n    :: else ->\n        t_go = 0;\n        if\n        :: lstate[m] == 0 -> lstate[m] = 1; t_go = 1 /* entry */\n");
    for (k, unit) in units.iter().enumerate() {
        unit_cases(out, unit, units.get(k + 1));
    }
    out.push_str("        :: else -> skip\n        fi\n    od\n}\n\n");
    out.push_str("/* dr_module_step(m): an idle module takes the mailbox, then one step of the switch. */\ninline step(m) {\n    if\n    :: lstate[m] == IDLE -> lstate[m] = mailbox[m]; mailbox[m] = IDLE\n    :: else -> skip\n    fi;\n    program_step(m);\n    end_check(m)\n}\n\n");
    let clear_marks = if o.restart_pending {
        "    t_j = 0;\n    do\n    :: t_j < P -> mark[m * P + t_j] = 0; t_j++\n    :: else -> break\n    od;\n"
    } else {
        ""
    };
    let _ = writeln!(
        out,
        "/* start() (e.10, every init and reset): copy <0, 0, {{}}>, idle, mailbox empty; the first\n * module puts state 0 in its mailbox. */\ninline paper_start(m) {{\n    mailbox[m] = IDLE;\n    g_state[m] = 0;\n    g_addr[m] = 0;\n    t_j = 0;\n    do\n    :: t_j < P -> pend[m * P + t_j] = 0; t_j++\n    :: else -> break\n    od;\n{clear_marks}    lstate[m] = IDLE;\n    if\n    :: ADDR(m) == FIRST_ADDRESS && g_state[m] == 0 -> mailbox[m] = 0\n    :: else -> skip\n    fi\n}}\n\ninline reset(m) {{\n    interrupt(m);\n    paper_start(m)\n}}\n"
    );
    let mut init = String::new();
    for k in 0..g.m() {
        let _ = writeln!(init, "    paper_start({k});");
    }
    let _ = writeln!(
        out,
        "/* The first dr_module_init of every module. */\ninline initialise() {{\n{init}    skip\n}}\n"
    );
    Ok(units
        .iter()
        .map(|u| (u.first_state, u.statements.clone()))
        .collect())
}

fn issue_all(unit: &PaperUnit) -> String {
    unit.statements
        .iter()
        .map(|i| format!("issue(m, {i}, 0); "))
        .collect()
}

/// The cases of one unit, as `paper.rs` `unit_cases` writes them in C.
fn unit_cases(out: &mut String, unit: &PaperUnit, next: Option<&PaperUnit>) {
    let s = u32::from(unit.first_state);
    let statements: Vec<String> = unit.statements.iter().map(|i| i.to_string()).collect();
    match unit.kind {
        PaperUnitKind::Parallel => {
            let (next_state, next_address) =
                next.map_or((254, 255), |n| (n.first_state, n.address));
            let _ = writeln!(
                out,
                "        :: lstate[m] == {s} -> /* module {}: statement {} & */\n            add_pending(m, {s}); {}lstate[m] = {}\n        :: lstate[m] == {} -> handover(m, {s}, {next_state}, {next_address}); lstate[m] = {}; t_go = 1\n        :: lstate[m] == {} ->\n            if\n            :: BUSY(m) -> skip\n            :: else -> remove_pending(m, {s}); lstate[m] = IDLE\n            fi",
                unit.address,
                statements.join(", "),
                issue_all(unit),
                s + 1,
                s + 1,
                s + 2,
                s + 2
            );
        }
        PaperUnitKind::Sequential | PaperUnitKind::Block => {
            let wait = if unit.kind == PaperUnitKind::Sequential {
                "HAS_PENDING(m) || BUSY(m)"
            } else {
                "BUSY(m) /* a block does not look at the pending set */"
            };
            let transfer = match next {
                Some(n) if n.address == unit.address => {
                    format!("lstate[m] = {}; t_go = 1", s + 2)
                }
                Some(n) => format!(
                    "send_state(m, {}, {}); lstate[m] = IDLE",
                    n.first_state, n.address
                ),
                None => "send_state(m, STATE_END, ADDRESS_ALL); lstate[m] = IDLE".to_string(),
            };
            let _ = writeln!(
                out,
                "        :: lstate[m] == {s} -> /* module {}: statement {} ; */\n            {}lstate[m] = {}\n        :: lstate[m] == {} ->\n            if\n            :: {wait} -> skip\n            :: else -> {transfer}\n            fi",
                unit.address,
                statements.join(", "),
                issue_all(unit),
                s + 1,
                s + 1
            );
        }
    }
}
