//! Kinematic models of modular robots (ATRON, M-TRAN) and their configurations.
//!
//! - [`RobotShape`] / [`RobotModel`]: the one robot API the other crates ask (modules, names,
//!   ids, connectors, genders, latches, joints; doing an [`Action`]; the motion of a turn).
//!   Each built-in robot's folder (`atron/`, `mtran/`) holds its lattice, configuration and
//!   world; `builtin/` implements the API over them (the modules' layering is in
//!   `builtin/mod.rs`); [`View`] is the borrowed handle callers query.
//! - [`Configuration::from_json_str`] / [`Configuration::to_json_string`]: the data-file JSON
//!   format, validated, with field paths in every error.
//! - [`World`]: the ATRON API (extend, retract, rotateFromToBy) on an exact integer lattice,
//!   with the acceptance rules of `README.md`.
//! - [`MtranWorld`]: connect, disconnect and joint turns for M-TRAN modules (`MTRAN.md`).
//! - [`compare`]: equality up to one of the 24 lattice rotations plus a translation.
//!
//! The crate does no input/output; it is deterministic (no hash-map iteration anywhere).

pub mod atron;
mod builtin;
mod common;
mod compare;
mod configuration;
mod file_format;
pub mod generated;
pub mod geometry;
mod graph;
mod json;
mod model;
mod motion;
pub mod mtran;
mod ops;
mod rigid;
mod structure;
mod view;
mod world_common;

pub use atron::{
    AtronConfiguration, AtronModule, Orientation, OrientationBase, World,
    MIN_SWEEP_DISTANCE_LATTICE,
};
pub use builtin::BUILTIN_ROBOTS;
pub use common::{ConfigError, Latch, Metadata, NamedConnection, Port};
pub use compare::{compare, compare_with_expected, Difference, JointDifference, Misplaced, Sides};
pub use configuration::{Configuration, Robot};
pub use geometry::{Rotation, Vec3};
pub use model::{Action, RobotModel, RobotShape};
pub use motion::TurnMotion;
pub use mtran::{MtranConfiguration, MtranJoint, MtranModule, MtranOrientation, MtranWorld};
pub use ops::{OpError, Outcome, Warning};
pub use view::View;
