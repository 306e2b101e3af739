//! Forward kinematics of RoFI universal modules: the pose of every shoe, found from one pinned
//! shoe along the module joints and the connections, every relation not used to place a shoe
//! then checked to close (a loop that does not close is an error, whichever edge shows it).
//!
//! Frames are RoFI's legacy ones (the numbers of `module.rs`), one unit being the distance
//! between a module's two shoe centres and between two mated shoes. From a shoe, the module's
//! other shoe is Rx(near)·Rz(γ)·T(0,0,1)·Ry(π)·Rx(−far), with (near, far) = (α, β) from shoe
//! A and (β, α) from shoe B; across a connection from dock d1 to dock d2 with twist o, the
//! partner's shoe is face(d1)·Rz(o·90°)·T(0,0,−1)·up(d2)·Rx(π), where face and up turn a
//! dock's face onto the shoe's −Z (±X docks: Rz(π)·Ry(±90°), −Z: none).

use crate::module::{Connection, Connector, Dock, Module, RofiConfiguration, Side};
use nalgebra::{Matrix4, Point3, Rotation3, Translation3, Unit, Vector3};
use std::collections::{BTreeMap, VecDeque};
use std::f64::consts::{FRAC_PI_2, PI};
use std::fmt;

/// How far (largest difference of one matrix entry) a shoe's pose found along a loop may be
/// from the pose it already has for the loop to count as closed: RoFI's legacy tolerance.
pub const LOOP_TOLERANCE: f64 = 1e-3;

/// A shoe: its module's ID and its side.
pub type Shoe = (u32, Side);

/// The pose of every shoe of a connected configuration, the pinned shoe at the identity.
#[derive(Clone, Debug)]
pub struct Poses {
    shoes: BTreeMap<Shoe, Matrix4<f64>>,
}

impl Poses {
    pub fn pose(&self, shoe: Shoe) -> Option<&Matrix4<f64>> {
        self.shoes.get(&shoe)
    }

    /// A shoe's centre, in units.
    pub fn centre(&self, shoe: Shoe) -> Option<Point3<f64>> {
        self.pose(shoe).map(centre_of)
    }

    /// Every shoe's centre, in shoe order (module ID, then side).
    pub fn centres(&self) -> impl Iterator<Item = (Shoe, Point3<f64>)> + '_ {
        self.shoes
            .iter()
            .map(|(shoe, pose)| (*shoe, centre_of(pose)))
    }
}

/// The centre of a shoe at `pose`.
pub(crate) fn centre_of(pose: &Matrix4<f64>) -> Point3<f64> {
    Point3::new(pose[(0, 3)], pose[(1, 3)], pose[(2, 3)])
}

/// Why the shoes of a configuration have no poses.
#[derive(Clone, Debug, PartialEq)]
pub enum KinematicsError {
    /// No module at all.
    Empty,
    /// Modules no connection path reaches from the pinned one.
    NotConnected { pinned: u32, unreached: Vec<u32> },
    /// A loop that does not close: the relation that shows it (a connection, or the module's
    /// own joints when `connection` is `None`) and by how much it misses.
    LoopDoesNotClose {
        from: Shoe,
        to: Shoe,
        connection: Option<Connection>,
        gap: f64,
    },
}

impl fmt::Display for KinematicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KinematicsError::Empty => write!(f, "the configuration has no module"),
            KinematicsError::NotConnected { pinned, unreached } => {
                let ids: Vec<String> = unreached.iter().map(u32::to_string).collect();
                write!(
                    f,
                    "the robot is not connected: no connection reaches module{} {} from module {pinned}",
                    if ids.len() == 1 { "" } else { "s" },
                    ids.join(", ")
                )
            }
            KinematicsError::LoopDoesNotClose {
                from,
                to,
                connection,
                gap,
            } => {
                let via = match connection {
                    Some(c) => format!(
                        "the connection of module {} connector {} to module {} connector {}",
                        c.from.0, c.from.1, c.to.0, c.to.1
                    ),
                    None => format!("module {}'s joints", from.0),
                };
                write!(
                    f,
                    "a loop does not close: along {via}, shoe {:?} of module {} lands {gap:.3} \
                     away from where the rest of the robot puts it (from shoe {:?} of module {})",
                    to.1, to.0, from.1, from.0
                )
            }
        }
    }
}

