//! How an ATRON module is drawn: two hemispheres sharing the module's centre, the north one
//! (part 0) with its dome against the axis, and its connectors half-way to the sites they
//! face (lattice units).

use crate::config::AtronConfiguration;
use dynarole_world::geometry::to_f64;
use dynarole_world::{Drawing, ModulePose, PartLook, PartPose, Picture, Ring, RobotShape, Solid};

impl AtronConfiguration {
    /// Every module's hemispheres and connector faces.
    pub fn poses(&self) -> Vec<ModulePose> {
        let connectors = RobotShape::connectors(self);
        self.modules()
            .iter()
            .map(|m| {
                let centre = to_f64(m.position);
                let axis = to_f64(m.orientation.axis());
                // The axis points from the north hemisphere (part 0) to the south one.
                let north = PartPose {
                    centre,
                    up: axis.map(|v| -v),
                };
                let south = PartPose { centre, up: axis };
                let connectors = (0..connectors)
                    .map(|k| {
                        let offset = m.connector_offset(k).map_or([0.0; 3], to_f64);
                        std::array::from_fn(|i| centre[i] + offset[i] / 2.0)
                    })
                    .collect();
                ModulePose {
                    parts: vec![north, south],
                    connectors,
                }
            })
            .collect()
    }
}

/// Drawn radius of a hemisphere in 3D, in lattice units.
const DOME_RADIUS: f64 = 0.48;

/// Drawn radius of a module in the flat picture, in lattice units (smaller than the real 0.69
/// so that neighbours seen at a slant stay apart).
const PICTURE_RADIUS: f64 = 0.36;

/// Two hemispheres, north blue and south orange (the colours of the module's own shells),
/// with the joint ring between them.
pub(crate) fn drawing() -> Drawing {
    let dome = Solid::Dome {
        radius: DOME_RADIUS,
    };
    Drawing {
        parts: vec![
            PartLook {
                colour: [52, 120, 190],
                legend: "north hemisphere (connectors 0-3)".into(),
                solid: dome,
            },
            PartLook {
                colour: [240, 145, 30],
                legend: "south hemisphere (connectors 4-7)".into(),
                solid: dome,
            },
        ],
        joint_ring: Some(Ring {
            radius: 0.485,
            tube: 0.025,
        }),
        picture: Picture::SplitDisc {
            radius: PICTURE_RADIUS,
        },
    }
}
