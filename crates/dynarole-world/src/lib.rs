//! The robot API: what every robot kind gives the tree, and the shared machinery robot
//! folders build on. Nothing here knows a robot by name.
//!
//! - [`RobotKind`] / [`Robots`]: a robot kind (its plugin, its data files) and a set of them;
//!   [`Robots::read_configuration`] picks the kind by a file's `robot` field.
//! - [`Configuration`]: a validated configuration of any kind, behind [`RobotConfiguration`].
//! - [`RobotShape`] / [`RobotModel`]: the questions a configuration answers (modules, names,
//!   ids, connectors, genders, latches, joints, topology) and a robot being reconfigured
//!   (doing an [`Action`]; the [`Motion`] it makes); [`View`] is the borrowed handle callers query.
//! - [`compare`]: equality up to one of the 24 lattice rotations plus a translation.
//! - For robot folders: `structure` (modules and latches), `world_common` (latching, turns
//!   and their sweeps), `graph`, `rigid`, `file_format` (the data-file layout every robot
//!   shares, errors with field paths) and `geometry`, with the `robot_shape!`,
//!   `robot_configuration!` and `configuration_queries!` macros.
//!
//! The crate does no input/output; it is deterministic (no hash-map iteration anywhere).

mod api;
pub mod common;
mod compare;
mod drawing;
pub mod file_format;
pub mod geometry;
pub mod graph;
mod motion;
mod ops;
pub mod rigid;
mod robot_set;
mod shape;
pub mod structure;
mod view;
pub mod world_common;

pub use api::{
    Configuration, GroupVerdict, ImportOptions, ImportedPlan, NetworkPreset, PlanError,
    PlanToExport, RobotConfiguration, RobotKind, RobotModel,
};
pub use common::{ConfigError, Latch, Metadata, NamedConnection, Port};
pub use compare::{
    compare, compare_with_expected, model_difference, Difference, JointDifference, Misplaced, Sides,
};
pub use drawing::{mean_centre, Drawing, ModulePose, PartLook, PartPose, Picture, Ring, Solid};
pub use geometry::{Rotation, Vec3};
pub use motion::{Carried, Leg, Motion};
pub use ops::{OpError, Outcome, Warning};
pub use robot_set::Robots;
pub use shape::{latched_or_male_to_free_female, Action, RobotShape, SweepCheck};
pub use view::View;
