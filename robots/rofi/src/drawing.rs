//! How a RoFI module is drawn: its two shoes (part 0 shoe A, part 1 shoe B) as cubes, their
//! up axes the shoes' own Z axes (towards the module's other half), the bodies and the gamma
//! joint between them as the bar that joins the shoes, and the six connector faces, in module
//! units.

use crate::module::{Connector, Side};
use crate::robot::{poses_of, RofiRobot};
use crate::turn::face_centre;
use dynarole_world::{Drawing, ModulePose, PartLook, PartPose, Picture, Solid};

/// Drawn edge of a shoe, in module units (mated shoes are one unit apart).
const SHOE_EDGE: f64 = 0.8;

/// Drawn half-size of a shoe in the flat picture.
const PICTURE_HALF_SHOE: f64 = 0.3;

impl RofiRobot {
    /// Every module's shoes and connector faces; none for a configuration without poses.
    pub fn poses(&self) -> Vec<ModulePose> {
        let Some(poses) = poses_of(self.configuration()) else {
            return Vec::new();
        };
        let module_pose = |id: u32| {
            let shoe = |side: Side| poses.pose((id, side)).copied().unwrap_or_default();
            let part = |side: Side| {
                let pose = shoe(side);
                PartPose {
                    centre: [pose[(0, 3)], pose[(1, 3)], pose[(2, 3)]],
                    up: [pose[(0, 2)], pose[(1, 2)], pose[(2, 2)]],
                }
            };
            let connectors = (0..Connector::COUNT)
                .filter_map(Connector::from_index)
                .map(|c| {
                    let face = face_centre(&shoe(c.side()), c);
                    [face.x, face.y, face.z]
                })
                .collect();
            ModulePose {
                parts: vec![part(Side::A), part(Side::B)],
                connectors,
            }
        };
        self.configuration()
            .modules()
            .map(|m| module_pose(m.id))
            .collect()
    }
}

/// Shoe A blue (connectors 0-2), shoe B orange (3-5), joined by the bodies' bar.
pub(crate) fn drawing() -> Drawing {
    let shoe = Solid::Cube { edge: SHOE_EDGE };
    Drawing {
        parts: vec![
            PartLook {
                colour: [52, 120, 190],
                legend: "shoe A (connectors 0-2, joint alpha)".into(),
                solid: shoe,
            },
            PartLook {
                colour: [240, 145, 30],
                legend: "shoe B (connectors 3-5, joint beta); grey bar: the bodies and gamma"
                    .into(),
                solid: shoe,
            },
        ],
        joint_ring: None,
        picture: Picture::LinkedCubes {
            half: PICTURE_HALF_SHOE,
        },
    }
}
