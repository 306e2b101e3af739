//! What the worlds of robots built on `structure.rs` share: looking a module up by name, the latch operations
//! (extend/connect, retract/disconnect), the checks of a joint turn (its angles, the loop that
//! locks a joint, its sweep) and its outcome. They differ only in the connector rules
//! ([`RobotModule`]), in how a facing connector is found and in the geometry of a turn.

use crate::common::{Latch, Port};
use crate::geometry::{sweep_closest_approach, Vec3};
use crate::graph::{split_at_joint, split_parts, Sides};
use crate::ops::{OpError, Outcome, Warning};
use crate::structure::{RobotModule, Structure};
use std::collections::BTreeSet;

/// A configuration the latch operations work on.
pub trait Latching {
    /// The robot's module type.
    type Module: RobotModule;

    /// Modules and latches.
    fn structure(&self) -> &Structure<Self::Module>;

    /// Modules and latches, to add or remove a latch.
    fn structure_mut(&mut self) -> &mut Structure<Self::Module>;

    /// The connector `port` faces, or what the error message should say is there instead.
    fn facing_or_why(&self, port: Port) -> Result<Port, String>;
}

/// An outcome with one warning.
pub fn warn(warning: Warning) -> Outcome {
    Outcome {
        warnings: vec![warning],
        ..Outcome::default()
    }
}

/// Index of the module called `module`, or the error naming it.
pub fn known_module<M: RobotModule>(
    structure: &Structure<M>,
    module: &str,
) -> Result<usize, OpError> {
    structure
        .module_index(module)
        .ok_or_else(|| OpError::UnknownModule {
            module: module.to_string(),
        })
}

/// `extend`/`connect` (`action`): latches a male connector onto the free female connector
/// facing it. A connector already latched is reported and left as is.
pub fn latch<C: Latching>(
    config: &mut C,
    module: &str,
    connector: u8,
    action: &'static str,
) -> Result<Outcome, OpError> {
    let structure = config.structure();
    let port = male_port(structure, module, connector, action)?;
    if let Some(partner) = structure.latched_to(port) {
        return Ok(warn(Warning::AlreadyLatched {
            port: structure.port_name(port),
            partner: structure.port_name(partner),
        }));
    }
    let female = free_female(config, port)?;
    config.structure_mut().latch(Latch { male: port, female });
    Ok(Outcome::default())
}

/// `retract`/`disconnect` (`action`): releases the latch of a male connector. A connector with
/// no latch is reported, and so is a release that splits the robot in two.
pub fn release<M: RobotModule>(
    structure: &mut Structure<M>,
    module: &str,
    connector: u8,
    action: &'static str,
) -> Result<Outcome, OpError> {
    let port = male_port(structure, module, connector, action)?;
    let Some(female) = structure.latched_to(port) else {
        return Ok(warn(Warning::NothingLatched {
            port: structure.port_name(port),
        }));
    };
    structure.unlatch(Latch { male: port, female });
    Ok(
        match split_parts(structure.latches(), port.module, female.module) {
            None => Outcome::default(),
            Some((first, second)) => warn(Warning::Split {
                first: structure.module_names(&first),
                second: structure.module_names(&second),
            }),
        },
    )
}

/// The port of a male connector, or why it cannot be commanded (only the male side of a latch
/// acts).
fn male_port<M: RobotModule>(
    structure: &Structure<M>,
    module: &str,
    connector: u8,
    action: &'static str,
) -> Result<Port, OpError> {
    let index = known_module(structure, module)?;
    if connector >= M::CONNECTOR_COUNT {
        return Err(OpError::NoSuchConnector {
            module: module.to_string(),
            connector,
            count: M::CONNECTOR_COUNT,
        });
    }
    let port = Port {
        module: index,
        connector,
    };
    if !M::is_male(connector) {
        return Err(OpError::FemaleConnector {
            port: structure.port_name(port),
            action,
        });
    }
    Ok(port)
}

