//! Faults as data: the TOML scenario file (network, timing, resets, power cycles, blocked
//! links, operation faults, the faults-on phase and the timeout). Every field is documented in
//! `SCENARIO.md`.

use dynarole_codegen::choice::{self, Choice};
use dynarole_core::robot::MAX_OPERATION_MS;
use dynarole_core::suggest::did_you_mean;
use dynarole_core::RobotApi;
use serde::{Deserialize, Serialize};

/// How the network and the modules' clocks behave: one of the robot's presets
/// (`RobotModel::network_presets`) or [`USSR`].
pub type Preset = dynarole_world::NetworkPreset;

/// The original simulator (USSR), for any robot: full duplex per channel, no collisions, every
/// module powered on at 0 and broadcasting in the same step every 100 ms.
pub const USSR: Preset = Preset {
    name: "ussr",
    half_duplex_sides: false,
    power_on_spread_us: 0,
    jitter_ms: 0,
};

/// The preset a scenario names (`network.preset`, and `timing.preset`: [`Timing`]); none: the
/// robot's default (its first preset, or [`USSR`] for a robot with no network presets).
#[derive(Clone, Debug, PartialEq, Eq, Deserialize, Serialize, Default)]
#[serde(transparent)]
pub struct PresetName(pub Option<String>);

impl PresetName {
    /// The preset `name`.
    pub fn named(name: &str) -> PresetName {
        PresetName(Some(name.to_string()))
    }

    /// The preset this names among the robot's `presets` and [`USSR`]; the error says which
    /// names there are.
    pub fn resolve(&self, presets: &[Preset]) -> Result<Preset, String> {
        let Some(name) = &self.0 else {
            return Ok(presets.first().copied().unwrap_or(USSR));
        };
        let known = || presets.iter().chain([&USSR]);
        known()
            .find(|p| p.name == name.as_str())
            .copied()
            .ok_or_else(|| {
                let names: Vec<String> = known().map(|p| format!("`{}`", p.name)).collect();
                format!(
                    "unknown preset `{name}`; this robot has {}",
                    names.join(" and ")
                )
            })
    }
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Network {
    pub loss: f64,
    pub dead_link_p: f64,
    pub dead_loss: f64,
    pub preset: PresetName,
}

impl Default for Network {
    fn default() -> Network {
        Network {
            loss: 0.0,
            dead_link_p: 0.0,
            dead_loss: 0.98,
            preset: PresetName::default(),
        }
    }
}

/// How long each kind of operation takes, in ms: a timing preset's durations with the
/// scenario's overrides ([`Timing::durations`]).
pub type Durations = dynarole_core::robot::Durations;

/// The simulator's built-in timing preset `ussr`, for a robot whose plugin declares none
/// (`dynarole_core::robot::USSR_TIMING`).
pub use dynarole_core::robot::USSR_TIMING;

fn timing_presets(robot: &RobotApi) -> Vec<(&str, Durations)> {
    robot.timing_presets()
}

/// The durations of `robot`'s default timing preset (its first, or [`USSR_TIMING`]): what a
/// scenario without `timing.preset` runs with, and what model recordings and makespan
/// estimates weigh operations by.
pub fn default_durations(robot: &RobotApi) -> Durations {
    timing_presets(robot).first().map_or(USSR_TIMING, |p| p.1)
}

/// How long operations take in a run (`[timing]`): one of the robot's timing presets, two of
/// its durations replaced if the scenario says, and a random variation.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Timing {
    /// Replaces the preset's extend duration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub extend_ms: Option<u64>,
    /// Replaces the preset's retract duration.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub retract_ms: Option<u64>,
    /// Replaces the preset's duration of a move's step (a lattice module's slide or pivot).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub move_ms: Option<u64>,
    /// One of the robot's timing presets (`RobotApi::timing`); none: its default
    /// ([`default_durations`]). `joint` is its name in older scenarios, from when the
    /// simulator had two joint models (`ussr`, `realistic`) for every robot.
    #[serde(alias = "joint")]
    pub preset: PresetName,
    /// Random variation of every operation's duration: each takes its nominal time times a
    /// factor drawn uniformly from [1 - variation, 1 + variation] (0: exact durations).
    pub variation: f64,
}

