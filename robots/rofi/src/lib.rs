//! RoFI universal modules, as one robot kind: a configuration of them (`module.rs`), RoFI's
//! old text format (`old_format.rs`), RofiWorld JSON (`rofiworld.rs`) and voxel JSON
//! (`voxel.rs`, worlds matched up to placement), told apart by their
//! content (`formats.rs`), and dynarole's own file (`json.rs`, `rofi.schema.json`); the forward
//! kinematics of their shoes along one spanning tree (`tree.rs`, `kinematics.rs`), the validity
//! RoFI asks of a configuration (`validity.rs`), a group of joint turns checked along its whole
//! motion over every relative timing or in lock-step (`sweep.rs`), one turn as a rigid motion
//! and the connector a free one mates with (`turn.rs`); a plan's steps (`steps.rs`) and the
//! program imported from it (`import.rs`); the configuration the rest of dynarole sees
//! (`robot.rs`), the robot model (`model.rs`), the drawing (`drawing.rs`) and the plugin
//! (`rofi.robot.toml`). [`KIND`] is what the registry lists.

mod drawing;
mod formats;
mod import;
mod json;
mod kinematics;
mod model;
mod module;
mod old_format;
mod robot;
mod rofiworld;
mod steps;
mod sweep;
mod tree;
mod turn;
mod validity;
mod voxel;

pub use formats::{read_plan, recognise, Format, FormatError, ReadPlan};
pub use kinematics::{poses, poses_from, KinematicsError, Poses};
pub use model::{RofiModel, MOTION_LIMIT};
pub use module::*;
pub use old_format::{read_old_format, write_old_format, OldFormatError, Plan};
pub use robot::RofiRobot;
pub use rofiworld::{read_rofiworld, RofiWorldError};
pub use steps::{plan_steps, plan_steps_at, step_between, PlanError, Step, StepError, Together};
pub use sweep::{
    sweep, sweep_within, SweepError, SweepVerdict, Timing, Turn, SWEEP_BUDGET, SWEEP_TOLERANCE,
};
pub use tree::{across_connection, across_module, Shoe, LOOP_TOLERANCE};
pub use turn::{face_centre, mate_of, turn_motion, TurnMotion};
pub use validity::{first_collision, validate, Collision, Invalid, COLLISION_DISTANCE_SQUARED};
pub use voxel::{read_voxel, VoxelError, VoxelPlan};

use dynarole_world::{ConfigError, Configuration, Drawing, ImportedPlan, NetworkPreset, RobotKind};

/// RoFICoM's network: each connector a full-duplex channel to the one connector it is
/// connected to, which nothing else hears; modules powered on at random instants in the first
/// 100 ms and broadcasts jittered by up to 20 ms, as the ATRON board's.
pub const NETWORK_PRESETS: [NetworkPreset; 1] = [NetworkPreset {
    name: "roficom",
    half_duplex_sides: false,
    power_on_spread_us: 100_000,
    jitter_ms: 20,
}];

/// The RoFI robot kind.
pub struct Rofi;

/// The one value of [`Rofi`] the registry lists.
pub static KIND: Rofi = Rofi;

impl RobotKind for Rofi {
    fn name(&self) -> &'static str {
        "rofi"
    }

    fn file_tag(&self) -> &'static str {
        json::FILE_TAG
    }

    fn plugin(&self) -> (&'static str, &'static str) {
        ("rofi.robot.toml", include_str!("../rofi.robot.toml"))
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

    /// `rofi.schema.json`: the structure of dynarole's RoFI files (`json.rs` reads them).
    fn schema(&self) -> Option<&'static str> {
        Some(include_str!("../rofi.schema.json"))
    }

    /// RoFI's old text format and RofiWorld JSON, one configuration.
    fn read_native(&self, text: &str) -> Option<Result<Configuration, ConfigError>> {
        import::read_native(text)
    }

    fn plan_formats(&self) -> Option<&'static str> {
        Some(
            "RoFI's old text format (`C` blocks of `M` and `E` lines; the `length`/`queue`/`cfgs` \
             lines rofi-reconfig prints after its path are skipped) or a JSON array of RofiWorlds",
        )
    }

    /// A plan in RoFI's old text format (several `C` blocks) or a JSON array of RofiWorlds.
    fn import_plan(
        &self,
        text: &str,
        sequence: &str,
        options: &dynarole_world::ImportOptions,
    ) -> Option<Result<ImportedPlan, dynarole_world::PlanError>> {
        let plan = import::import_plan(text, sequence)?;
        if !options.ground.is_empty() {
            // Said rather than ignored: the modules the user meant to hold still would move.
            return Some(Err(dynarole_world::PlanError {
                line: 1,
                column: 1,
                message: "RoFI's plans have no module groups: a ground (`--ground`) is for \
                          plans that have them"
                    .into(),
            }));
        }
        Some(plan)
    }
}

dynarole_world::robot_configuration!(RofiRobot, KIND, RofiModel::new);
