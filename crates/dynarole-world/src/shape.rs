//! The questions every command asks of a configuration, whatever the robot: [`RobotShape`]
//! (modules, names, ids, connectors, male or female, latches, joints, which connectors hear
//! which) and the [`Action`]s a plugin's operations are. The `robot_shape!` macro writes
//! `RobotShape` for a robot built on the shared module structure (`structure.rs`).

use crate::common::Port;

/// What a configuration of a robot answers, whatever the robot. Modules are numbered
/// `0..len()` in a fixed order; connectors `0..connectors()` on every module.
pub trait RobotShape {
    /// Connectors of every module.
    fn connectors(&self) -> u8;
    /// Whether `connector` is a male one (the side of a latch that can release).
    fn is_male(&self, connector: u8) -> bool;
    /// Which rigid side of its module `connector` is fixed on: 0 for the side that turns
    /// against the others, 1 for the rest. The connectors of one side share its transceiver
    /// (a half-duplex network preset's collisions), and a recording draws a connector on its
    /// side.
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
    /// Where a packet sent on `port` arrives, in the configuration as it is (the robot's
    /// communication topology: which connectors hear which, in which states).
    fn link_target(&self, port: Port) -> Option<Port>;
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
    /// Move the whole module as the robot's move operation `operation` (its place among its
    /// part's operations, the plugin's order) does, with its integer arguments in order,
    /// padded with zeros: a lattice module's slide or pivot.
    Move { operation: u8, args: [i64; 4] },
}

impl Action {
    /// Refused by a robot that has no whole-module moves (a robot of joints and connectors).
    pub fn unsupported(&self, module: &str) -> crate::OpError {
        crate::OpError::Unsupported {
            module: module.to_string(),
            action: match self {
                Action::Extend { .. } => "extend",
                Action::Retract { .. } => "retract",
                Action::Turn { .. } => "turn",
                Action::Move { .. } => "move",
            },
        }
    }
}

/// Who checks a turn's sweep when it is applied.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepCheck {
    /// The model: the turn alone, against everything it does not move.
    Alone,
    /// The caller, with the turns it moves in lock-step with (a synchronous group): the turn
    /// alone may pass where, moving with them, it never is.
    WithOthers,
}

/// Where a packet sent on `port` goes on a robot whose connectors talk through a latch or,
/// unlatched, from a male connector to the free female connector facing it: the rule a robot
/// may give as its `link_target`.
///
/// Generic, so that a robot's own `link_target` calls its queries directly (the simulator asks
/// this for every connector whenever the topology changes).
pub fn latched_or_male_to_free_female<S: RobotShape + ?Sized>(
    shape: &S,
    port: Port,
) -> Option<Port> {
    if let Some(p) = shape.latched_to(port) {
        return Some(p);
    }
    if !shape.is_male(port.connector) {
        return None;
    }
    let other = shape.facing(port)?;
    let free_female = !shape.is_male(other.connector) && shape.latched_to(other).is_none();
    free_female.then_some(other)
}

/// `impl RobotShape` for a robot's configuration (`$config`, of `$module`s, both built on
/// `structure.rs`): the questions its modules and latches answer alike for every robot built
/// that way; `$joint(module, joint)` reads a joint's angle in the plugin's unit, and the
/// configuration's own `facing` and `link_target` give its geometry and topology.
#[macro_export]
macro_rules! robot_shape {
    ($config:ty, $module:ty, $joint:path) => {
        impl $crate::RobotShape for $config {
            fn connectors(&self) -> u8 {
                <$module as $crate::structure::RobotModule>::CONNECTOR_COUNT
            }

            fn is_male(&self, connector: u8) -> bool {
                <$module as $crate::structure::RobotModule>::is_male(connector)
            }

            fn side(&self, connector: u8) -> usize {
                usize::from(!<$module as $crate::structure::RobotModule>::is_north_side(
                    connector,
                ))
            }

            fn len(&self) -> usize {
                self.modules().len()
            }

            fn name(&self, m: usize) -> Option<&str> {
                self.module(m).map(|x| x.name.as_str())
            }

            fn id(&self, m: usize) -> Option<u32> {
                self.module(m).and_then(|x| x.id)
            }

            fn index(&self, name: &str) -> Option<usize> {
                self.module_index(name)
            }

            fn index_by_id(&self, id: u32) -> Option<usize> {
                self.module_index_by_id(id)
            }

            fn joint(&self, m: usize, joint: u8) -> Option<i64> {
                self.module(m).and_then(|x| $joint(x, joint))
            }

            fn latched_to(&self, port: $crate::Port) -> Option<$crate::Port> {
                <$config>::latched_to(self, port)
            }

            fn facing(&self, port: $crate::Port) -> Option<$crate::Port> {
                <$config>::facing(self, port)
            }

            fn link_target(&self, port: $crate::Port) -> Option<$crate::Port> {
                <$config>::link_target(self, port)
            }

            fn port_name(&self, port: $crate::Port) -> String {
                <$config>::port_name(self, port)
            }
        }
    };
}
