//! One question-answering view over any robot's configuration (modules, names, ids,
//! connectors, male or female, latches, joints), so that no other crate dispatches on the
//! robot: a thin handle on [`RobotShape`] with the facts derived from it.

use crate::api::Configuration;
use crate::common::Port;
use crate::shape::RobotShape;

/// A configuration of any robot, borrowed.
#[derive(Clone, Copy)]
pub struct View<'c>(&'c dyn RobotShape);

impl<'c> View<'c> {
    /// The view of a configuration of any robot.
    pub fn of(config: &'c Configuration) -> View<'c> {
        View(config.shape())
    }

    /// The view of any robot's shape.
    pub fn new(shape: &'c dyn RobotShape) -> View<'c> {
        View(shape)
    }

    /// Connectors of every module of this robot.
    pub fn connectors(self) -> u8 {
        self.0.connectors()
    }

    pub fn is_male(self, connector: u8) -> bool {
        self.0.is_male(connector)
    }

    /// Which rigid side of its module a connector is on, as the robot says
    /// (`RobotShape::side`).
    pub fn side(self, connector: u8) -> usize {
        self.0.side(connector)
    }

    /// Number of modules.
    pub fn len(self) -> usize {
        self.0.len()
    }

    pub fn is_empty(self) -> bool {
        self.len() == 0
    }

    /// Module `m`'s name (empty when there is no such module).
    pub fn name(self, m: usize) -> String {
        self.0.name(m).unwrap_or_default().to_string()
    }

    pub fn id(self, m: usize) -> Option<u32> {
        self.0.id(m)
    }

    pub fn index(self, name: &str) -> Option<usize> {
        self.0.index(name)
    }

    pub fn index_by_id(self, id: u32) -> Option<usize> {
        self.0.index_by_id(id)
    }

    /// Joint `joint` of module `m`, in the unit its robot's plugin uses for angles.
    pub fn joint(self, m: usize, joint: u8) -> Option<i64> {
        self.0.joint(m, joint)
    }

    pub fn latched_to(self, port: Port) -> Option<Port> {
        self.0.latched_to(port)
    }

    pub fn facing(self, port: Port) -> Option<Port> {
        self.0.facing(port)
    }

    /// Where a packet sent on `port` goes, as the robot's topology says
    /// (`RobotShape::link_target`).
    pub fn link_target(self, port: Port) -> Option<Port> {
        self.0.link_target(port)
    }

    pub fn port_name(self, port: Port) -> String {
        self.0.port_name(port)
    }
}
