//! The mechanical critical path of a compiled sequence: the longest chain of dependencies
//! (the IR's `deps`, what the sequence means) weighted by the timing preset's operation
//! durations, and the hand-overs along it (dependency edges between statements of different
//! modules). No run can complete sooner; a protocol that passes the baton from one module to
//! the next by broadcast pays about one broadcast period per hand-over on top. A synchronous
//! group's members weigh the runtime's countdown plus the group's lock-step duration.

use crate::scenario::Durations;
use crate::sequence::{OpKind, Sequence};
use dynarole_codegen::synchronous_delay_ms;
use dynarole_core::check::ResolvedStatement;
use dynarole_core::lower::Ir;
use dynarole_core::synchronous::lockstep_ms;
use serde::Serialize;
use std::collections::BTreeMap;

/// The heaviest dependency chain of a sequence.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct CriticalPath {
    /// Sum of the operation durations along the chain (ms).
    pub duration_ms: u64,
    /// The chain, first statement first (indices of the IR's statements).
    pub statements: Vec<usize>,
    /// Dependency edges along the chain between statements of different modules.
    pub handovers: usize,
}

impl CriticalPath {
    /// The critical path plus `period_ms` per hand-over (ms).
    pub fn with_handovers(&self, period_ms: u64) -> u64 {
        self.duration_ms + period_ms * self.handovers as u64
    }
}

/// Which edges a chain follows.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Order {
    /// The IR's `deps`: what the sequence means.
    Meaning,
    /// Also `previous_on_module`: a module runs one operation at a time, in source order (two
    /// `&` statements of one module one after the other; the lattice runtime overlaps them).
    OneAtATime,
}

/// The longest chain through `deps` (and, by `order`, each module's own order), statement `s`
/// weighing `duration(s)`. Among chains of equal duration, the one with the most hand-overs
/// (the stricter bound), then the earliest statements. Dependencies point backwards (lowering
/// guarantees it; others are ignored).
fn chain(ir: &Ir, order: Order, duration: impl Fn(usize) -> u64) -> CriticalPath {
    // For each statement: (finish, hand-overs) of the heaviest chain ending with it, and the
    // previous statement on that chain.
    let mut best: Vec<((u64, usize), Option<usize>)> = Vec::with_capacity(ir.statements.len());
    for (s, st) in ir.statements.iter().enumerate() {
        let mut top = ((0, 0), None);
        let previous = st.previous_on_module.filter(|_| order == Order::OneAtATime);
        for d in st
            .deps
            .iter()
            .chain(&previous)
            .map(|d| usize::from(*d))
            .filter(|d| *d < s)
        {
            let ((finish, handovers), _) = best[d];
            let handovers = handovers + usize::from(ir.statements[d].address != st.address);
            if top.1.is_none() || (finish, handovers) > top.0 {
                top = ((finish, handovers), Some(d));
            }
        }
        let ((finish, handovers), previous) = top;
        best.push(((finish.saturating_add(duration(s)), handovers), previous));
    }
    let mut last = None;
    for (s, (weight, _)) in best.iter().enumerate() {
        if last.is_none_or(|l: usize| *weight > best[l].0) {
            last = Some(s);
        }
    }
    let mut statements = Vec::new();
    let mut at = last;
    while let Some(s) = at {
        statements.push(s);
        at = best[s].1;
    }
    statements.reverse();
    let ((duration_ms, handovers), _) = last.map_or(((0, 0), None), |s| best[s]);
    CriticalPath {
        duration_ms,
        statements,
        handovers,
    }
}

/// The critical path of `seq` with `durations`. A turn's duration comes from its
/// arguments: `rotateFromToBy` names where it starts; `rotateToBy` is taken to start where
/// the same module's previous turn of that joint ended (0 when there is none), an estimate.
pub fn critical_path(seq: &Sequence, durations: &Durations) -> CriticalPath {
    chain(&seq.ir, Order::Meaning, statement_durations(seq, durations))
}

/// The critical path as the lattice runtime can run it at best: `critical_path` plus the
/// order of each module's own statements (one operation at a time), so that two `&`
/// statements of one module weigh the sum of their durations. Still a lower bound of any run.
pub fn one_at_a_time(seq: &Sequence, durations: &Durations) -> CriticalPath {
    chain(
        &seq.ir,
        Order::OneAtATime,
        statement_durations(seq, durations),
    )
}

/// Each statement's duration with `durations` (see `critical_path`), computed in one pass:
/// the angle a `rotateToBy` starts from is the last target of the same module's joint so far
/// (a backward search per turn was quadratic on long sequences).
fn statement_durations(seq: &Sequence, durations: &Durations) -> impl Fn(usize) -> u64 {
    let mut last_target: BTreeMap<(u8, u8), i64> = BTreeMap::new();
    let mut out = Vec::with_capacity(seq.len());
    for (s, st) in seq.ir.statements.iter().enumerate() {
        let kind = seq.kinds[s];
        let quarters = if kind == OpKind::Turn {
            let joint = (st.address, st.index);
            let current = last_target.get(&joint).copied().unwrap_or(0);
            if let Some(to) = seq.turn_target(s) {
                last_target.insert(joint, to);
            }
            seq.quarters(s, current)
        } else {
            0
        };
        out.push(kind.nominal_ms(durations, quarters));
    }
    // A synchronous group's turns all take the longest's time, as the simulator runs them,
    // and start no sooner than the runtime's countdown after their dependencies are done.
    for (s, duration) in out.iter_mut().enumerate() {
        if let Some(group) = seq.synchronous(s) {
            let members: Vec<&ResolvedStatement> = group.map(|k| &seq.resolved[k]).collect();
            let countdown = synchronous_delay_ms(members.len());
            *duration = countdown + lockstep_ms(&seq.robot, *durations, &members);
        }
    }
    move |s: usize| out.get(s).copied().unwrap_or(0)
}

#[cfg(test)]
#[path = "../tests/unit/critical.rs"]
mod tests;
