//! Where a module's rigid parts are, as its robot places them: what a recording, `show` and
//! the viewer draw. A module is a list of rigid parts (a module of two hemispheres has two,
//! a cube one), each with a centre and the direction its up axis points,
//! and its connectors' faces; positions are in the robot's drawing unit.

use serde::{Deserialize, Serialize};

/// One rigid part of a module, placed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartPose {
    pub centre: [f64; 3],
    /// The direction the part's own up axis points (a unit vector).
    pub up: [f64; 3],
}

/// One module, placed: its parts in the robot's part order and its connectors' faces, by
/// connector number. Its centre is the mean of its parts' centres.
#[derive(Clone, Debug, PartialEq)]
pub struct ModulePose {
    pub parts: Vec<PartPose>,
    pub connectors: Vec<[f64; 3]>,
}

impl ModulePose {
    /// The mean of the parts' centres.
    pub fn centre(&self) -> [f64; 3] {
        mean_centre(&self.parts)
    }
}

/// The mean of the parts' centres (the origin for none).
pub fn mean_centre(parts: &[PartPose]) -> [f64; 3] {
    if parts.is_empty() {
        return [0.0; 3];
    }
    let n = parts.len() as f64;
    std::array::from_fn(|i| parts.iter().map(|p| p.centre[i]).sum::<f64>() / n)
}

/// How a robot kind's modules look, as data every drawer reads (the recording carries it to
/// the viewer; `show` paints from it): each part's colour, words and solid, a joint ring if
/// the robot shows one, and how a flat picture draws a module.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Drawing {
    /// By part index, as [`ModulePose::parts`].
    pub parts: Vec<PartLook>,
    /// A ring about part 0's up axis at the module's centre (a joint between its parts).
    pub joint_ring: Option<Ring>,
    /// How the flat picture (`show`) draws a module.
    pub picture: Picture,
}

/// One part's look.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PartLook {
    /// Red, green, blue.
    pub colour: [u8; 3],
    /// What the colour means, for legends.
    pub legend: String,
    pub solid: Solid,
}

/// A part's solid in its own frame, its up axis along the pose's `up`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Solid {
    /// Half a sphere whose dome points along the up axis, its flat face through the centre.
    Dome { radius: f64 },
    /// A cube centred on the part's centre.
    Cube { edge: f64 },
}

/// A torus about an axis.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Ring {
    pub radius: f64,
    pub tube: f64,
}

/// How a flat picture draws a module.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Picture {
    /// One disc of `radius` at the module's centre, split between the colours of parts 0 and 1
    /// across part 1's up axis.
    SplitDisc { radius: f64 },
    /// Each part a cube of half-size `half` in its colour, consecutive parts joined by a bar.
    LinkedCubes { half: f64 },
}
