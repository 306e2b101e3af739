//! Robot API plugins: which parts a robot has, their operations, and how each one reverses.
//!
//! A plugin is data: a TOML text (each robot folder's `NAME.robot.toml`, docs/robots.md)
//! loaded by [`RobotApi::from_toml`]. The registry's robots give theirs as such texts compiled
//! into the binary, so users' plugins go through exactly the same loader and checks.

mod plugin;

pub use plugin::PluginError;

/// The API of one kind of robot.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RobotApi {
    pub name: String,
    pub description: String,
    pub parts: Vec<Part>,
    /// `$NAME` constants, from the parts' index names.
    pub constants: Vec<Constant>,
    /// The part whose index the role queries `connected(c)` and `neighbour_id(c)` take.
    pub connector_part: Option<usize>,
    /// The part the role query `joint` (or `joint(j)`) reads.
    pub joint_part: Option<usize>,
    /// How its joints' angles are counted (`[joint_angle]`).
    pub joint_angle: JointAngle,
    /// How long its operations take in the simulator (`[[timing]]`), the default first; empty
    /// for a plugin that declares none (the simulator then takes its built-in `ussr`).
    pub timing: Vec<TimingPreset>,
}

/// The longest an operation may take in a timing preset: 10^9 ms, the simulator's longest run
/// (an operation any longer could never complete in one).
pub const MAX_OPERATION_MS: u64 = 1_000_000_000;

/// A named set of operation durations (one `[[timing]]` table of a plugin), which a scenario
/// picks by its name (`timing.preset`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TimingPreset {
    pub name: String,
    /// What it models, for people reading the plugin.
    pub doc: String,
    pub durations: Durations,
}

/// The simulator's built-in timing preset `ussr`, for a robot whose plugin declares none (as
/// the network preset `ussr` is for a robot with no network presets): the original
/// simulator's durations, extend 3 s, retract 2 s, a quarter turn 0.55 s and 0.31 s per
/// further quarter (and a move's step 1 s, [`MOVE_MS`], which USSR did not have).
pub const USSR_TIMING: Durations = Durations {
    extend_ms: 3000,
    retract_ms: 2000,
    turn_first_quarter_ms: 550,
    turn_further_quarter_ms: 310,
    move_ms: MOVE_MS,
};

/// A move's step where the robot's plugin gives no timing: one second, as the cube planners'
/// viewers play a move set.
pub const MOVE_MS: u64 = 1000;

/// The name of [`USSR_TIMING`] in scenarios.
const USSR_TIMING_NAME: &str = "ussr";

impl RobotApi {
    /// The timing presets a scenario may name, the default first: the plugin's `[[timing]]`
    /// alone (a robot that declares its durations gets no other robot's), or [`USSR_TIMING`]
    /// for a plugin that declares none.
    pub fn timing_presets(&self) -> Vec<(&str, Durations)> {
        if self.timing.is_empty() {
            return vec![(USSR_TIMING_NAME, USSR_TIMING)];
        }
        (self.timing.iter())
            .map(|p| (p.name.as_str(), p.durations))
            .collect()
    }
}

/// How long each kind of operation takes, in ms. A duration of a kind the robot has no
/// operation of may be left out of its plugin: it is 0, and never used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Durations {
    pub extend_ms: u64,
    pub retract_ms: u64,
    /// A turn's first quarter turn (a turn of one quarter takes this long).
    pub turn_first_quarter_ms: u64,
    /// Each further quarter turn of the same turn.
    pub turn_further_quarter_ms: u64,
    /// One step of a move (kind `move`).
    pub move_ms: u64,
}

impl Durations {
    /// A turn through `quarters` quarter turns: the first quarter, then each further one (0
    /// for a turn that moves nothing). Saturates rather than overflows on absurd arguments.
    pub fn turn_ms(self, quarters: u64) -> u64 {
        match quarters {
            0 => 0,
            q => self
                .turn_first_quarter_ms
                .saturating_add(self.turn_further_quarter_ms.saturating_mul(q - 1)),
        }
    }
}

/// How a robot's joint angles are counted (a plugin's `[joint_angle]`): the units of a quarter
/// turn, and whether a joint turns round (its angles wrap at four quarters) or stops at the
/// ends of its range. What the critical path counts a turn's quarters with, for any robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JointAngle {
    /// Units of a quarter turn (108 for a plugin counting 1/432 turn, 90 for degrees).
    pub quarter: i64,
    /// The joint turns round: an angle and the same plus four quarters are one position.
    pub wraps: bool,
}