impl Timing {
    /// The durations this names for `robot`: its preset `preset` (or its default), with
    /// `extend_ms`, `retract_ms` and `move_ms` in place of the preset's where given. An unknown preset is
    /// an error at `timing.preset` naming the robot's presets, with the closest one as a hint.
    pub fn durations(&self, robot: &RobotApi) -> Result<Durations, ScenarioError> {
        let preset = match &self.preset.0 {
            None => default_durations(robot),
            Some(name) => named_durations(robot, name)?,
        };
        Ok(Durations {
            extend_ms: self.extend_ms.unwrap_or(preset.extend_ms),
            retract_ms: self.retract_ms.unwrap_or(preset.retract_ms),
            move_ms: self.move_ms.unwrap_or(preset.move_ms),
            ..preset
        })
    }

    /// `extend_ms`, `retract_ms` and `move_ms` are at most [`MAX_OPERATION_MS`], as a preset's are.
    fn check_overrides(&self) -> Result<(), ScenarioError> {
        let overrides = [
            ("timing.extend_ms", self.extend_ms),
            ("timing.retract_ms", self.retract_ms),
            ("timing.move_ms", self.move_ms),
        ];
        for (field, ms) in overrides {
            if let Some(ms) = ms.filter(|ms| *ms > MAX_OPERATION_MS) {
                let message = format!(
                    "{ms} ms is more than {MAX_OPERATION_MS} ms, the longest an operation may take"
                );
                return Err(error(field, message));
            }
        }
        Ok(())
    }
}

/// The durations of `robot`'s timing preset `name`.
fn named_durations(robot: &RobotApi, name: &str) -> Result<Durations, ScenarioError> {
    let presets = timing_presets(robot);
    if let Some((_, durations)) = presets.iter().find(|(n, _)| *n == name) {
        return Ok(*durations);
    }
    let mut names: Vec<String> = presets.iter().map(|(n, _)| format!("`{n}`")).collect();
    let last = names.pop().unwrap_or_default();
    let listed = match names.is_empty() {
        true => last,
        false => format!("{} and {last}", names.join(", ")),
    };
    let message = format!(
        "unknown timing preset `{name}`; robot `{}` has {listed}",
        robot.name
    );
    let mut error = error("timing.preset", message);
    error.hint = did_you_mean(name, presets.iter().map(|(n, _)| *n));
    Err(error)
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Reset {
    pub module: String,
    pub at_ms: u64,
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Power {
    pub module: String,
    pub off_ms: u64,
    pub on_ms: u64,
}

#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Block {
    pub module: String,
    pub connector: u8,
    pub from_ms: u64,
    pub to_ms: u64,
}

/// A second robot running the same program in infrared range of one module: from `from_ms`
/// to `to_ms`, every `interval_ms`, `module` hears on `connector` what the other robot's
/// module of the same name broadcast last in a fault-free run of its own (the end, once it
/// has finished), sent under the other robot's identity `robot` in execution `execution`
/// (with `robot` this robot's own: a recording of another launch of it, replayed).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Foreign {
    pub module: String,
    pub connector: u8,
    pub robot: u16,
    pub from_ms: u64,
    pub to_ms: u64,
    #[serde(default = "foreign_interval_ms")]
    pub interval_ms: u64,
    /// The other launch's execution (`DR_EXECUTION`, runtime/dr_conf.h); `None`: the one
    /// before this robot's (`execution_beside`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub execution: Option<u32>,
}

impl Foreign {
    /// The execution its packets are sent in when this robot's is `own`: the entry's, else
    /// the launch before (`own - 1`, wrapping), never this one. A recording of this very
    /// execution is asked for by giving it: what a launch that reused its value would hear.
    pub fn execution_beside(&self, own: u32) -> u32 {
        self.execution.unwrap_or(own.wrapping_sub(1))
    }
}

fn foreign_interval_ms() -> u64 {
    100
}

/// Operation faults of the faults-on phase (`[faults]`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct Faults {
    /// The probability that one physical attempt of an operation fails without effect.
    pub operation_failure: OperationFailure,
}

impl Faults {
    /// Whether this is `[faults]` left out (nothing is written for it then).
    pub fn is_off(&self) -> bool {
        *self == Faults::default()
    }
}

/// `faults.operation_failure`: one probability for every operation, or one per kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum OperationFailure {
    Every(f64),
    ByKind(FailureByKind),
}

