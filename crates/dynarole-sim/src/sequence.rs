//! What the simulator knows of the compiled sequence, from the IR (never from the C): each
//! statement's module address, operation, dependencies and transitive dependents, the
//! resolved statement the world applies (the configuration queries the HAL answers are
//! `dynarole_world::View`).

use dynarole_core::check::ResolvedStatement;
use dynarole_core::lower::Ir;
use dynarole_core::robot::Value;
use dynarole_core::RobotApi;

/// The physical kind of an operation (for its duration and the links it breaks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpKind {
    Extend,
    Retract,
    Turn,
    Other,
}

/// The compiled sequence, as the simulator's checks and world need it.
#[derive(Clone, Debug)]
pub struct Sequence {
    pub robot: RobotApi,
    pub ir: Ir,
    pub resolved: Vec<ResolvedStatement>,
    pub kinds: Vec<OpKind>,
    /// For each statement, every statement that depends on it directly or transitively.
    pub dependents: Vec<Vec<usize>>,
}

impl Sequence {
    pub fn new(robot: RobotApi, ir: Ir, resolved: Vec<ResolvedStatement>) -> Sequence {
        let kinds = ir
            .statements
            .iter()
            .map(|s| match ir.operations.get(usize::from(s.op)) {
                Some((part, op)) => kind(part, op),
                None => OpKind::Other,
            })
            .collect();
        let dependents = ir.dependents();
        Sequence {
            robot,
            ir,
            resolved,
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

    /// The angle a turn ends at (plugin units), for the "already there" rule.
    pub fn turn_target(&self, s: usize) -> Option<i64> {
        let st = self.resolved.get(s)?;
        let name = self.op_name(s);
        let at = match name {
            "rotateFromToBy" => 1,
            "rotateToBy" => 0,
            _ => return None,
        };
        match st.args.get(at) {
            Some(Value::Int(v)) => Some(*v),
            _ => None,
        }
    }

    /// Quarter turns a turn makes from joint angle `current` (ATRON units of 1/432 turn,
    /// M-TRAN degrees).
    pub fn quarters(&self, s: usize, current: i64, atron: bool) -> u64 {
        let Some(st) = self.resolved.get(s) else {
            return 0;
        };
        let (full, quarter) = if atron { (432, 108) } else { (360, 90) };
        let (from, to, increasing) = match (self.op_name(s), st.args.as_slice()) {
            ("rotateFromToBy", [Value::Int(f), Value::Int(t), Value::Bool(d), ..]) => (*f, *t, *d),
            ("rotateToBy", [Value::Int(t), Value::Bool(d), ..]) => (current, *t, *d),
            _ => return 0,
        };
        let delta = if !atron {
            (to - from).abs()
        } else if increasing {
            (to - from).rem_euclid(full)
        } else {
            (from - to).rem_euclid(full)
        };
        u64::try_from((delta + quarter - 1) / quarter).unwrap_or(0)
    }

    fn op_name(&self, s: usize) -> &str {
        self.ir
            .statements
            .get(s)
            .and_then(|st| self.ir.operations.get(usize::from(st.op)))
            .map_or("", |(_, op)| op.as_str())
    }
}

fn kind(part: &str, op: &str) -> OpKind {
    match (part, op) {
        ("Connector", "extend") => OpKind::Extend,
        ("Connector", "retract") => OpKind::Retract,
        ("Joint", _) => OpKind::Turn,
        _ => OpKind::Other,
    }
}
