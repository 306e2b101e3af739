//! The one robot API the other crates ask: [`RobotShape`] answers questions about a
//! configuration (modules, names, ids, connectors, male or female, latches, joints) and
//! [`RobotModel`] is a robot being reconfigured (its shape, doing an [`Action`], the motion of
//! a turn). ATRON and M-TRAN implement both in `builtin/`, over their folders (`atron/`,
//! `mtran/`); a new robot is one more implementation, which may live outside this crate.

use crate::common::Port;
use crate::configuration::Configuration;
use crate::motion::TurnMotion;
use crate::ops::{OpError, Outcome};
use std::any::Any;
use std::fmt;

/// What a configuration of a robot answers, whatever the robot. Modules are numbered
/// `0..len()` in a fixed order; connectors `0..connectors()` on every module.
pub trait RobotShape {
    /// Connectors of every module.
    fn connectors(&self) -> u8;
    /// Whether `connector` is a male one (the side of a latch that can release).
    fn is_male(&self, connector: u8) -> bool;
    /// Which rigid side of its module `connector` is fixed on: 0 for the side that turns
    /// against the others (ATRON's north hemisphere, M-TRAN's north block), 1 for the rest.
    /// The connectors of one side share its infrared transceiver (the ATRON preset's
    /// collisions), and a recording draws a connector on its side.
    fn side(&self, connector: u8) -> usize;
    /// Number of modules.
    fn len(&self) -> usize;
    /// Whether there is no module.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Module `m`'s name.
    fn name(&self, m: usize) -> Option<&str>;
    /// Module `m`'s numeric ID, if it has one.
    fn id(&self, m: usize) -> Option<u32>;
    /// Index of the module called `name`.
    fn index(&self, name: &str) -> Option<usize>;
    /// Index of the module with numeric ID `id`.
    fn index_by_id(&self, id: u32) -> Option<usize>;
    /// Joint `joint` of module `m`, in the unit the robot's plugin uses for angles.
    fn joint(&self, m: usize, joint: u8) -> Option<i64>;
    /// The port latched to `port`, if any.
    fn latched_to(&self, port: Port) -> Option<Port>;
    /// The connector of another module that `port` faces (latched or not), if any.
    fn facing(&self, port: Port) -> Option<Port>;
    /// `M3.C4` for a port, for messages.
    fn port_name(&self, port: Port) -> String;
}

/// What an operation does to the robot, as the plugin declares it (`kind = "extend"` and so
/// on, with the arguments in the order that kind fixes). Angles are in the plugin's unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Latch male connector `connector` onto the female connector facing it.
    Extend { connector: u8 },
    /// Release the latch of male connector `connector`.
    Retract { connector: u8 },
    /// Turn joint `joint` from `from` (the angle it has now when `None`) to `to`, in the
    /// increasing (positive) direction if `increasing`.
    Turn {
        joint: u8,
        from: Option<i64>,
        to: i64,
        increasing: bool,
    },
}

/// A robot being reconfigured: the configuration it has now, and what an action does to it.
/// Every action either succeeds (possibly with warnings) and leaves a valid configuration, or
/// fails and changes nothing.
pub trait RobotModel: fmt::Debug + Send + Sync {
    /// The name of the robot plugin this model is for (`atron`): a sequence written for
    /// another robot is refused.
    fn robot(&self) -> &str;
    /// The current configuration's answers.
    fn shape(&self) -> &dyn RobotShape;
    /// Does `action` on `module` (a name); the error is why the robot cannot.
    fn apply(&mut self, module: &str, action: &Action) -> Result<Outcome, OpError>;
    /// The motion a turn would make, without doing it; `None` for an action that is not a
    /// turn, or a turn refused before anything moves (a wrong angle, a locked joint).
    fn turn_motion(&self, module: &str, action: &Action) -> Option<TurnMotion>;
    /// Quarter turns (rounded up) a joint passes through from `from` to `to` in the given
    /// direction: what a turn's duration is counted in.
    fn quarter_turns(&self, from: i64, to: i64, increasing: bool) -> u64;
    /// The unit of the positions and distances of its turn motions, for messages
    /// (`lattice units`).
    fn length_unit(&self) -> &str;
    /// Module centres, when a turn always moves whole modules about their joints, so that two
    /// turns with disjoint moving sides commute (ATRON); `None` when it moves parts of
    /// modules (M-TRAN blocks) or the robot does not say.
    fn rigid_module_centres(&self) -> Option<Vec<[f64; 3]>> {
        None
    }
    /// The configuration in the data-file format, for a robot that has one.
    fn configuration(&self) -> Option<Configuration>;
    /// The configuration moved out of the model at its end (no copy: a large robot's
    /// simulation ends with this).
    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        self.configuration()
    }
    /// How the configuration differs from `other`'s (equal up to rigid motion: `None`); the
    /// first line of the answer is a summary.
    fn difference(&self, other: &dyn RobotModel) -> Option<String>;
    /// A copy, to try actions on.
    fn clone_model(&self) -> Box<dyn RobotModel>;
    /// This model as `Any`, so that an implementation can recognise another of its kind.
    fn as_any(&self) -> &dyn Any;
}

impl Clone for Box<dyn RobotModel> {
    fn clone(&self) -> Self {
        self.clone_model()
    }
}