impl Default for OperationFailure {
    fn default() -> OperationFailure {
        OperationFailure::Every(0.0)
    }
}

impl OperationFailure {
    /// Every probability it gives, with its field.
    fn fields(&self) -> Vec<(&'static str, f64)> {
        match self {
            OperationFailure::Every(p) => vec![("faults.operation_failure", *p)],
            OperationFailure::ByKind(k) => vec![
                ("faults.operation_failure.extend", k.extend),
                ("faults.operation_failure.retract", k.retract),
                ("faults.operation_failure.turn", k.turn),
                ("faults.operation_failure.move", k.moves),
                ("faults.operation_failure.other", k.other),
            ],
        }
    }
}

/// `[faults.operation_failure]`: a probability per kind of operation
/// (`crate::sequence::OpKind`); a kind left out never fails.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize, Default)]
#[serde(deny_unknown_fields, default)]
pub struct FailureByKind {
    pub extend: f64,
    pub retract: f64,
    pub turn: f64,
    #[serde(rename = "move")]
    pub moves: f64,
    pub other: f64,
}

/// A number reads as [`OperationFailure::Every`], a table as [`OperationFailure::ByKind`]
/// (read by its own derived reader, so that an unknown kind is refused naming it: an untagged
/// enum would only say that nothing matched).
impl<'de> Deserialize<'de> for OperationFailure {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(FailureVisitor)
    }
}

struct FailureVisitor;

impl<'de> serde::de::Visitor<'de> for FailureVisitor {
    type Value = OperationFailure;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a probability, or a table of probabilities by kind of operation")
    }

    fn visit_f64<E>(self, p: f64) -> Result<OperationFailure, E> {
        Ok(OperationFailure::Every(p))
    }

    // `operation_failure = 1` is an integer in TOML.
    fn visit_i64<E>(self, p: i64) -> Result<OperationFailure, E> {
        Ok(OperationFailure::Every(p as f64))
    }

    fn visit_u64<E>(self, p: u64) -> Result<OperationFailure, E> {
        Ok(OperationFailure::Every(p as f64))
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<OperationFailure, A::Error> {
        let reader = serde::de::value::MapAccessDeserializer::new(map);
        FailureByKind::deserialize(reader).map(OperationFailure::ByKind)
    }
}

/// A part of one module that is broken from `from_ms` on: every attempt of an operation on
/// it that begins then or later fails without effect (`[[stuck]]`).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Stuck {
    pub module: String,
    /// The part as the language writes it: `Joint`, `Connector[0]`.
    pub part: String,
    pub from_ms: u64,
}

/// A module that dies in place at `at_ms` (`[[dead]]`): no more steps, packets or
/// operations; its parts stay where they are, latched as they are.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Dead {
    pub module: String,
    pub at_ms: u64,
}

/// A `[[stuck]]` entry resolved against the configuration and the robot.
#[derive(Clone, Debug, PartialEq)]
pub struct StuckPart {
    pub module: usize,
    /// The part (`RobotApi::parts`) and its index, as a resolved statement names them.
    pub part: usize,
    pub index: Option<i64>,
    pub from_us: u64,
    /// `Connector[0]`, for the trace.
    pub name: String,
}

/// `Connector[0]` as (`Connector`, `Some(0)`), `Joint` as (`Joint`, `None`).
fn parse_part(text: &str) -> Option<(&str, Option<i64>)> {
    let (name, index) = match text.split_once('[') {
        None => (text, None),
        Some((name, rest)) => {
            let digits = rest.strip_suffix(']')?;
            let all_digits = !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
            (name, Some(digits.parse().ok().filter(|_| all_digits)?))
        }
    };
    let mut chars = name.chars();
    let identifier = chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
    identifier.then_some((name, index))
}

/// Why `text` is no part string (`stuck[i].part`).
fn malformed_part(text: &str) -> String {
    format!(
        "`{text}` is not a part: expected a part name with an index in brackets if the part \
         has several (`Joint`, `Connector[0]`), as the program writes it"
    )
}

