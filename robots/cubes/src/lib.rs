//! Sliding and pivoting cubes on the integer lattice, as one robot kind: the lattice and its
//! moves with the cube planners' move rules and parallel-move rules (`lattice.rs`), a
//! configuration of cubes as the rest of dynarole sees it (`robot.rs`), dynarole's data file
//! (`json.rs`, `cubes.schema.json`), the robot model (`model.rs`), the drawing
//! (`drawing.rs`), MRWT's `.scen` scenarios (`scen.rs`), their lines as moves (`decode.rs`),
//! the program imported from one (`import.rs`), a sequence written as one (`export.rs`), and
//! the plugin (`cubes.robot.toml`).
//! [`KIND`] is what the registry lists.

pub mod decode;
mod drawing;
mod export;
mod import;
mod json;
pub mod lattice;
mod model;
mod robot;
pub mod scen;

pub use export::scen_lines;
pub use json::{FILE_TAG, MAX_COORDINATE};
pub use model::{CubesModel, MOTION_LIMIT};
pub use robot::{face_of, Cube, CubesRobot};

use dynarole_world::{ConfigError, Configuration, Drawing, ImportedPlan, NetworkPreset, RobotKind};

/// Cubes talk through the faces they share: each face a full-duplex channel to the face it
/// touches, which nothing else hears; modules powered on at random instants in the first
/// 100 ms and broadcasts jittered by up to 20 ms, as the ATRON board's.
pub const NETWORK_PRESETS: [NetworkPreset; 1] = [NetworkPreset {
    name: "faces",
    half_duplex_sides: false,
    power_on_spread_us: 100_000,
    jitter_ms: 20,
}];

/// The cubes robot kind.
pub struct Cubes;

/// The one value of [`Cubes`] the registry lists.
pub static KIND: Cubes = Cubes;

impl RobotKind for Cubes {
    fn name(&self) -> &'static str {
        "cubes"
    }

    fn file_tag(&self) -> &'static str {
        FILE_TAG
    }

    fn plugin(&self) -> (&'static str, &'static str) {
        ("cubes.robot.toml", include_str!("../cubes.robot.toml"))
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

    /// `cubes.schema.json`: the structure of dynarole's cube files (`json.rs` reads them).
    fn schema(&self) -> Option<&'static str> {
        Some(include_str!("../cubes.schema.json"))
    }

    /// A `.scen` scenario's first configuration: its modules where the file puts them.
    fn read_native(&self, text: &str) -> Option<Result<Configuration, ConfigError>> {
        import::read_native(text)
    }

    fn plan_formats(&self) -> Option<&'static str> {
        Some("an MRWT scenario (`.scen`: header, groups, modules, then one block per move set)")
    }

    fn export_formats(&self) -> &'static [&'static str] {
        &["scen"]
    }

    /// `scen`: an MRWT scenario, one move set per parallel group.
    fn export_plan(
        &self,
        format: &str,
        plan: &dynarole_world::PlanToExport<'_>,
    ) -> Option<Result<String, String>> {
        (format == "scen").then(|| export::export_scen(plan))
    }

    /// An MRWT scenario: its move sets as `&` groups joined by `;`, the modules of the
    /// groups `ground` fixed.
    fn import_plan(
        &self,
        text: &str,
        sequence: &str,
        options: &dynarole_world::ImportOptions,
    ) -> Option<Result<ImportedPlan, dynarole_world::PlanError>> {
        import::import_plan(text, sequence, &options.ground)
    }
}

dynarole_world::robot_configuration!(CubesRobot, KIND, CubesModel::new);
