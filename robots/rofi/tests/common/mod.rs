//! What the RoFI tests share: modules, connections and configurations written briefly.

#![allow(dead_code)] // each test file uses its own part of it

use dynarole_robot_rofi::{
    Connection, Connector, Dock, Module, Orientation, RofiConfiguration, Side,
};

pub fn module(id: u32, alpha: f64, beta: f64, gamma: f64) -> Module {
    Module::new(id, alpha, beta, gamma)
}

/// A connection from (module, side, dock) to (module, side, dock) with twist `o`.
pub fn edge(from: (u32, Side, Dock), o: Orientation, to: (u32, Side, Dock)) -> Connection {
    Connection {
        from: (from.0, Connector::new(from.1, from.2)),
        orientation: o,
        to: (to.0, Connector::new(to.1, to.2)),
    }
}

pub fn configuration(modules: &[Module], edges: &[Connection]) -> RofiConfiguration {
    RofiConfiguration::from_parts(modules, edges).expect("a configuration")
}