/// The free female connector facing `port`, or why there is none.
fn free_female<C: Latching>(config: &C, port: Port) -> Result<Port, OpError> {
    let structure = config.structure();
    let nothing = |reason: String| OpError::NothingToLatchOnto {
        port: structure.port_name(port),
        reason,
    };
    let other = config.facing_or_why(port).map_err(nothing)?;
    let other_name = structure.port_name(other);
    if C::Module::is_male(other.connector) {
        return Err(nothing(format!(
            "{other_name} faces it but is male; a latch needs {}",
            C::Module::FEMALE_CONNECTOR
        )));
    }
    if let Some(holder) = structure.latched_to(other) {
        return Err(nothing(format!(
            "{other_name} is already latched to {}",
            structure.port_name(holder)
        )));
    }
    Ok(other)
}

/// The two sides of the joints of module `index`, or the loop of latches that joins them and
/// locks the joint.
pub fn joint_sides<M: RobotModule>(
    structure: &Structure<M>,
    index: usize,
) -> Result<Sides, OpError> {
    split_at_joint(structure.latches(), index, M::is_north_side, |c| {
        !M::is_north_side(c)
    })
    .map_err(|loop_side| OpError::JointLocked {
        module: structure.module_name(index),
        loop_modules: structure.module_names(&loop_side),
    })
}

/// Checks that both angles of a turn of `module` are positions the joint can take (`legal`;
/// `rule` says which they are) and that the joint is at `from` now (`actual`).
pub fn check_turn_angles<A: Copy + PartialEq + Into<i32>>(
    module: String,
    (from, to): (A, A),
    actual: A,
    legal: impl Fn(A) -> bool,
    rule: &str,
) -> Result<(), OpError> {
    if let Some(angle) = [from, to].into_iter().find(|a| !legal(*a)) {
        return Err(OpError::InvalidAngle {
            module,
            angle: angle.into(),
            reason: rule.to_string(),
        });
    }
    if actual != from {
        return Err(OpError::WrongStartAngle {
            module,
            from: from.into(),
            actual: actual.into(),
        });
    }
    Ok(())
}

/// The outcome of a turn asked to go nowhere.
pub fn no_motion(module: &str) -> Outcome {
    warn(Warning::NoMotion {
        module: module.to_string(),
    })
}

/// The outcome of a turn done: the modules `moved` and the closest approach of the sweep.
pub fn turned<M: RobotModule>(
    structure: &Structure<M>,
    moved: &BTreeSet<usize>,
    closest_approach: Option<f64>,
) -> Outcome {
    Outcome {
        warnings: Vec::new(),
        moved: structure.module_names(moved),
        closest_approach,
    }
}

/// A point of the robot during a turn, the centre of a module or of one of its parts, with
/// the index of its module.
pub struct SweptPoint {
    pub module: usize,
    pub centre: [f64; 3],
}

/// A turn as the sweep check sees it: `quarters` signed quarter turns about `axis` through
/// `pivot`, the points that move and those that stay still, and the smallest distance
/// allowed between the two (`limit`).
pub struct Sweep {
    pub pivot: [f64; 3],
    pub axis: Vec3,
    pub quarters: i32,
    pub moving: Vec<SweptPoint>,
    pub still: Vec<SweptPoint>,
    pub limit: f64,
}

impl Sweep {
    /// The closest approach of the turn of module `index`, or the collision when it comes
    /// under the limit, naming the turning module and the moving and still ones of the
    /// closest pair.
    pub fn verdict<M: RobotModule>(
        &self,
        structure: &Structure<M>,
        index: usize,
    ) -> Result<Option<f64>, OpError> {
        let centres = |points: &[SweptPoint]| points.iter().map(|p| p.centre).collect::<Vec<_>>();
        let Some(approach) = sweep_closest_approach(
            self.pivot,
            self.axis.map(f64::from),
            90.0 * f64::from(self.quarters),
            &centres(&self.moving),
            &centres(&self.still),
        ) else {
            return Ok(None);
        };
        if approach.distance < self.limit {
            let name = |points: &[SweptPoint], i: usize| {
                points
                    .get(i)
                    .map(|p| structure.module_name(p.module))
                    .unwrap_or_default()
            };
            return Err(OpError::SweepCollision {
                module: structure.module_name(index),
                moving: name(&self.moving, approach.moving),
                still: name(&self.still, approach.still),
                distance: approach.distance,
                limit: self.limit,
                angle_deg: approach.angle_deg,
            });
        }
        Ok(Some(approach.distance))
    }
}
