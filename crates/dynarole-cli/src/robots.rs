//! The robot kinds this run of the program knows: the registry's (`dynarole_robots`), or the
//! set a program embedding dynarole gives [`crate::main_with`]. Chosen once, before any
//! command runs, and read by every command that reads a configuration or checks a program.

use crate::failure::Failure;
use dynarole_core::RobotRegistry;
use dynarole_world::Robots;
use std::sync::OnceLock;

static ROBOTS: OnceLock<Robots> = OnceLock::new();

/// The robot kinds of this run (the registry's when none were installed).
pub fn robots() -> &'static Robots {
    ROBOTS.get_or_init(dynarole_robots::robots)
}

/// Makes `robots` the kinds of this run; the first call wins (a process runs one set).
pub fn install(robots: Robots) {
    // A second call (another command in the same test process) keeps the first set.
    let _ = ROBOTS.set(robots);
}

/// The API plugins of this run's robot kinds.
pub fn plugins() -> Result<RobotRegistry, Failure> {
    dynarole_robots::plugins_of(robots()).map_err(Failure::Internal)
}