/// The part `text` names on `robot` (its index in `robot.parts`, and its own index), or why
/// it names none, as an error at `field`.
fn robot_part(
    robot: &RobotApi,
    text: &str,
    field: &str,
) -> Result<(usize, Option<i64>), ScenarioError> {
    let Some((name, index)) = parse_part(text) else {
        return Err(error(field, malformed_part(text)));
    };
    let Some(part) = robot.parts.iter().position(|p| p.name == name) else {
        let names: Vec<String> = robot
            .parts
            .iter()
            .map(|p| format!("`{}`", p.name))
            .collect();
        let message = format!(
            "robot `{}` has no part `{name}`; its parts are {}",
            robot.name,
            names.join(", ")
        );
        let mut e = error(field, message);
        e.hint = did_you_mean(name, robot.parts.iter().map(|p| p.name.as_str()));
        return Err(e);
    };
    let message = match (index, robot.parts[part].count) {
        (Some(i), Some(n)) if i >= i64::from(n) => format!(
            "`{name}[{i}]` is out of range: robot `{}` has `{name}[0]` to `{name}[{}]`",
            robot.name,
            n.saturating_sub(1)
        ),
        (Some(_), None) => format!("`{name}` takes no index: write `{name}`"),
        (None, Some(_)) => format!("`{name}` needs an index, as in `{name}[0]`"),
        _ => return Ok((part, index)),
    };
    Err(error(field, message))
}

/// The longest run a scenario may ask for (`timeout_ms`): 10^9 ms, about 11.6 days of
/// simulated time. A run costs wall time in proportion to its simulated time (eight2car's
/// seven modules run about 10,000 times faster than real time when nothing finishes, so this
/// bound is minutes; 10^12 ms would be days with no end in sight).
pub const MAX_TIMEOUT_MS: u64 = 1_000_000_000;

/// Most packets one `[[foreign]]` entry may inject (bounds the work of any scenario).
pub const MAX_FOREIGN_PACKETS: u64 = 1_000_000;

/// Spontaneous resets as in the original experiments: module k checks every
/// `interval_ms + k * 1000 / 7` ms and resets with probability `probability`.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RandomResets {
    pub interval_ms: u64,
    pub probability: f64,
}

/// How the simulator runs each module's C between events (`stepping` in a scenario).
/// Both give the same run, byte for byte (`docs/simulator.md`, "Stepping").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stepping {
    /// A step every 5 ms on every powered module, as the controller of a real module runs.
    Fixed,
    /// A step only at the 5 ms instants the module asked for (`dr_module_next_wakeup`), after
    /// a packet that made one useful, and after its operation completed.
    #[default]
    Tickless,
}

/// The names of `stepping` in scenarios and of `simulate --stepping`, read through
/// [`dynarole_codegen::choice`] like the protocols' own.
impl Choice for Stepping {
    const WHAT: &'static str = "stepping";
    const ALL: &'static [Stepping] = &[Stepping::Fixed, Stepping::Tickless];
    fn name(self) -> &'static str {
        match self {
            Stepping::Fixed => "fixed",
            Stepping::Tickless => "tickless",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Stepping::Fixed => "A step every 5 ms on every powered module",
            Stepping::Tickless => {
                "A step only when the module needs one (the default; the same run)"
            }
        }
    }
}

/// A whole scenario. Every field has a default, so an empty file is the fault-free run.
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scenario {
    pub timeout_ms: u64,
    /// After this time: no loss, dead links pass everything, no blocks, no resets, no
    /// transient operation failures (stuck parts and dead modules stay as they are).
    pub faults_until_ms: Option<u64>,
    pub network: Network,
    pub timing: Timing,
    pub reset: Vec<Reset>,
    pub power: Vec<Power>,
    pub block: Vec<Block>,
    pub random_resets: Option<RandomResets>,
    pub foreign: Vec<Foreign>,
    /// Transient operation failures (`[faults]`); left out of what is written when absent, as
    /// are `stuck` and `dead`, so that scenarios without them read and write as before.
    #[serde(skip_serializing_if = "Faults::is_off")]
    pub faults: Faults,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stuck: Vec<Stuck>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub dead: Vec<Dead>,
    #[serde(
        deserialize_with = "choice::deserialize",
        serialize_with = "choice::serialize"
    )]
    pub stepping: Stepping,
}

impl Default for Scenario {
    fn default() -> Scenario {
        Scenario {
            timeout_ms: 300_000,
            faults_until_ms: None,
            network: Network::default(),
            timing: Timing::default(),
            reset: Vec::new(),
            power: Vec::new(),
            block: Vec::new(),
            random_resets: None,
            foreign: Vec::new(),
            faults: Faults::default(),
            stuck: Vec::new(),
            dead: Vec::new(),
            stepping: Stepping::default(),
        }
    }
}

