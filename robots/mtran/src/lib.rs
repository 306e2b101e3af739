//! M-TRAN, as one robot kind: the module model and the validated configuration
//! (`module.rs`), its data file (`json.rs`), the world and its operations (`world.rs`), the
//! robot API over them (`model.rs`) and its plugin (`mtran.robot.toml`); [`KIND`] is what the
//! registry lists.

mod drawing;
mod json;
mod model;
mod module;
mod world;

pub use module::*;
pub use world::MtranWorld;

use dynarole_world::{ConfigError, Configuration, Drawing, NetworkPreset, RobotKind};

/// M-TRAN's network is not modelled on its own: its runs use the ATRON board's model (one
/// half-duplex transceiver per block, random power-on in the first 100 ms, 20 ms broadcast
/// jitter), that robot's own preset under its name, as they always have.
pub const NETWORK_PRESETS: [NetworkPreset; 1] = dynarole_robot_atron::NETWORK_PRESETS;

/// The M-TRAN robot kind.
pub struct Mtran;

/// The one value of [`Mtran`] the registry lists.
pub static KIND: Mtran = Mtran;

impl RobotKind for Mtran {
    fn name(&self) -> &'static str {
        "mtran"
    }

    fn file_tag(&self) -> &'static str {
        "MTRAN"
    }

    fn plugin(&self) -> (&'static str, &'static str) {
        ("mtran.robot.toml", include_str!("../mtran.robot.toml"))
    }

    fn read_configuration(&self, text: &str) -> Result<Configuration, ConfigError> {
        json::read(text).map(Configuration::new)
    }

    fn drawing(&self) -> Drawing {
        drawing::drawing()
    }

    fn network_presets(&self) -> &'static [NetworkPreset] {
        &NETWORK_PRESETS
    }

    /// `mtran.schema.json`: the structure of its data files (`json.rs` reads them).
    fn schema(&self) -> Option<&'static str> {
        Some(include_str!("../mtran.schema.json"))
    }
}

dynarole_world::robot_configuration!(MtranConfiguration, KIND, MtranWorld::new);
