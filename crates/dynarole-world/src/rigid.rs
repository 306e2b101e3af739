//! A configuration reduced to what a rigid motion acts on (each module's position, frame and
//! joints, and the connections), which `compare.rs` matches up to a rigid motion; each robot
//! gives its own (`RobotConfiguration::rigid_shape`).

use crate::common::NamedConnection;
use crate::geometry::{Rotation, Vec3};
use crate::structure::{RobotModule, Structure};
use std::collections::{BTreeMap, BTreeSet};

/// A module reduced to what a rigid motion acts on.
pub struct Body {
    pub id: Option<u32>,
    pub position: Vec3,
    pub frame: Rotation,
    pub joints: Vec<i32>,
}

/// A robot's configuration reduced to bodies and connections.
pub struct Shape {
    pub bodies: BTreeMap<String, Body>,
    pub connections: BTreeSet<String>,
    pub name_frame: fn(Rotation) -> String,
    /// Internal position units per file unit (2 where positions are kept in halves).
    pub position_scale: i32,
    /// Positions are where the robot stands (a lattice robot's cells, which its moves change
    /// exactly): compared as they are, not up to a rigid motion.
    pub anchored: bool,
    /// The configuration with its modules' names left out, where the robot can say it.
    pub unnamed: Option<Unnamed>,
}

/// A configuration without names: what a file that names no module (a planner's anonymous
/// world) can be compared by.
pub struct Unnamed {
    /// The robot's description of the configuration in a form that neither the modules'
    /// names nor a rigid motion change: two configurations are the same shape when their
    /// forms are equal.
    pub form: String,
    /// The file names no module: this configuration is compared by its form alone.
    pub anonymous: bool,
}

fn connection_names(connections: Vec<NamedConnection>) -> BTreeSet<String> {
    connections
        .into_iter()
        .map(|(a, ca, b, cb)| format!("{a}.C{ca}-{b}.C{cb}"))
        .collect()
}

/// A robot's modules reduced by `body`, keyed by name, and its connections.
pub fn shape_of<M: RobotModule>(
    structure: &Structure<M>,
    body: fn(&M) -> Body,
    name_frame: fn(Rotation) -> String,
    position_scale: i32,
) -> Shape {
    Shape {
        bodies: structure
            .modules()
            .iter()
            .map(|m| (m.name().to_string(), body(m)))
            .collect(),
        connections: connection_names(structure.named_connections()),
        name_frame,
        position_scale,
        anchored: false,
        unnamed: None,
    }
}
