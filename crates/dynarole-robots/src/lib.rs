//! The registry: the robot kinds dynarole is built with, one line each. Adding a robot is
//! adding its folder under `robots/` (a crate) and its line in [`BUILT_IN`] (with the
//! dependency in this crate's manifest); nothing else in the tree names it.

use dynarole_core::{RobotApi, RobotRegistry};
use dynarole_world::{ConfigError, Configuration, RobotKind, Robots};

/// Every robot kind of the tree, in the order messages list them.
pub const BUILT_IN: [&dyn RobotKind; 4] = [
    &dynarole_robot_atron::KIND,
    &dynarole_robot_mtran::KIND,
    &dynarole_robot_rofi::KIND,
    &dynarole_robot_cubes::KIND,
];

/// The built-in robot kinds.
pub fn robots() -> Robots {
    Robots::new(BUILT_IN)
}

/// The API plugins of `robots`, as the front end checks programs against them; the error
/// names a plugin that does not load (a defect of that robot's folder, whose tests load it).
pub fn plugins_of(robots: &Robots) -> Result<RobotRegistry, String> {
    let mut registry = RobotRegistry::default();
    for kind in robots.kinds() {
        let (file, text) = kind.plugin();
        let api = RobotApi::from_toml(text).map_err(|e| format!("{file}: {e}"))?;
        registry.add(api);
    }
    Ok(registry)
}

/// The built-in robots' API plugins.
///
/// # Panics
/// When a built-in plugin does not load, which its robot's tests rule out.
pub fn plugins() -> RobotRegistry {
    plugins_of(&robots()).expect("the built-in plugins load")
}

/// Reads a configuration file of any built-in robot kind.
pub fn read_configuration(text: &str) -> Result<Configuration, ConfigError> {
    robots().read_configuration(text)
}
