//! RoFI behind the robot API: [`RofiModel`] is the [`RobotModel`] that connects, disconnects
//! and turns joints, every motion checked on RoFI's physical model. A turn is checked along
//! its whole sweep (`sweep.rs`, a proof, not samples) and refused where a loop of connections
//! would open; `connect` only makes a connection between free connectors whose shoes mate;
//! `disconnect` is refused where the robot would come apart.

use crate::module::{Connector, Joint, RofiConfiguration, Side, SHOE_JOINT_LIMIT_DEG};
use crate::robot::{whole, RofiRobot};
use crate::sweep::{sweep, SweepVerdict, Timing, Turn, SWEEP_TOLERANCE};
use crate::turn::{mate_of, turn_motion, TurnMotion};
use dynarole_world::{
    model_difference, Action, Carried, Configuration, GroupVerdict, Leg, Motion, OpError, Outcome,
    Port, RobotKind, RobotModel, RobotShape, SweepCheck, Warning,
};
use std::any::Any;
use std::collections::BTreeSet;

/// The least distance of two shoe centres the generic checks of turns done together hold a
/// motion to (`Motion::limit`): one unit less the tolerance the exact sweep proves to, since
/// shoes that end mated are exactly one unit apart.
pub const MOTION_LIMIT: f64 = 1.0 - SWEEP_TOLERANCE;

/// A RoFI robot being reconfigured.
#[derive(Clone, Debug, PartialEq)]
pub struct RofiModel {
    robot: RofiRobot,
}

impl RofiModel {
    pub fn new(robot: RofiRobot) -> RofiModel {
        RofiModel { robot }
    }

    pub fn robot(&self) -> &RofiRobot {
        &self.robot
    }

    fn config(&self) -> &RofiConfiguration {
        self.robot.configuration()
    }

    fn port(&self, module: &str, connector: u8) -> Result<(Port, (u32, Connector)), OpError> {
        let index = self.known(module)?;
        let port = Port {
            module: index,
            connector,
        };
        let rofi = self.robot.rofi_port(port).ok_or(OpError::NoSuchConnector {
            module: module.to_string(),
            connector,
            count: Connector::COUNT,
        })?;
        Ok((port, rofi))
    }

    fn known(&self, module: &str) -> Result<usize, OpError> {
        self.robot
            .index(module)
            .ok_or_else(|| OpError::UnknownModule {
                module: module.to_string(),
            })
    }

    fn name_of(&self, id: u32) -> String {
        (self.robot.index_of_id(id))
            .and_then(|m| self.robot.name(m))
            .unwrap_or("?")
            .to_string()
    }

    /// Connects `connector` to the free connector its shoe mates with.
    pub fn connect(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        let (port, rofi) = self.port(module, connector)?;
        if let Some(partner) = self.robot.latched_to(port) {
            return Ok(warned(Warning::AlreadyLatched {
                port: self.robot.port_name(port),
                partner: self.robot.port_name(partner),
            }));
        }
        let connection =
            mate_of(self.config(), rofi).ok_or_else(|| OpError::NothingToLatchOnto {
                port: self.robot.port_name(port),
                reason: "no free connector of another module mates with it (its shoe one unit \
                     along the face, the faces opposed)"
                    .into(),
            })?;
        let mut config = self.config().clone();
        config
            .connect(connection)
            .map_err(|e| OpError::NothingToLatchOnto {
                port: self.robot.port_name(port),
                reason: e.to_string(),
            })?;
        self.robot = self.robot.with_configuration(config);
        Ok(Outcome::default())
    }

    /// Releases the connection `connector` holds, unless the robot would come apart.
    pub fn disconnect(&mut self, module: &str, connector: u8) -> Result<Outcome, OpError> {
        let (port, rofi) = self.port(module, connector)?;
        let mut config = self.config().clone();
        if config.disconnect(rofi).is_none() {
            return Ok(warned(Warning::NothingLatched {
                port: self.robot.port_name(port),
            }));
        }
        if let Err(crate::KinematicsError::NotConnected { unreached, .. }) = crate::poses(&config) {
            let all: Vec<u32> = config.modules().map(|m| m.id).collect();
            let apart: Vec<u32> = if unreached.contains(&rofi.0) {
                all.into_iter()
                    .filter(|id| !unreached.contains(id))
                    .collect()
            } else {
                unreached
            };
            return Err(OpError::WouldSplit {
                port: self.robot.port_name(port),
                apart: apart.into_iter().map(|id| self.name_of(id)).collect(),
            });
        }
        self.robot = self.robot.with_configuration(config);
        Ok(Outcome::default())
    }

