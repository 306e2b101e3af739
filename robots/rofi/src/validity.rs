//! The validity RoFI asks of a configuration: connected, every loop closed (`kinematics.rs`)
//! and no two shoes overlapping, shoes being unit-diameter spheres at their centres.

use crate::kinematics::{poses, KinematicsError, Poses};
use crate::module::RofiConfiguration;
use crate::tree::Shoe;
use std::fmt;

/// Two shoes overlap when their centres are closer than this squared (in units²): one unit,
/// less RoFI's rounding of the squared distance to three decimals (0.9995 rounds to 1).
pub const COLLISION_DISTANCE_SQUARED: f64 = 0.9995;

/// Two shoes that overlap, and how far apart their centres are.
#[derive(Clone, Debug, PartialEq)]
pub struct Collision {
    pub shoes: (Shoe, Shoe),
    pub distance: f64,
}

/// Why a configuration is not valid.
#[derive(Clone, Debug, PartialEq)]
pub enum Invalid {
    Kinematics(KinematicsError),
    Collision(Collision),
}

impl fmt::Display for Invalid {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Invalid::Kinematics(e) => e.fmt(f),
            Invalid::Collision(Collision {
                shoes: (a, b),
                distance,
            }) => write!(
                f,
                "shoe {:?} of module {} and shoe {:?} of module {} overlap: their centres are \
                 {distance:.3} apart, under 1",
                a.1, a.0, b.1, b.0
            ),
        }
    }
}

/// The shoes' poses of a valid configuration, or the first rule it breaks.
pub fn validate(config: &RofiConfiguration) -> Result<Poses, Invalid> {
    let poses = poses(config).map_err(Invalid::Kinematics)?;
    match first_collision(&poses) {
        Some(collision) => Err(Invalid::Collision(collision)),
        None => Ok(poses),
    }
}

/// The first pair of shoes (in shoe order) whose spheres overlap. A module's own two shoes are
/// compared too, as RoFI does (they are always one unit apart).
pub fn first_collision(poses: &Poses) -> Option<Collision> {
    let centres: Vec<(Shoe, nalgebra::Point3<f64>)> = poses.centres().collect();
    for (i, (a, pa)) in centres.iter().enumerate() {
        for (b, pb) in &centres[i + 1..] {
            let squared = (pa - pb).norm_squared();
            if squared < COLLISION_DISTANCE_SQUARED {
                return Some(Collision {
                    shoes: (*a, *b),
                    distance: squared.sqrt(),
                });
            }
        }
    }
    None
}
