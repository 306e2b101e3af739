//! How a hinged cube is drawn: part 0 its hinged front face (the male connector's side, which
//! the hinge turns), part 1 its body (the female back connector's side), in cube edges, the
//! chain's plane at z = 0.

use super::configuration::{CubesConfiguration, BACK, FRONT};
use dynarole_world::{Drawing, ModulePose, PartLook, PartPose, Picture, Solid};

/// Drawn edge of a cube's body, in cube edges (a gap shows where two cubes meet).
const BODY_EDGE: f64 = 0.8;
/// Drawn edge of the hinged front face's block.
const FACE_EDGE: f64 = 0.3;
/// How far the front face's block sits from the body's centre, towards the front.
const FACE_OFFSET: f64 = 0.35;
/// Drawn half-size of a part in the flat picture.
const PICTURE_HALF: f64 = 0.2;

/// Up, out of the chain's plane.
const UP: [f64; 3] = [0.0, 0.0, 1.0];

impl CubesConfiguration {
    /// Every cube's front face and body, and its two connector faces.
    pub fn poses(&self) -> Vec<ModulePose> {
        (0..self.cubes.len()).map(|m| self.pose(m)).collect()
    }

    fn pose(&self, m: usize) -> ModulePose {
        let cell = self.cubes[m].cell;
        let centre = [f64::from(cell[0]), f64::from(cell[1]), 0.0];
        let towards = |connector: u8, distance: f64| {
            let d = self.direction(m, connector).unwrap_or([0, 0]);
            [
                centre[0] + distance * f64::from(d[0]),
                centre[1] + distance * f64::from(d[1]),
                0.0,
            ]
        };
        ModulePose {
            parts: vec![
                PartPose {
                    centre: towards(FRONT, FACE_OFFSET),
                    up: UP,
                },
                PartPose { centre, up: UP },
            ],
            connectors: vec![towards(FRONT, 0.5), towards(BACK, 0.5)],
        }
    }
}

/// A small green block for the hinged front face, a grey cube for the body.
pub(super) fn drawing() -> Drawing {
    Drawing {
        parts: vec![
            PartLook {
                colour: [60, 160, 90],
                legend: "hinged front face (male connector 0)".into(),
                solid: Solid::Cube { edge: FACE_EDGE },
            },
            PartLook {
                colour: [150, 150, 160],
                legend: "cube body (female back connector 1)".into(),
                solid: Solid::Cube { edge: BODY_EDGE },
            },
        ],
        joint_ring: None,
        picture: Picture::LinkedCubes { half: PICTURE_HALF },
    }
}