impl Default for JointAngle {
    /// Degrees, with end stops: what a plugin without `[joint_angle]` means.
    fn default() -> JointAngle {
        JointAngle {
            quarter: 90,
            wraps: false,
        }
    }
}

impl JointAngle {
    /// Quarter turns (rounded up) a joint passes from `from` to `to`, upwards if `increasing`:
    /// the way round matters only for a joint that turns round.
    pub fn quarter_turns(self, from: i64, to: i64, increasing: bool) -> u64 {
        let delta = if !self.wraps {
            to.saturating_sub(from).saturating_abs()
        } else {
            let full = self.quarter.saturating_mul(4);
            let forward = to.saturating_sub(from);
            (if increasing {
                forward
            } else {
                forward.saturating_neg()
            })
            .rem_euclid(full)
        };
        u64::try_from(delta).map_or(0, |d| d.div_ceil(self.quarter.unsigned_abs()))
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Part {
    pub name: String,
    /// Number of instances (`Connector[0..count]`); `None` for a part that takes no index.
    pub count: Option<u32>,
    /// Indices of male instances; only these may run operations that require a male one.
    pub male: Vec<u32>,
    pub operations: Vec<Operation>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Operation {
    pub name: String,
    pub doc: String,
    pub params: Vec<Param>,
    pub requires_male: bool,
    pub inverse: Option<Inverse>,
    /// Steps of the robot's planner the operation is made of (a monkey move: two pivots), for
    /// a `move`: it takes `move_ms` per step. 1 for every other kind.
    pub steps: u64,
    /// What it does to the robot (`kind = "extend"`), so that the models and the simulator
    /// never decide it from the operation's name.
    pub kind: OperationKind,
}

/// What an operation does to the robot, as its plugin declares it. The loader checks that
/// the operation's index and parameters fit the kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum OperationKind {
    /// Nothing the robot models know of (a lamp, a sensor): the models refuse it and the
    /// simulator gives it no duration. What an operation without `kind` is.
    #[default]
    None,
    /// Latches the indexed (male) connector onto the one facing it; no parameters.
    Extend,
    /// Releases the indexed (male) connector's latch; no parameters.
    Retract,
    /// Turns the joint (the indexed one, or the only one): parameters `from` (int), `to`
    /// (int), the direction (bool, `true` = increasing), then any others.
    Turn,
    /// Turns the joint from wherever it is: parameters `to` (int), the direction (bool),
    /// then any others.
    TurnTo,
    /// Moves the whole module (a lattice module's slide or pivot): up to
    /// [`MAX_MOVE_PARAMS`] integer parameters, which the robot's model reads by the
    /// operation's place among its part's operations. Takes `move_ms` per step
    /// ([`Operation::steps`]).
    Move,
}

/// The most parameters an operation of kind `move` takes (what `Action::Move` carries).
pub const MAX_MOVE_PARAMS: usize = 4;

impl OperationKind {
    /// The name a plugin writes (what `serde` reads: the variant in snake case).
    pub fn name(self) -> &'static str {
        match self {
            OperationKind::None => "none",
            OperationKind::Extend => "extend",
            OperationKind::Retract => "retract",
            OperationKind::Turn => "turn",
            OperationKind::TurnTo => "turn_to",
            OperationKind::Move => "move",
        }
    }

    /// A connector operation (extend or retract).
    pub fn is_latch(self) -> bool {
        matches!(self, OperationKind::Extend | OperationKind::Retract)
    }

    /// A joint turn (with or without its start angle).
    pub fn is_turn(self) -> bool {
        matches!(self, OperationKind::Turn | OperationKind::TurnTo)
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Param {
    pub name: String,
    pub ty: ParamType,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ParamType {
    Bool,
    /// An integer in `min..=max`, further restricted to `values` when given.
    Int {
        min: i64,
        max: i64,
        values: Option<Vec<i64>>,
    },
}

/// How to undo an operation: another operation of the same part (same index) and its
/// arguments as functions of the original arguments.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Inverse {
    pub operation: usize,
    pub args: Vec<Template>,
}

#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Template {
    /// The original argument at this position.
    Param(usize),
    Not(Box<Template>),
    Negate(Box<Template>),
    Int(i64),
    Bool(bool),
}

/// A named value such as `$CONNECTOR_4`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Constant {
    pub name: String,
    pub value: i64,
    /// The part this constant indexes, if it is an index name.
    pub part: Option<usize>,
}

/// A value of an argument, after constants are resolved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Value {
    Int(i64),
    Bool(bool),
}

