//! What the simulator knows of the compiled sequence, from the IR (never from the C): each
//! statement's module address, operation, dependencies and direct dependents (transitive ones
//! are walked when asked), the resolved statement the world applies (the configuration
//! queries the HAL answers are `dynarole_world::View`). Everything here is linear in the
//! statements and their dependency edges: a table of every statement's transitive dependents
//! was quadratic (1 GB at 10,000 statements; `tests/sequence_memory.rs` keeps it linear).

use crate::scenario::Durations;
use dynarole_core::check::ResolvedStatement;
use dynarole_core::lower::Ir;
use dynarole_core::RobotApi;
use dynarole_world::Action;

/// The physical kind of an operation (for its duration and the links it breaks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpKind {
    Extend,
    Retract,
    Turn,
    /// A whole module's move, of `steps` planner steps.
    Move {
        steps: u64,
    },
    Other,
}

impl OpKind {
    /// The kind of `statement` on `robot`, by the kind its plugin declares for the operation
    /// (`dynarole_replay::action`), never by its text.
    pub fn of_statement(robot: &RobotApi, statement: &ResolvedStatement) -> OpKind {
        let steps = steps_of(robot, statement);
        OpKind::of(dynarole_replay::action(robot, statement), steps)
    }

    /// Whether operations of this kind move modules (their links break while they last).
    pub fn moves(self) -> bool {
        matches!(self, OpKind::Turn | OpKind::Move { .. })
    }

    /// The nominal duration of an operation of this kind with `durations`, a turn passing
    /// `quarters` quarter turns (0 for a turn that moves nothing): the one rule the run, the
    /// critical path and the model recordings share.
    pub fn nominal_ms(self, durations: &Durations, quarters: u64) -> u64 {
        match self {
            OpKind::Extend => durations.extend_ms,
            OpKind::Retract => durations.retract_ms,
            OpKind::Turn => durations.turn_ms(quarters),
            OpKind::Move { steps } => durations.move_ms.saturating_mul(steps),
            OpKind::Other => 0,
        }
    }

    fn of(action: Option<Action>, steps: u64) -> OpKind {
        match action {
            Some(Action::Extend { .. }) => OpKind::Extend,
            Some(Action::Retract { .. }) => OpKind::Retract,
            Some(Action::Turn { .. }) => OpKind::Turn,
            Some(Action::Move { .. }) => OpKind::Move { steps },
            None => OpKind::Other,
        }
    }
}

/// The planner steps `statement`'s operation is made of (`Operation::steps`).
fn steps_of(robot: &RobotApi, statement: &ResolvedStatement) -> u64 {
    (robot.parts.get(statement.part))
        .and_then(|p| p.operations.get(statement.operation))
        .map_or(1, |op| op.steps)
}

/// The compiled sequence, as the simulator's checks and world need it.
#[derive(Clone, Debug)]
pub struct Sequence {
    pub robot: RobotApi,
    pub ir: Ir,
    pub resolved: Vec<ResolvedStatement>,
    /// What each statement does to the robot (`dynarole_replay::action`).
    pub actions: Vec<Option<Action>>,
    pub kinds: Vec<OpKind>,
    /// Direct dependents, all statements' in one list: statement `s`'s are
    /// `dependents[first_dependent[s]..first_dependent[s + 1]]`, ascending (the reverse of
    /// the IR's `deps`, one entry per edge).
    dependents: Vec<u16>,
    first_dependent: Vec<u32>,
    /// The execution the build is stamped with (`DR_EXECUTION`; 0 unless the simulator's
    /// caller sets it): `[[foreign]]` packets are of another one unless the scenario says.
    pub execution: u32,
}

impl Sequence {
    /// The statements of the synchronous group statement `s` belongs to, if any.
    pub fn synchronous(&self, s: usize) -> Option<std::ops::Range<usize>> {
        let group = self.ir.statements.get(s)?.synchronous?;
        let first = usize::from(group.first);
        Some(first..first + usize::from(group.size))
    }

