//! Shared by the registry's cross-robot tests: every robot's data files (embedded at compile
//! time), read by the registry.
#![allow(dead_code)]

use dynarole_robot_atron::AtronConfiguration;
use dynarole_world::Configuration;

/// Every data file, by name.
pub const FILES: [(&str, &str); 16] = [
    (
        "eight",
        include_str!("../../../../robots/atron/examples/eight.json"),
    ),
    (
        "car",
        include_str!("../../../../robots/atron/examples/car.json"),
    ),
    (
        "snake",
        include_str!("../../../../robots/atron/examples/snake.json"),
    ),
    (
        "car-xml",
        include_str!("../../../../robots/atron/examples/car-xml.json"),
    ),
    (
        "car-builder4",
        include_str!("../../../../robots/atron/examples/car-builder4.json"),
    ),
    (
        "snake-builder4",
        include_str!("../../../../robots/atron/examples/snake-builder4.json"),
    ),
    (
        "rotation-chain-1",
        include_str!("../../../../robots/atron/examples/rotation-chain-1.json"),
    ),
    (
        "rotation-chain-5",
        include_str!("../../../../robots/atron/examples/rotation-chain-5.json"),
    ),
    (
        "rotation-chain-10",
        include_str!("../../../../robots/atron/examples/rotation-chain-10.json"),
    ),
    (
        "rotation-chain-15",
        include_str!("../../../../robots/atron/examples/rotation-chain-15.json"),
    ),
    (
        "rotation-chain-20",
        include_str!("../../../../robots/atron/examples/rotation-chain-20.json"),
    ),
    (
        "mtran-snake4",
        include_str!("../../../../robots/mtran/examples/mtran-snake4.json"),
    ),
    (
        "mtran-snake5",
        include_str!("../../../../robots/mtran/examples/mtran-snake5.json"),
    ),
    (
        "mtran-snake8",
        include_str!("../../../../robots/mtran/examples/mtran-snake8.json"),
    ),
    (
        "cubes-row4",
        include_str!("../../../../robots/cubes/examples/cubes-row4.json"),
    ),
    (
        "cubes-row4-end",
        include_str!("../../../../robots/cubes/examples/cubes-row4-end.json"),
    ),
];

/// The text of a data file.
pub fn text(name: &str) -> Result<&'static str, String> {
    FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| *t)
        .ok_or_else(|| format!("no data file {name}"))
}

/// A data file, parsed.
pub fn load(name: &str) -> Result<Configuration, String> {
    dynarole_robots::read_configuration(text(name)?).map_err(|e| format!("{name}: {e}"))
}

/// An ATRON data file, parsed.
pub fn load_atron(name: &str) -> Result<AtronConfiguration, String> {
    load(name)?
        .downcast_ref::<dynarole_robot_atron::AtronConfiguration>()
        .cloned()
        .ok_or_else(|| format!("{name} is not ATRON"))
}
