//! How a cube is drawn: one part, a cube at its cell (its up axis +z, which a cube's pose
//! never turns: a move ends at a cell, and the viewer turns it along the move's motion), and
//! its six faces as connectors, in cube edges.

use crate::lattice::Dir;
use crate::robot::CubesRobot;
use dynarole_world::{Drawing, ModulePose, PartLook, PartPose, Picture, Solid};

/// Drawn edge of a cube, in cube edges: a gap shows where two cubes meet.
const DRAWN_EDGE: f64 = 0.92;

impl CubesRobot {
    /// Every cube at its cell, with its faces.
    pub fn poses(&self) -> Vec<ModulePose> {
        (self.cubes().iter())
            .map(|cube| {
                let centre = cube.position.map(f64::from);
                let mut connectors: Vec<[f64; 3]> = (Dir::ALL.iter())
                    .map(|d| std::array::from_fn(|k| centre[k] + f64::from(d.vector()[k]) / 2.0))
                    .collect();
                // The ground's wiring comes out of the cube's bottom.
                let bottom = [centre[0], centre[1], centre[2] - 0.5];
                connectors.extend([bottom, bottom]);
                ModulePose {
                    parts: vec![PartPose {
                        centre,
                        up: [0.0, 0.0, 1.0],
                    }],
                    connectors,
                }
            })
            .collect()
    }
}

/// One grey-blue cube per module.
pub(crate) fn drawing() -> Drawing {
    Drawing {
        parts: vec![PartLook {
            colour: [90, 140, 200],
            legend: "a cube (its six faces are its connectors)".into(),
            solid: Solid::Cube { edge: DRAWN_EDGE },
        }],
        joint_ring: None,
        picture: Picture::LinkedCubes {
            half: DRAWN_EDGE / 2.0,
        },
    }
}
