//! A configuration reduced to what a rigid motion acts on (each module's position, frame and
//! joints, and the connections), which `compare.rs` matches up to a rigid motion; each robot
//! gives its own (`AtronConfiguration::rigid_shape`, `MtranConfiguration::rigid_shape`).

use crate::common::NamedConnection;
use crate::geometry::{Rotation, Vec3};
use crate::structure::{RobotModule, Structure};
use std::collections::{BTreeMap, BTreeSet};

/// A module reduced to what a rigid motion acts on.
pub(crate) struct Body {
    pub(crate) id: Option<u32>,
    pub(crate) position: Vec3,
    pub(crate) frame: Rotation,
    pub(crate) joints: Vec<i32>,
}

/// A robot's configuration reduced to bodies and connections.
pub(crate) struct Shape {
    pub(crate) bodies: BTreeMap<String, Body>,
    pub(crate) connections: BTreeSet<String>,
    pub(crate) name_frame: fn(Rotation) -> String,
    /// Internal position units per file unit (1 for ATRON, 2 for M-TRAN quarter pitches).
    pub(crate) position_scale: i32,
}

fn connection_names(connections: Vec<NamedConnection>) -> BTreeSet<String> {
    connections
        .into_iter()
        .map(|(a, ca, b, cb)| format!("{a}.C{ca}-{b}.C{cb}"))
        .collect()
}

/// A robot's modules reduced by `body`, keyed by name, and its connections.
pub(crate) fn shape_of<M: RobotModule>(
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
    }
}
