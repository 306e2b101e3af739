//! The hinged cubes as one robot kind, kept beside the program that adds it: a planar chain of
//! cubes, each with a female back connector and a male front connector on a face that a hinge
//! turns a quarter turn either way. Its plugin (`hinged.robot.toml`), its data file
//! (`configuration.rs`), its model (`model.rs`) and its drawing (`drawing.rs`); [`KIND`] is
//! what the program adds to the registry's robots.

mod configuration;
mod drawing;
mod model;

pub use configuration::CubesConfiguration;
pub use model::CubesWorld;

use dynarole_world::{ConfigError, Configuration, Drawing, RobotKind};

/// The plugin name a program gives in `robot hinged;`.
pub const NAME: &str = "hinged";

/// The `robot` field of its data files.
pub const FILE_TAG: &str = "HINGED";

/// The hinged-cubes robot kind.
pub struct HingedCubes;

/// The one value of [`HingedCubes`] a program adds to its robots.
pub static KIND: HingedCubes = HingedCubes;

impl RobotKind for HingedCubes {
    fn name(&self) -> &'static str {
        NAME
    }

    fn file_tag(&self) -> &'static str {
        FILE_TAG
    }

    fn plugin(&self) -> (&'static str, &'static str) {
        ("hinged.robot.toml", include_str!("../hinged.robot.toml"))
    }

    fn read_configuration(&self, text: &str) -> Result<Configuration, ConfigError> {
        configuration::read(text).map(Configuration::new)
    }

    fn drawing(&self) -> Drawing {
        drawing::drawing()
    }

    /// `hinged.schema.json`: the structure of its data files (`configuration.rs` reads them).
    fn schema(&self) -> Option<&'static str> {
        Some(include_str!("../hinged.schema.json"))
    }
}

dynarole_world::robot_configuration!(CubesConfiguration, KIND, CubesWorld::new);