impl Value {
    pub fn type_name(self) -> &'static str {
        match self {
            Value::Int(_) => "a number",
            Value::Bool(_) => "a boolean",
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Int(n) => write!(f, "{n}"),
            Value::Bool(b) => write!(f, "{b}"),
        }
    }
}

impl ParamType {
    pub fn describe(&self) -> String {
        match self {
            ParamType::Bool => "a boolean".into(),
            ParamType::Int { .. } => "a number".into(),
        }
    }

    /// Whether `value` is in range; types are checked separately.
    pub fn allows(&self, value: i64) -> bool {
        match self {
            ParamType::Bool => false,
            ParamType::Int { min, max, values } => {
                (*min..=*max).contains(&value) && values.as_ref().is_none_or(|v| v.contains(&value))
            }
        }
    }

    /// The allowed values in words, for messages.
    pub fn allowed(&self) -> String {
        match self {
            ParamType::Bool => "true or false".into(),
            ParamType::Int {
                values: Some(values),
                ..
            } => {
                let list: Vec<String> = values.iter().map(i64::to_string).collect();
                format!("one of {}", list.join(", "))
            }
            ParamType::Int { min, max, .. } => format!("{min} to {max}"),
        }
    }
}

impl Part {
    pub fn is_male(&self, index: i64) -> bool {
        u32::try_from(index).is_ok_and(|i| self.male.contains(&i))
    }

    pub fn operation(&self, name: &str) -> Option<(usize, &Operation)> {
        self.operations
            .iter()
            .enumerate()
            .find(|(_, op)| op.name == name)
    }
}

impl Operation {
    /// `rotateFromToBy(from, to, increasing, speed)`, for messages.
    pub fn signature(&self) -> String {
        let params: Vec<&str> = self.params.iter().map(|p| p.name.as_str()).collect();
        format!("{}({})", self.name, params.join(", "))
    }
}

impl Template {
    /// The argument this template yields from the original arguments `args`.
    pub fn apply(&self, args: &[Value]) -> Option<Value> {
        match self {
            Template::Param(i) => args.get(*i).copied(),
            Template::Not(inner) => match inner.apply(args)? {
                Value::Bool(b) => Some(Value::Bool(!b)),
                Value::Int(_) => None,
            },
            Template::Negate(inner) => match inner.apply(args)? {
                Value::Int(n) => n.checked_neg().map(Value::Int),
                Value::Bool(_) => None,
            },
            Template::Int(n) => Some(Value::Int(*n)),
            Template::Bool(b) => Some(Value::Bool(*b)),
        }
    }
}

impl RobotApi {
    pub fn part(&self, name: &str) -> Option<(usize, &Part)> {
        self.parts.iter().enumerate().find(|(_, p)| p.name == name)
    }

    pub fn constant(&self, name: &str) -> Option<&Constant> {
        self.constants.iter().find(|c| c.name == name)
    }

    /// The kind of operation `op` of part `part` (`None` for one that does not exist).
    pub fn kind(&self, part: usize, op: usize) -> OperationKind {
        self.parts
            .get(part)
            .and_then(|p| p.operations.get(op))
            .map_or(OperationKind::None, |o| o.kind)
    }

    /// The inverse of operation `op` of part `part` applied to `args`, if it has one.
    pub fn invert(&self, part: usize, op: usize, args: &[Value]) -> Option<(usize, Vec<Value>)> {
        let inverse = self.parts.get(part)?.operations.get(op)?.inverse.as_ref()?;
        let args = inverse
            .args
            .iter()
            .map(|t| t.apply(args))
            .collect::<Option<Vec<Value>>>()?;
        Some((inverse.operation, args))
    }
}

/// The robots a file may name in its `robot` declaration.
#[derive(Clone, Debug, Default)]
pub struct RobotRegistry {
    robots: Vec<RobotApi>,
}

impl RobotRegistry {
    /// Adds a robot, replacing one of the same name.
    pub fn add(&mut self, api: RobotApi) {
        self.robots.retain(|r| r.name != api.name);
        self.robots.push(api);
    }

    pub fn get(&self, name: &str) -> Option<&RobotApi> {
        self.robots.iter().find(|r| r.name == name)
    }

    pub fn names(&self) -> Vec<String> {
        self.robots.iter().map(|r| r.name.clone()).collect()
    }
}
