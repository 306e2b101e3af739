//! Results of world operations shared by both robots: the outcome of an accepted operation
//! (with warnings) and the reasons an operation is rejected.

use std::fmt;

/// Something worth telling about an accepted operation; the world is still consistent.
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// Extend/connect on a connector that is already latched: nothing changed.
    AlreadyLatched {
        /// `M0.C0`.
        port: String,
        /// The port it is latched to.
        partner: String,
    },
    /// Retract/disconnect on a connector that holds no latch: nothing changed.
    NothingLatched {
        /// `M0.C0`.
        port: String,
    },
    /// Releasing the latch split the robot into two parts that no latch joins.
    Split {
        /// Modules on the commanding module's side.
        first: Vec<String>,
        /// Modules on the released side.
        second: Vec<String>,
    },
    /// A turn to the angle the joint already has: it completes at once.
    NoMotion {
        /// The module whose joint was commanded.
        module: String,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::AlreadyLatched { port, partner } => {
                write!(f, "{port} is already latched to {partner}; nothing to do")
            }
            Warning::NothingLatched { port } => {
                write!(f, "{port} holds no latch; nothing to release")
            }
            Warning::Split { first, second } => write!(
                f,
                "the robot is now in two parts: [{}] and [{}]",
                first.join(", "),
                second.join(", ")
            ),
            Warning::NoMotion { module } => {
                write!(f, "{module}'s joint is already at the target angle")
            }
        }
    }
}

/// What an accepted operation did.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Outcome {
    /// Things to report; empty for a plain success.
    pub warnings: Vec<Warning>,
    /// Names of the modules whose pose changed (joint turns only; the commanding module is
    /// included when its own frame turned).
    pub moved: Vec<String>,
    /// Closest centre-to-centre approach between a moving and a still module during a turn
    /// (in the robot's length unit, `RobotModel::length_unit`); `None` when nothing swept past
    /// anything.
    pub closest_approach: Option<f64>,
}

/// Why an operation was rejected; the world is left unchanged.
#[derive(Clone, Debug, PartialEq)]
pub enum OpError {
    /// No module has this name.
    UnknownModule {
        /// The name asked for.
        module: String,
    },
    /// The connector number does not exist on this robot.
    NoSuchConnector {
        /// The module.
        module: String,
        /// The connector asked for.
        connector: u8,
        /// How many connectors a module has.
        count: u8,
    },
    /// Only male connectors are commanded to extend/retract (connect/disconnect).
    FemaleConnector {
        /// `M2.C1`.
        port: String,
        /// `extend`, `retract`, `connect` or `disconnect`.
        action: &'static str,
    },
    /// Extend/connect found no female connector facing back.
    NothingToLatchOnto {
        /// The extending port.
        port: String,
        /// What is (not) there.
        reason: String,
    },
    /// A joint angle that is not allowed.
    InvalidAngle {
        /// The module.
        module: String,
        /// The angle given.
        angle: i32,
        /// Which angles are allowed.
        reason: String,
    },
    /// The joint is not at the `from` angle.
    WrongStartAngle {
        /// The module.
        module: String,
        /// The `from` argument.
        from: i32,
        /// The joint's actual angle.
        actual: i32,
    },
    /// The two sides of the joint are latched together through other modules.
    JointLocked {
        /// The module.
        module: String,
        /// Modules on the loop's side.
        loop_modules: Vec<String>,
    },
    /// A module on the turning side would pass too close to a still one.
    SweepCollision {
        /// The module whose joint turns.
        module: String,
        /// The moving module.
        moving: String,
        /// The still module it would hit.
        still: String,
        /// Closest centre distance, in the robot's length unit.
        distance: f64,
        /// The limit it violates.
        limit: f64,
        /// Degrees into the turn at which the closest approach happens.
        angle_deg: f64,
    },
    /// Releasing the connection would leave the robot in two parts, which this robot refuses
    /// (its modules cannot stand apart).
    WouldSplit {
        /// `M2.C1`.
        port: String,
        /// The modules that would come apart from the commanding module's side.
        apart: Vec<String>,
    },
    /// The robot has no operation of this kind (a robot of joints asked for a whole module's
    /// move): its plugin's loader rules it out, so only a program built by hand meets it.
    Unsupported {
        /// The module asked.
        module: String,
        /// What it was asked to do (`move`).
        action: &'static str,
    },
    /// The robot's model could not prove the motion safe within its search's bound (it is
    /// refused, never assumed to be).
    Unproven {
        /// The module whose operation it is.
        module: String,
        /// What was left unproven.
        reason: String,
    },
}

impl fmt::Display for OpError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            OpError::UnknownModule { module } => write!(f, "no module is called \"{module}\""),
            OpError::NoSuchConnector {
                module,
                connector,
                count,
            } => write!(
                f,
                "{module} has no connector {connector} (connectors are 0-{})",
                count.saturating_sub(1)
            ),
            OpError::FemaleConnector { port, action } => write!(
                f,
                "cannot {action} {port}: it is a female connector; only the male side of a latch \
                 can {action}"
            ),
            OpError::NothingToLatchOnto { port, reason } => {
                write!(f, "{port} has nothing to latch onto: {reason}")
            }
            OpError::InvalidAngle {
                module,
                angle,
                reason,
            } => write!(f, "{module}: joint angle {angle} is not allowed: {reason}"),
            OpError::WrongStartAngle {
                module,
                from,
                actual,
            } => write!(
                f,
                "{module}'s joint is at {actual}, not at {from} as the rotation expects"
            ),
            OpError::JointLocked {
                module,
                loop_modules,
            } => write!(
                f,
                "{module}'s joint cannot turn: its two halves are latched together through a \
                 loop of modules ({})",
                loop_modules.join(", ")
            ),
            OpError::SweepCollision {
                module,
                moving,
                still,
                distance,
                limit,
                angle_deg,
            } => write!(
                f,
                "{module}'s turn would sweep {moving} through {still}: their centres come \
                 {distance:.3} apart ({angle_deg:.1} deg into the turn), under the limit {limit}"
            ),
            OpError::WouldSplit { port, apart } => write!(
                f,
                "cannot disconnect {port}: the robot would come apart ([{}] would be left on \
                 their own)",
                apart.join(", ")
            ),
            OpError::Unsupported { module, action } => {
                write!(
                    f,
                    "{module} cannot {action}: this robot has no such operation"
                )
            }
            OpError::Unproven { module, reason } => {
                write!(f, "{module}'s operation is refused: {reason}")
            }
        }
    }
}

impl std::error::Error for OpError {}
