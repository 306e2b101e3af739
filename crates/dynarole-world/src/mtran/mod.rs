//! M-TRAN: the module model and the validated configuration (`module.rs`), its data file
//! (`json.rs`), the world and its operations (`world.rs`); `builtin/mtran.rs` puts it behind the robot API, above the shared
//! `Configuration` and `compare` (which use the types here).

pub(crate) mod json;
pub(crate) mod module;
pub(crate) mod world;

pub use module::*;
pub use world::MtranWorld;