/// A scenario that does not parse or does not make sense: the field, the message, the span.
pub type ScenarioError = dynarole_core::toml_error::TomlError;

fn error(field: impl Into<String>, message: impl Into<String>) -> ScenarioError {
    ScenarioError::new(field, message)
}

impl Scenario {
    /// Parses and checks a scenario. Module names are checked later, against the
    /// configuration ([`Scenario::check_modules`]).
    pub fn from_toml_str(text: &str) -> Result<Scenario, ScenarioError> {
        let scenario: Scenario = toml::from_str(text).map_err(|e| ScenarioError::from_de(&e))?;
        scenario.check().map_err(|e| e.locate(text))?;
        Ok(scenario)
    }

    /// The end of the faults-on phase (the timeout when there is none).
    pub fn faults_end_ms(&self) -> u64 {
        self.faults_until_ms.unwrap_or(self.timeout_ms)
    }

    /// Checks ranges and times.
    pub fn check(&self) -> Result<(), ScenarioError> {
        probability("network.loss", self.network.loss)?;
        probability("network.dead_link_p", self.network.dead_link_p)?;
        probability("network.dead_loss", self.network.dead_loss)?;
        if !(0.0..1.0).contains(&self.timing.variation) {
            return Err(error(
                "timing.variation",
                format!(
                    "{} is not a fraction from 0 up to (not including) 1",
                    self.timing.variation
                ),
            ));
        }
        self.timing.check_overrides()?;
        if self.timeout_ms == 0 {
            return Err(error("timeout_ms", "must be above 0"));
        }
        if self.timeout_ms > MAX_TIMEOUT_MS {
            let message = format!(
                "{} ms is more than {MAX_TIMEOUT_MS} ms (about 11.6 days of simulated time), the longest run the simulator runs",
                self.timeout_ms
            );
            return Err(error("timeout_ms", message));
        }
        let end = self.faults_end_ms();
        if end > self.timeout_ms {
            return Err(error("faults_until_ms", "is after timeout_ms"));
        }
        for (i, r) in self.reset.iter().enumerate() {
            before(&format!("reset[{i}].at_ms"), r.at_ms, end)?;
        }
        for (i, p) in self.power.iter().enumerate() {
            before(&format!("power[{i}].off_ms"), p.off_ms, end)?;
            if p.on_ms <= p.off_ms {
                return Err(error(format!("power[{i}].on_ms"), "must be after off_ms"));
            }
        }
        no_overlapping_power(&self.power)?;
        for (i, b) in self.block.iter().enumerate() {
            if b.to_ms <= b.from_ms {
                return Err(error(format!("block[{i}].to_ms"), "must be after from_ms"));
            }
        }
        for (i, f) in self.foreign.iter().enumerate() {
            if f.to_ms <= f.from_ms {
                return Err(error(
                    format!("foreign[{i}].to_ms"),
                    "must be after from_ms",
                ));
            }
            if f.interval_ms == 0 {
                return Err(error(
                    format!("foreign[{i}].interval_ms"),
                    "must be above 0",
                ));
            }
            if (f.to_ms - f.from_ms) / f.interval_ms > MAX_FOREIGN_PACKETS {
                let message = format!("more than {MAX_FOREIGN_PACKETS} packets: widen interval_ms");
                return Err(error(format!("foreign[{i}]"), message));
            }
        }
        if let Some(r) = &self.random_resets {
            probability("random_resets.probability", r.probability)?;
            if r.interval_ms == 0 {
                return Err(error("random_resets.interval_ms", "must be above 0"));
            }
        }
        self.check_operation_faults()
    }

    /// The failure probabilities are probabilities, and every stuck part is written as a part.
    fn check_operation_faults(&self) -> Result<(), ScenarioError> {
        for (field, p) in self.faults.operation_failure.fields() {
            probability(field, p)?;
        }
        for (i, s) in self.stuck.iter().enumerate() {
            if parse_part(&s.part).is_none() {
                return Err(error(format!("stuck[{i}].part"), malformed_part(&s.part)));
            }
        }
        Ok(())
    }

