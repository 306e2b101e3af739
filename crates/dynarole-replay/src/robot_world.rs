//! The bridge from checked statements to the kinematic models: which world operation each
//! plugin operation is, for the robots that have a model (ATRON and M-TRAN).

use dynarole_core::check::ResolvedStatement;
use dynarole_core::robot::Value;
use dynarole_core::RobotApi;
use dynarole_world::{compare, Configuration, MtranJoint, MtranWorld, Outcome, TurnMotion, World};

/// A robot being reconfigured, of either kind.
#[derive(Clone, Debug)]
pub enum RobotWorld {
    Atron(World),
    Mtran(MtranWorld),
}

/// What an accepted step did (warnings included).
pub type StepOutcome = Outcome;

impl RobotWorld {
    /// The robot-neutral view of the current configuration.
    pub fn view(&self) -> dynarole_world::View<'_> {
        match self {
            RobotWorld::Atron(w) => dynarole_world::View::Atron(w.configuration()),
            RobotWorld::Mtran(w) => dynarole_world::View::Mtran(w.configuration()),
        }
    }

    /// Starts from `config`; fails when the configuration is not of the plugin's robot.
    pub fn new(config: Configuration, robot: &RobotApi) -> Result<RobotWorld, String> {
        match (robot.name.as_str(), config) {
            ("atron", Configuration::Atron(c)) => Ok(RobotWorld::Atron(World::new(c))),
            ("mtran", Configuration::Mtran(c)) => Ok(RobotWorld::Mtran(MtranWorld::new(c))),
            ("atron" | "mtran", other) => Err(format!(
                "the sequence is for robot `{}` but the configuration is an {} robot",
                robot.name,
                other.robot().name()
            )),
            (name, _) => Err(format!(
                "robot `{name}` has no kinematic model (only atron and mtran have one)"
            )),
        }
    }

    pub fn configuration(&self) -> Configuration {
        match self {
            RobotWorld::Atron(w) => Configuration::Atron(w.configuration().clone()),
            RobotWorld::Mtran(w) => Configuration::Mtran(w.configuration().clone()),
        }
    }

    /// Does `statement` on `module`; the error is the reason the model refuses it.
    pub fn apply(
        &mut self,
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: &str,
    ) -> Result<StepOutcome, String> {
        let (part, op) = names(robot, statement);
        let index = statement.index.and_then(|i| u8::try_from(i).ok());
        let result = match (self, part, op, index, statement.args.as_slice()) {
            (RobotWorld::Atron(w), "Connector", "extend", Some(c), []) => w.extend(module, c),
            (RobotWorld::Atron(w), "Connector", "retract", Some(c), []) => w.retract(module, c),
            (
                RobotWorld::Atron(w),
                "Joint",
                "rotateFromToBy",
                None,
                [Value::Int(f), Value::Int(t), Value::Bool(d), _],
            ) => w.rotate(module, units(*f), units(*t), *d),
            (
                RobotWorld::Atron(w),
                "Joint",
                "rotateToBy",
                None,
                [Value::Int(t), Value::Bool(d), _],
            ) => {
                let from = atron_joint(w, module);
                w.rotate(module, from, units(*t), *d)
            }
            (RobotWorld::Mtran(w), "Connector", "extend", Some(c), []) => w.connect(module, c),
            (RobotWorld::Mtran(w), "Connector", "retract", Some(c), []) => w.disconnect(module, c),
            (
                RobotWorld::Mtran(w),
                "Joint",
                "rotateFromToBy",
                Some(j),
                [Value::Int(f), Value::Int(t), Value::Bool(d), _],
            ) => w.rotate(module, mtran_joint(j), degrees(*f), degrees(*t), *d),
            _ => {
                return Err(format!(
                    "the robot model has no operation `{part}.{op}` with these arguments"
                ))
            }
        };
        result.map_err(|e| e.to_string())
    }

    /// The motion of a joint turn (ATRON or M-TRAN), without doing it; `None` for anything
    /// else, or a turn the model refuses before moving (a wrong angle, a locked joint).
    pub fn turn_motion(
        &self,
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: &str,
    ) -> Option<TurnMotion> {
        let index = statement.index.and_then(|i| u8::try_from(i).ok());
        match (self, names(robot, statement), statement.args.as_slice()) {
            (
                RobotWorld::Atron(w),
                ("Joint", "rotateFromToBy"),
                [Value::Int(f), Value::Int(t), Value::Bool(d), _],
            ) => w.turn_motion(module, units(*f), units(*t), *d).ok(),
            (RobotWorld::Atron(w), ("Joint", "rotateToBy"), [Value::Int(t), Value::Bool(d), _]) => {
                w.turn_motion(module, atron_joint(w, module), units(*t), *d)
                    .ok()
            }
            (
                RobotWorld::Mtran(w),
                ("Joint", "rotateFromToBy"),
                [Value::Int(f), Value::Int(t), Value::Bool(d), _],
            ) => w
                .turn_motion(module, mtran_joint(index?), degrees(*f), degrees(*t), *d)
                .ok(),
            _ => None,
        }
    }
}

/// The same configuration, exactly or up to rigid motion (what `check --from` compares).
pub(crate) fn same_configuration(a: &RobotWorld, b: &RobotWorld) -> bool {
    // Exact equality first, on the worlds' own configurations (no copy).
    let equal = match (a, b) {
        (RobotWorld::Atron(x), RobotWorld::Atron(y)) => x.configuration() == y.configuration(),
        (RobotWorld::Mtran(x), RobotWorld::Mtran(y)) => x.configuration() == y.configuration(),
        _ => false,
    };
    equal || compare(&a.configuration(), &b.configuration()).is_ok()
}

fn names<'r>(robot: &'r RobotApi, statement: &ResolvedStatement) -> (&'r str, &'r str) {
    let part = robot.parts.get(statement.part);
    let op = part.and_then(|p| p.operations.get(statement.operation));
    (
        part.map_or("?", |p| p.name.as_str()),
        op.map_or("?", |o| o.name.as_str()),
    )
}

/// M-TRAN joint 0 is the north one, 1 the south one (the plugin allows no other index).
fn mtran_joint(index: u8) -> MtranJoint {
    if index == 0 {
        MtranJoint::North
    } else {
        MtranJoint::South
    }
}

fn atron_joint(world: &World, module: &str) -> u16 {
    let config = world.configuration();
    config
        .module_index(module)
        .and_then(|i| config.module(i))
        .map_or(0, |m| m.joint_units)
}

/// Angles were range-checked by the plugin; out-of-range values cannot reach here.
fn units(angle: i64) -> u16 {
    u16::try_from(angle).unwrap_or(u16::MAX)
}

fn degrees(angle: i64) -> i16 {
    i16::try_from(angle).unwrap_or(i16::MAX)
}
