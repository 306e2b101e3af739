//! ATRON: the lattice and module frames (`lattice.rs`), the validated configuration
//! (`config.rs`), the world and its operations (`world.rs`), and the robot API (`model.rs`).

pub(crate) mod config;
pub(crate) mod lattice;
mod model;
pub(crate) mod world;

pub use config::{AtronConfiguration, AtronModule};
pub use lattice::*;
pub use world::World;