    /// Turns a joint, its sweep checked here when `sweep` is [`SweepCheck::Alone`].
    fn rotate(
        &mut self,
        module: &str,
        (joint, from, to, increasing): (u8, Option<i64>, i64, bool),
        check: SweepCheck,
    ) -> Result<Outcome, OpError> {
        let Some(turn) = self.plan(module, joint, from, to, increasing)? else {
            return Ok(warned(Warning::NoMotion {
                module: module.to_string(),
            }));
        };
        let motion = self.turn_motion_of(module, &turn)?;
        if check == SweepCheck::Alone {
            self.check_sweep(module, &turn, &motion)?;
        }
        let mut config = self.config().clone();
        config.set_joint(turn.module, turn.joint, turn.from + turn.by);
        let moved: BTreeSet<u32> = motion.moving.iter().map(|(id, _)| *id).collect();
        self.robot = self.robot.with_configuration(config);
        Ok(Outcome {
            warnings: Vec::new(),
            moved: moved.into_iter().map(|id| self.name_of(id)).collect(),
            closest_approach: None,
        })
    }

    /// The motion of a planned turn, or the loop it would open.
    fn turn_motion_of(&self, module: &str, turn: &Turn) -> Result<TurnMotion, OpError> {
        let motion =
            turn_motion(self.config(), turn.module, turn.joint, turn.by).ok_or_else(|| {
                OpError::UnknownModule {
                    module: module.to_string(),
                }
            })?;
        if let Some(c) = motion.opens {
            return Err(OpError::JointLocked {
                module: module.to_string(),
                loop_modules: vec![self.name_of(c.from.0), self.name_of(c.to.0)],
            });
        }
        Ok(motion)
    }

    /// The turn's whole sweep, alone, against every shoe it does not move.
    fn check_sweep(&self, module: &str, turn: &Turn, motion: &TurnMotion) -> Result<(), OpError> {
        let verdict =
            sweep(self.config(), &[*turn], Timing::Every).map_err(|e| OpError::Unproven {
                module: module.to_string(),
                reason: e.to_string(),
            })?;
        match verdict {
            SweepVerdict::Clear => Ok(()),
            SweepVerdict::Collides {
                fractions,
                collision,
            } => {
                let (a, b) = collision.shoes;
                let (moving, still) = if motion.moving.contains(&a) {
                    (a, b)
                } else {
                    (b, a)
                };
                Err(OpError::SweepCollision {
                    module: module.to_string(),
                    moving: self.name_of(moving.0),
                    still: self.name_of(still.0),
                    distance: collision.distance,
                    limit: 1.0,
                    angle_deg: fractions.first().copied().unwrap_or(0.0) * turn.by.abs(),
                })
            }
            SweepVerdict::OpensLoop { connection: c, .. } => Err(OpError::JointLocked {
                module: module.to_string(),
                loop_modules: vec![self.name_of(c.from.0), self.name_of(c.to.0)],
            }),
            SweepVerdict::Unproven { lower_bound, shoes } => Err(OpError::Unproven {
                module: module.to_string(),
                reason: format!(
                    "the sweep could not be proven to keep {} and {} apart (proven \
                     {lower_bound:.4} units, within the search's budget)",
                    self.name_of(shoes.0 .0),
                    self.name_of(shoes.1 .0)
                ),
            }),
        }
    }

