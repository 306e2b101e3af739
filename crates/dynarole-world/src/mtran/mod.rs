//! M-TRAN: the module model and the validated configuration (`module.rs`), the world and its
//! operations (`world.rs`), and the robot API (`model.rs`).

mod model;
pub(crate) mod module;
pub(crate) mod world;

pub use module::*;
pub use world::MtranWorld;
