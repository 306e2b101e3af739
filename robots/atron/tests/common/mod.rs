//! Shared by this robot's integration tests: its data files (embedded at compile time) read
//! by its own kind, and a tiny statement type for replaying sequences on the world.
#![allow(dead_code)]

use dynarole_robot_atron::{AtronConfiguration, World, KIND};
use dynarole_world::{Configuration, OpError, Outcome, RobotKind};

/// Every ATRON example, by name.
pub const FILES: [(&str, &str); 11] = [
    ("eight", include_str!("../../examples/eight.json")),
    ("car", include_str!("../../examples/car.json")),
    ("snake", include_str!("../../examples/snake.json")),
    ("car-xml", include_str!("../../examples/car-xml.json")),
    (
        "car-builder4",
        include_str!("../../examples/car-builder4.json"),
    ),
    (
        "snake-builder4",
        include_str!("../../examples/snake-builder4.json"),
    ),
    (
        "rotation-chain-1",
        include_str!("../../examples/rotation-chain-1.json"),
    ),
    (
        "rotation-chain-5",
        include_str!("../../examples/rotation-chain-5.json"),
    ),
    (
        "rotation-chain-10",
        include_str!("../../examples/rotation-chain-10.json"),
    ),
    (
        "rotation-chain-15",
        include_str!("../../examples/rotation-chain-15.json"),
    ),
    (
        "rotation-chain-20",
        include_str!("../../examples/rotation-chain-20.json"),
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
    KIND.read_configuration(text(name)?)
        .map_err(|e| format!("{name}: {e}"))
}

/// A data file as the ATRON configuration it is.
pub fn load_atron(name: &str) -> Result<AtronConfiguration, String> {
    load(name)?
        .downcast_ref::<AtronConfiguration>()
        .cloned()
        .ok_or_else(|| format!("{name} is not ATRON"))
}

/// One ATRON API call of a DynaRole sequence.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Statement {
    Extend(&'static str, u8),
    Retract(&'static str, u8),
    /// module, from, to, direction (true = increasing)
    Rotate(&'static str, u16, u16, bool),
}

impl Statement {
    /// The reverse operation (DynaRole's reversal rules).
    pub fn reversed(self) -> Statement {
        match self {
            Statement::Extend(m, c) => Statement::Retract(m, c),
            Statement::Retract(m, c) => Statement::Extend(m, c),
            Statement::Rotate(m, f, t, d) => Statement::Rotate(m, t, f, !d),
        }
    }

    /// Runs the statement on `world`.
    pub fn run(self, world: &mut World) -> Result<Outcome, OpError> {
        match self {
            Statement::Extend(m, c) => world.extend(m, c),
            Statement::Retract(m, c) => world.retract(m, c),
            Statement::Rotate(m, f, t, d) => world.rotate(m, f, t, d),
        }
    }
}

/// Reverses a sequence of parallel groups: groups in reverse order, members in reverse order,
/// each statement reversed.
pub fn reverse(groups: &[Vec<Statement>]) -> Vec<Vec<Statement>> {
    groups
        .iter()
        .rev()
        .map(|g| g.iter().rev().map(|s| s.reversed()).collect())
        .collect()
}