    /// The turn a `rotateFromToBy` asks for, its angles checked (`by` signed: gamma's
    /// direction is in the sign): `None` when it goes nowhere.
    fn plan(
        &self,
        module: &str,
        joint: u8,
        from: Option<i64>,
        to: i64,
        increasing: bool,
    ) -> Result<Option<Turn>, OpError> {
        let index = self.known(module)?;
        let invalid = |angle: i64, reason: String| OpError::InvalidAngle {
            module: module.to_string(),
            angle: i32::try_from(angle).unwrap_or(i32::MAX),
            reason,
        };
        let Some(&which) = Joint::ALL.get(usize::from(joint)) else {
            return Err(invalid(
                to,
                format!("RoFI modules have joints 0-2, not {joint}"),
            ));
        };
        let id = self.robot.id_at(index).unwrap_or_default();
        let now = self.config().module(id).map_or(0.0, |m| m.joint(which));
        let from = from.unwrap_or(whole(now));
        let by = match which {
            Joint::Gamma => gamma_turn(from, to, increasing),
            _ => shoe_turn(from, to, increasing).map_err(|(angle, why)| invalid(angle, why))?,
        };
        let at_start = match which {
            Joint::Gamma => crate::module::circular(now - from as f64).abs() < 1e-9,
            _ => (now - from as f64).abs() < 1e-9,
        };
        if !at_start {
            return Err(OpError::WrongStartAngle {
                module: module.to_string(),
                from: i32::try_from(from).unwrap_or(i32::MAX),
                actual: i32::try_from(whole(now)).unwrap_or(i32::MAX),
            });
        }
        if by == 0 {
            return Ok(None);
        }
        let turn = Turn {
            module: id,
            joint: which,
            from: from as f64,
            by: by as f64,
        };
        Ok(Some(turn))
    }

    /// The turn a motion this model gave is (its joint found by its pivot and axis, which
    /// differ between a module's three joints), from the joint's angle now.
    fn turn_of(&self, motion: &Motion, turner: usize) -> Option<Turn> {
        let [Leg::Rotate {
            pivot,
            axis,
            angle_deg,
        }] = motion.legs.as_slice()
        else {
            return None;
        };
        let id = self.robot.id_at(turner)?;
        let module = self.config().module(id)?;
        Joint::ALL.into_iter().find_map(|joint| {
            let unit = turn_motion(self.config(), id, joint, 1.0)?;
            let at = |k: usize| (unit.pivot[k] - pivot[k]).abs() < 1e-9;
            let dot: f64 = (0..3).map(|k| unit.axis[k] * axis[k]).sum();
            let same_axis = (dot.abs() - 1.0).abs() < 1e-9;
            (at(0) && at(1) && at(2) && same_axis).then(|| Turn {
                module: id,
                joint,
                from: module.joint(joint),
                by: angle_deg * dot.signum() / unit.angle_deg,
            })
        })
    }

    /// The motion of a checked turn for the generic checks and the drawing.
    fn motion_of(&self, motion: &TurnMotion) -> Motion {
        let poses = crate::robot::poses_of(self.config());
        let centre = |shoe: (u32, Side)| {
            (poses.as_ref())
                .and_then(|p| p.centre(shoe))
                .map_or([0.0; 3], |c| [c.x, c.y, c.z])
        };
        let mut carried = Vec::new();
        for m in self.config().modules() {
            let moves = |side| motion.moving.contains(&(m.id, side));
            let part = match (moves(Side::A), moves(Side::B)) {
                (true, true) => None,
                (true, false) => Some(0),
                (false, true) => Some(1),
                (false, false) => continue,
            };
            carried.push(Carried {
                module: self.name_of(m.id),
                part,
            });
        }
        Motion {
            legs: vec![Leg::Rotate {
                pivot: [motion.pivot.x, motion.pivot.y, motion.pivot.z],
                axis: [motion.axis.x, motion.axis.y, motion.axis.z],
                angle_deg: motion.angle_deg,
            }],
            carried,
            moving: (motion.moving.iter())
                .map(|shoe| (self.name_of(shoe.0), centre(*shoe)))
                .collect(),
            limit: MOTION_LIMIT,
        }
    }
}

/// An outcome with one warning.
fn warned(warning: Warning) -> Outcome {
    Outcome {
        warnings: vec![warning],
        ..Outcome::default()
    }
}

/// Degrees a shoe joint (alpha, beta) turns from `from` to `to`, which must both be within
/// its range and lie the way `increasing` says; the error is the angle at fault and why.
fn shoe_turn(from: i64, to: i64, increasing: bool) -> Result<i64, (i64, String)> {
    let limit = SHOE_JOINT_LIMIT_DEG as i64;
    if let Some(angle) = [from, to].into_iter().find(|a| a.abs() > limit) {
        return Err((angle, format!("alpha and beta take -{limit}..{limit}")));
    }
    if from != to && (to > from) != increasing {
        let way = if increasing {
            "increasing"
        } else {
            "decreasing"
        };
        return Err((
            to,
            format!("turning the {way} way from {from} cannot reach {to} within -{limit}..{limit}"),
        ));
    }
    Ok(to - from)
}

/// Degrees gamma turns from `from` to `to` the way `increasing` says (round the circle).
fn gamma_turn(from: i64, to: i64, increasing: bool) -> i64 {
    if increasing {
        (to - from).rem_euclid(360)
    } else {
        -(from - to).rem_euclid(360)
    }
}

