//! The paper's protocol in Promela: a transcription of `runtime/paper/dr_paper.c` (every
//! inline names the C function it mirrors) and of the Fig. 2 switch that `paper.rs` generates,
//! state for state, from the same layout (`Ir::paper_layout`), so that the model splits steps
//! exactly as the generated C does. The switch is tables indexed by the state, read by one
//! inline, so that a step's code does not grow with the sequence (spin limits a `d_step`).
//!
//! Abstractions: a packet is the sender's (state, address, pending slots) (the alternate flag
//! is always 0, framing and CRC drop what is corrupted: a loss); the periodic broadcast is "a
//! link may deliver the sender's current copy at any time"; the "started" marks (e.2) are
//! modelled only with the pending restart, the one thing that reads them.

use super::Gen;
use crate::protocol::PaperMerge;
use dynarole_core::lower::{
    LimitError, PaperUnit, PaperUnitKind, PAPER_ADDRESS_ALL, PAPER_STATE_END, PAPER_STATE_IDLE,
};
use std::fmt::Write;

/// What the paper protocol's part of the model leaves for the rest: the layout's (first
/// state, statements) of each unit, and the assignments that fill the switch's tables (run by
/// `init`).
pub(crate) struct Written {
    pub states: Vec<(u8, Vec<usize>)>,
    pub fill: String,
}

/// Writes the paper protocol's part of the model.
pub(crate) fn write(g: &Gen, out: &mut String, slots: usize) -> Result<Written, LimitError> {
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
        "#define P {slots}            /* DR_CONF_MAX_PENDING */\n#define MERGE {merge}        /* 0 printed (> and), 1 Java (> or), 2 C port (>= or) */\n#define SINGLE_STEP_HANDOVER {}\n#define FIRST_ADDRESS {first_address}\n#define STATE_END {PAPER_STATE_END}\n#define IDLE {PAPER_STATE_IDLE}\n#define ADDRESS_ALL {PAPER_ADDRESS_ALL}\n",
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

    let fill = switch(out, &units);
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
    let states = units
        .iter()
        .map(|u| (u.first_state, u.statements.clone()))
        .collect();
    Ok(Written { states, fill })
}

/// What a state of the switch does (`sw_kind`), by the unit it belongs to.
#[derive(Clone, Copy)]
enum Case {
    /// No case: the switch does nothing (the C `default`).
    None = 0,
    /// Parallel `S`: add pending S, start the statement.
    ParallelStart = 1,
    /// Parallel `S+1`: the hand-over, then fall through.
    Handover = 2,
    /// Parallel `S+2`: wait for the operation, remove pending S.
    ParallelWait = 3,
    /// Sequential or block `S`: start the statements.
    Start = 4,
    /// Sequential `S+1`: wait for the operation and an empty pending set, then transfer.
    SequentialWait = 5,
    /// Block `S+1`: wait for the operations (not the pending set), then transfer.
    BlockWait = 6,
}

/// One state's row of the switch's tables.
struct Row {
    case: Case,
    /// The statements a start state issues.
    issues: Vec<usize>,
    /// Where control goes next: (state, address); `local`: the next unit is on the same
    /// module, which falls through to it instead of sending.
    next: (u8, u8),
    local: bool,
}

/// The switch's rows, one per state from 0 to the last unit's last state.
fn rows(units: &[PaperUnit]) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    let mut put = |state: u8, row: Row| {
        let at = usize::from(state);
        while rows.len() <= at {
            rows.push(Row {
                case: Case::None,
                issues: Vec::new(),
                next: (0, 0),
                local: false,
            });
        }
        rows[at] = row;
    };
    for (k, unit) in units.iter().enumerate() {
        let next = units.get(k + 1);
        let target = next.map_or((PAPER_STATE_END, PAPER_ADDRESS_ALL), |n| {
            (n.first_state, n.address)
        });
        let local = next.is_some_and(|n| n.address == unit.address);
        let s = unit.first_state;
        let row = |case: Case, issues: Vec<usize>| Row {
            case,
            issues,
            next: target,
            local,
        };
        match unit.kind {
            PaperUnitKind::Parallel => {
                put(s, row(Case::ParallelStart, unit.statements.clone()));
                // The hand-over always sends (the C writes handover(), never a fall-through).
                put(
                    s + 1,
                    Row {
                        local: false,
                        ..row(Case::Handover, Vec::new())
                    },
                );
                put(s + 2, row(Case::ParallelWait, Vec::new()));
            }
            PaperUnitKind::Sequential | PaperUnitKind::Block => {
                put(s, row(Case::Start, unit.statements.clone()));
                let wait = if unit.kind == PaperUnitKind::Sequential {
                    Case::SequentialWait
                } else {
                    Case::BlockWait
                };
                put(s + 1, row(wait, Vec::new()));
            }
        }
    }
    rows
}

