//! What the ATRON and M-TRAN worlds share: looking a module up by name, the latch operations
//! (extend/connect, retract/disconnect) and the verdict on a joint turn's sweep. They differ
//! only in the connector rules ([`RobotModule`]) and in how a facing connector is found.

use crate::common::{Latch, Port};
use crate::geometry::SweepApproach;
use crate::graph::split_parts;
use crate::ops::{OpError, Outcome, Warning};
use crate::structure::{RobotModule, Structure};

/// A configuration the latch operations work on.
pub(crate) trait Latching {
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
pub(crate) fn warn(warning: Warning) -> Outcome {
    Outcome {
        warnings: vec![warning],
        ..Outcome::default()
    }
}

/// Index of the module called `module`, or the error naming it.
pub(crate) fn known_module<M: RobotModule>(
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
pub(crate) fn latch<C: Latching>(
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
pub(crate) fn release<M: RobotModule>(
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

/// The closest approach of a turn, or the collision when it comes under `limit`; `culprits`
/// names the turning module and the moving and still ones of the closest pair, for the error.
pub(crate) fn sweep_verdict(
    approach: Option<SweepApproach>,
    limit: f64,
    culprits: impl FnOnce(&SweepApproach) -> [String; 3],
) -> Result<Option<f64>, OpError> {
    let Some(approach) = approach else {
        return Ok(None);
    };
    if approach.distance < limit {
        let [module, moving, still] = culprits(&approach);
        return Err(OpError::SweepCollision {
            module,
            moving,
            still,
            distance: approach.distance,
            limit,
            angle_deg: approach.angle_deg,
        });
    }
    Ok(Some(approach.distance))
}
