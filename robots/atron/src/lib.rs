//! ATRON, as one robot kind: the lattice and module frames (`lattice.rs`), the validated
//! configuration (`config.rs`), its data file (`json.rs`), the world and its operations
//! (`world.rs`), the robot API over them (`model.rs`), chains made by rule (`generated.rs`)
//! and its plugin (`atron.robot.toml`); [`KIND`] is what the registry lists.

mod config;
mod drawing;
pub mod generated;
mod json;
mod lattice;
mod model;
mod world;

pub use config::{AtronConfiguration, AtronModule};
pub use lattice::*;
pub use world::World;

use dynarole_world::{ConfigError, Configuration, Drawing, NetworkPreset, RobotKind};

/// The physical ATRON network (atron.md a.8): one half-duplex UART per hemisphere (packets
/// heard at once collide), modules powered on at random instants in the first 100 ms, and
/// broadcasts jittered by up to 20 ms. The default.
pub const NETWORK_PRESETS: [NetworkPreset; 1] = [NetworkPreset {
    name: "atron",
    half_duplex_sides: true,
    power_on_spread_us: 100_000,
    jitter_ms: 20,
}];

/// The ATRON robot kind.
pub struct Atron;

/// The one value of [`Atron`] the registry lists.
pub static KIND: Atron = Atron;

impl RobotKind for Atron {
    fn name(&self) -> &'static str {
        "atron"
    }

    fn file_tag(&self) -> &'static str {
        "ATRON"
    }

    fn plugin(&self) -> (&'static str, &'static str) {
        ("atron.robot.toml", include_str!("../atron.robot.toml"))
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

    /// Its modules' hemisphere board, an ATmega128 at 16 MHz (`runtime/avr`).
    fn firmware_boards(&self) -> &'static [&'static str] {
        &["avr"]
    }

    /// `atron.schema.json`: the structure of its data files (`json.rs` reads them).
    fn schema(&self) -> Option<&'static str> {
        Some(include_str!("../atron.schema.json"))
    }
}

dynarole_world::robot_configuration!(AtronConfiguration, KIND, World::new);
