//! How an M-TRAN module is drawn: its two blocks (part 0 the north one) with the joint axis
//! as their up direction, and its connector faces, in block pitches.

use crate::module::MtranConfiguration;
use dynarole_world::geometry::to_f64;
use dynarole_world::{Drawing, ModulePose, PartLook, PartPose, Picture, RobotShape, Solid};

impl MtranConfiguration {
    /// Every module's blocks and connector faces.
    pub fn poses(&self) -> Vec<ModulePose> {
        let connectors = RobotShape::connectors(self);
        self.modules()
            .iter()
            .map(|m| {
                let pitch = |v: [i32; 3]| to_f64(v).map(|x| x / 2.0);
                let up = to_f64(m.joint_axis());
                let [n, s] = m.block_centres().map(pitch);
                let connectors = (0..connectors)
                    .map(|k| {
                        m.connector(k)
                            .map_or([0.0; 3], |p| pitch(p.face_quarter_pitch))
                    })
                    .collect();
                ModulePose {
                    parts: vec![PartPose { centre: n, up }, PartPose { centre: s, up }],
                    connectors,
                }
            })
            .collect()
    }
}

/// Drawn edge of a block in 3D, in block pitches.
const BLOCK_EDGE: f64 = 0.9;

/// Drawn half-size of a block in the flat picture, in block pitches.
const PICTURE_HALF_BLOCK: f64 = 0.36;

/// Two blocks, north blue (the male connectors) and south orange, joined by the link.
pub(crate) fn drawing() -> Drawing {
    let block = Solid::Cube { edge: BLOCK_EDGE };
    Drawing {
        parts: vec![
            PartLook {
                colour: [52, 120, 190],
                legend: "north block (male connectors 0-2)".into(),
                solid: block,
            },
            PartLook {
                colour: [240, 145, 30],
                legend: "south block (female connectors 3-5); grey bar: the module's link".into(),
                solid: block,
            },
        ],
        joint_ring: None,
        picture: Picture::LinkedCubes {
            half: PICTURE_HALF_BLOCK,
        },
    }
}
