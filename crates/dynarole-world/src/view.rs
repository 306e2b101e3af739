//! One question-answering view over either robot's configuration (modules, names, ids,
//! connectors, male or female, latches, joints), so that no other crate dispatches on the robot.

use crate::atron::{is_male, CONNECTOR_COUNT};
use crate::mtran::{is_mtran_male, MTRAN_CONNECTOR_COUNT};
use crate::{AtronConfiguration, Configuration, MtranConfiguration, Port};

/// A configuration of either robot, borrowed.
#[derive(Clone, Copy)]
pub enum View<'c> {
    Atron(&'c AtronConfiguration),
    Mtran(&'c MtranConfiguration),
}

impl<'c> View<'c> {
    pub fn of(config: &'c Configuration) -> View<'c> {
        match config {
            Configuration::Atron(c) => View::Atron(c),
            Configuration::Mtran(c) => View::Mtran(c),
        }
    }

    /// Connectors of every module of this robot.
    pub fn connectors(self) -> u8 {
        match self {
            View::Atron(_) => CONNECTOR_COUNT,
            View::Mtran(_) => MTRAN_CONNECTOR_COUNT,
        }
    }

    pub fn is_male(self, connector: u8) -> bool {
        match self {
            View::Atron(_) => is_male(connector),
            View::Mtran(_) => is_mtran_male(connector),
        }
    }

    /// Which half of a module a connector is on (an ATRON hemisphere, an M-TRAN block).
    pub fn hemisphere(self, connector: u8) -> usize {
        usize::from(connector >= self.connectors() / 2)
    }

    /// Number of modules.
    pub fn len(self) -> usize {
        match self {
            View::Atron(c) => c.modules().len(),
            View::Mtran(c) => c.modules().len(),
        }
    }

    pub fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Module `m`'s name (empty when there is no such module).
    pub fn name(self, m: usize) -> String {
        match self {
            View::Atron(c) => c.module(m).map(|x| x.name.clone()),
            View::Mtran(c) => c.modules().get(m).map(|x| x.name.clone()),
        }
        .unwrap_or_default()
    }

    pub fn id(self, m: usize) -> Option<u32> {
        match self {
            View::Atron(c) => c.module(m).and_then(|x| x.id),
            View::Mtran(c) => c.modules().get(m).and_then(|x| x.id),
        }
    }

    pub fn index(self, name: &str) -> Option<usize> {
        match self {
            View::Atron(c) => c.module_index(name),
            View::Mtran(c) => c.module_index(name),
        }
    }

    pub fn index_by_id(self, id: u32) -> Option<usize> {
        match self {
            View::Atron(c) => c.module_index_by_id(id),
            View::Mtran(c) => c.module_index_by_id(id),
        }
    }

    /// Joint `joint` of module `m`, in the robot's units (ATRON 1/432 turn, M-TRAN degrees).
    pub fn joint(self, m: usize, joint: u8) -> Option<i64> {
        match self {
            View::Atron(c) => c.module(m).map(|x| i64::from(x.joint_units)),
            View::Mtran(c) => c
                .modules()
                .get(m)
                .and_then(|x| x.joints_deg.get(usize::from(joint)))
                .map(|d| i64::from(*d)),
        }
    }

    pub fn latched_to(self, port: Port) -> Option<Port> {
        match self {
            View::Atron(c) => c.latched_to(port),
            View::Mtran(c) => c.latched_to(port),
        }
    }

    pub fn facing(self, port: Port) -> Option<Port> {
        match self {
            View::Atron(c) => c.facing(port),
            View::Mtran(c) => c.facing(port),
        }
    }

    /// Where a packet sent on `port` goes (atron.md a.8): the latched partner, or, for an
    /// unlatched male connector, an unlatched female connector facing it.
    pub fn link_target(self, port: Port) -> Option<Port> {
        if let Some(p) = self.latched_to(port) {
            return Some(p);
        }
        if !self.is_male(port.connector) {
            return None;
        }
        let other = self.facing(port)?;
        let free_female = !self.is_male(other.connector) && self.latched_to(other).is_none();
        free_female.then_some(other)
    }

    pub fn port_name(self, port: Port) -> String {
        match self {
            View::Atron(c) => c.port_name(port),
            View::Mtran(c) => c.port_name(port),
        }
    }
}