/// The poses of every shoe, shoe A of the lowest-ID module pinned at the identity (RoFI's
/// legacy convention).
pub fn poses(config: &RofiConfiguration) -> Result<Poses, KinematicsError> {
    let first = config.modules().next().ok_or(KinematicsError::Empty)?;
    poses_from(config, (first.id, Side::A), Matrix4::identity())
}

/// The poses of every shoe with `pinned` at `pose`.
pub fn poses_from(
    config: &RofiConfiguration,
    pinned: Shoe,
    pose: Matrix4<f64>,
) -> Result<Poses, KinematicsError> {
    let mut shoes = BTreeMap::from([(pinned, pose)]);
    let mut queue = VecDeque::from([pinned]);
    while let Some(shoe) = queue.pop_front() {
        // Every queued shoe was placed before it was queued.
        let Some(here) = shoes.get(&shoe).copied() else {
            continue;
        };
        for (next, step, connection) in relations(config, shoe) {
            let there = here * step;
            match shoes.get(&next) {
                None => {
                    shoes.insert(next, there);
                    queue.push_back(next);
                }
                Some(placed) => {
                    let gap = (placed - there).abs().max();
                    if gap > LOOP_TOLERANCE {
                        let (from, to) = (shoe, next);
                        return Err(KinematicsError::LoopDoesNotClose {
                            from,
                            to,
                            connection,
                            gap,
                        });
                    }
                }
            }
        }
    }
    let unreached: Vec<u32> = (config.modules())
        .map(|m| m.id)
        .filter(|id| !shoes.contains_key(&(*id, Side::A)))
        .collect();
    if !unreached.is_empty() {
        return Err(KinematicsError::NotConnected {
            pinned: pinned.0,
            unreached,
        });
    }
    Ok(Poses { shoes })
}

/// What a shoe is rigidly related to: its module's other shoe (through the joints) and the
/// shoe of each connection on its connectors, with the transform from it.
fn relations(
    config: &RofiConfiguration,
    (id, side): Shoe,
) -> Vec<(Shoe, Matrix4<f64>, Option<Connection>)> {
    let mut out = Vec::new();
    if let Some(module) = config.module(id) {
        out.push(((id, side.other()), across_module(module, side), None));
    }
    for dock in Dock::ALL {
        if let Some(c) = config.connection_at((id, Connector::new(side, dock))) {
            let step = across_connection(dock, c.orientation.quarter_turns(), c.to.1.dock());
            out.push(((c.to.0, c.to.1.side()), step, Some(c)));
        }
    }
    out
}

/// From shoe `from` of `module` to its other shoe.
pub fn across_module(module: &Module, from: Side) -> Matrix4<f64> {
    let (near, far) = match from {
        Side::A => (module.alpha, module.beta),
        Side::B => (module.beta, module.alpha),
    };
    rotation(Vector3::x(), near.to_radians())
        * rotation(Vector3::z(), module.gamma.to_radians())
        * translation(Vector3::z())
        * rotation(Vector3::y(), PI)
        * rotation(Vector3::x(), -far.to_radians())
}

/// From a shoe to the shoe mated at its dock `from` (partner's dock `to`, twist in quarter
/// turns).
pub fn across_connection(from: Dock, quarter_turns: u8, to: Dock) -> Matrix4<f64> {
    face_to_dock(from)
        * rotation(Vector3::z(), f64::from(quarter_turns) * FRAC_PI_2)
        * translation(-Vector3::z())
        * dock_face_up(to)
        * rotation(Vector3::x(), PI)
}

/// Turns the shoe's −Z face onto dock `dock`'s face (the way out of the shoe).
fn face_to_dock(dock: Dock) -> Matrix4<f64> {
    match dock {
        Dock::PlusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), FRAC_PI_2),
        Dock::MinusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), -FRAC_PI_2),
        Dock::MinusZ => Matrix4::identity(),
    }
}

/// Turns dock `dock`'s face onto the shoe's −Z face (the way into the partner's shoe).
fn dock_face_up(dock: Dock) -> Matrix4<f64> {
    match dock {
        Dock::PlusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), -FRAC_PI_2),
        Dock::MinusX => rotation(Vector3::z(), PI) * rotation(Vector3::y(), FRAC_PI_2),
        Dock::MinusZ => Matrix4::identity(),
    }
}

fn rotation(axis: Vector3<f64>, radians: f64) -> Matrix4<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), radians).to_homogeneous()
}

fn translation(by: Vector3<f64>) -> Matrix4<f64> {
    Translation3::from(by).to_homogeneous()
}
