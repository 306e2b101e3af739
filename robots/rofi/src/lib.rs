//! RoFI universal modules (issue 30, first part): a configuration of them (`module.rs`), RoFI's
//! old text format read with located errors (`old_format.rs`) and its RofiWorld JSON, one world
//! or a plan of them, with errors naming the field (`rofiworld.rs`), the forward kinematics of their
//! shoes along one spanning tree (`tree.rs`, `kinematics.rs`) and the validity RoFI asks of a configuration, connected, every
//! loop closed and no two shoes overlapping (`validity.rs`), and a group of joint turns checked
//! along its whole motion, over every relative timing or in lock-step (`sweep.rs`); a plan's
//! consecutive configurations as steps, each checked and its turns classed (`steps.rs`). Not
//! yet a robot of the registry.

mod kinematics;
mod module;
mod old_format;
mod rofiworld;
mod steps;
mod sweep;
mod tree;
mod validity;

pub use kinematics::{poses, poses_from, KinematicsError, Poses};
pub use module::*;
pub use old_format::{read_old_format, write_old_format, OldFormatError, Plan};
pub use rofiworld::{read_rofiworld, RofiWorldError};
pub use steps::{plan_steps, plan_steps_at, step_between, PlanError, Step, StepError, Together};
pub use sweep::{
    sweep, sweep_within, SweepError, SweepVerdict, Timing, Turn, SWEEP_BUDGET, SWEEP_TOLERANCE,
};
pub use tree::{across_connection, across_module, Shoe, LOOP_TOLERANCE};
pub use validity::{first_collision, validate, Collision, Invalid, COLLISION_DISTANCE_SQUARED};
