//! ATRON: the lattice and module frames (`lattice.rs`), the validated configuration
//! (`config.rs`), its data file (`json.rs`) and the world and its operations (`world.rs`); `builtin/atron.rs` puts it
//! behind the robot API, above the shared `Configuration` and `compare` (which use its types).

pub(crate) mod config;
pub(crate) mod json;
pub(crate) mod lattice;
pub(crate) mod world;

pub use config::{AtronConfiguration, AtronModule};
pub use lattice::*;
pub use world::World;
