//! Forward kinematics of RoFI universal modules: the pose of every shoe, placed along the
//! spanning tree of `tree.rs` and expressed with one pinned shoe at a given pose; every
//! connection the tree does not use must then close (a loop that does not close is an error
//! naming the connection). One unit is the distance between a module's two shoe centres and
//! between two mated shoes.

use crate::module::{Connection, RofiConfiguration, Side};
use crate::tree::{Shoe, Tree};
use nalgebra::{Matrix4, Point3};
use std::collections::BTreeMap;
use std::fmt;

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
    /// A loop that does not close: the connection that shows it, its two shoes, and by how
    /// much it misses (the largest difference of one matrix entry).
    LoopDoesNotClose {
        from: Shoe,
        to: Shoe,
        connection: Connection,
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
                connection: c,
                gap,
            } => write!(
                f,
                "a loop does not close: along the connection of module {} connector {} to \
                 module {} connector {}, shoe {:?} of module {} lands {gap:.3} away from where \
                 the rest of the robot puts it (from shoe {:?} of module {})",
                c.from.0, c.from.1, c.to.0, c.to.1, to.1, to.0, from.1, from.0
            ),
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
    if config.is_empty() {
        return Err(KinematicsError::Empty);
    }
    let tree = Tree::of(config).map_err(|unreached| KinematicsError::NotConnected {
        pinned: pinned.0,
        unreached,
    })?;
    let placed = tree.poses(&tree.modules);
    if let Some((connection, gap)) = tree.open_loop(&placed) {
        let end = |(id, c): (u32, crate::module::Connector)| (id, c.side());
        return Err(KinematicsError::LoopDoesNotClose {
            from: end(connection.from),
            to: end(connection.to),
            connection,
            gap,
        });
    }
    let Some(at) = tree.shoe_index(pinned) else {
        let unreached = tree.modules.iter().map(|m| m.id).collect();
        return Err(KinematicsError::NotConnected {
            pinned: pinned.0,
            unreached,
        });
    };
    // The tree places its root at the identity: move everything so that `pinned` is at `pose`.
    let rebase = pose * rigid_inverse(&placed[at]);
    let shoes = (placed.iter().enumerate())
        .map(|(i, p)| (tree.shoe_of(i), rebase * p))
        .collect();
    Ok(Poses { shoes })
}

/// The inverse of a rigid transform: the rotation transposed, the translation undone.
fn rigid_inverse(pose: &Matrix4<f64>) -> Matrix4<f64> {
    let rotation = pose.fixed_view::<3, 3>(0, 0).transpose();
    let translation = -(rotation * pose.fixed_view::<3, 1>(0, 3));
    let mut inverse = Matrix4::identity();
    inverse.fixed_view_mut::<3, 3>(0, 0).copy_from(&rotation);
    inverse.fixed_view_mut::<3, 1>(0, 3).copy_from(&translation);
    inverse
}