    /// Every stuck part is a part of the program's robot (with an index in range when the
    /// robot says how many it has), checked with the configuration's module names.
    pub fn check_parts(&self, robot: &RobotApi) -> Result<(), ScenarioError> {
        for (i, s) in self.stuck.iter().enumerate() {
            robot_part(robot, &s.part, &format!("stuck[{i}].part"))?;
        }
        Ok(())
    }

    /// The `[[stuck]]` entries resolved: module index (`index` of a module name) and part.
    /// Entries that do not resolve are left out (`check_modules` and `check_parts` refuse
    /// them before any run).
    pub(crate) fn stuck_parts(
        &self,
        robot: &RobotApi,
        index: impl Fn(&str) -> Option<usize>,
    ) -> Vec<StuckPart> {
        let resolve = |s: &Stuck| {
            let (part, i) = robot_part(robot, &s.part, "").ok()?;
            Some(StuckPart {
                module: index(&s.module)?,
                part,
                index: i,
                from_us: s.from_ms.saturating_mul(1000),
                name: match i {
                    Some(i) => format!("{}[{i}]", robot.parts[part].name),
                    None => robot.parts[part].name.clone(),
                },
            })
        };
        self.stuck.iter().filter_map(resolve).collect()
    }

    /// Every module a fault names must exist, and every connector must be below `connectors`.
    pub fn check_modules(
        &self,
        exists: impl Fn(&str) -> bool,
        connectors: u8,
    ) -> Result<(), ScenarioError> {
        let unknown = |field: String, name: &str| {
            error(
                field,
                format!("no module named `{name}` in the configuration"),
            )
        };
        for (i, r) in self.reset.iter().enumerate() {
            if !exists(&r.module) {
                return Err(unknown(format!("reset[{i}].module"), &r.module));
            }
        }
        for (i, p) in self.power.iter().enumerate() {
            if !exists(&p.module) {
                return Err(unknown(format!("power[{i}].module"), &p.module));
            }
        }
        for (i, s) in self.stuck.iter().enumerate() {
            if !exists(&s.module) {
                return Err(unknown(format!("stuck[{i}].module"), &s.module));
            }
        }
        for (i, d) in self.dead.iter().enumerate() {
            if !exists(&d.module) {
                return Err(unknown(format!("dead[{i}].module"), &d.module));
            }
        }
        let ports = self
            .block
            .iter()
            .map(|b| ("block", &b.module, b.connector))
            .chain(
                self.foreign
                    .iter()
                    .map(|f| ("foreign", &f.module, f.connector)),
            );
        for (i, (table, module, connector)) in ports.enumerate() {
            let i = if table == "block" {
                i
            } else {
                i - self.block.len()
            };
            if !exists(module) {
                return Err(unknown(format!("{table}[{i}].module"), module));
            }
            if connector >= connectors {
                let message = format!("a module has connectors 0 to {}", connectors - 1);
                return Err(error(format!("{table}[{i}].connector"), message));
            }
        }
        Ok(())
    }
}

fn probability(field: &str, p: f64) -> Result<(), ScenarioError> {
    if (0.0..=1.0).contains(&p) {
        Ok(())
    } else {
        Err(error(field, format!("{p} is not a probability (0 to 1)")))
    }
}

fn before(field: &str, at: u64, end: u64) -> Result<(), ScenarioError> {
    if at < end {
        Ok(())
    } else {
        Err(error(
            field,
            format!("{at} is not inside the faults-on phase (ends at {end} ms)"),
        ))
    }
}

/// Two `[[power]]` windows of one module that overlap are refused: the module cannot be off
/// twice at once, and taking either window's end would silently shorten the other.
fn no_overlapping_power(power: &[Power]) -> Result<(), ScenarioError> {
    let mut order: Vec<usize> = (0..power.len()).collect();
    order.sort_by_key(|&i| (&power[i].module, power[i].off_ms, i));
    for pair in order.windows(2) {
        let (a, b) = (&power[pair[0]], &power[pair[1]]);
        if a.module == b.module && b.off_ms < a.on_ms {
            let message = format!(
                "overlaps power[{}] of the same module `{}` (off {} to {} ms): merge the two \
                 windows into one, or make them disjoint",
                pair[0], a.module, a.off_ms, a.on_ms
            );
            return Err(error(format!("power[{}].off_ms", pair[1]), message));
        }
    }
    Ok(())
}

#[cfg(test)]
#[path = "../tests/unit/scenario.rs"]
mod tests;
