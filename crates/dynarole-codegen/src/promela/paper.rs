//! The paper's protocol in Promela: a transcription of `runtime/paper/dr_paper.c` (every
//! inline names the C function it mirrors; the template `runtime/paper/dr_paper.pml`, which
//! this file fills) and of the Fig. 2 switch that `paper.rs` generates,
//! state for state, from the same layout (`Ir::paper_layout`), so that the model splits steps
//! exactly as the generated C does. The switch is tables indexed by the state, read by one
//! inline, so that a step's code does not grow with the sequence (spin limits a `d_step`).
//!
//! Abstractions: a packet is the sender's (state, address, pending slots) (the alternate flag
//! is always 0, framing and CRC drop what is corrupted: a loss); the periodic broadcast is "a
//! link may deliver the sender's current copy at any time"; the "started" marks (e.2) are
//! modelled only with the pending restart, the one thing that reads them.

use super::events::{expr, printf, EventKind};
use super::template::{Holes, TemplateFile};
use super::Gen;
use crate::protocol::PaperMerge;
use dynarole_core::lower::{
    LimitError, PaperUnit, PaperUnitKind, PAPER_ADDRESS_ALL, PAPER_STATE_END, PAPER_STATE_IDLE,
};
use std::fmt::Write;

/// The transcription: `runtime/paper/dr_paper.pml`.
pub(super) static PAPER: TemplateFile = TemplateFile {
    path: "runtime/paper/dr_paper.pml",
    text: include_str!("../../../../runtime/paper/dr_paper.pml"),
};

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
    let has_pending: Vec<String> = (0..slots)
        .map(|k| format!("pend[m * P + {k}] != 0"))
        .collect();
    // checkPendingStateResponsibility
    let responsible: Vec<String> = (units.iter())
        .filter(|u| u.kind == PaperUnitKind::Parallel)
        .map(|u| format!("(p == {} && a == {})", u.first_state, u.address))
        .collect();
    let starts: Vec<String> = (0..g.m())
        .map(|k| format!("    paper_start({k});"))
        .collect();
    let rows = rows(&units);
    let holes = Holes::new()
        .text("slots", slots)
        .text("merge", merge)
        .text("single_step_handover", u8::from(o.single_step_handover))
        .text("first_address", first_address)
        .text("state_end", PAPER_STATE_END)
        .text("idle", PAPER_STATE_IDLE)
        .text("address_all", PAPER_ADDRESS_ALL)
        .flag("restart", o.restart_pending)
        .flag("late", g.options.late > 0)
        .text("has_pending", has_pending.join(" || "))
        .text(
            "responsible",
            if responsible.is_empty() {
                "0".to_string()
            } else {
                responsible.join(" || ")
            },
        )
        .text("starts", starts.join("\n"));
    let holes = switch(events(holes, slots), &units, &rows);
    out.push_str(&PAPER.part("paper").fill(&holes));
    let states = units
        .iter()
        .map(|u| (u.first_state, u.statements.clone()))
        .collect();
    Ok(Written {
        states,
        fill: switch_fill(&rows),
    })
}

/// The `printf`s of the protocol's events: a delivery (of a late packet too) and a copy
/// (`state address pending..`).
fn events(holes: Holes<'_>, slots: usize) -> Holes<'_> {
    let deliver = |from: &str, to: &str| {
        let mut args = vec![expr(from), expr(to), expr("in_state"), expr("in_addr")];
        args.extend((0..slots).map(|k| expr(format!("in_pend[{k}]"))));
        printf(EventKind::Deliver, &args)
    };
    let mut copy = vec![expr("m"), expr("g_state[m]"), expr("g_addr[m]")];
    copy.extend((0..slots).map(|k| expr(format!("pend[m * P + {k}]"))));
    holes
        .text("print_deliver", deliver("from", "to"))
        .text("print_deliver_late", deliver("l_from[slot]", "l_to[slot]"))
        .text("print_copy", printf(EventKind::Copy, &copy))
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
/// that interprets them (`program_step` in the template): a step's code no longer grows with
/// the sequence, which keeps it within spin's limit on the length of a `d_step`. Fills the
/// layout comment and the tables' sizes and case numbers.
fn switch<'h>(holes: Holes<'h>, units: &[PaperUnit], rows: &[Row]) -> Holes<'h> {
    let layout: Vec<String> = (units.iter())
        .map(|unit| {
            let kind = match unit.kind {
                PaperUnitKind::Parallel => "&",
                PaperUnitKind::Sequential => ";",
                PaperUnitKind::Block => "block",
            };
            let statements: Vec<String> = unit.statements.iter().map(|i| i.to_string()).collect();
            format!(
                "/*   {:>3}  {kind:<5}  module {}: statement {} */",
                unit.first_state,
                unit.address,
                statements.join(", ")
            )
        })
        .collect();
    let issued: usize = rows.iter().map(|r| r.issues.len()).sum();
    holes
        .text("layout", layout.join("\n"))
        .text("sw_states", rows.len())
        .text("sw_parallel_start", Case::ParallelStart as u8)
        .text("sw_handover", Case::Handover as u8)
        .text("sw_parallel_wait", Case::ParallelWait as u8)
        .text("sw_start", Case::Start as u8)
        .text("sw_sequential_wait", Case::SequentialWait as u8)
        .text("sw_block_wait", Case::BlockWait as u8)
        .text("sw_issue_size", issued.max(1))
}

/// The assignments that fill the switch's tables (run by `init`).
fn switch_fill(rows: &[Row]) -> String {
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
