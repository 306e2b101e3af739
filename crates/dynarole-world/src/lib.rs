//! Kinematic models of modular robots (ATRON, M-TRAN) and their configurations.
//!
//! - [`Configuration::from_json_str`] / [`Configuration::to_json_string`]: the data-file JSON
//!   format, validated, with field paths in every error.
//! - [`World`]: the ATRON API (extend, retract, rotateFromToBy) on an exact integer lattice,
//!   with the acceptance rules of `README.md`.
//! - [`MtranWorld`]: connect, disconnect and joint turns for M-TRAN modules (`MTRAN.md`).
//! - [`compare`]: equality up to one of the 24 lattice rotations plus a translation.
//!
//! The crate does no input/output; it is deterministic (no hash-map iteration anywhere).

pub mod atron;
mod compare;
mod config;
pub mod generated;
pub mod geometry;
mod graph;
mod json;
pub mod mtran;
mod mtran_world;
mod ops;
mod structure;
mod view;
mod world;
mod world_common;

pub use atron::{Orientation, OrientationBase, MIN_SWEEP_DISTANCE_LATTICE};
pub use compare::{compare, Difference, JointDifference, Misplaced};
pub use config::{
    AtronConfiguration, AtronModule, ConfigError, Configuration, Latch, Metadata, NamedConnection,
    Port, Robot,
};
pub use geometry::{Rotation, Vec3};
pub use mtran::{MtranConfiguration, MtranJoint, MtranModule, MtranOrientation};
pub use mtran_world::MtranWorld;
pub use ops::{OpError, Outcome, Warning};
pub use view::View;
pub use world::{TurnMotion, World};
