//! The lattice protocol in Promela: a transcription of `runtime/lattice/dr_lattice.c`
//! (every inline names the C function it mirrors), written beside it as the template
//! `runtime/lattice/dr_lattice.pml`; this file fills it for the options and the IR.
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

use super::events::{expr, printf, EventKind};
use super::template::{Holes, TemplateFile};
use super::{Fault, Gen};
use crate::c::LATTICE_BATCH;

/// The transcription: `runtime/lattice/dr_lattice.pml`.
pub(super) static LATTICE: TemplateFile = TemplateFile {
    path: "runtime/lattice/dr_lattice.pml",
    text: include_str!("../../../../runtime/lattice/dr_lattice.pml"),
};

pub(crate) fn write(g: &Gen, out: &mut String) {
    let w = g.ir.window;
    let no_nv = g.options.compile.no_nv;
    let nv = !no_nv && g.options.resets > 0;
    // connected(): the in-links that exist throughout (assumed to deliver in every stage).
    let connected = g.per_module("m", |k| {
        let mask: u64 = (g.topology.links.iter())
            .filter(|l| l.to == k && (0..=g.n()).all(|t| l.fair_stages.contains(&t)))
            .fold(0, |acc, l| acc | (1u64 << l.from));
        mask.to_string()
    });
    // Assumption (b) without NV: no packet crosses a reset.
    let crossing: Vec<String> = (0..g.options.late)
        .map(|slot| {
            format!("    if\n    :: l_from[{slot}] == m || l_to[{slot}] == m -> l_full[{slot}] = 0\n    :: else -> skip\n    fi;")
        })
        .collect();
    let unheard: Vec<String> = (0..g.m())
        .map(|k| format!("    unheard[{k}] = CONNECTED({k});"))
        .collect();
    let holes = Holes::new()
        .text("w", w)
        .text("batch", LATTICE_BATCH)
        .text("wmask", (1u64 << w) - 1)
        .flag("nv", nv)
        .flag("no_nv", no_nv)
        .flag("no_persist", !nv && !no_nv)
        .flag("late", g.options.late > 0)
        .flag(
            "fault_drops_done",
            g.options.fault == Some(Fault::JoinDropsDone),
        )
        .flag(
            "fault_no_rebase",
            g.options.fault == Some(Fault::JoinNoRebase),
        )
        // The full model's fair links (the compositional one has its own delivery rule).
        .flag(
            "wants",
            g.options.compile.dissemination == crate::Dissemination::Adaptive
                && g.checked.is_none(),
        )
        // The compositional model: what the module marks done, the truth records.
        .flag("record", g.checked.is_some())
        .text("connected", connected)
        .text("crossing", crossing.join("\n"))
        .text("unheard", unheard.join("\n"));
    out.push_str(&LATTICE.part("lattice").fill(&events(holes)));
}

/// The `printf`s of the protocol's events: a completion, a delivery (of a late packet too),
/// a copy (`epoch low done`).
fn events(holes: Holes<'_>) -> Holes<'_> {
    let deliver = |from: &str, to: &str| {
        let fields = [from, to, "in_epoch", "in_low", "in_done"];
        printf(EventKind::Deliver, &fields.map(expr))
    };
    holes
        .text(
            "print_complete",
            printf(EventKind::Complete, &[expr("m"), expr("t_s")]),
        )
        .text("print_deliver", deliver("from", "to"))
        .text("print_deliver_late", deliver("l_from[slot]", "l_to[slot]"))
        .text(
            "print_copy",
            printf(
                EventKind::Copy,
                &[expr("m"), expr("epoch[m]"), expr("low[m]"), expr("done[m]")],
            ),
        )
}

#[cfg(test)]
#[path = "../../tests/unit/promela_lattice.rs"]
mod tests;