impl RobotModel for RofiModel {
    fn robot(&self) -> &str {
        crate::KIND.name()
    }

    fn shape(&self) -> &dyn RobotShape {
        &self.robot
    }

    fn apply(&mut self, module: &str, action: &Action) -> Result<Outcome, OpError> {
        self.apply_swept(module, action, SweepCheck::Alone)
    }

    fn apply_swept(
        &mut self,
        module: &str,
        action: &Action,
        sweep: SweepCheck,
    ) -> Result<Outcome, OpError> {
        match *action {
            Action::Extend { connector } => self.connect(module, connector),
            Action::Retract { connector } => self.disconnect(module, connector),
            Action::Turn {
                joint,
                from,
                to,
                increasing,
            } => self.rotate(module, (joint, from, to, increasing), sweep),
            Action::Move { .. } => Err(action.unsupported(module)),
        }
    }

    fn motion(&self, module: &str, action: &Action) -> Option<Motion> {
        let Action::Turn {
            joint,
            from,
            to,
            increasing,
        } = *action
        else {
            if matches!(action, Action::Move { .. }) {
                return None;
            }
            // A RoFICoM's slide moves inside its shoe: nothing a sweep or a drawing sees.
            return self.robot.index(module).map(|_| Motion::in_place());
        };
        let Some(turn) = self.plan(module, joint, from, to, increasing).ok()? else {
            return Some(Motion {
                limit: MOTION_LIMIT,
                ..Motion::in_place()
            });
        };
        let motion = self.turn_motion_of(module, &turn).ok()?;
        Some(self.motion_of(&motion))
    }

    fn quarter_turns(&self, from: i64, to: i64, increasing: bool) -> u64 {
        let delta = gamma_turn(from, to, increasing).unsigned_abs();
        delta.div_ceil(90)
    }

    fn length_unit(&self) -> &str {
        "module units"
    }

    /// Both shoes of every module (RoFI's collision spheres), in module units.
    fn sweep_points(&self) -> Option<Vec<(usize, [f64; 3])>> {
        let poses = crate::robot::poses_of(self.config())?;
        let points = poses
            .centres()
            .filter_map(|((id, _), c)| Some((self.robot.index_of_id(id)?, [c.x, c.y, c.z])));
        Some(points.collect())
    }

    /// RoFI's own exact sweep (`sweep.rs`) over every relative timing, or over the lock-step
    /// band of a synchronous group: the generic search links turns of whole modules, not two
    /// joints of one module turning at once.
    fn turns_together(
        &self,
        turns: &[(&Motion, usize)],
        skew: Option<f64>,
    ) -> Option<GroupVerdict> {
        let found = (turns.iter())
            .map(|(motion, turner)| self.turn_of(motion, *turner))
            .collect::<Option<Vec<Turn>>>()?;
        let index = |id: u32| self.robot.index_of_id(id).unwrap_or(0);
        let timing = skew.map_or(Timing::Every, Timing::Band);
        Some(match sweep(self.config(), &found, timing).ok()? {
            SweepVerdict::Clear => GroupVerdict::Clear,
            SweepVerdict::Collides { collision, .. } => GroupVerdict::Closest {
                distance: collision.distance,
                modules: (index(collision.shoes.0 .0), index(collision.shoes.1 .0)),
            },
            // Each turn was accepted alone, so none lies on a loop: this is not reached.
            SweepVerdict::OpensLoop { connection: c, .. } => GroupVerdict::Unproven {
                distance: 0.0,
                modules: (index(c.from.0), index(c.to.0)),
            },
            SweepVerdict::Unproven { lower_bound, shoes } => GroupVerdict::Unproven {
                distance: lower_bound,
                modules: (index(shoes.0 .0), index(shoes.1 .0)),
            },
        })
    }

    fn configuration(&self) -> Option<Configuration> {
        Some(Configuration::new(self.robot.clone()))
    }

    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        Some(Configuration::new(self.robot))
    }

    fn difference(&self, other: &dyn RobotModel) -> Option<String> {
        model_difference(self, other)
    }

    fn clone_model(&self) -> Box<dyn RobotModel> {
        Box::new(self.clone())
    }

    fn network_presets(&self) -> &'static [dynarole_world::NetworkPreset] {
        crate::KIND.network_presets()
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
