//! The bridge from checked statements to the robot models: which [`Action`] each plugin
//! operation is, done on any robot through the [`RobotModel`] trait (a robot kind of the
//! registry, or a model made elsewhere).

use dynarole_core::check::ResolvedStatement;
use dynarole_core::robot::{OperationKind, Value};
use dynarole_core::RobotApi;
use dynarole_world::{Action, Configuration, Motion, Outcome, RobotModel, SweepCheck, View};

/// A robot being reconfigured, of any kind.
#[derive(Clone, Debug)]
pub struct RobotWorld {
    model: Box<dyn RobotModel>,
}

/// What an accepted step did (warnings included).
pub type StepOutcome = Outcome;

/// A warning of the model on the way through a run of steps: the step it came from and the
/// warning (two orders of a pair are compared by the warning only).
pub(crate) type Warned = (String, dynarole_world::Warning);

impl RobotWorld {
    /// Starts from `config`; fails when the configuration is not of the plugin's robot.
    pub fn new(config: Configuration, robot: &RobotApi) -> Result<RobotWorld, String> {
        let file_robot = config.kind().file_tag();
        let model = config.into_model();
        if model.robot() == robot.name {
            return Ok(RobotWorld { model });
        }
        Err(format!(
            "the sequence is for robot `{}` but the configuration is an {file_robot} robot",
            robot.name
        ))
    }

    /// Starts from a model of any robot (one defined outside this crate, say); fails when it
    /// is not a model of the plugin's robot.
    pub fn from_model(model: Box<dyn RobotModel>, robot: &RobotApi) -> Result<RobotWorld, String> {
        if model.robot() == robot.name {
            Ok(RobotWorld { model })
        } else {
            Err(format!(
                "the sequence is for robot `{}` but the model is of robot `{}`",
                robot.name,
                model.robot()
            ))
        }
    }

    /// The network presets of the robot's kind, the default first.
    pub fn network_presets(&self) -> &'static [dynarole_world::NetworkPreset] {
        self.model.network_presets()
    }

    /// The robot-neutral view of the current configuration.
    pub fn view(&self) -> View<'_> {
        View::new(self.model.shape())
    }

    /// The model itself.
    pub fn model(&self) -> &dyn RobotModel {
        self.model.as_ref()
    }

    /// The current configuration in the data-file format (every built-in robot has one).
    pub fn configuration(&self) -> Option<Configuration> {
        self.model.configuration()
    }

    /// The configuration in the data-file format, moved out at the end.
    pub fn into_configuration(self) -> Option<Configuration> {
        self.model.into_configuration()
    }

    /// Does `statement` on `module`; the error is the reason the model refuses it.
    pub fn apply(
        &mut self,
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: &str,
    ) -> Result<StepOutcome, String> {
        let Some(action) = action(robot, statement) else {
            let (part, op) = names(robot, statement);
            return Err(format!(
                "the robot model has no operation `{part}.{op}` with these arguments"
            ));
        };
        self.model.apply(module, &action).map_err(|e| e.to_string())
    }

    /// [`RobotWorld::apply`] with its sweep checked as `sweep` says (`RobotModel::apply_swept`).
    pub fn apply_swept(
        &mut self,
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: &str,
        sweep: SweepCheck,
    ) -> Result<StepOutcome, String> {
        let Some(action) = action(robot, statement) else {
            return self.apply(robot, statement, module);
        };
        (self.model.apply_swept(module, &action, sweep)).map_err(|e| e.to_string())
    }

    /// The motion `statement` would make on `module`, without doing it
    /// (`RobotModel::motion`); `None` for an operation of kind `none`, or one the model
    /// refuses before moving (a wrong angle, a locked joint).
    pub fn motion(
        &self,
        robot: &RobotApi,
        statement: &ResolvedStatement,
        module: &str,
    ) -> Option<Motion> {
        self.model.motion(module, &action(robot, statement)?)
    }

    /// How the configuration differs from `other`'s (`None`: the same up to rigid motion).
    pub fn difference(&self, other: &RobotWorld) -> Option<String> {
        self.model.difference(other.model())
    }
}

/// What `statement` does to the robot: the one place where a plugin operation becomes a model
/// action, by the kind its plugin declares. `None` for an operation of kind `none`, or
/// arguments that do not fit the kind (the loader and the checker make that impossible).
pub fn action(robot: &RobotApi, statement: &ResolvedStatement) -> Option<Action> {
    let index = statement.index.and_then(|i| u8::try_from(i).ok());
    let turn = |from, to, increasing| Action::Turn {
        joint: index.unwrap_or(0),
        from,
        to,
        increasing,
    };
    let kind = robot.kind(statement.part, statement.operation);
    match (kind, statement.args.as_slice()) {
        (OperationKind::Extend, _) => Some(Action::Extend { connector: index? }),
        (OperationKind::Retract, _) => Some(Action::Retract { connector: index? }),
        (OperationKind::Turn, [Value::Int(f), Value::Int(t), Value::Bool(d), ..]) => {
            Some(turn(Some(*f), *t, *d))
        }
        (OperationKind::TurnTo, [Value::Int(t), Value::Bool(d), ..]) => Some(turn(None, *t, *d)),
        (OperationKind::Move, values) => move_action(statement.operation, values),
        _ => None,
    }
}

/// A move's action: its operation's place and its integer arguments, padded with zeros.
fn move_action(operation: usize, values: &[Value]) -> Option<Action> {
    let mut args = [0; 4];
    if values.len() > args.len() {
        return None;
    }
    for (slot, value) in args.iter_mut().zip(values) {
        let Value::Int(n) = value else { return None };
        *slot = *n;
    }
    let operation = u8::try_from(operation).ok()?;
    Some(Action::Move { operation, args })
}

fn names<'r>(robot: &'r RobotApi, statement: &ResolvedStatement) -> (&'r str, &'r str) {
    let part = robot.parts.get(statement.part);
    let op = part.and_then(|p| p.operations.get(statement.operation));
    (
        part.map_or("?", |p| p.name.as_str()),
        op.map_or("?", |o| o.name.as_str()),
    )
}
