//! M-TRAN behind the robot API: the configuration answers [`RobotShape`], the
//! [`MtranWorld`] is the [`RobotModel`] (two joints, angles in degrees, no wrapping).

use crate::module::{MtranConfiguration, MtranJoint, MtranModule};
use crate::world::MtranWorld;
use dynarole_world::model_difference;
use dynarole_world::Configuration;
use dynarole_world::Motion;
use dynarole_world::{Action, RobotKind, RobotModel, RobotShape, SweepCheck};
use dynarole_world::{OpError, Outcome};
use std::any::Any;

/// Degrees in a quarter turn.
const QUARTER_DEG: i64 = 90;

dynarole_world::robot_shape!(MtranConfiguration, MtranModule, joint_angle);

/// Joint `joint` (0 north, 1 south) in degrees.
fn joint_angle(module: &MtranModule, joint: u8) -> Option<i64> {
    module
        .joints_deg
        .get(usize::from(joint))
        .map(|d| i64::from(*d))
}

impl RobotModel for MtranWorld {
    fn robot(&self) -> &str {
        crate::KIND.name()
    }

    fn shape(&self) -> &dyn RobotShape {
        self.configuration()
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
            } => {
                let from = self.joint_from(module, joint, from);
                let angles = (from, degrees(to), increasing);
                self.rotate_swept(module, mtran_joint(joint), angles, sweep)
            }
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
            // A connector's latch moves inside its block: nothing the sweep or the drawing sees.
            return self.shape().index(module).map(|_| Motion::in_place());
        };
        let from = self.joint_from(module, joint, from);
        MtranWorld::turn_motion(
            self,
            module,
            mtran_joint(joint),
            from,
            degrees(to),
            increasing,
        )
        .ok()
    }

    fn quarter_turns(&self, from: i64, to: i64, _increasing: bool) -> u64 {
        quarter_turns(from, to)
    }

    fn length_unit(&self) -> &str {
        "block pitches"
    }

    /// Both blocks of every module, in block pitches: what its turns' sweeps are checked with.
    fn sweep_points(&self) -> Option<Vec<(usize, [f64; 3])>> {
        let modules = MtranWorld::configuration(self).modules();
        let blocks = modules
            .iter()
            .enumerate()
            .flat_map(|(i, m)| m.block_centres().map(|b| (i, crate::world::pitches(b))));
        Some(blocks.collect())
    }

    fn configuration(&self) -> Option<Configuration> {
        Some(Configuration::new(MtranWorld::configuration(self).clone()))
    }

    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        Some(Configuration::new(MtranWorld::into_configuration(*self)))
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

impl MtranWorld {
    /// The start angle of a turn: the given one, or the joint's angle now.
    fn joint_from(&self, module: &str, joint: u8, from: Option<i64>) -> i16 {
        match from {
            Some(angle) => degrees(angle),
            None => {
                let config = self.configuration();
                let index = config.module_index(module);
                let now = index.and_then(|m| RobotShape::joint(config, m, joint));
                degrees(now.unwrap_or(0))
            }
        }
    }
}

/// Joint 0 is the north one, 1 the south one (the plugin allows no other index).
fn mtran_joint(index: u8) -> MtranJoint {
    if index == 0 {
        MtranJoint::North
    } else {
        MtranJoint::South
    }
}

/// An angle the plugin range-checked; anything else becomes one the world refuses.
fn degrees(angle: i64) -> i16 {
    i16::try_from(angle).unwrap_or(i16::MAX)
}

/// Quarter turns of a joint from `from` to `to` (degrees). The joint does not wrap: the turn
/// is the difference of the angles.
pub(crate) fn quarter_turns(from: i64, to: i64) -> u64 {
    let delta = (to - from).abs();
    u64::try_from((delta + QUARTER_DEG - 1) / QUARTER_DEG).unwrap_or(0)
}
