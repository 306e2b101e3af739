//! ATRON behind the robot API: the configuration answers [`RobotShape`], the [`World`]
//! is the [`RobotModel`] (one joint per module, angles in 1/432 turn).

use crate::config::{AtronConfiguration, AtronModule};
use crate::lattice::{JOINT_UNITS_PER_TURN, QUARTER_TURN_UNITS};
use crate::world::World;
use dynarole_world::geometry::to_f64;
use dynarole_world::model_difference;
use dynarole_world::Configuration;
use dynarole_world::Motion;
use dynarole_world::{Action, RobotKind, RobotModel, RobotShape, SweepCheck};
use dynarole_world::{OpError, Outcome};
use std::any::Any;

dynarole_world::robot_shape!(AtronConfiguration, AtronModule, joint_angle);

/// ATRON has one joint; every joint index reads it.
fn joint_angle(module: &AtronModule, _joint: u8) -> Option<i64> {
    Some(i64::from(module.joint_units))
}

impl RobotModel for World {
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
            Action::Extend { connector } => self.extend(module, connector),
            Action::Retract { connector } => self.retract(module, connector),
            Action::Turn {
                from,
                to,
                increasing,
                ..
            } => {
                let from = self.joint_from(module, from);
                self.rotate_swept(module, (from, units(to), increasing), sweep)
            }
            Action::Move { .. } => Err(action.unsupported(module)),
        }
    }

    fn motion(&self, module: &str, action: &Action) -> Option<Motion> {
        match *action {
            // The hooks move inside the module: nothing the sweep or the drawing sees.
            Action::Extend { .. } | Action::Retract { .. } => {
                self.shape().index(module).map(|_| Motion::in_place())
            }
            Action::Turn {
                from,
                to,
                increasing,
                ..
            } => {
                let from = self.joint_from(module, from);
                World::turn_motion(self, module, from, units(to), increasing).ok()
            }
            Action::Move { .. } => None,
        }
    }

    fn quarter_turns(&self, from: i64, to: i64, increasing: bool) -> u64 {
        quarter_turns(from, to, increasing)
    }

    fn length_unit(&self) -> &str {
        "lattice units"
    }

    fn rigid_module_centres(&self) -> Option<Vec<[f64; 3]>> {
        let modules = self.configuration().modules();
        Some(modules.iter().map(|m| to_f64(m.position)).collect())
    }

    fn configuration(&self) -> Option<Configuration> {
        Some(Configuration::new(World::configuration(self).clone()))
    }

    fn into_configuration(self: Box<Self>) -> Option<Configuration> {
        Some(Configuration::new(World::into_configuration(*self)))
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

impl World {
    /// The start angle of a turn: the given one, or the joint's angle now.
    fn joint_from(&self, module: &str, from: Option<i64>) -> u16 {
        match from {
            Some(angle) => units(angle),
            None => {
                let config = self.configuration();
                config
                    .module_index(module)
                    .and_then(|i| config.module(i))
                    .map_or(0, |m| m.joint_units)
            }
        }
    }
}

/// An angle the plugin range-checked; anything else becomes one the world refuses.
fn units(angle: i64) -> u16 {
    u16::try_from(angle).unwrap_or(u16::MAX)
}

/// Quarter turns of a joint from `from` to `to` (1/432 turn units). The joint wraps:
/// `(0, 108, false)` is three quarter turns.
pub(crate) fn quarter_turns(from: i64, to: i64, increasing: bool) -> u64 {
    let full = i64::from(JOINT_UNITS_PER_TURN);
    let quarter = i64::from(QUARTER_TURN_UNITS);
    let delta = if increasing {
        (to - from).rem_euclid(full)
    } else {
        (from - to).rem_euclid(full)
    };
    u64::try_from((delta + quarter - 1) / quarter).unwrap_or(0)
}