    pub fn new(robot: RobotApi, ir: Ir, resolved: Vec<ResolvedStatement>) -> Sequence {
        let actions: Vec<Option<Action>> = resolved
            .iter()
            .map(|s| dynarole_replay::action(&robot, s))
            .collect();
        let kinds = (actions.iter().zip(&resolved))
            .map(|(a, s)| OpKind::of(*a, steps_of(&robot, s)))
            .collect();
        let (first_dependent, dependents) = reverse_edges(&ir);
        Sequence {
            robot,
            ir,
            resolved,
            actions,
            kinds,
            dependents,
            first_dependent,
            execution: 0,
        }
    }

    /// The statements that depend on `s` directly.
    fn direct_dependents(&self, s: usize) -> &[u16] {
        let at = |k: usize| self.first_dependent.get(k).map_or(0, |&i| i as usize);
        self.dependents.get(at(s)..at(s + 1)).unwrap_or_default()
    }

    /// Every statement that depends on `s` directly or transitively, ascending (what
    /// `Ir::dependents` gives for `s`), walked from the direct dependents: asked only when a
    /// statement is re-issued (S2), so the run keeps no table of them.
    pub fn transitive_dependents(&self, s: usize) -> Vec<usize> {
        let mut seen = vec![false; self.len()];
        let mut stack: Vec<usize> = vec![s];
        while let Some(t) = stack.pop() {
            for &d in self.direct_dependents(t) {
                let d = usize::from(d);
                if let Some(slot) = seen.get_mut(d).filter(|v| !**v) {
                    *slot = true;
                    stack.push(d);
                }
            }
        }
        (0..self.len()).filter(|&t| t != s && seen[t]).collect()
    }

    pub fn len(&self) -> usize {
        self.ir.statements.len()
    }

    pub fn text(&self, s: usize) -> &str {
        self.ir.statements.get(s).map_or("?", |st| st.text.as_str())
    }

    /// Whether statement `s` is the call (address, op, index, args) a module made; the C
    /// passes the arguments padded with zeros to `DR_CONF_MAX_ARGS`.
    pub fn matches(&self, s: usize, address: u8, op: u8, index: u8, args: &[i16]) -> bool {
        let Some(st) = self.ir.statements.get(s) else {
            return false;
        };
        let padded = |k: usize| st.args.get(k).copied().unwrap_or(0);
        st.address == address
            && st.op == op
            && st.index == index
            && args.iter().enumerate().all(|(k, a)| *a == padded(k))
    }

    /// The angle a turn ends at (plugin units).
    pub fn turn_target(&self, s: usize) -> Option<i64> {
        match self.actions.get(s)? {
            Some(Action::Turn { to, .. }) => Some(*to),
            _ => None,
        }
    }

    /// Quarter turns a turn makes from joint angle `current`, for the critical path, which has
    /// no robot model to ask: counted as the robot's plugin says its angles are
    /// (`RobotApi::joint_angle`; a run asks its model, which agrees: `tests/joint_angle.rs`).
    pub fn quarters(&self, s: usize, current: i64) -> u64 {
        let Some(Some(Action::Turn {
            from,
            to,
            increasing,
            ..
        })) = self.actions.get(s).copied()
        else {
            return 0;
        };
        let from = from.unwrap_or(current);
        self.robot.joint_angle.quarter_turns(from, to, increasing)
    }
}

/// The IR's dependency edges reversed, in one list indexed by statement (counting sort: two
/// passes over the edges), so that each statement's dependents are a slice.
fn reverse_edges(ir: &Ir) -> (Vec<u32>, Vec<u16>) {
    let n = ir.statements.len();
    let mut first = vec![0u32; n + 1];
    for st in &ir.statements {
        for &d in &st.deps {
            if let Some(count) = first.get_mut(usize::from(d) + 1) {
                *count += 1;
            }
        }
    }
    for k in 1..first.len() {
        first[k] += first[k - 1];
    }
    let mut next = first.clone();
    let mut dependents = vec![0u16; first[n] as usize];
    for (s, st) in ir.statements.iter().enumerate() {
        for &d in &st.deps {
            if let Some(at) = next.get_mut(usize::from(d)) {
                // Fits: statement numbers are 16 bits (`lower::MAX_STATEMENTS`).
                dependents[*at as usize] = s as u16;
                *at += 1;
            }
        }
    }
    (first, dependents)
}

#[cfg(test)]
#[path = "../tests/unit/sequence.rs"]
mod tests;
