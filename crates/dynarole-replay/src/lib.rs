//! Runs checked sequences on the kinematic robot models (no network): replay, the role
//! assignment on a configuration, and the independence check of parallel groups.
//!
//! Everything a step does or refuses becomes a language [`Diagnostic`] at the statement's
//! source location, so the CLI renders it like any other message.

mod bitset;
mod independence;
mod lockstep;
mod motion;
mod orders;
mod parallel;
mod prepare;
mod robot_world;
mod roles;
mod routes;
mod run;
mod simultaneous;
mod topology;
mod warnings;

pub use independence::{check_independence, check_independence_exhaustive};
pub use parallel::{
    dependency_graph, group_checked_graph, parallelise, transitive_reduction, Form, FormKind,
    Layout, ParalleliseError, Parallelised, Request,
};
pub use prepare::{prepare, PrepareError, Prepared};
pub use robot_world::{action, RobotWorld, StepOutcome};
pub use roles::{assign_modules, assign_modules_on, Assignment};
pub use routes::token_routes;
pub use run::{replay, Replay};
pub use simultaneous::{first_contact, Along, Contact, Pairs};
pub use topology::{communication_graph, CommGraph};