/// The Fig. 2 switch that `paper.rs` generates in C, as tables indexed by the state (what
/// each case does, which statements it starts, where it transfers control) and one inline
/// that interprets them: a step's code no longer grows with the sequence, which keeps it
/// within spin's limit on the length of a `d_step`. Writes the layout as a comment, the
/// tables and `program_step`; returns the assignments that fill the tables.
fn switch(out: &mut String, units: &[PaperUnit]) -> String {
    let rows = rows(units);
    out.push_str(
        "/* The switch's layout (paper.rs): first state, kind, module address, statements. */\n",
    );
    for unit in units {
        let kind = match unit.kind {
            PaperUnitKind::Parallel => "&",
            PaperUnitKind::Sequential => ";",
            PaperUnitKind::Block => "block",
        };
        let statements: Vec<String> = unit.statements.iter().map(|i| i.to_string()).collect();
        let _ = writeln!(
            out,
            "/*   {:>3}  {kind:<5}  module {}: statement {} */",
            unit.first_state,
            unit.address,
            statements.join(", ")
        );
    }
    let issued: usize = rows.iter().map(|r| r.issues.len()).sum();
    let _ = writeln!(
        out,
        "#define SW_STATES {}\n#define SW_PARALLEL_START {}\n#define SW_HANDOVER {}\n#define SW_PARALLEL_WAIT {}\n#define SW_START {}\n#define SW_SEQUENTIAL_WAIT {}\n#define SW_BLOCK_WAIT {}\n/* State t's case (SW_*, 0: none), the statements it starts (sw_issue[sw_issue_first[t] ..\n * sw_issue_first[t + 1])), where control goes next (state, address) and whether by falling\n * through (the next unit is on the same module). */\nhidden byte sw_kind[SW_STATES];\nhidden short sw_issue_first[SW_STATES + 1];\nhidden byte sw_issue[{}];\nhidden byte sw_next[SW_STATES];\nhidden byte sw_next_addr[SW_STATES];\nhidden byte sw_local[SW_STATES];\nhidden byte t_u, t_v;\nhidden short t_w;\n",
        rows.len(),
        Case::ParallelStart as u8,
        Case::Handover as u8,
        Case::ParallelWait as u8,
        Case::Start as u8,
        Case::SequentialWait as u8,
        Case::BlockWait as u8,
        issued.max(1)
    );
    out.push_str(PROGRAM_STEP);
    let mut fill = String::new();
    let mut at = 0;
    for (t, row) in rows.iter().enumerate() {
        let _ = writeln!(fill, "        sw_issue_first[{t}] = {at};");
        if let Case::None = row.case {
            continue;
        }
        let _ = writeln!(
            fill,
            "        sw_kind[{t}] = {};\n        sw_next[{t}] = {};\n        sw_next_addr[{t}] = {};\n        sw_local[{t}] = {};",
            row.case as u8,
            row.next.0,
            row.next.1,
            u8::from(row.local)
        );
        for &i in &row.issues {
            let _ = writeln!(fill, "        sw_issue[{at}] = {i};");
            at += 1;
        }
    }
    let _ = writeln!(fill, "        sw_issue_first[{}] = {at};", rows.len());
    fill
}

/// The interpreter of the switch's tables: one case per iteration, a C fall-through is
/// `t_go = 1`. `t_u` is the state, `t_v` the unit's pending state or the transfer's target.
const PROGRAM_STEP: &str = "/* dr_program_step(m): the generated switch, case for case from the tables. */
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

";
