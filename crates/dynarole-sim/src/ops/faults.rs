//! The scenario's operation faults: attempts that fail without effect (a transient failure
//! drawn per attempt, or a stuck part), and modules that die in place. Both leave the world
//! as it was, and the statement failed as a refusal leaves it, so `dr_hal_op_status` answers
//! FAILED and the module's runtime decides what to do about it.

use crate::scenario::OperationFailure;
use crate::sequence::OpKind;
use crate::state::{uniform, Injected, State};
use dynarole_recording::TraceEvent;

/// The probability that one attempt of an operation of `kind` fails.
fn failure_probability(failure: &OperationFailure, kind: OpKind) -> f64 {
    let by_kind = match failure {
        OperationFailure::Every(p) => return *p,
        OperationFailure::ByKind(k) => k,
    };
    match kind {
        OpKind::Extend => by_kind.extend,
        OpKind::Retract => by_kind.retract,
        OpKind::Turn => by_kind.turn,
        OpKind::Move { .. } => by_kind.moves,
        OpKind::Other => by_kind.other,
    }
}

impl State {
    /// Whether the attempt of statement `s` that module `m` begins now fails, and why. One
    /// draw of its own stream per attempt whose kind may fail while the faults are on, none
    /// otherwise (runs without these faults keep every stream as it was); drawn even when a
    /// stuck part decides, so that adding a stuck part changes no other attempt's draw.
    pub(super) fn injected_fault(&mut self, m: usize, s: usize) -> Option<Injected> {
        let p = failure_probability(&self.scenario.faults.operation_failure, self.seq.kinds[s]);
        let transient = p > 0.0 && self.faults_on() && uniform(&mut self.rng_operations) < p;
        let resolved = &self.seq.resolved[s];
        let stuck = self.stuck.iter().position(|k| {
            k.module == m
                && k.part == resolved.part
                && k.index == resolved.index
                && self.now >= k.from_us
        });
        match (stuck, transient) {
            (Some(k), _) => Some(Injected::Stuck(k)),
            (None, true) => Some(Injected::Transient),
            (None, false) => None,
        }
    }

    /// An attempt that was to fail has run its time: it ends without effect, its statement
    /// failed as a refused one is.
    pub(super) fn failed_by_fault(&mut self, m: usize, s: usize, label: String, fault: Injected) {
        self.phys[s].failed = true;
        self.counters.ops_failed += 1;
        self.mark_failed(s);
        if self.tracing() {
            let why = match fault {
                Injected::Transient => "transient".to_string(),
                Injected::Stuck(k) => {
                    let part = self.stuck.get(k).map_or("?", |p| p.name.as_str());
                    format!("stuck {part}")
                }
            };
            self.log(Some(m), TraceEvent::Failed, format!("{label}: {why}"));
        }
    }

    /// Module `m` dies now if its death is due and it has not died yet: off for good, its
    /// operations stopped where they are (interrupted, not failed by a fault). Nothing of
    /// the world changes: its parts stay where they are, and its latches hold.
    pub(crate) fn die_if_due(&mut self, m: usize) -> bool {
        let due = self.death_at.get(&m).is_some_and(|at| *at <= self.now);
        if !due || !self.died.insert(m) {
            return false;
        }
        self.counters.deaths += 1;
        self.log(Some(m), TraceEvent::Dead, "dies in place");
        if let Some(module) = self.modules.get_mut(m) {
            if module.powered {
                // A new generation cancels the steps in the queue, as a power-off does.
                module.powered = false;
                module.generation = module.generation.wrapping_add(1);
                module.next_step = None;
            }
        }
        self.op_waiters.remove(&m);
        self.interrupt_operations(m);
        true
    }
}
