//! What the simulator knows of the compiled sequence, from the IR (never from the C): each
//! statement's module address, operation, dependencies and transitive dependents, the
//! resolved statement the world applies (the configuration queries the HAL answers are
//! `dynarole_world::View`).

use dynarole_core::check::ResolvedStatement;
use dynarole_core::lower::Ir;
use dynarole_core::RobotApi;
use dynarole_world::{builtin_quarter_turns, Action};

/// Degrees in a quarter turn: the estimate's unit for a robot with no built-in model.
const DEGREES_PER_QUARTER: u64 = 90;

/// The physical kind of an operation (for its duration and the links it breaks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpKind {
    Extend,
    Retract,
    Turn,
    Other,
}

impl OpKind {
    fn of(action: Option<Action>) -> OpKind {
        match action {
            Some(Action::Extend { .. }) => OpKind::Extend,
            Some(Action::Retract { .. }) => OpKind::Retract,
            Some(Action::Turn { .. }) => OpKind::Turn,
            None => OpKind::Other,
        }
    }
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
    /// For each statement, every statement that depends on it directly or transitively.
    pub dependents: Vec<Vec<usize>>,
}

impl Sequence {
    pub fn new(robot: RobotApi, ir: Ir, resolved: Vec<ResolvedStatement>) -> Sequence {
        let actions: Vec<Option<Action>> = resolved
            .iter()
            .map(|s| dynarole_replay::action(&robot, s))
            .collect();
        let kinds = actions.iter().map(|a| OpKind::of(*a)).collect();
        let dependents = ir.dependents();
        Sequence {
            robot,
            ir,
            resolved,
            actions,
            kinds,
            dependents,
        }
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
    /// no robot model to ask: a built-in robot's own count (`builtin_quarter_turns`); for a
    /// robot defined elsewhere, angles taken as degrees that do not wrap (an estimate: a run
    /// asks its model).
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
        builtin_quarter_turns(&self.robot.name, from, to, increasing)
            .unwrap_or_else(|| (to - from).unsigned_abs().div_ceil(DEGREES_PER_QUARTER))
    }
}
